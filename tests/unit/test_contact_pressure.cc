/**
 * @file test_contact_pressure.cc
 * Unit test of the optional dense closure (include/granhydro/physics/contact_pressure.h)
 * inside the granular equation of state (granular_gas.h):
 *  1. p_f = n^2 dw/dn (the contact pressure is the one its potential implies), checked
 *     against a central difference of n w(n); a 4th-order difference with step 1e-4 of
 *     the pole distance (c - phi)/v has truncation error ~1e-15 and round-off ~1e-12
 *     relative, so 1e-9 relative leaves room;
 *  2. dp_f/dn against a central difference of p_f (same tolerance reasoning);
 *  3. the law is Johnson–Jackson's F (phi-a)^r/(c-phi)^s times the smooth factor of the
 *     header: exactly 1 at phi_c, (a/c)^2 (r+1)/(s-1) at phi_min (evaluated in closed form);
 *  4. primitive round trip T -> U -> T with the potential in the energy: T comes from
 *     E - |u|^2/2 - w, so its error is round-off of the larger terms, bounded by
 *     8 eps (E + w)/(3T/2) (the potential costs digits when it dwarfs 3T/2);
 *  5. the sound speed equals the Euler system's c^2 = dp/dn|_{nE} + (nE + p)/n dp/d(nE)
 *     at rest, by central differences of the full pressure p(U) (kinetic + contact),
 *     to 1e-6 relative (2nd-order differences with step 1e-4 of the pole distance:
 *     truncation ~1e-8, round-off of the potential's cancellation ~1e-16 w/(h T));
 *  6. the guard: beyond phi_c - delta the potential continues linearly (C1), finite.
 * Standalone: prints each check, returns non-zero on any failure.
 */
#include <granhydro/physics/granular_gas.h>

#include "common/bound_checks.h"

#include <cmath>
#include <iostream>
#include <string>

using namespace granhydro::physics;

using granhydro::testing::check;
using granhydro::testing::failures;
using granhydro::testing::rel;

