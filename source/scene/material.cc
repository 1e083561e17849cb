#include <granhydro/scene/material.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <cmath>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  double MaterialParameters::grain_mass() const
  {
    return material_density * M_PI * std::pow(grain_diameter, 3) / 6.;
  }

  void MaterialParameters::declare_parameters(ParameterHandler &prm)
  {
    const MaterialParameters defaults;
    prm.enter_subsection("Material");
    {
      prm.declare_entry("Model", to_string(defaults.model), selection_of<physics::Model>(),
                        "Constitutive model. 'ideal gas': verification model (p = n T, "
                        "no transport), the dilute elastic limit of granular gases. "
                        "'granular': hard spheres, p = n T Z(phi) with Torquato's pair "
                        "correlation and Garzo-Dufty (1999) transport (doc/physics.md 2, 3).");
      prm.declare_entry("Restitution coefficient", default_text(defaults.restitution), Patterns::Double(0, 1),
                        "Normal coefficient of restitution eps of grain-grain collisions "
                        "(granular model; 0.5 <= eps <= 1).");
      prm.declare_entry("Friction coefficient", default_text(defaults.friction), Patterns::Double(0, 1),
                        "Coulomb friction coefficient mu between grains (granular model; 0 = "
                        "smooth spheres). The cooling rate uses Chialvo & Sundaresan's (2013) "
                        "effective restitution e_eff = eps - (3/2) mu exp(-3 mu); pressure and "
                        "transport keep eps (doc/user-guide.md, 'Frictional grains').");
      prm.declare_entry("Freezing packing fraction", default_text(defaults.phi_freezing),
                        Patterns::Double(0, 1), "phi_f of Torquato's pair correlation (granular model).");
      prm.declare_entry("Close packing fraction", default_text(defaults.phi_close_packing),
                        Patterns::Double(0, 1),
                        "phi_c, random close packing: chi has its pole here (granular model).");
      prm.declare_entry("Close packing guard", default_text(defaults.guard_delta), Patterns::Double(0, 0.1),
                        "delta: chi is continued linearly (C1) beyond phi_c - delta, so "
                        "coefficients stay finite (doc/physics.md 2, guard).");
      prm.declare_entry("Maximum mean free path", default_text(defaults.max_free_path),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Knudsen cap L [m] (granular model; 0 = off, the paper's model): where "
                        "the mean free path l = 1/(sqrt(2) pi n sigma^2) exceeds L, the "
                        "transport coefficients eta, gamma, kappa, mu are scaled by L/l, so the "
                        "diffusivities stay below ~L sqrt(T/m) instead of diverging as n -> 0 "
                        "(doc/physics.md P14). Hydrodynamics has no meaning there anyway; use a few "
                        "cell sizes for scenes with near-vacuum. Required (> 0) where the initial "
                        "packing fraction falls below 1e-6 and viscosity or heat conduction is on.");
      prm.declare_entry("Cohesionless", default_text(defaults.cohesionless), Patterns::Bool(),
                        "Granular model: grains cannot pull. At every face of the diffusion "
                        "step the tensile viscous normal stress (kinetic and frictional) is "
                        "bounded by the pressure there, so the total normal stress stays "
                        "compressive, at walls too (a floor cannot suck a bed down); its work "
                        "uses the same bounded stress (energy stays conserved). Counted in the "
                        "run summary. false: the paper's literal Navier-Stokes stress, which "
                        "lets a wall or a tearing layer pull on the grains "
                        "(doc/physics.md 4.7).");
      prm.declare_entry("Grain diameter", default_text(defaults.grain_diameter),
                        Patterns::Double(0, Patterns::Double::max_double_value), "Grain diameter sigma [m].");
      prm.declare_entry("Material density", default_text(defaults.material_density),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Material density rho_s [kg/m^3], 1e-3 .. 1e6; grain mass m = rho_s pi sigma^3 / 6.");
      prm.declare_entry("Adiabatic index", default_text(defaults.adiabatic_index), Patterns::Double(1, 3),
                        "Adiabatic index gamma_a of the ideal-gas model (5/3 = dilute "
                        "elastic grains, internal energy 3T/2 per grain).");
    }
    prm.leave_subsection();
  }

  void MaterialParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    model             = get_enum<physics::Model>(prm, "Material", "Model");
    grain_diameter    = prm.get_double("Grain diameter");
    material_density  = prm.get_double("Material density");
    adiabatic_index   = prm.get_double("Adiabatic index");
    restitution       = prm.get_double("Restitution coefficient");
    friction          = prm.get_double("Friction coefficient");
    phi_freezing      = prm.get_double("Freezing packing fraction");
    phi_close_packing = prm.get_double("Close packing fraction");
    guard_delta       = prm.get_double("Close packing guard");
    max_free_path     = prm.get_double("Maximum mean free path");
    cohesionless      = prm.get_bool("Cohesionless");
    prm.leave_subsection();
  }

  void MaterialParameters::check(const Scene &s)
  {
    const unsigned int dim = s.dimension;
    if (!(s.grain_diameter >= 1e-9 && s.grain_diameter <= 10))
      fail(s, "Material/Grain diameter",
           fmt(s.grain_diameter) + " m; allowed 1e-9 .. 10 m (the "
                                   "internal units are built on it)");
    // the grain mass is the internal mass unit: 1e308 kg/m^3 made the scaled temperature
    // nan in the first step (the densest solids are near 2.3e4 kg/m^3)
    if (!(s.material_density >= 1e-3 && s.material_density <= 1e6))
      fail(s, "Material/Material density",
           fmt(s.material_density) + " kg/m^3; allowed 1e-3 .. 1e6 "
                                     "kg/m^3 (the grain mass is the internal mass unit)");
    if (s.adiabatic_index <= 1)
      fail(s, "Material/Adiabatic index", "must exceed 1");
    if (s.model == physics::Model::granular)
      {
        if (s.restitution < 0.5 || s.restitution > 1)
          fail(s, "Material/Restitution coefficient",
               "must lie in [0.5, 1] (Garzo-Dufty coefficients are verified positive there)");
        if (!(s.friction >= 0 && s.friction <= 1))
          fail(s, "Material/Friction coefficient", "must lie in [0, 1] (0: smooth spheres)");
        // the densest packing of equal spheres is pi / (3 sqrt 2) = 0.7405
        if (!(s.phi_close_packing <= M_PI / (3 * std::sqrt(2.))))
          fail(s, "Material/Close packing fraction",
               "must not exceed 0.7405, the densest packing of "
               "equal spheres (random close packing: 0.63-0.64)");
        if (!(s.phi_freezing > 0))
          fail(s, "Material/Freezing packing fraction", "must be positive (0.49 for hard spheres)");
        if (!(s.phi_freezing < s.phi_close_packing))
          fail(s, "Material/Freezing packing fraction", "must be below 'Close packing fraction'");
        if (!(s.guard_delta > 0))
          fail(s, "Material/Close packing guard", "must be positive (default 1e-3)");
        if (!(s.guard_delta < s.phi_close_packing - s.phi_freezing))
          fail(s, "Material/Close packing guard", "must be smaller than phi_c - phi_f");
      }
    else
      {
        if (s.restitution != 1)
          fail(s, "Material/Restitution coefficient",
               "the ideal-gas model is elastic; use 'Model = granular' for eps < 1");
        if (s.friction != 0)
          fail(s, "Material/Friction coefficient",
               "the ideal-gas model has smooth grains; use 'Model = granular' for mu > 0");
        for (unsigned int d = 0; d < dim; ++d)
          if (s.gravity[d] != 0)
            fail(s, "Effects/Gravity",
                 "the ideal-gas verification model has no body force; use "
                 "'Material/Model = granular'");
      }
  }
} // namespace granhydro::scene
