#pragma once
/**
 * @file granular_gas.h
 * The hyperbolic (convective) system of granular hydrodynamics, paper eq. (2.5),
 * for hard spheres with the Garzó–Dufty/Torquato equation of state:
 * p = n T Z(phi), Z = 1 + 2(1 + eps) phi chi(phi), internal energy 3T/2 per
 * grain (physics.md 1, 2), sound speed of physics.md 1.1. Same interface as
 * IdealGas (a "description", design.md), used by the convection operator.
 *
 * Units: the code's scaled units (sigma = 1, m = 1), so phi = pi n / 6.
 * Admissible set: n > 0, T > 0, phi < phi_c (physics.md 2, guard item 1).
 */
#include <granhydro/physics/contact_pressure.h>
#include <granhydro/physics/garzo_dufty.h>
#include <granhydro/physics/ideal_gas.h>

#include <cmath>

namespace granhydro::physics
{
  template <int dim>
  struct GranularGas
  {
    static constexpr unsigned int n_components = dim + 2;
    static constexpr unsigned int energy       = dim + 1;
    static constexpr double       phi_per_n    = M_PI / 6.; // sigma = 1

    GarzoDufty1999  model;
    double          phi_c = 0.64;
    ContactPressure contact; ///< optional dense closure (inactive by default)

    GranularGas() = default;
    explicit GranularGas(const GarzoDufty1999 &m)
      : model(m)
      , phi_c(m.pair_correlation().phi_c())
    {}

    /// internal energy per grain in units of T: 3/2 (hard spheres, physics.md 1.1)
    double heat_capacity() const { return 1.5; }

    double kinetic_energy(const State<dim> &U) const { return physics::kinetic_energy<dim>(U); }

    /// T = (2/3)(E - |u|^2/2 - w(phi)) (physics.md 1, primitive recovery; w = contact
    /// potential per grain of the optional dense closure, 0 without it)
    double temperature(const State<dim> &U) const
    {
      return (2. / 3.) * (U[energy] - kinetic_energy(U) - contact.energy_density(U[0])) / U[0];
    }

    /// p = n T Z(phi) (+ p_f(n) with the dense closure)
    double pressure(const State<dim> &U) const
    {
      const double n = U[0];
      return n * temperature(U) * model.Z(n * phi_per_n) + contact.pressure(n);
    }

    /// c^2 = T [Z + phi dZ/dphi + (2/3) Z^2] (physics.md 1.1) (+ dp_f/dn), from n and p
    double sound_speed(const double n, const double p) const
    {
      const double phi = n * phi_per_n, Z = model.Z(phi);
      const double T   = (p - contact.pressure(n)) / (n * Z);
      return std::sqrt(std::max(T, 0.) * (Z + phi * model.dZ_dphi(phi) + (2. / 3.) * Z * Z) +
                       contact.dpressure_dn(n));
    }

    double max_wave_speed(const State<dim> &U, const unsigned int d) const
    {
      const double p = pressure(U);
      return std::abs(U[1 + d] / U[0]) + sound_speed(U[0], p > 0 ? p : 0.);
    }

    double flux(const State<dim> &U, const unsigned int d, State<dim> &F) const
    {
      const double p = pressure(U);
      euler_flux<dim>(U, p, d, F);
      return p;
    }

    bool admissible(const State<dim> &U) const
    {
      if (!(U[0] > 0.) || !std::isfinite(U[energy]) || !(U[0] * phi_per_n < phi_c))
        return false;
      const double e = U[energy] - kinetic_energy(U);
      return e > 0. && std::isfinite(e);
    }

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
      U[energy] = ke + 1.5 * n * T + contact.energy_density(n);
      return U;
    }
  };
} // namespace granhydro::physics
