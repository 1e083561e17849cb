#pragma once
/**
 * @file units.h
 * The scaled unit system every layer computes in: lengths in grain diameters, masses in
 * grain masses, velocities in V0 (scene/ chooses them; doc/developer.md, "Internal units").
 */
namespace granhydro
{
  /// Scaled units: length sigma, mass m (grain mass), velocity V0.
  struct Units
  {
    double length   = 1; // [m]
    double mass     = 1; // [kg]
    double velocity = 1; // [m/s]
    double time() const { return length / velocity; }
    double energy() const { return mass * velocity * velocity; }
    double number_density() const { return 1. / (length * length * length); }
    /// energy density and pressure [J/m^3 = Pa]
    double pressure() const { return energy() * number_density(); }
  };
} // namespace granhydro
