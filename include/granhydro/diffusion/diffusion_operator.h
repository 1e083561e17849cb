#pragma once
/**
 * @file diffusion_operator.h
 * The diffusive operator and the sources of granular hydrodynamics, the
 * right-hand side of the paper's step V (eqs. 3.2, 5.1-5.9):
 *   f(U) = sum_i d_i F_i^v(U, grad U) + S(U)
 * on the uniform Cartesian patch, with
 *  - face fluxes F_i^v evaluated at the face state U_f = (U_L + U_R)/2 with the
 *    Garzo-Dufty coefficients there; the normal derivative is (U_R - U_L)/dx_i,
 *    the tangential derivatives (full flux, doc/physics.md 4.3) the average of the
 *    two cells' central differences; "diagonal only" keeps D_ii d_i U (paper 5.6);
 *  - sources: gravity n g, m n u.g and inelastic cooling -(3/2) n T zeta0
 *    (doc/physics.md 1, 3.5).
 * Adaptive meshes: a hanging face is a fine sub-face; its normal derivative is
 * the two-point difference over the true centre distance (h_coarse + h_fine)/2
 * and the coarse cell takes 1/2^(dim-1) of the flux; the tangential
 * derivatives use each cell's gradient neighbours (one-sided where the
 * neighbour is finer). The Jacobian is assembled the same way.
 * Walls: the mirror ghost states of the patch give exactly the slip-wall flux
 * of doc/physics.md 5.1 (no tangential stress, q = 0); no-slip ghosts (velocity
 * mirrored about the wall velocity) give the wall shear stress from the
 * one-sided gradient with u = u_w on the wall and the work (tau_w . e) . u_w
 * (doc/physics.md 5.1, P10); a dissipative wall adds the heat flux into the wall
 * q_w = (1 - eps_w) p_w sqrt(2 T/(pi m)) of doc/physics.md 5.2 (contact theorem,
 * replaces the paper's eq. 6.2, P11) with p_w, T of the adjacent cell;
 * outflow: zero gradient.
 *
 * f is evaluated 4 faces (fluxes) and 4 cells (sources, sums) at a time on GCC vectors of
 * doubles (physics/lanes.h), in a default-target and an AVX2 (no FMA) copy of the loop;
 * every lane does the scalar IEEE operations, so the result is that of the scalar code
 * bit for bit (unit.lanes_physics) and the scalar face_flux() of the Jacobian is the same
 * template at width 1.
 *
 * The Jacobian df/dU used by the implicit integrators is the exact derivative
 * of the normal-derivative part of every face flux (including the dependence
 * of the coefficients on the face state), obtained by finite differences of
 * the face flux, plus the exact source Jacobian. By default the
 * tangential-derivative (cross) terms are lagged, i.e. their dependence on U is
 * left out of the Jacobian (deferred correction, allowed by doc/physics.md 4.3);
 * Newton still converges to the full nonlinear residual. With cross_terms =
 * true their derivatives with respect to the edge neighbours are included too
 * (the fully coupled variant; 19-point stencil in 3D), which the integrator
 * uses when the lagged iteration stalls (near-vacuum, doc/physics.md P14).
 */
#include <granhydro/boundary/dissipative_wall.h>
#include <granhydro/boundary/moving_frame.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/physics/granular_gas.h>

#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <array>
#include <cstdint>
#include <vector>

namespace granhydro::diffusion
{
  struct DiffusionSettings
  {
    bool viscous = true, heat = true, cooling = true;
    bool diagonal_only = false;
    /// Knudsen cap (scaled, grain diameters; 0 = off): eta, gamma, kappa, mu times
    /// min(1, L / l) with the dilute mean free path l = 1/(sqrt(2) pi n)
    double max_free_path = 0;
    /// gravity, when the body force acts in this step (scaled)
    physics::BodyForce body;
    /// the vibrated container's motion: the inertial force of its frame joins gravity (scaled)
    boundary::MovingFrame container_motion;
    /// cohesionless grains: the tensile viscous normal stress at a face is bounded by the
    /// pressure there (doc/physics.md 4.7)
    bool no_tension = true;
  };

