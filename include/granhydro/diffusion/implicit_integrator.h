#pragma once
/**
 * @file implicit_integrator.h
 * Step V of the Strang splitting: dU/dt = f(U) (diffusion + sources) over dt
 * with an implicit Runge-Kutta method, solved by a modified Newton iteration
 * with a frozen Jacobian (Houbak, Norsett & Thomsen 1985):
 *   stage slopes K_i = f(U0 + dt sum_j a_ij K_j),  U1 = U0 + dt sum_i b_i K_i,
 *   Newton matrix I - dt A (x) J with J = df/dU at U0 (interleaved numbering
 *   dof * stages + stage), assembled into granhydro's block-sparse matrix and
 *   solved by GMRES with block ILU(0) (block_sparse.h), or into a Trilinos matrix
 *   with Ifpack ILU or ML AMG (IntegratorSettings::block_ilu, amg).
 * Methods (their Butcher tables in butcher_tables.h): Gauss-Legendre 2, the implicit
 * midpoint rule and SDIRK2. SDIRK2 is L-stable and stiffly accurate, so a stiff mode
 * is damped to 0 in one step where Gauss-Legendre keeps |R(-inf)| = 1. Its stages are
 * solved one after the other, each with the one-stage Newton matrix I - g dt J, which
 * both stages share (one Jacobian and one preconditioner per step, 5 unknowns per cell
 * in 3D against 10 for the coupled Gauss-Legendre system).
 * Inexact Newton: each GMRES solve stops at a relative residual eta_k from the
 * forcing rule of Eisenstat & Walker (1996, choice 2, gamma 0.9, alpha 2), kept in
 * [Linear solver tolerance, 0.1]: the modified Newton iteration converges linearly,
 * so solving its correction far below its contraction is wasted work. The Newton
 * tolerance stays the accuracy control; 'Linear forcing = fixed' restores the fixed
 * tolerance.
 * Automatic switch: Gauss-Legendre (order 4) by default; when its modified
 * Newton iteration does not converge within the iteration cap (slow
 * contraction signals stiffness the frozen Jacobian cannot follow, the
 * criterion of Norsett & Thomsen's switching codes) the step is redone with
 * the implicit midpoint rule (one stage, half the linear system); every switch
 * is counted and logged. A step that fails with every method returns false and
 * the time loop retries with a smaller dt; it is never accepted silently.
 * RKL2 super-time-stepping (Meyer, Balsara & Aslam 2014, J. Comput. Phys. 257):
 * an explicit s-stage Runge-Kutta-Legendre method of order 2, stable for
 * dt <= dt_E (s^2 + s - 2) / 4 with dt_E the explicit limit below, so its cost
 * grows like sqrt(dt / dt_E) evaluations of f instead of dt / dt_E. Its stages
 * are combinations of states and f in flux form: mass is conserved to round-off.
 * A step whose result is inadmissible fails (the time loop retries with a
 * smaller dt). 'cost-based' chooses per step between SDIRK2 and RKL2 by a
 * deterministic cost model in units of one evaluation of f (the same choice on
 * any number of ranks): RKL2 costs s(dt); SDIRK2 costs its Jacobian (2 (dim + 2)
 * + 1 evaluations of the face fluxes), its preconditioner (Ifpack: calibrated at 15) and
 * per Newton iteration 1 evaluation plus GMRES (calibrated at 2.5: ~3 GMRES
 * iterations per Newton iteration with Eisenstat-Walker forcing; block ILU: 2 and
 * 1), for a fixed 12 Newton iterations per step (sdirk2_cost()). An RKL2 step that
 * fails is redone with SDIRK2 and RKL2 is not tried again for 10 steps (counted).
 * The explicit variant (forward Euler, sub-cycled at the explicit diffusive
 * limit dt_sub = 0.9 / max_cells sum_d 2 D / dx_d^2) is kept only as the
 * baseline that shows the time-step collapse near close packing.
 */
#include <granhydro/diffusion/block_sparse.h>
#include <granhydro/diffusion/butcher_tables.h>
#include <granhydro/diffusion/diffusion_operator.h>

#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <limits>
#include <string>
#include <vector>

namespace granhydro::diffusion
{
  /// Newton's convergence scale of every unknown of the owned cells (U: NC values per
  /// cell): each cell's own state - its density, sqrt(2 n E) for the momenta (>= |n u|),
  /// its energy density - so that dilute cells converge as tightly as dense ones, but at
  /// least newton_scale_floor times the largest of that component over all ranks (a cell
  /// near vacuum is not asked for round-off accuracy)
  std::vector<double> newton_scale(const std::vector<double> &U, const unsigned int NC, const MPI_Comm comm);
  inline constexpr double newton_scale_floor = 1e-3;

