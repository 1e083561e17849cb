#pragma once
/**
 * @file material.h
 * The 'Material' subsection of a scene: the constitutive model and the grains.
 */
#include <granhydro/physics/material_model.h>

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace granhydro::scene
{
  struct Scene;

  struct MaterialParameters
  {
    physics::Model model             = physics::Model::ideal_gas;
    double         grain_diameter    = 1e-3;
    double         material_density  = 2600;
    double         adiabatic_index   = 5. / 3.;
    double         restitution       = 1.;   // eps (granular model)
    double         friction          = 0.;   // mu, grain-grain Coulomb friction (granular model)
    double         phi_freezing      = 0.49; // phi_f of Torquato's chi
    double         phi_close_packing = 0.64; // phi_c
    double         guard_delta       = 1e-3; // C1 continuation of chi beyond phi_c - delta
    double         max_free_path     = 0;    // [m] Knudsen cap of the transport coefficients; 0 = off
    bool           cohesionless      = true; // tensile viscous normal stress bounded by the pressure

    double grain_mass() const;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// the grains, and what each model allows (the ideal gas: elastic, smooth, no gravity)
    static void check(const Scene &s);
  };
} // namespace granhydro::scene
