#pragma once
/**
 * @file hydrostatic.h
 * Isothermal hydrostatic equilibria of the granular gas, for the well-balanced gravity of
 * the convective step (Käppeli & Mishra, J. Comput. Phys. 259 (2014) 199, with a
 * non-ideal equation of state; doc/physics.md 6(d), doc/numerics.md "Well-balanced
 * gravity"). At fixed T the pressure p(n, T) = n T Z(phi) + p_f(n) has the chemical
 * potential (per grain, scaled units m = sigma = 1)
 *
 *   mu(n, T) = T G(phi) + w(phi) + p_f(n) / n,   G = ln phi + Z(phi) + 2 (1 + e) X(phi),
 *
 * X = int_0^phi chi (pair_correlation.h), w the contact potential per grain and p_f = n^2
 * dw/dn (contact_pressure.h), so that d mu = dp / n at fixed T (Gibbs-Duhem). A state at
 * rest with uniform T is in equilibrium under the body force g when mu + phi_g is
 * uniform, phi_g = -g . x: along a direction d, n(x) solves mu(n, T) = mu_i + g_d (x -
 * x_i). equilibrium_density() inverts mu by Newton's method in ln n (mu increases with n
 * wherever dp/dn > 0).
 */
#include <granhydro/physics/granular_gas.h>

#include <cmath>
#include <limits>

namespace granhydro::physics::hydrostatic
{
  /// p(n, T) = n T Z(phi) + p_f(n): the pressure of the equation of state at given n and T
  template <int dim>
  double pressure(const GranularGas<dim> &gas, const double n, const double T)
  {
    return n * T * gas.model.Z(n * gas.phi_per_n) + gas.contact.pressure(n);
  }

  /// dp/dn at fixed T: T (Z + phi dZ/dphi) + dp_f/dn
  template <int dim>
  double dp_dn(const GranularGas<dim> &gas, const double n, const double T)
  {
    double       Z, dZ;
    const double phi = n * gas.phi_per_n;
    gas.model.Z_and_derivative(phi, Z, dZ);
    return T * (Z + phi * dZ) + gas.contact.dpressure_dn(n);
  }

  /// mu(n, T) = T G(phi) + w + p_f / n (see the file's comment); n > 0
  template <int dim>
  double chemical_potential(const GranularGas<dim> &gas, const double n, const double T)
  {
    const double phi = n * gas.phi_per_n;
    const double G   = std::log(phi) + gas.model.Z(phi) +
                     2 * (1 + gas.model.eps()) * gas.model.pair_correlation().integral(phi);
    return T * G + (gas.contact.energy_density(n) + gas.contact.pressure(n)) / n;
  }

  /**
   * The density n with mu(n, T) = mu (T >= 0), by Newton's method in y = ln n from
   * n_guess > 0 (d mu / dy = dp/dn): steps capped at |dy| <= 1, converged when a step is
   * below 1e-9 (the next error is then below round-off: quadratic convergence; that step
   * is taken). Returns NaN when it does not converge within 40 iterations or dp/dn <= 0 is
   * met (no unique equilibrium): the caller then keeps the point source.
   */
  template <int dim>
  double equilibrium_density(const GranularGas<dim> &gas, const double mu, const double T,
                             const double n_guess)
  {
    double y = std::log(n_guess);
    for (unsigned int it = 0; it < 40; ++it)
      {
        const double n = std::exp(y), slope = dp_dn(gas, n, T);
        if (!(slope > 0) || !std::isfinite(slope))
          return std::numeric_limits<double>::quiet_NaN();
        double dy = (chemical_potential(gas, n, T) - mu) / slope;
        if (!std::isfinite(dy))
          return std::numeric_limits<double>::quiet_NaN();
        dy = std::max(-1., std::min(1., dy));
        y -= dy;
        if (std::abs(dy) < 1e-9)
          return std::exp(y);
      }
    return std::numeric_limits<double>::quiet_NaN();
  }
} // namespace granhydro::physics::hydrostatic
