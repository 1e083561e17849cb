#pragma once
/**
 * @file contact_step.h
 * The implicit contact step ('Numerics/Contact pressure = implicit'): the stiff part of
 * the pressure in a dense pile - the dense closure's contact pressure p_f(n) and the
 * kinetic pressure's growth at the pole of Torquato's pair correlation - applied after
 * each convective step by a linearly implicit correction, together with gravity, so that
 * their sound speeds (metres per second in a settled pile, hundreds of times the kinetic
 * one of a cold gas) no longer set the CFL step.
 *
 * The scheme is the first-order IMEX pressure splitting of the all-speed / low-Mach
 * literature (Haack, Jin & Liu, Commun. Comput. Phys. 12, 955 (2012); Degond & Tang,
 * Commun. Comput. Phys. 10, 1 (2011)) applied to the stiff part of our pressure only:
 *  - the convective step (WENO5 + MUSTA, SSP-RK3) runs with explicit_description(): no
 *    dense closure, and Carnahan-Starling's pair correlation chi_CS, whose pressure
 *    p_e = n T Z_e(phi) stays soft up to close packing; it works on the energy without the
 *    contact energy n w(n) (shift_energy()), which the state regains from its new density;
 *  - then, with the convective result (n*, m*, E*, T*) and h the convective step, the
 *    implicit pressure P_s(n) = p_f(n) + n T*_s (Z(phi) - Z_e(phi)) (T frozen per cell),
 *      J_f = -h [ (P_R(n_R) - P_L(n_L) + p_e(n*_R) - p_e(n*_L)) / delta_f - (n_L + n_R)/2 g_d ]
 *      n_i = n*_i - h / dx_i sum_f (+-) frac_f J_f                   (backward Euler in n)
 *    on every face (normal d, centre distance delta_f) with a cell above min(phi_min, phi_f):
 *    J_f is the momentum the face gains in the step from the whole pressure gradient net of
 *    gravity (the explicit part lagged) and the mass it moves. Substituted, a nonlinear
 *    elliptic equation n - h^2 div(grad P(n) - n g) = rhs for the density alone, solved by
 *    Newton's method with GMRES and block ILU(0) (diffusion/block_sparse.h, one unknown per
 *    cell). Then the momentum takes the implicit pressure's face averages (hydrostatically
 *    extrapolated to walls) and gravity, m_i += -h grad P(n) + h n_i g, conservatively;
 *  - the energy keeps the thermal energy per grain up to the kinetic pressure's reversible
 *    compression (GranularGas::compressed_temperature()): by the convective step's density
 *    change with Z - Z_e (the part whose work that step did not do) and by this step's with
 *    Z, and E = |m|^2/2n + n w(n) + (3/2) n T: the contact pressure's work goes to n w.
 *    Gravity acts here instead of in the diffusion step.
 *
 * Properties (doc/user-guide.md, 'Implicit contact pressure'): unconditionally stable for
 * the stiff acoustics (backward Euler of n_tt = div grad P(n)), first order in time for
 * them; mass conserved to round-off (flux form), momentum too along periodic directions; a
 * pile in discrete balance ((P_R - P_L + p_e,R - p_e,L)/delta = n_f g at every dense face)
 * has J = 0. Energy is not in flux form: the acoustic energy backward Euler damps is lost,
 * not turned into heat.
 */
