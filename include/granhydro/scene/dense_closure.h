#pragma once
/**
 * @file dense_closure.h
 * The 'Dense closure' subsection of a scene: the optional contact/frictional stresses of
 * the dense regime (off by default; physics/contact_pressure.h).
 */
#include <deal.II/base/parameter_handler.h>

#include <string>

namespace granhydro
{
  struct Scene;

  struct DenseClosureParameters
  {
    std::string dense_closure = "none"; // none | johnson-jackson
    double      closure_F       = 0.05; // [Pa]
    double      closure_phi_min = 0.5;
    double      closure_r       = 2;
    double      closure_s       = 5;
    std::string frictional_stress = "newtonian"; // | srivastava-sundaresan
    double      closure_time    = 0.5;  // t_f [s]: mu_f = t_f sin(theta_f) p_f, or its bound
    double      closure_angle   = 28.5; // theta_f [degrees]

    static void declare_parameters(dealii::ParameterHandler &prm);
    void parse_parameters(dealii::ParameterHandler &prm);
    /// the closure's coefficients against the material's packing limits (granular model)
    static void check(const Scene &s);
  };
} // namespace granhydro