  /// what the face fluxes bounded, counted over all evaluations of f on the faces this rank
  /// owns (a face belongs to the rank owning its low cell, or its only cell at a wall)
  struct FaceFluxCounts
  {
    unsigned long long faces                 = 0; ///< face flux evaluations
    unsigned long long tension_bounded       = 0; ///< tensile normal stress bounded by the pressure
    unsigned long long tension_bounded_walls = 0; ///< of which on wall faces
    unsigned long long friction_capped       = 0;
    /// face state with T < 0, taken as 0 in the coefficients (and the wall heat flux)
    unsigned long long negative_temperature = 0; ///< frictional viscosity held at the Newtonian bound
  };

  template <int dim>
  class DiffusionOperator
  {
  public:
    static constexpr unsigned int NC = dim + 2;

    DiffusionOperator(const mesh::CartesianPatch<dim> &patch, const physics::GranularGas<dim> &desc,
                      const DiffusionSettings &settings, const double length_unit);

    void setup();

    /// f(U) for owned cells (n_owned * NC values) from the slot array W
    void residual(const double *W, double *f) const;

    /// sparsity of the Jacobian (owned rows; face and edge neighbours), with each
    /// entry repeated for s x s stages (interleaved numbering stages * dof + stage)
    void make_sparsity(dealii::TrilinosWrappers::SparsityPattern &sp, const unsigned int stages,
                       const bool edge_neighbours) const;

    /// J = df/dU at the slot array W by finite differences: per owned cell s, the
    /// NC x NC blocks df_s/dU_t of the cells t of its stencil (t in the partitioner's local
    /// cell numbering: owned, then MPI ghosts; each t once). Face neighbours always; with
    /// cross_terms also the gradient (edge) neighbours of the tangential derivatives.
    using JacobianBlocks =
      std::vector<std::vector<std::pair<unsigned int, std::array<double, (dim + 2) * (dim + 2)>>>>;
    void jacobian(const double *W, JacobianBlocks &J, const bool cross_terms = false) const;

    /**
     * M = I - dt (A (x) J) for the Butcher matrix A (stages x stages) with J = df/dU
     * at the slot array W, assembled into M (built on make_sparsity()).
     */
    void assemble_newton_matrix(const double *W, const std::vector<std::vector<double>> &A, const double dt,
                                dealii::TrilinosWrappers::SparseMatrix &M,
                                const bool                              cross_terms = false) const;

    /// largest explicit diffusion rate max(2 D / dx^2 summed over directions) on owned cells
    double explicit_rate(const double *W) const;

    const mesh::CartesianPatch<dim> &get_patch() const { return patch; }

    /// Frictional dissipation rate of the last residual() call, summed over this rank's
    /// owned cells (scaled energy per time, times the scaled cell volume): the work of the
    /// frictional stress, div(tau_f . u) - u . div tau_f ~ mu_f Phi_f, that leaves the
    /// grains as heat instead of becoming granular temperature (doc/physics.md 4.5)
    double friction_power() const { return friction_power_; }

    /// the face fluxes of the last residual() call, NC values per face of patch.faces(d)
    /// (shared scratch: valid until the next convective or diffusion step)
    /// (without the frictional work; for diagnostics and tests)
    const double *last_face_fluxes(const unsigned int d) const { return Fp[d]; }

    /// this rank's face flux counts since construction
    const FaceFluxCounts &face_counts() const { return counts_; }

    /// true when the frictional viscosity of the dense closure is on
    bool friction() const { return friction_active; }

    /// true when the fluxes use the diagonal (normal-gradient) part only
    bool diagonal_only() const { return settings.diagonal_only; }

    /// time (scaled) at which the sources are evaluated (vibrated container)
    void set_time(const double t) const
    {
      time  = t;
      force = boundary::effective_body_force(settings.body, settings.container_motion,
                                             t); // once per time, not per cell
    }

    /// the body force per unit mass at the current time (scaled units)
    const std::array<double, 3> &body_force() const { return force; }

  private:
    /// a face on a dissipative wall (boundary/dissipative_wall.h; the grain-wall
    /// restitution of a wall is the mesh's, CartesianPatch::wall_settings())
    using WallFace = boundary::DissipativeWallFace;
    /// flux through a face normal to d between slots l and r; ihn: 1/(centre distance).
    /// With the frictional viscosity on, F holds its momentum flux but not its work, and
    /// friction (if given) receives (work flux tau_f.u, frictional momentum flux, 0).
    /// bounded, capped, cold (if given): the tensile normal stress was bounded by the
    /// pressure, the frictional viscosity held at its bound, the face state's T < 0.
    void face_flux(const double *W, const unsigned int d, const double ihn, const unsigned int l,
                   const unsigned int r, const physics::State<dim> &UL, const physics::State<dim> &UR,
                   const WallFace &wall, physics::State<dim> &F, physics::State<dim> *friction = nullptr,
                   bool *bounded = nullptr, bool *capped = nullptr, bool *cold = nullptr) const;
    void source(const physics::State<dim> &U, physics::State<dim> &S) const;
    /// kinetic-theory coefficients at (n, T) with the Knudsen cap and the switches; V is
    /// double or a GCC vector of doubles (lanes: states side by side, each lane bit for
    /// bit the double result)
    template <class V>
    physics::TransportCoefficientsT<V> coefficients(const V n, const V T) const;

