#include <granhydro/scene/diffusion_step.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void DiffusionStepParameters::declare_parameters(ParameterHandler &prm)
  {
    const DiffusionStepParameters defaults;
    prm.enter_subsection("Diffusion step");
    {
      prm.declare_entry("Integrator", to_string(defaults.integrator),
                        selection_of<diffusion::ImplicitMethod>(),
                        "Time integrator of the diffusion/source step V: 2-stage Gauss-Legendre "
                        "(order 4, A-stable), implicit midpoint (order 2, A-stable), sdirk2 "
                        "(Alexander's 2-stage SDIRK, order 2, L-stable: damps stiff modes; stages "
                        "solved one after the other), rkl2 (Runge-Kutta-Legendre super-time-"
                        "stepping, order 2, explicit: ~sqrt(dt / explicit limit) evaluations), "
                        "cost-based (per step the cheaper of sdirk2 and rkl2 by a deterministic "
                        "cost model), automatic (Gauss-Legendre, "
                        "implicit midpoint when its Newton iteration fails), or the sub-cycled "
                        "explicit Euler baseline.");
      prm.declare_entry("Newton tolerance", default_text(defaults.newton_tolerance), Patterns::Double(0, 1),
                        "Modified Newton stops when dt * |change of stage slopes| is below "
                        "this times the cell's own scale in every cell: its density, "
                        "sqrt(2 n E) for momenta, its energy density (at least 1e-3 of that "
                        "component's largest value in the domain).");
      prm.declare_entry("Newton maximum iterations", default_text(defaults.newton_max_iterations),
                        Patterns::Integer(1, 200),
                        "Cap on modified Newton iterations; a step that does not converge is "
                        "retried with half the time step.");
      prm.declare_entry("Linear solver tolerance", default_text(defaults.linear_tolerance),
                        Patterns::Double(0, 1),
                        "Relative residual of Trilinos GMRES (with Linear forcing = "
                        "eisenstat-walker: the smallest one it may ask for).");
      prm.declare_entry("Linear forcing", "eisenstat-walker", Patterns::Selection("eisenstat-walker|fixed"),
                        "GMRES tolerance per Newton iteration: eisenstat-walker (inexact Newton, "
                        "Eisenstat & Walker 1996 choice 2: 0.9 (|r_k|/|r_k-1|)^2 in [Linear solver "
                        "tolerance, 0.1]; the Newton tolerance stays the accuracy control) or "
                        "fixed (always Linear solver tolerance).");
      prm.declare_entry("Reuse Newton matrix", default_text(defaults.reuse_matrix), Patterns::Bool(),
                        "Keep the Newton matrix and its preconditioner for up to 8 further steps "
                        "while the previous step converged in <= 7 Newton iterations per stage "
                        "and dt changed by <= 10 %; a step whose iteration then fails is redone "
                        "with a fresh matrix (counted in the summary).");
      prm.declare_entry("Preconditioner", to_string(defaults.preconditioner), selection_of<Preconditioner>(),
                        "Newton matrix and preconditioner of GMRES: block ilu (granhydro's "
                        "block-sparse matrix, one dense block per pair of neighbouring cells, "
                        "with block ILU(0): the leanest and fastest), ilu (Trilinos Epetra "
                        "matrix with Ifpack ILU(0)) or amg (Trilinos Epetra matrix with ML).");
      prm.declare_entry("Jacobian", "lagged", Patterns::Selection("lagged|full"),
                        "Cross-derivative terms in the Newton matrix: lagged (deferred "
                        "correction; a step whose iteration stalls is redone fully coupled) "
                        "or full (always fully coupled, 19-point stencil in 3D).");
    }
    prm.leave_subsection();
  }

  void DiffusionStepParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Diffusion step");
    integrator            = get_enum<diffusion::ImplicitMethod>(prm, "Diffusion step", "Integrator");
    newton_tolerance      = prm.get_double("Newton tolerance");
    newton_max_iterations = prm.get_integer("Newton maximum iterations");
    linear_tolerance      = prm.get_double("Linear solver tolerance");
    inexact_newton        = prm.get("Linear forcing") == "eisenstat-walker";
    reuse_matrix          = prm.get_bool("Reuse Newton matrix");
    preconditioner        = get_enum<Preconditioner>(prm, "Diffusion step", "Preconditioner");
    full_jacobian         = prm.get("Jacobian") == "full";
    prm.leave_subsection();
  }

  void DiffusionStepParameters::check(const Scene &s)
  {
    if (!(s.linear_tolerance > 0))
      fail(s, "Diffusion step/Linear solver tolerance", "must be positive (GMRES cannot reach 0)");
  }
} // namespace granhydro::scene
