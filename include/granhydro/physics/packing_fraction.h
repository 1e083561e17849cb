#pragma once
/**
 * @file packing_fraction.h
 * The packing fraction of hard spheres of diameter sigma at number density n,
 * phi = n pi sigma^3 / 6, in scaled units (sigma = 1): the one copy that the
 * solver's messages, diagnostics and output call. (GranularGas keeps the
 * factor pi/6 as phi_per_n for its closures.)
 */
#include <cmath>

namespace granhydro::physics
{
  /// phi = n pi / 6 for the scaled number density n (sigma = 1)
  inline double packing_fraction(const double n) { return n * M_PI / 6.; }
} // namespace granhydro::physics
