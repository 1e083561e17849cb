#include <granhydro/scene/effects.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <cmath>
#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void EffectsParameters::declare_parameters(ParameterHandler &prm)
  {
    const EffectsParameters defaults;
    prm.enter_subsection("Effects");
    {
      prm.declare_entry("Convection", default_text(defaults.convection), Patterns::Bool(),
                        "Run the convective step C (Euler part, paper section 4).");
      prm.declare_entry("Viscosity", default_text(defaults.viscosity), Patterns::Bool(),
                        "Viscous stress (shear and bulk viscosity; granular model).");
      prm.declare_entry("Heat conduction", default_text(defaults.heat_conduction), Patterns::Bool(),
                        "Heat flux q = -kappa grad T - mu grad n (granular model).");
      prm.declare_entry("Cooling", default_text(defaults.cooling), Patterns::Bool(),
                        "Inelastic cooling -(3/2) n T zeta0 (granular model, eps < 1).");
      prm.declare_entry("Diffusive flux", "full", Patterns::Selection("full|diagonal"),
                        "full: all cross-derivative terms (doc/physics.md 4.3); diagonal: only "
                        "D_ii d_i U as in the paper's eq. 5.6.");
      prm.declare_entry("Gravity", default_text(defaults.gravity), Patterns::Anything(),
                        "Body force per unit mass g [m/s^2], one value per dimension "
                        "(e.g. 0, -9.81 in 2D), |g| up to 1e5 m/s^2. Granular model only.");
      prm.declare_entry("Vibration amplitude", default_text(defaults.vibration_amplitude),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Amplitude A [m] of the container motion s(t) = A sin(2 pi f t) e_s. "
                        "The equations are solved in the container frame (all walls at rest) "
                        "with the inertial body force g + A (2 pi f)^2 sin(2 pi f t) e_s "
                        "(doc/physics.md 5.3); output velocities and kinetic energy densities are in "
                        "the lab frame (container velocity ds/dt added).");
      prm.declare_entry("Vibration frequency", default_text(defaults.vibration_frequency),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Frequency f [Hz] of the container motion.");
      prm.declare_entry("Vibration direction", "y", Patterns::Selection("x|y|z"),
                        "Direction e_s of the container motion.");
    }
    prm.leave_subsection();
  }

  void EffectsParameters::parse_parameters(ParameterHandler &prm, const unsigned int dim)
  {
    prm.enter_subsection("Effects");
    convection          = prm.get_bool("Convection");
    viscosity           = prm.get_bool("Viscosity");
    heat_conduction     = prm.get_bool("Heat conduction");
    cooling             = prm.get_bool("Cooling");
    diagonal_flux       = prm.get("Diffusive flux") == "diagonal";
    gravity             = parse_list<double, 3>(prm.get("Gravity"), "Effects/Gravity", dim, 0.);
    vibration_amplitude = prm.get_double("Vibration amplitude");
    vibration_frequency = prm.get_double("Vibration frequency");
    {
      const std::string v = prm.get("Vibration direction");
      vibration_direction = v == "x" ? 0 : (v == "y" ? 1 : 2);
    }
    prm.leave_subsection();
  }

  void EffectsParameters::check_body_force(const Scene &s)
  {
    const unsigned int dim = s.dimension;
    // body forces beyond any centrifuge only overflow the scaled units; |g| = 1e6 m/s^2
    // (1e5 g) already stopped a granular box in its first implicit step (Newton), 1e5 ran
    {
      double g2 = 0;
      for (unsigned int d = 0; d < dim; ++d)
        g2 += s.gravity[d] * s.gravity[d];
      if (!(std::sqrt(g2) <= 1e5))
        fail(s, "Effects/Gravity", "|g| = " + fmt(std::sqrt(g2)) + " m/s^2; allowed up to 1e5 m/s^2");
      const double a = s.vibration_amplitude * std::pow(2 * M_PI * s.vibration_frequency, 2);
      if (!(a <= 1e6))
        fail(s, "Effects/Vibration amplitude",
             "the container's acceleration A (2 pi f)^2 = " + fmt(a) + " m/s^2; allowed up to 1e6 m/s^2");
    }
  }

  void EffectsParameters::check_vibration(const Scene &s)
  {
    const unsigned int dim = s.dimension;
    if ((s.vibration_amplitude > 0) != (s.vibration_frequency > 0))
      fail(s, "Effects/Vibration frequency",
           "a vibrated container needs both a positive "
           "'Vibration amplitude' and 'Vibration frequency'");
    if (s.vibration_amplitude > 0 && s.vibration_direction >= dim)
      fail(s, "Effects/Vibration direction",
           "names a direction the " + std::to_string(dim) + "D scene does not resolve");
    if (s.vibration_amplitude > 0 && s.model != physics::Model::granular)
      fail(s, "Effects/Vibration amplitude", "a vibrated container needs 'Material/Model = granular'");
  }
} // namespace granhydro::scene
