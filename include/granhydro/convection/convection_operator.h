#pragma once
/**
 * @file convection_operator.h
 * The convective operator L(U) of paper eq. (4.4) on a uniform Cartesian
 * patch and its SSP-RK3 time integrator, eq. (4.10).
 *
 * Reconstruction is dimension by dimension (paper section 4, fig. 2): for the
 * faces normal to d, stage A reconstructs along d to the two faces of every
 * cell (face averages), stage B along the first transverse direction to its
 * two Gauss points, stage C along the second; the face flux is the
 * Gauss-weighted sum of the numerical flux at the 2^(dim-1) points (eq. 4.6).
 * With midpoint quadrature the transverse stages reconstruct to the face
 * centre instead (one point per face; midpoint rule, second order).
 *
 * Positivity: if any reconstructed point value of a cell in direction d is
 * inadmissible, all of that cell's point values in direction d fall back to
 * the cell average (first order), counted in the statistics.
 *
 * Adaptive meshes: the reconstruction runs on the patch's same-level
 * neighbourhood, completed by virtual cells (restriction/prolongation) next
 * to level changes; a hanging face is a fine sub-face whose flux the coarse
 * cell takes with weight 1/2^(dim-1); on it the coarse side's value is its
 * Gauss point inside that sub-face.
 *
 * Well-balanced gravity (ConvectionSettings::gravity, Käppeli & Mishra 2014): the body
 * force is a source of this operator. Along a direction d with g_d != 0 that is not
 * periodic (a periodic direction holds no hydrostatic profile: there the point source n g), stage A
 * reconstructs each cell's deviation from its local isothermal equilibrium
 * (physics/hydrostatic.h) and adds it back at the faces; the momentum source is the
 * difference of the equilibrium pressures at the cell's faces, the energy source g . m
 * of the cell (0 at rest; the face mass fluxes of Käppeli & Mishra would make a dilute
 * cell beside a dense one pay the dissipation of their jump from its thermal energy). Wall faces normal to d take the mirror of
 * the interior face state as the ghost's, and the first-order fallbacks (positivity,
 * a posteriori) use the equilibrium face densities, so a pile at rest with uniform T
 * whose cell values lie on one equilibrium is a steady state to round-off.
 *
 * Hot loops run over flat slot lists with precomputed neighbour indices.
 */
#include <granhydro/boundary/convective_wall_flux.h>
#include <granhydro/convection/numerical_flux.h>
#include <granhydro/convection/reconstruction.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/mesh/slot_exchange.h>

#include <deal.II/base/array_view.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <vector>

namespace granhydro::convection
{
  struct ConvectionStatistics
  {
    FluxStatistics flux;
    /// cells x directions x stages whose reconstruction fell back to the cell average
    unsigned long long limited_cells = 0;
    /// cells x stages whose update was redone with first-order Rusanov fluxes (a posteriori)
    unsigned long long fallback_cells = 0;
    unsigned long long cell_updates = 0, rhs_evaluations = 0;
    /// wall face fluxes whose negative normal momentum flux (a wall pulling) was set to 0
    /// (cohesionless grains), on the faces of owned cells
    unsigned long long wall_tension_bounded = 0;
    /// well-balanced gravity: cells x directions x stages whose body force was the point
    /// source n g (no hydrostatic profile: dp/dn too small to carry the weight across the
    /// cell, or no equilibrium density found)
    unsigned long long gravity_point_sources = 0;
  };

  template <int dim, class Description>
  class ConvectionOperator
  {
  public:
    static constexpr unsigned int NC = dim + 2;
    using Vector                     = dealii::LinearAlgebra::distributed::Vector<double>;

    ConvectionOperator(const mesh::CartesianPatch<dim> &patch, const Description &desc,
                       const ConvectionSettings &settings);

    /// the stencil half width of the scene's reconstruction (ghost width - 1)
    static unsigned int stencil_half_width(const ReconstructionType t);

    /// (re)build the slot lists; call after the patch changed
    void setup();

    /// W: slot array (owned + MPI ghosts + boundary ghosts); rhs: n_owned*NC;
    /// repair_energy: the step's splitting allowance of the temperature repair (scaled, per
    /// grain; physics::GranularGas::admissible()), which MUSTA's predictor states may use
    void apply(const double *W, double *rhs, const double repair_energy) const;