int main()
{
  // MFIX/OpenFOAM defaults in scaled units of a 1 mm, 2600 kg/m^3 grain (p0 = 13.36 Pa):
  // F = 0.05 Pa, phi_min = 0.5, r = 2, s = 5, phi_c = 0.64, delta = 1e-3
  const double          F = 0.05 / 13.36, a = 0.5, c = 0.64, r = 2, s = 5, delta = 1e-3;
  const ContactPressure cp(F, a, c, r, s, delta, FrictionalStress{});
  const double          v = M_PI / 6;

  for (const double phi : {0.52, 0.56, 0.6, 0.62, 0.635})
    {
      // step relative to the distance to the pole, where p_f varies on the scale c - phi
      const double n = phi / v, h = 1e-4 * (c - phi) / v;
      auto         W = [&](const double x) { return cp.energy_density(x); };
      auto         w = [&](const double x) { return W(x) / x; };
      // 4th-order central differences
      const double dw = (-w(n + 2 * h) + 8 * w(n + h) - 8 * w(n - h) + w(n - 2 * h)) / (12 * h);
      check(rel(cp.pressure(n), n * n * dw) < 1e-9, "p_f = n^2 dw/dn at phi = " + std::to_string(phi),
            rel(cp.pressure(n), n * n * dw), 1e-9);
      auto         P  = [&](const double x) { return cp.pressure(x); };
      const double dp = (-P(n + 2 * h) + 8 * P(n + h) - 8 * P(n - h) + P(n - 2 * h)) / (12 * h);
      check(rel(cp.dpressure_dn(n), dp) < 1e-9, "dp_f/dn at phi = " + std::to_string(phi),
            rel(cp.dpressure_dn(n), dp), 1e-9);
      const double jj = F * std::pow(phi - a, r) / std::pow(c - phi, s);
      const double factor =
        (phi / c) * (phi / c) * ((r + 1) * (c - phi) + (s - 1) * (phi - a)) / ((s - 1) * (c - a));
      check(rel(cp.pressure(n), jj * factor) < 1e-13,
            "Johnson-Jackson law times its factor at phi = " + std::to_string(phi),
            rel(cp.pressure(n), jj * factor), 1e-13);
    }
  {
    // the factor's end values
    const double f_c = 1., f_a = (a / c) * (a / c) * (r + 1) / (s - 1);
    const double phi = c - delta, n = phi / v;
    const double ratio = cp.pressure(n) / (F * std::pow(phi - a, r) / std::pow(c - phi, s));
    check(std::abs(ratio - f_c) < 0.02, "factor -> 1 at phi_c (at phi_c - delta)", ratio, 0.02);
    check(std::abs(f_a - 0.4578) < 1e-4, "factor at phi_min = (a/c)^2 (r+1)/(s-1)", f_a, 0.4578);
    check(cp.pressure(0.49 / v) == 0 && cp.energy_density(0.49 / v) == 0, "no contact stress below phi_min",
          0, 0);
  }

  GarzoDufty1999 gd(0.9, 0.49, 0.64, 1e-3);
  GranularGas<3> gas(gd);
  gas.contact = cp;
  for (const double phi : {0.3, 0.55, 0.6, 0.63})
    for (const double T : {1e-3, 0.5})
      {
        const double n     = phi / v;
        const double u[3]  = {0.3, -0.2, 0.1};
        const auto   U     = gas.from_primitive(n, u, T);
        const double bound = 8 * 2.2e-16 * (U[4] / n + cp.energy_density(n) / n) / (1.5 * T);
        check(rel(gas.temperature(U), T) < bound,
              "T round trip at phi = " + std::to_string(phi) + ", T = " + std::to_string(T),
              rel(gas.temperature(U), T), bound);
        // c^2 of the Euler system at rest: dp/dn|_{nE} + (nE + p)/n dp/d(nE)
        const double ur[3] = {0, 0, 0};
        const auto   U0    = gas.from_primitive(n, ur, T);
        const double hn = 1e-4 * std::min(n, (c - phi) / v), he = 1e-4 * U0[4];
        auto         Un = [&](const double dn, const double de) {
          State<3> X = U0;
          X[0] += dn;
          X[4] += de;
          return gas.pressure(X);
        };
        const double dpdn = (Un(hn, 0) - Un(-hn, 0)) / (2 * hn);
        const double dpde = (Un(0, he) - Un(0, -he)) / (2 * he);
        const double p = gas.pressure(U0), c2 = dpdn + (U0[4] + p) / n * dpde;
        const double cs = gas.sound_speed(n, p);
        check(rel(cs * cs, c2) < 1e-6,
              "c^2 = Euler system's at phi = " + std::to_string(phi) + ", T = " + std::to_string(T),
              rel(cs * cs, c2), 1e-6);
      }
  {
    // guard: finite and C1 beyond phi_c - delta
    const double pm = c - delta, n1 = (pm - 1e-9) / v, n2 = (pm + 1e-9) / v, n3 = (c + 0.01) / v;
    check(rel(cp.pressure(n1), cp.pressure(n2)) < 1e-5, "p_f continuous at phi_c - delta",
          rel(cp.pressure(n1), cp.pressure(n2)), 1e-5);
    check(std::isfinite(cp.pressure(n3)) && cp.pressure(n3) > cp.pressure(n2),
          "finite and increasing beyond phi_c", cp.pressure(n3), 0);
  }
  {
    // admissibility under the closure (regression: it tested E - KE > 0, so a pile with
    // T < 0 passed because E holds the contact energy n w): at phi = 0.58 a state whose
    // thermal deficit per grain is 2e-4 of the contact enthalpy h = w + p_f/n (> the
    // repairable 1e-4 h + splitting allowance 0) is inadmissible; a deficit of 0.5e-4 h
    // is repairable: admissible, and repair_temperature() sets T to the floor exactly,
    // adding the deficit
    const double n = 0.58 / v, w = cp.energy_density(n) / n, h = w + cp.pressure(n) / n;
    const double u[3] = {0, 0, 0};
    auto         U    = gas.from_primitive(n, u, 1.0);
    U[4]              = cp.energy_density(n) - n * 2e-4 * h;
    check(!gas.admissible(U), "deficit 2e-4 (w + p_f/n) with the closure is inadmissible", gas.temperature(U),
          0);
    const double T_small = -0.5e-4 * h / 1.5; // deficit 0.5e-4 h per grain
    U[4]                 = cp.energy_density(n) + 1.5 * n * T_small;
    check(gas.admissible(U) && !gas.strictly_admissible(U),
          "deficit 0.5e-4 (w + p_f/n): repairable, not strictly admissible", T_small, 0);
    const double added = gas.repair_temperature(U, 0.);
    check(rel(gas.temperature(U), gas.temperature_floor) < 1e-3 && gas.strictly_admissible(U),
          "repair sets T to the floor", gas.temperature(U), gas.temperature_floor);
    check(rel(added, 1.5 * n * (gas.temperature_floor - T_small)) < 1e-9, "repair adds exactly the deficit",
          added, 1.5 * n * (gas.temperature_floor - T_small));
    // inside a step, the splitting allowance (g dt)^2 widens the repairable set
    U[4] = cp.energy_density(n) - n * 2e-4 * h;
    check(gas.admissible(U, 2e-4 * h), "deficit 2e-4 h per grain within a 2e-4 h splitting allowance",
          gas.temperature(U), 0);
    // the allowance of a step whose body force changes the velocity by g dt = 0.01: 10 (g dt)^2
    // = 1e-3 (to round-off: two roundings)
    check(rel(gas.splitting_repair_energy(0.01), 1e-3) < 1e-15, "splitting allowance 10 (g dt)^2",
          gas.splitting_repair_energy(0.01), 1e-3);
  }
  std::cout << (failures ? "FAILED\n" : "all passed\n");
  return failures ? 1 : 0;
}
