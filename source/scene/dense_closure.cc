#include <granhydro/scene/dense_closure.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void DenseClosureParameters::declare_parameters(ParameterHandler &prm)
  {
    const DenseClosureParameters defaults;
    prm.enter_subsection("Dense closure");
    {
      prm.declare_entry("Model", to_string(defaults.dense_closure), selection_of<DenseClosure>(),
                        "Contact/frictional stresses of the dense regime (granular model; the "
                        "paper has none). 'johnson-jackson': pressure p_f ~ F (phi - phi_min)^r "
                        "/ (phi_c - phi)^s from a contact potential in the energy (T stays "
                        "positive on expansion) and a frictional shear stress (Frictional stress). "
                        "Without it a pile cooling at rest reaches phi_c in finite time and the "
                        "run stops with a diagnostic (doc/user-guide.md, 'Dense closure').");
      prm.declare_entry("Coefficient", default_text(defaults.closure_F),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "F [Pa] (Johnson, Nott & Jackson 1990; MFIX/OpenFOAM default 0.05).");
      prm.declare_entry("Minimum packing fraction", default_text(defaults.closure_phi_min),
                        Patterns::Double(0, 1),
                        "phi_min: no contact stress below it. Default 0.62 for smooth "
                        "(frictionless) spheres, whose enduring contact network only forms "
                        "next to random close packing, so a settled pile sits at 0.62-0.64; "
                        "0.5 is Johnson-Jackson's value for frictional grains (piles at about "
                        "0.58). doc/user-guide.md, 'Dense closure'.");
      prm.declare_entry("Exponent r", default_text(defaults.closure_r), Patterns::Double(1, 10),
                        "r (default 2, at least 1).");
      prm.declare_entry("Exponent s", default_text(defaults.closure_s), Patterns::Double(1.5, 20),
                        "s (default 5, above 1).");
      prm.declare_entry("Frictional stress", to_string(defaults.frictional_stress),
                        selection_of<physics::FrictionalLaw>(),
                        "'newtonian' (default): mu_f = t_f sin(theta_f) p_f (OpenFOAM's "
                        "Johnson-Jackson choice), unbounded stress. "
                        "'srivastava-sundaresan': Srivastava & Sundaresan (2003), as MFIX's "
                        "Princeton model - rate-independent, bounded by p_f sin(theta_f) in "
                        "shear, vanishing in fast dilation, regularised by the granular "
                        "temperature, its viscosity bounded by the Newtonian one; not yet the "
                        "default: it stops the quarter-resolution chute at t = 0.11 s "
                        "(doc/physics.md 4.5).");
      prm.declare_entry("Viscosity time", default_text(defaults.closure_time),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "t_f [s]: the Newtonian frictional viscosity mu_f = t_f sin(theta_f) p_f "
                        "(OpenFOAM's Johnson-Jackson choice 0.5 s), and the bound of the "
                        "Srivastava-Sundaresan one (below strain rates of about 1/(sqrt(2) t_f) a "
                        "cold pile creeps; counted in the run summary); 0 switches the "
                        "frictional stress off, whichever law.");
      prm.declare_entry("Friction angle", default_text(defaults.closure_angle), Patterns::Double(0, 90),
                        "theta_f [degrees] of the frictional viscosity.");
    }
    prm.leave_subsection();
  }

  void DenseClosureParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Dense closure");
    dense_closure     = get_enum<DenseClosure>(prm, "Dense closure", "Model");
    closure_F         = prm.get_double("Coefficient");
    closure_phi_min   = prm.get_double("Minimum packing fraction");
    closure_r         = prm.get_double("Exponent r");
    closure_s         = prm.get_double("Exponent s");
    frictional_stress = get_enum<physics::FrictionalLaw>(prm, "Dense closure", "Frictional stress");
    closure_time      = prm.get_double("Viscosity time");
    closure_angle     = prm.get_double("Friction angle");
    prm.leave_subsection();
  }

  void DenseClosureParameters::check(const Scene &s)
  {
    // the ideal gas refuses a closure later, with the other needs of the granular model
    if (s.model != physics::Model::granular || s.dense_closure == DenseClosure::none)
      return;
    if (!(s.closure_F > 0))
      fail(s, "Dense closure/Coefficient", "must be positive");
    if (!(s.closure_phi_min < s.phi_close_packing - s.guard_delta))
      fail(s, "Dense closure/Minimum packing fraction",
           "must be below phi_c - delta (Material/Close packing fraction minus guard)");
  }
} // namespace granhydro::scene