#include <granhydro/diffusion/block_sparse.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/physics/granular_gas.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace granhydro::diffusion
{
  struct ContactStepSettings
  {
    /// gravity (scaled units)
    std::array<double, 3> gravity{{0, 0, 0}};
    /// Newton stops when the largest density update is below this times the largest density
    double       newton_tolerance      = 1e-10;
    unsigned int newton_max_iterations = 25;
    /// GMRES relative tolerance per Newton iteration
    double linear_tolerance = 1e-6;
  };

  /// what the contact step did over a run (the same on every rank)
  struct ContactStepCounts
  {
    unsigned long long steps = 0, newton_iterations = 0, linear_iterations = 0, failures = 0;
    unsigned int       max_newton_iterations = 0;
    /// this rank's owned cells whose thermal energy (total minus kinetic minus contact)
    /// entered a step negative, read as T* = 0 (the explicit pressure's temperature), and
    /// its wall faces (per accepted step) where the cell's pressure extrapolated
    /// hydrostatically to the wall fell below 0 and was taken as 0; summed over the ranks
    /// in the run summary
    unsigned long long negative_thermal_cells = 0, wall_pressure_floors = 0;
  };

  template <int dim>
  class ContactStep
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    /// desc: the scene's description; explicit: the convective step's (no dense closure,
    /// Carnahan-Starling's pair correlation: explicit_description())
    ContactStep(const mesh::CartesianPatch<dim> &patch, const physics::GranularGas<dim> &desc,
                const physics::GranularGas<dim> &explicit_desc, const ContactStepSettings &settings,
                const double length_unit);
    /// the convective step's description for desc: no dense closure, and the pair
    /// correlation of Carnahan and Starling up to phi_c - 2 delta (Torquato's pole only in
    /// the last 2 delta), so that its sound speed in a pile is the smooth equation of state's
    static physics::GranularGas<dim> explicit_description(const physics::GranularGas<dim> &desc);
    /// (re)build the cell partitioner and geometry after the mesh changed
    void setup();
    /// correct U (on the patch's partitioner) after a convective step of scaled length h;
    /// false if Newton's method did not converge or a density became non-positive (U then
    /// undefined; last_failure() says why)
    bool step(Vector &U, const double h);

    /// E += sign n w(n) on the owned cells of U: the convective step, whose description has
    /// no dense closure, works on the energy without the contact energy (sign -1 before it,
    /// +1 after it with the new densities)
    void shift_energy(Vector &U, const double sign) const;
    /// the contact energy n w(n) of each owned cell of U into w (what shift_energy(U, -1)
    /// takes off)
    void contact_energies(const Vector &U, double *w) const;
    /// before a convective step on U: record its densities (step() needs them) and take the
    /// contact energy out of E (shift_energy(U, -1))
    void begin_convective_step(Vector &U);

    const ContactStepCounts &counts() const { return counts_; }
    void                     reset_counts() { counts_ = ContactStepCounts(); }
    const std::string       &last_failure() const { return last_failure_; }

  private:
    static constexpr unsigned int NC = dim + 2;
    /// the corrective face flux J_f and its derivatives by n_L and n_R
    struct FaceFlux
    {
      double J, dJ_dl, dJ_dr;
    };
    /// J_f of the face between real slots l and r normal to d, or nothing (inactive face)
    bool face_flux(const unsigned int d, const unsigned int l, const unsigned int r, const double h,
                   const double *n, FaceFlux &F) const;

    /// n*, T*, the explicit pressure and the thermal energy from the convective result U;
    /// n_iter = n*. Returns the largest density
    double read_state(Vector &U);
    /// the residual R_i of owned cell i at the iterate n (all local slots), and the row of
    /// -dR_i/dn (the matrix is I minus it), one entry per column
    double residual_row(const unsigned int i, const double h, const double *n,
                        std::vector<std::pair<unsigned int, std::array<double, 1>>> &row) const;
    /// Newton's method for the density (n_iter); false if it failed (last_failure_ says why)
    bool newton(const double h, const double n_max);
    /// momentum and energy of U from the converged density
    void update(Vector &U, const double h);

    const mesh::CartesianPatch<dim>                           &patch;
    const physics::GranularGas<dim>                           &desc;
    const physics::GranularGas<dim>                           &explicit_desc;
    const ContactStepSettings                                  settings;
    const double                                               length_unit;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> cells; ///< one value per cell
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> owned; ///< the same, no ghosts
    /// faces with a cell above this density take part: grains in contact (phi_min) or on
    /// Torquato's dense branch (phi_f), where the two pair correlations differ
    double n_min = 0;
    /// the implicit pressure of local slot s at density n: the contact pressure and the
    /// kinetic pressure's part beyond the explicit equation of state, n T* (Z - Z_e), with
    /// the slot's temperature after the convective step; and its derivative by n
    void implicit_pressure(const unsigned int s, const double n, double &p, double &dp_dn) const;

    // per local cell (owned, then MPI ghosts): n*, T*, the explicit kinetic pressure at n*,
    // the implicit pressure and its derivative at the iterate; per owned cell the thermal
    // energy density after the convective step. They live in the patch's work array
    // mesh::Scratch::stage_c during step() (read_state() points them there) and are
    // undefined outside it
    double *n_star = nullptr, *T_star = nullptr, *p_exp = nullptr, *p_imp = nullptr, *dp_imp = nullptr,
           *thermal = nullptr;
    std::vector<double> n_before; ///< owned densities before the convective step
    std::vector<std::vector<std::pair<unsigned int, std::array<double, 1>>>> J; ///< Newton rows
    /// scaled 1/dx per refinement level and direction
    std::array<std::array<double, dim>, mesh::max_levels> inv_h_level{};
    double inv_h(const unsigned int s, const unsigned int d) const { return inv_h_level[patch.level(s)][d]; }
    BlockSparseMatrix matrix;
    BlockILU          ilu;
    Vector            n_iter, rhs, delta;
    ContactStepCounts counts_;
    std::string       last_failure_;
  };
} // namespace granhydro::diffusion
