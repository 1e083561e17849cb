#pragma once
/**
 * @file dense_closure.h
 * The 'Dense closure' subsection of a scene: the optional contact/frictional stresses of
 * the dense regime (off by default; physics/contact_pressure.h).
 */
#include <granhydro/base/enum_names.h>
#include <granhydro/physics/frictional_stress.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <string>

namespace granhydro::scene
{
  /// Dense closure/Model
  enum class DenseClosure
  {
    none,
    johnson_jackson
  };
  constexpr auto enum_names(DenseClosure)
  {
    return enum_table(EnumName{DenseClosure::none, "none"},
                      EnumName{DenseClosure::johnson_jackson, "johnson-jackson"});
  }
  static_assert(check_enum_names(enum_names(DenseClosure{})));

  struct Scene;

  struct DenseClosureParameters
  {
    DenseClosure           dense_closure     = DenseClosure::none;
    double                 closure_F         = 0.05; // [Pa]
    double                 closure_phi_min   = 0.62;
    double                 closure_r         = 2;
    double                 closure_s         = 5;
    physics::FrictionalLaw frictional_stress = physics::FrictionalLaw::newtonian;
    double                 closure_time      = 0.5;  // t_f [s]: mu_f = t_f sin(theta_f) p_f, or its bound
    double                 closure_angle     = 28.5; // theta_f [degrees]

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// the closure's coefficients against the material's packing limits (granular model)
    static void check(const Scene &s);
  };
} // namespace granhydro::scene
