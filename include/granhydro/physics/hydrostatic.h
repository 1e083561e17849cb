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
  /// p(n, T) = n T Z(phi) + p_f(n) with p_f = p_f(n) already evaluated
  template <int dim>
  double pressure(const GranularGas<dim> &gas, const double n, const double T, const double pf)
  {
    return n * T * gas.model.Z(n * gas.phi_per_n) + pf;
  }

  /// p(n, T) = n T Z(phi) + p_f(n): the pressure of the equation of state at given n and T
  template <int dim>
  double pressure(const GranularGas<dim> &gas, const double n, const double T)
  {
    return pressure(gas, n, T, gas.contact.pressure(n));
  }

  /// mu(n, T) = T G(phi) + w + p_f / n (see the file's comment; n > 0) and dp/dn at fixed T,
  /// T (Z + phi dZ/dphi) + dp_f/dn, from one evaluation of chi, with the contact
  /// potential's n w, p_f and dp_f/dn at n already evaluated (ContactPressure::evaluate())
  template <int dim>
  void chemical_potential_and_slope(const GranularGas<dim> &gas, const double n, const double T,
                                    const double W, const double pf, const double dpf, double &mu,
                                    double &dp_dn)
  {
    double       Z, dZ;
    const double phi = n * gas.phi_per_n;
    gas.model.Z_and_derivative(phi, Z, dZ);
    const double G =
      std::log(phi) + Z + 2 * (1 + gas.model.eps()) * gas.model.pair_correlation().integral(phi);
    mu    = T * G + (W + pf) / n;
    dp_dn = T * (Z + phi * dZ) + dpf;
  }

  /// the same evaluating the contact potential
  template <int dim>
  void chemical_potential_and_slope(const GranularGas<dim> &gas, const double n, const double T, double &mu,
                                    double &dp_dn)
  {
    double W, pf, dpf;
    gas.contact.evaluate(n, W, pf, dpf);
    chemical_potential_and_slope(gas, n, T, W, pf, dpf, mu, dp_dn);
  }

  /// dp/dn at fixed T
  template <int dim>
  double dp_dn(const GranularGas<dim> &gas, const double n, const double T)
  {
    double mu, slope;
    chemical_potential_and_slope(gas, n, T, mu, slope);
    return slope;
  }

  /// mu(n, T)
  template <int dim>
  double chemical_potential(const GranularGas<dim> &gas, const double n, const double T)
  {
    double mu, slope;
    chemical_potential_and_slope(gas, n, T, mu, slope);
    return mu;
  }

  /**
   * The density n with mu(n, T) = mu (T >= 0): Newton's method in y = ln n from n_guess
   * (0 < n_guess < 1/v; d mu / dy = dp/dn), safeguarded by a bracket (mu increases with y)
   * within [ln n_guess - 80, ln(1/v)] (phi from e^-80 of the guess to 1: the pair
   * correlation and the contact potential continue linearly beyond phi_c - delta, so mu
   * is finite there) that every evaluation narrows: steps capped at |dy| <= 2, bisection
   * where a step leaves the bracket. Converged when a Newton step is below 1e-9 (the next
   * error is then below round-off: quadratic convergence; that step is taken) or the
   * bracket is below 1e-15 with states on both sides of the target seen. Returns NaN when
   * the bracket holds no root, dp/dn <= 0 is met (no unique equilibrium) or 100 iterations
   * do not converge: the caller then keeps the point source.
   */
  template <int dim>
  double equilibrium_density(const GranularGas<dim> &gas, const double mu, const double T,
                             const double n_guess)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    double       y   = std::log(n_guess);
    double       lo = y - 80, hi = std::log(1. / gas.phi_per_n);
    bool         below = false, above = false; // a state with mu below / above the target seen
    for (unsigned int it = 0; it < 100 && y < hi; ++it)
      {
        double m, slope;
        chemical_potential_and_slope(gas, std::exp(y), T, m, slope);
        const double f = m - mu;
        if (!(slope > 0) || !std::isfinite(slope) || !std::isfinite(f))
          return nan;
        (f < 0 ? lo : hi)       = y;
        (f < 0 ? below : above) = true;
        // a Newton step of at most 2 (a factor e^2 in n); converged when it is below 1e-9
        // (taken even if it does not move y: the guess was the root to round-off);
        // bisection if it leaves the bracket
        const double dy = std::max(-2., std::min(2., f / slope));
        if (std::abs(dy) < 1e-9)
          return std::exp(y - dy);
        if (y - dy > lo && y - dy < hi)
          y -= dy;
        else
          y = 0.5 * (lo + hi);
        if (hi - lo < 1e-15 * std::max(1., std::abs(y)))
          return below && above ? std::exp(y) : nan;
      }
    return nan;
  }
} // namespace granhydro::physics::hydrostatic
