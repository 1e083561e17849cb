/**
 * @file test_hydrostatic_equilibrium.cc
 * Unit test of the isothermal hydrostatic equilibria (include/granhydro/physics/hydrostatic.h)
 * that the well-balanced gravity reconstructs about, for elastic and inelastic grains,
 * without and with the dense closure (the code's defaults in scaled units of a 1 mm,
 * 2600 kg/m^3 grain: F = 0.05 Pa / 13.36 Pa, phi_min = 0.5, r = 2, s = 5):
 *  1. Gibbs-Duhem: d mu/dn = (dp/dn)/n at fixed T, with mu against a 4th-order central
 *     difference (step 1e-4 of min(n, pole distance): truncation ~1e-15, round-off
 *     ~1e-16 mu / h ~ 1e-11 relative), to 1e-8 relative;
 *  2. dp/dn against a 4th-order central difference of p(n, T), to 1e-8 relative;
 *  3. the pressure at fixed (n, T) is the equation of state's p(U) for the state at rest
 *     (granular_gas.h), to 4 ulp-scale (1e-14 relative: U's energy carries 3T/2 + w);
 *  4. equilibrium_density inverts mu: n(mu(n0, T) + dmu, T) for dmu = 0 and up to twice
 *     the range the reconstruction asks for (|dmu| <= 2 dp/dn), from the state and from
 *     guesses 10x off: the residual mu(n) - mu within 1e-14 of dp/dn + |mu| (Newton stops
 *     a step after 1e-9, so the error is round-off of mu's terms); NaN where the
 *     equilibrium lies below the bracket (a vacuum: n < guess e^-80);
 *  5. the dilute limit: n(mu - g dz) = n exp(-g dz / T) for phi = 1e-6 (ideal gas;
 *     Z - 1 and X are O(phi)), to 1e-5 relative (their O(phi) share);
 *  6. no equilibrium where dp/dn <= 0 is met: a cold state below phi_min with T = 0 gives
 *     NaN (the caller's point source).
 * Standalone: prints each check, returns non-zero on any failure.
 */
#include <granhydro/physics/hydrostatic.h>

#include "common/bound_checks.h"

#include <cmath>
#include <iostream>
#include <string>

using namespace granhydro::physics;
namespace hs = granhydro::physics::hydrostatic;

using granhydro::testing::check;
using granhydro::testing::failures;
using granhydro::testing::rel;

int main()
{
  const double v = M_PI / 6;
  for (const double eps : {1.0, 0.9})
    for (const bool dense : {false, true})
      {
        GranularGas<3> gas{GarzoDufty1999(eps)};
        if (dense)
          gas.contact = ContactPressure(0.05 / 13.36, 0.5, 0.64, 2, 5, 1e-3, FrictionalStress{});
        const std::string tag =
          std::string("eps = ") + std::to_string(eps).substr(0, 3) + (dense ? ", dense closure" : "");
        for (const double phi : {0.05, 0.3, 0.52, 0.6, 0.63})
          for (const double T : {1e-6, 1.0})
            {
              const double      n = phi / v, h = 1e-4 * std::min(n, (0.64 - phi) / v);
              const std::string at = tag + ", phi " + std::to_string(phi) + ", T " + std::to_string(T);
              auto              mu = [&](const double x) { return hs::chemical_potential(gas, x, T); };
              auto              p  = [&](const double x) { return hs::pressure(gas, x, T); };
              auto              d4 = [&](auto f) {
                return (-f(n + 2 * h) + 8 * f(n + h) - 8 * f(n - h) + f(n - 2 * h)) / (12 * h);
              };
              const double dpdn = hs::dp_dn(gas, n, T);
              check(rel(d4(mu), dpdn / n) < 1e-8, at + ": d mu/dn = (dp/dn)/n", rel(d4(mu), dpdn / n), 1e-8);
              check(rel(d4(p), dpdn) < 1e-8, at + ": dp/dn", rel(d4(p), dpdn), 1e-8);
              const double u[3] = {0, 0, 0};
              const auto   U    = gas.from_primitive(n, u, T);
              check(rel(p(n), gas.pressure(U)) < 1e-14 * (1 + gas.contact.energy_density(n) / (1.5 * n * T)),
                    at + ": p(n, T) = p(U) at rest", rel(p(n), gas.pressure(U)), 1e-14);
              // the well-balanced reconstruction asks for the equilibrium up to two cells
              // away where a cell's weight g h is below (dp/dn)/2, so |d mu| < dp/dn; near
              // the pole dp/dn falls steeply with n, and the equilibrium that far up may be
              // a vacuum below the bracket (n e^-80): then NaN is the answer
              for (const double f : {0., 0.01, -0.01, 0.1, -0.1, 1., -1., 2., -2.})
                for (const double guess : {n, 10 * n, 0.1 * n})
                  {
                    const double target = mu(n) + f * dpdn;
                    const double g0     = std::min(guess, 0.639 / v);
                    const double m      = hs::equilibrium_density(gas, target, T, g0);
                    if (target < mu(g0 * std::exp(-80.)))
                      {
                        check(std::isnan(m), at + ": beyond the bracket, NaN", m, 0);
                        continue;
                      }
                    // the residual relative to dp/dn + |mu| (d mu = dp/dn dn/n): round-off of
                    // mu's terms, whose size near the pole is hundreds of T
                    const double err = std::abs(mu(m) - target) / (hs::dp_dn(gas, m, T) + std::abs(target));
                    if (err >= 1e-14 || guess == n)
                      check(err < 1e-14,
                            at + ": mu(n(mu)) for dmu = " + std::to_string(f) + " dp/dn, guess x" +
                              std::to_string(guess / n).substr(0, 4),
                            err, 1e-14);
                  }
            }
      }
  {
    GranularGas<3> gas{GarzoDufty1999(1.0)};
    const double   n = 1e-6 / v, T = 2.0, g = 1.0, dz = 0.5;
    const double   m = hs::equilibrium_density(gas, hs::chemical_potential(gas, n, T) - g * dz, T, n);
    check(rel(m, n * std::exp(-g * dz / T)) < 1e-5, "dilute limit: barometric n exp(-g dz / T)",
          rel(m, n * std::exp(-g * dz / T)), 1e-5);
    GranularGas<3> dense{GarzoDufty1999(0.9)};
    dense.contact = ContactPressure(0.05 / 13.36, 0.5, 0.64, 2, 5, 1e-3, FrictionalStress{});
    const double c =
      hs::equilibrium_density(dense, hs::chemical_potential(dense, 0.3 / v, 0.) - 1., 0., 0.3 / v);
    check(std::isnan(c), "cold dust below phi_min (dp/dn = 0): no equilibrium (NaN)", c, 0);
  }
  std::cout << (failures ? "FAILED" : "PASSED") << "\n";
  return failures != 0;
}