    /// face_flux() for the faces whose slots are l[i], r[i] in the lanes i of V (double:
    /// one face), without the dissipative-wall heat flux: the one flux formula of this
    /// operator, which residual() runs on vectors and the Jacobian on single faces
    template <class V>
    void face_flux_lanes(const double *W, const unsigned int d, const V ihn, const unsigned int *l,
                         const unsigned int *r, const std::array<V, dim + 2> &UL,
                         const std::array<V, dim + 2> &UR, std::array<V, dim + 2> &F,
                         std::array<V, dim + 2> *friction, V *bounded = nullptr, V *capped = nullptr,
                         V *cold = nullptr) const;

    /// residual() with V-wide lanes, compiled for the default target and for AVX2
    template <class V>
    void residual_lanes(const double *W, double *f) const;
    void residual_default(const double *W, double *f) const;
    void residual_avx2(const double *W, double *f) const;

    /// source() for the cells in the lanes of V
    template <class V>
    void source_lanes(const std::array<V, dim + 2> &U, std::array<V, dim + 2> &S) const;

    /// residual() for the owned cells [s0, s0 + lanes of V) from the face fluxes
    template <class V>
    void cell_residuals(const double *W, const unsigned int s0, double *f) const;

    /// counts_ for face k normal to d (counted_[d][k] != 0)
    void count_face(const unsigned int d, const std::size_t k, const bool bounded, const bool capped,
                    const bool cold) const;

    /// the fluxes of all faces normal to d into Fp[d] (and Ff[d]), V-wide lanes of faces
    template <class V>
    void face_fluxes(const double *W, const unsigned int d) const;

    const mesh::CartesianPatch<dim> &patch;
    const physics::GranularGas<dim> &desc;
    DiffusionSettings                settings;
    double                           length_unit;
    /// 1/dx_d (scaled) of a cell of refinement level k (patch.level()): inv_h[d][k]
    double inv_h[dim][mesh::max_levels] = {};
    /// 1/(centre distance) (scaled) across a face normal to d between cells of levels a, b
    double inv_dist[dim][mesh::max_levels][mesh::max_levels] = {};
    /// the wall of face k of patch.faces(d): wall_kinds[wall_of[d][k]] (0: no wall, sign 0)
    std::vector<std::uint16_t> wall_of[dim];
    std::vector<WallFace>      wall_kinds;
    const WallFace            &wall(const unsigned int d, const std::size_t k) const
    {
      return wall_kinds[wall_of[d][k]];
    }
    double ih(const unsigned int d, const unsigned int s) const { return inv_h[d][patch.level(s)]; }
    double ihn(const unsigned int d, const unsigned int l, const unsigned int r) const
    {
      return inv_dist[d][patch.level(l)][patch.level(r)];
    }
    std::vector<unsigned int> src;  ///< slot -> real slot carrying its data
    std::vector<unsigned int> flip; ///< slot -> momentum sign flips relative to src
    /// per face: the flux, and the frictional work flux and momentum flux (the patch's
    /// shared scratch, mesh::Scratch, asked for at the start of each residual())
    mutable double               *Fp[dim] = {};
    mutable double               *Ff[dim] = {};
    mutable double                time    = 0;
    mutable std::array<double, 3> force{{0, 0, 0}}; ///< the body force at time (gravity and frame)
    mutable double                friction_power_ = 0;
    mutable FaceFluxCounts        counts_;
    /// whether face k of direction d is counted on this rank (FaceFluxCounts): 0 no, 1 yes,
    /// 2 yes and it is a wall face
    std::vector<unsigned char> counted_[dim];
    double                     cell_volume[mesh::max_levels] = {}; ///< scaled volume of a cell of level k
    bool                       friction_active               = false;
  };
} // namespace granhydro::diffusion
