#pragma once
/**
 * @file ideal_gas.h
 * The hyperbolic (convective) system of granular hydrodynamics, paper eq. (2.5),
 * for the verification model "ideal gas": pressure p = n T (Z = 1) and internal
 * energy T/(gamma_a - 1) per particle. With gamma_a = 5/3 this is exactly the
 * dilute elastic limit of the granular system (doc/physics.md 6(b)).
 *
 * Units: the code's scaled units (length sigma, mass m = grain mass), so the
 * mass density equals the number density and the momentum row of (2.5) is the
 * ordinary Euler momentum equation. State U = (n, n u_1..n u_dim, nE).
 *
 * This is a "description" (doc/developer.md, "Layout"): it bundles the state,
 * the physical flux, pressure, wave speed and the admissible set. A second
 * description (Garzó–Dufty granular gas) follows the same interface.
 */
#include <granhydro/physics/euler_flux.h>
#include <granhydro/physics/lanes.h>

#include <array>
#include <cmath>

namespace granhydro::physics
{
  template <int dim>
  struct IdealGas
  {
    static constexpr unsigned int n_components = dim + 2;
    static constexpr unsigned int energy       = dim + 1;
    /// the convective formulas below are templates on the value type T: double or a
    /// vector of doubles whose lanes are independent states (physics/lanes.h)
    static constexpr bool vector_lanes = true;
    template <class T>
    using StateT = std::array<T, dim + 2>;

    /// adiabatic index gamma_a; 5/3 = monatomic gas = elastic dilute grains
    double gamma = 5. / 3.;

    /// internal energy per grain in units of T: 1/(gamma_a - 1)
    double heat_capacity() const { return 1. / (gamma - 1.); }

    template <class T>
    T kinetic_energy(const StateT<T> &U) const
    {
      return physics::kinetic_energy<dim>(U);
    }

    template <class T>
    T pressure(const StateT<T> &U) const
    {
      return (gamma - 1.) * (U[energy] - kinetic_energy(U));
    }

    /// what the formulas read of a state's density, evaluated once per state (the
    /// interface of GranularGas::density_terms(): nothing for an ideal gas)
    template <class T>
    struct DensityTerms
    {};
    template <class T>
    DensityTerms<T> density_terms(const T) const
    {
      return {};
    }
    template <class T>
    T pressure(const StateT<T> &U, const DensityTerms<T> &) const
    {
      return pressure(U);
    }

    /// granular temperature in energy units: T = p / n
    double temperature(const State<dim> &U) const { return pressure(U) / U[0]; }

    template <class T>
    T sound_speed(const T n, const T p) const
    {
      return lanes::sqrt(gamma * p / n);
    }

    /// |u_d| + c for a state, used by CFL and the Riemann fluxes
    double max_wave_speed(const State<dim> &U, const unsigned int d) const
    {
      return max_wave_speed(U, d, pressure(U));
    }

    /// the same with the state's pressure p = pressure(U) already evaluated (Riemann
    /// solvers that need p for the flux too)
    template <class T>
    T max_wave_speed(const StateT<T> &U, const unsigned int d, const T p) const
    {
      return lanes::abs(U[1 + d] / U[0]) + sound_speed(U[0], p > T() ? p : T());
    }
    template <class T>
    T max_wave_speed(const StateT<T> &U, const unsigned int d, const T p, const DensityTerms<T> &) const
    {
      return max_wave_speed(U, d, p);
    }

    /// physical flux F_d(U) (paper 2.6 with m = 1); returns the pressure too
    template <class T>
    T flux(const StateT<T> &U, const unsigned int d, StateT<T> &F) const
    {
      const T p = pressure(U);
      flux(U, p, d, F);
      return p;
    }

    /// the same with the state's pressure p = pressure(U) already evaluated
    template <class T>
    void flux(const StateT<T> &U, const T p, const unsigned int d, StateT<T> &F) const
    {
      euler_flux<dim>(U, p, d, F);
    }

    /// admissible set: n > 0, T > 0, finite (per lane: a mask)
    template <class T>
    lanes::Mask<T> admissible(const StateT<T> &U) const
    {
      const T p = pressure(U);
      return (U[0] > T()) & lanes::isfinite(U[energy]) & (p > T()) & lanes::isfinite(p);
    }

    /// the same inside a step (the interface of GranularGas::admissible(); no splitting
    /// allowance for an ideal gas)
    template <class T>
    lanes::Mask<T> admissible(const StateT<T> &U, const double) const
    {
      return admissible(U);
    }

    /// the same with the density's terms
    template <class T>
    lanes::Mask<T> admissible(const StateT<T> &U, const DensityTerms<T> &, const double) const
    {
      return admissible(U);
    }

    /// the same test inside the convective step (GranularGas distinguishes them)
    bool convectively_admissible(const State<dim> &U) const { return admissible(U); }
    /// the same inside a step with a body force in the convective step (no allowance here)
    bool convectively_admissible(const State<dim> &U, const double) const { return admissible(U); }

    /// conservative state from n, velocity (first dim components used) and T
    State<dim> from_primitive(const double n, const double *u, const double T) const
    {
      State<dim> U;
      U[0]      = n;
      double ke = 0;
      for (int d = 0; d < dim; ++d)
        {
          U[1 + d] = n * u[d];
          ke += 0.5 * n * u[d] * u[d];
        }
      U[energy] = ke + n * T / (gamma - 1.);
      return U;
    }
  };
} // namespace granhydro::physics