    /// max over owned cells of sum_d (|u_d| + c)/dx_d (global MPI max). energy_shift (per
    /// owned cell, or none): taken off each cell's energy first (the implicit contact
    /// step's contact energy, which this operator's description does not hold)
    double max_rate(const Vector &U, const double *energy_shift = nullptr) const;

    /// one SSP-RK3 step (eq. 4.10) of size dt; U must be built on patch.partitioner().
    /// Returns false (U then undefined) if a stage stays inadmissible even with
    /// first-order fluxes: the caller retries with a smaller dt. repair_energy: the
    /// splitting allowance of the step it is part of (as in apply())
    bool ssp_rk3_step(Vector &U, const double dt, const double repair_energy) const;

    /// true if every owned cell is admissible outside a step (no splitting allowance; a
    /// state after the temperature repair passes with any allowance) (global); on
    /// failure, where/what; energy_shift as in max_rate()
    bool admissible(const Vector &U, std::string *what = nullptr, const double *energy_shift = nullptr) const;

    const ConvectionStatistics &statistics() const { return stats; }

    /// seconds this rank spent computing convective right-hand sides (apply()), without
    /// the waits for other ranks' halo values: the measured cost that 'Adaptivity/Load
    /// balance = measured cost' weighs this rank's cells with
    double busy_seconds() const { return busy_seconds_; }
    /// seconds this rank waited for other ranks' halo stage values in apply() (the slot
    /// exchange's finish; 0 on one rank), and in the all-reduce of each stage's
    /// admissibility (the vote that decides the first-order fallback)
    double halo_wait_seconds() const { return halo_wait_seconds_; }
    double vote_seconds() const { return vote_seconds_; }

    /// where the last rejected SSP-RK3 step failed (this rank; empty if elsewhere)
    const std::string   &failure() const { return last_failure; }
    ConvectionStatistics global_statistics() const;

  private:
    template <class Recon>
    void apply_impl(const Recon &rec, const double *W, double *rhs, const double repair_energy) const;
    void assemble_rhs(double *rhs) const;

    // well-balanced gravity (well_balanced.cc)
    /// which directions carry gravity, and the mirror rows of the stencils at their walls
    void setup_well_balanced();
    /// stage A along d (g_d != 0) for the slots of range: deviations from each slot's
    /// equilibrium reconstructed, its momentum source along d stored for owned slots
    template <class Recon>
    void reconstruct_well_balanced(const Recon &rec, const dealii::ArrayView<const unsigned int> &range,
                                   const unsigned int d, const double *Wp, double *out) const;
    /// the first-order face state of slot s on its side (0 lower, 1 upper) normal to d: the
    /// equilibrium face density with the slot's velocity and temperature (the slot's state
    /// along directions without gravity or where it takes the point source)
    void first_order_face_state(const double *Wp, const unsigned int s, const unsigned int d,
                                const unsigned int side, physics::State<dim> &U) const;
    /// wall face k normal to d (wb_wall_ghost[d][k] >= 0) with npts states on its low and
    /// high side: the ghost side's become the mirror of the cell side's
    void mirror_wall_face(const unsigned int d, const std::size_t k, double *low, double *high,
                          const unsigned int npts = 1) const;
    /// mirror_wall_face() on every wall face normal to d (points: [slot][side][point][component])
    void mirror_wall_points(const unsigned int d, double *points, const unsigned int npts) const;
    /// the body force's sources on the owned cells (momentum from the stored equilibrium
    /// pressures, energy g . m of the cell)
    void add_gravity_sources(double *rhs) const;
    bool stage_update(Vector &U, const double a, const double b, const double den, const double dt,
                      const double repair_energy) const;
    /// owned cell s of U, energy_shift[s] taken off its energy (none: nullptr)
    physics::State<dim> owned_state(const Vector &U, const unsigned int s, const double *energy_shift) const;