  struct IntegratorSettings
  {
    ImplicitMethod method                = ImplicitMethod::gauss_legendre;
    double         newton_tolerance      = 1e-10; ///< relative to each cell's own state (newton_scale())
    unsigned int   newton_max_iterations = 25;
    double         linear_tolerance      = 1e-12; ///< relative GMRES residual
    bool           amg                   = false;
    /// the Newton matrix as granhydro's block-sparse matrix with block ILU(0) (true) or as a
    /// Trilinos matrix with Ifpack ILU(0) / ML AMG (false; amg needs false)
    bool block_ilu = true;
    /// GMRES tolerance: Eisenstat-Walker forcing (true) or linear_tolerance always (false)
    bool inexact_newton = true;
    /// keep the Newton matrix and its preconditioner across steps while the modified
    /// Newton iteration contracts fast (see ImplicitIntegrator::irk_attempt)
    bool reuse_matrix = true;
    /// Jacobian of the cross terms: false = lagged, retried fully coupled when Newton
    /// stalls; true = always fully coupled
    bool full_jacobian = false;
  };

  struct IntegratorStatistics
  {
    unsigned long long steps = 0, newton_iterations = 0, linear_iterations = 0, newton_failures = 0,
                       linear_failures = 0, switches_to_midpoint = 0, explicit_substeps = 0, jacobians = 0,
                       full_jacobian_retries = 0, matrix_reuses = 0, stale_matrix_retries = 0;
    /// wall time (this rank) in the finite-difference Jacobian and Newton-matrix assembly,
    /// in the preconditioner set-up, and in GMRES
    double jacobian_seconds = 0, preconditioner_seconds = 0, linear_seconds = 0;
    /// RKL2 steps, their stages (evaluations of f), failed RKL2 steps redone implicitly
    /// (cost-based), and the wall time (this rank) of the RKL2 and of the implicit steps
    unsigned long long rkl2_steps = 0, rkl2_stages = 0, rkl2_fallbacks = 0, implicit_steps = 0;
    double             rkl2_seconds = 0, implicit_seconds = 0;
    /// the explicit diffusive limit 0.9 / max_cells sum_d 2 D / dx_d^2 (scaled time), smallest
    /// over all steps, and the time (scaled) where it was smallest: what an explicit code
    /// would have been held to; measured in every step, whatever the integrator
    double min_explicit_dt = std::numeric_limits<double>::infinity(), min_explicit_dt_time = 0;
    /// largest ratio of the step taken to the explicit diffusive limit
    double max_dt_over_explicit = 0;
    /// energy dissipated by the frictional stress of the dense closure over all accepted
    /// steps (scaled energy density times scaled volume; DiffusionOperator::friction_power)
    double friction_dissipation = 0;
    /// face flux evaluations of f (all ranks) and those bounded: tensile normal stress held
    /// at the pressure (cohesionless grains; on walls), frictional viscosity held at the
    /// Newtonian bound (DiffusionOperator::face_counts)
    FaceFluxCounts faces;
  };

  template <int dim>
  class ImplicitIntegrator
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;
    using Table  = std::vector<std::vector<double>>;

    ImplicitIntegrator(const DiffusionOperator<dim> &op, const physics::GranularGas<dim> &desc,
                       const IntegratorSettings &settings);

    /// advance U (on the patch partitioner) from time t by dt; false if the step failed.
    /// Time-dependent sources are evaluated at the stage times t + c_i dt. repair_energy:
    /// the splitting allowance of the temperature repair in the step this is part of
    /// (scaled, per grain; physics::GranularGas::admissible()), which its result may use
    bool step(Vector &U, const double t, const double dt, const double repair_energy);

    /// forget the sparsity patterns and work vectors after the mesh changed
    void mesh_changed()
    {
      matrix_valid = false;
      for (auto &row : have_pattern)
        row[0] = row[1] = false;
      for (auto &p : block_part)
        p.reset();
      for (auto &p : block_part_owned)
        p.reset();
      bmat.clear();
      bilu.clear();
      Y.reinit(0);
    }

    /// forget what the step history decides - the kept Newton matrix and the cost model's
    /// counts - as at the start of a run. Called at every output time (where a checkpoint
    /// may be written), so that a run restarted from a checkpoint takes exactly the
    /// decisions of the uninterrupted run, whether checkpoints are written or not
    void restart_point()
    {
      matrix_valid = false;
      rkl2_blocked = 0;
    }

    /// what restart_point() forgets, for a checkpoint taken between output times (an
    /// interrupted run): the cost model's RKL2 rest and the kept Newton matrix, which is
    /// rebuilt on restore from the state it was built from (state: owned values)
    struct History
    {
      unsigned int        rkl2_blocked = 0;
      bool                matrix_valid = false, matrix_coupled = false;
      unsigned int        matrix_age = 0;
      double              matrix_t = 0, matrix_dt = 0;
      Table               matrix_N;
      std::vector<double> state;
    };
    History history() const;
    /// continue with this history (after restart_point() semantics would have cleared it)
    void restore(const History &h);

