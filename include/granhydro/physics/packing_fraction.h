#pragma once
/**
 * @file packing_fraction.h
 * The packing fraction of hard spheres of diameter sigma at number density n,
 * phi = n pi sigma^3 / 6, in scaled units (sigma = 1): the one copy that the
 * solver's messages, diagnostics and output call, and its inverse in SI for the
 * initial state. (GranularGas keeps the factor pi/6 as phi_per_n for its closures.)
 */
#include <cmath>

namespace granhydro::physics
{
  /// phi = n pi / 6 for the scaled number density n (sigma = 1)
  inline double packing_fraction(const double n) { return n * M_PI / 6.; }

  /// n = 6 phi / (pi sigma^3): the number density (SI, per m^3) of spheres of diameter
  /// sigma (m) at packing fraction phi
  inline double number_density_si(const double phi, const double sigma)
  {
    return 6. * phi / (M_PI * sigma * sigma * sigma);
  }
} // namespace granhydro::physics