    const mesh::CartesianPatch<dim> &patch;
    const Description               &desc;
    NumericalFlux<dim, Description>  numflux;
    ReconstructionType               rtype;
    bool                             transverse; // transverse reconstruction stages B (and C in 3D)
    unsigned int                     P;          // points per transverse direction: 2 Gauss, 1 centre
    double                           length_unit;
    /// 1/dx_d in scaled units of a cell of refinement level k (patch.level()): inv_h[d][k]
    double     inv_h[dim][mesh::max_levels] = {};
    FirstOrder rec1;
    Muscl      rec_muscl;
    Weno3      rec3;
    Weno5      rec5;

    // slot lists per direction (on several ranks without the MPI ghosts, whose stage
    // values come from their owners through halo)
    std::vector<unsigned int> listA[dim], listB[dim], listC[dim];
    bool                      halo_exchange = false;
    mesh::SlotExchange        halo;
    /// the exchange channel of stage j (0: A, 1: B, 2: C) of direction d
    static unsigned int channel(const unsigned int d, const unsigned int j) { return 3 * d + j; }
    /// per direction and stage: the first split entries of the list are the slots other
    /// ranks read (computed and sent first), the rest follow
    std::size_t split[dim][3] = {};
    /// reconstruction stages per direction: A, then B and C (3D) with transverse stages
    unsigned int n_stages() const { return transverse ? dim : 1; }
    /// the direction stage j of the faces normal to d reconstructs along
    static unsigned int stage_direction(const unsigned int d, const unsigned int j)
    {
      return j == 0 ? d : (dim == 3 ? (d + j) % 3 : 1 - d);
    }
    /// per face of patch.faces(d): its boundary::ConvectiveWallKind (0: not a wall; the
    /// rule: boundary/convective_wall_flux.h)
    std::vector<char> wall[dim];
    bool              no_slip_pressure_flux = false;
    bool              no_wall_tension       = false;
    /// the wall flux rule on the flux F of a wall face; a negative wall pressure set to 0
    /// counted in stats when owned
    void wall_flux(const char kind, const unsigned int d, double *F, const bool owned) const
    {
      if (boundary::apply_convective_wall_flux<dim>(kind, d, F, no_wall_tension) && owned)
        ++stats.wall_tension_bounded;
    }
    /// whether the wall face k normal to d belongs to an owned cell
    bool owned_wall_face(const unsigned int d, const std::size_t k) const
    {
      const auto &f = patch.faces(d)[k];
      return (patch.is_cell(f.l) ? f.l : f.r) < patch.n_owned();
    }

    // the work arrays of a step are the patch's shared scratch (mesh::Scratch: the stage
    // arrays A, B, C serve one direction at a time), asked for at the start of apply() and
    // of ssp_rk3_step()
    mutable double *Fp[dim] = {}; // flux per face of patch.faces(d)
    mutable double *cand    = nullptr;
    /// per slot (owned and MPI ghosts): 1 if its update is redone first order (a float per
    /// cell, on the cells' partitioner cell_partitioner)
    mutable dealii::LinearAlgebra::distributed::Vector<float>  flags;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> cell_partitioner;
    mutable double                                            *W = nullptr, *rhs0 = nullptr, *U0 = nullptr;
    mutable ConvectionStatistics                               stats;
    mutable double      busy_seconds_ = 0, halo_wait_seconds_ = 0, vote_seconds_ = 0;
    mutable std::string last_failure;

    /// well-balanced gravity: g_d (scaled) and whether it acts along d
    double gravity[dim] = {};
    bool   wb_dir[dim]  = {};
    bool   wb_any       = false; // gravity is this step's (in some direction)
    /// the equilibrium's first-order face states need the cell's equilibrium; the stencils
    /// that reach behind a wall normal to d: per slot the row in wb_mirror[d] (-1: none; -2: a ghost behind such a wall),
    /// per row and stencil position (o + r) the mirrored position (o' + r) or -1
    std::vector<int>                        wb_row[dim];
    std::vector<std::array<signed char, 5>> wb_mirror[dim];
    /// per wall face normal to d: the ghost slot's boundary-ghost record (-1: not a wall)
    std::vector<int> wb_wall_ghost[dim];
    /// per owned cell: the momentum source along d of the last apply()
    mutable std::vector<double> wb_source[dim];
    /// the slot array the sources were computed from (apply()'s)
    mutable const double *wb_W = nullptr;
    /// boundary-ghost record index per slot (-1: not a boundary ghost)
    std::vector<int> ghost_record;
  };
} // namespace granhydro::convection
