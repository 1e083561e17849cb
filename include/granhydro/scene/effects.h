#pragma once
/**
 * @file effects.h
 * The 'Effects' subsection of a scene: which terms run (granular model), the body force
 * and the container vibration.
 */
#include <deal.II/base/parameter_handler.h>

#include <array>

namespace granhydro::scene
{
  struct Scene;

  struct EffectsParameters
  {
    bool                  convection      = true;
    bool                  viscosity       = true;
    bool                  heat_conduction = true;
    bool                  cooling         = true;
    bool                  diagonal_flux   = false; // paper's D_ii-only flux (5.6)
    std::array<double, 3> gravity{{0, 0, 0}};      // [m/s^2]
    double                vibration_amplitude = 0; // [m], container displacement A sin(w t)
    double                vibration_frequency = 0; // [Hz]
    unsigned int          vibration_direction = 1;

    static void declare_parameters(dealii::ParameterHandler &prm);
    /// the gravity list holds `dim` values or 3
    void parse_parameters(dealii::ParameterHandler &prm, unsigned int dim);

    // Checks, in the order validate() runs them (the first failure is the message).

    /// gravity and the container's acceleration within 1e6 m/s^2
    static void check_body_force(const Scene &s);
    /// a vibration has amplitude and frequency, a resolved direction, the granular model
    static void check_vibration(const Scene &s);
  };
} // namespace granhydro::scene