    const IntegratorStatistics &statistics() const { return stats; }

    /// why the last failed step failed (this rank's view)
    const std::string   &failure() const { return last_failure; }
    IntegratorStatistics global_statistics() const;

  private:
    /// one step of the Runge-Kutta method of the tableau; diagonally implicit methods (A lower
    /// triangular with one diagonal value) are solved stage by stage. Redone with the
    /// fully coupled Jacobian when the lagged one stalls.
    bool irk_step(Vector &U, const double t, const double dt, const ButcherTableau &tableau);
    bool irk_attempt(Vector &U, const double t, const double dt, const ButcherTableau &tableau,
                     const bool full);
    /// Newton matrix I - dt N (x) J with J at the gathered state W, and its preconditioner
    /// false if the block ILU met a singular diagonal block (Newton then fails)
    bool setup_newton(const double dt, const Table &N, const bool coupled);
    /// modified Newton for the slopes K (interleaved, N.size() stages) of the stage values
    /// Y_k = base + dt sum_j N_kj K_j at the times tk[k], with the matrix of setup_newton;
    /// K holds the first guess. On success K_k = f(Y_k) at the converged stage values and
    /// power[k] is the frictional power there. Converged when dt |change of K| <= Newton
    /// tolerance x scale[i] for every owned unknown i (newton_scale()).
    bool newton(const std::vector<double> &base, const std::vector<double> &tk, const double dt,
                const Table &N, const std::vector<double> &scale, std::vector<double> &K,
                std::vector<double> &power, unsigned int &iterations);
    /// one GMRES solve of the Newton correction (the block system brhs -> bdelta, or rhs ->
    /// delta with the Trilinos matrix M) to the tolerance of control; false if GMRES failed
    bool solve_correction(dealii::SolverControl &control, const dealii::TrilinosWrappers::MPI::Vector &rhs,
                          dealii::TrilinosWrappers::MPI::Vector &delta);
    bool explicit_step(Vector &U, const double t, const double dt);
    /// RKL2 super-time-step (explicit_limit and W from step())
    bool rkl2_step(Vector &U, const double t, const double dt);
    /// implicit SDIRK2 step, timed and counted for the cost model
    bool implicit_step(Vector &U, const double t, const double dt, const ButcherTableau &tableau);
    /// every owned cell of the owned values U admissible (collective)
    bool admissible_owned(const double *U);

    const DiffusionOperator<dim>    &op;
    const mesh::CartesianPatch<dim> &patch;
    const physics::GranularGas<dim> &desc;
    IntegratorSettings               settings;
    IntegratorStatistics             stats;
    // indexed by [number of stages][cross terms coupled]: the lagged Jacobian only
    // couples face neighbours (7-point in 3D), the fully coupled one adds the edge
    // neighbours (19-point); a 19-point pattern full of zeros makes ILU ~3x dearer
    dealii::TrilinosWrappers::SparseMatrix  M_[3][2];
    bool                                    have_pattern[3][2] = {};
    dealii::TrilinosWrappers::SparseMatrix *M                  = nullptr; ///< the Newton matrix of this step
    /// the Newton matrix (and preconditioner) in M can serve the next step: built for
    /// the coefficients matrix_N, cross terms matrix_coupled, step matrix_dt, matrix_age
    /// steps ago
    bool         matrix_valid = false, matrix_coupled = false;
    Table        matrix_N;
    double       matrix_dt  = 0;
    unsigned int matrix_age = 0;
    /// the time and owned state the kept matrix was built from (history())
    double              matrix_t = 0;
    std::vector<double> matrix_state;
    bool                gmres_failed = false; ///< the last Newton iteration failed in GMRES
    /// cost-based: steps left before RKL2 may be tried again after a failure
    unsigned int                              rkl2_blocked = 0;
    dealii::TrilinosWrappers::PreconditionILU ilu;
    /// settings.block_ilu: the Newton matrix, its block ILU(0), and vectors on the
    /// partitioner with `stages` values per unknown (index: stages)
    BlockSparseMatrix bmat;
    BlockILU          bilu;
    /// per stage count: the block vectors' partitioner with the mesh's ghost cells (the
    /// matrix's product imports them) and without (GMRES's Krylov vectors: the ghost
    /// storage of 30 vectors would grow with the halo, i.e. with the number of ranks)
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> block_part[3], block_part_owned[3];
    Vector                                                     brhs, bdelta;
    dealii::TrilinosWrappers::PreconditionAMG                  amg;
    std::vector<double>                                        U0, f;
    /// the gathered slot array of the step (the patch's shared scratch, mesh::Scratch;
    /// asked for in step() and restore())
    double     *W = nullptr;
    std::string last_failure;
    double      explicit_limit = 0; ///< of the current step (scaled)
    double      repair_energy_ = 0; ///< of the current step (step()'s argument)
    Vector      Y;
  };
} // namespace granhydro::diffusion
