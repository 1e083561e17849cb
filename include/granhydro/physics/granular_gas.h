#pragma once
/**
 * @file granular_gas.h
 * The hyperbolic (convective) system of granular hydrodynamics, paper eq. (2.5),
 * for hard spheres with the Garzó–Dufty/Torquato equation of state:
 * p = n T Z(phi), Z = 1 + 2(1 + eps) phi chi(phi), internal energy 3T/2 per
 * grain (doc/physics.md 1, 2), sound speed of doc/physics.md 1.1. Same interface as
 * IdealGas (a "description", doc/developer.md "Layout"), used by the convection operator.
 *
 * Units: the code's scaled units (sigma = 1, m = 1), so phi = pi n / 6.
 * Admissible set: n > 0, T > 0, phi < phi_c (doc/physics.md 2, guard item 1).
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
    /// the convective formulas (pressure, sound and wave speeds, flux, admissible set)
    /// are templates on the value type: double, or a GCC vector of doubles whose lanes
    /// are independent states, each lane bit for bit the double result (physics/lanes.h;
    /// the MUSTA flux runs 4 Gauss points at once)
    static constexpr bool vector_lanes = true;
    template <class Number>
    using StateT = std::array<Number, dim + 2>;

    GarzoDufty1999  model;
    double          phi_c = 0.64;
    ContactPressure contact; ///< optional dense closure (inactive by default)

    GranularGas() = default;
    explicit GranularGas(const GarzoDufty1999 &m)
      : model(m)
      , phi_c(m.pair_correlation().phi_c())
    {}

    /// internal energy per grain in units of T: 3/2 (hard spheres, doc/physics.md 1.1)
    double heat_capacity() const { return 1.5; }

    double kinetic_energy(const State<dim> &U) const { return physics::kinetic_energy<dim>(U); }

    /// T = (2/3)(E - |u|^2/2 - w(phi)) (doc/physics.md 1, primitive recovery; w = contact
    /// potential per grain of the optional dense closure, 0 without it)
    double temperature(const State<dim> &U) const { return temperature(U, contact.energy_density(U[0])); }

    /// T after a compression from n0 to n1 (grains per volume, scaled) by the kinetic pressure
    /// alone, adiabatic and reversible: (3/2) n dT = p_kin dn / n with p_kin = n T Z(phi), Z
    /// frozen at n0: T1 = T0 (n1/n0)^(2 Z/3) (the implicit contact step's temperature: the
    /// contact pressure's work is stored in the contact energy n w, never in T)
    double compressed_temperature(const double T0, const double n0, const double n1) const
    {
      return T0 * std::exp((2. / 3.) * model.Z(n0 * phi_per_n) * std::log(n1 / n0));
    }

    /// the same with the contact energy density n w already evaluated (T = double, or a
    /// GCC vector of doubles: states side by side, each lane bit for bit the double result)
    template <class T>
    __attribute__((always_inline)) inline T temperature(const std::array<T, dim + 2> &U, const T nw) const
    {
      return (2. / 3.) * (U[energy] - physics::kinetic_energy<dim>(U) - nw) / U[0];
    }

    /**
     * What the convective formulas of a state read of its density n, evaluated once (MUSTA:
     * once per state and stage, for its pressure, wave speed and admissibility): phi, Z and
     * dZ/dphi (one chi), and the dense closure's n w, p_f, dp_f/dn and p_f as
     * ContactPressure::pressure() rounds it (one evaluation of the potential, lane by lane;
     * zeros without the closure). The functions that take it are bit for bit those without.
     */
    template <class Number>
    struct DensityTerms
    {
      Number phi, Z, dZ, W, pf, dpf, pf_n2;
    };

    template <class Number>
    __attribute__((always_inline)) inline DensityTerms<Number> density_terms(const Number n) const
    {
      DensityTerms<Number> t;
      t.phi = n * phi_per_n;
      model.Z_and_derivative(t.phi, t.Z, t.dZ);
      if constexpr (lanes::is_vector<Number>)
        {
          t.W = t.pf = t.dpf = t.pf_n2 = Number{};
          if (contact.active)
            for (unsigned int i = 0; i < lanes::width<Number>; ++i)
              contact.evaluate(lanes::get(n, i), lanes::ref(t.W, i), lanes::ref(t.pf, i),
                               lanes::ref(t.dpf, i), lanes::ref(t.pf_n2, i));
        }
      else
        contact.evaluate(n, t.W, t.pf, t.dpf, t.pf_n2);
      return t;
    }

    /// p = n T Z(phi) (+ p_f(n) with the dense closure)
    template <class Number>
    __attribute__((always_inline)) inline Number pressure(const StateT<Number> &U) const
    {
      return pressure(U, density_terms(U[0]));
    }

    /// the same with the density's terms t = density_terms(U[0])
    template <class Number>
    __attribute__((always_inline)) inline Number pressure(const StateT<Number>       &U,
                                                          const DensityTerms<Number> &t) const
    {
      const Number n = U[0];
      if (!contact.active)
        return n * temperature(U, Number{}) * t.Z;
      return n * temperature(U, t.W) * t.Z + t.pf;
    }

    /// c^2 = T [Z + phi dZ/dphi + (2/3) Z^2] (doc/physics.md 1.1) (+ dp_f/dn), from n and p
    template <class Number>
    __attribute__((always_inline)) inline Number sound_speed(const Number n, const Number p) const
    {
      return sound_speed(n, p, density_terms(n));
    }

    /// the same with the density's terms t = density_terms(n)
    template <class Number>
    __attribute__((always_inline)) inline Number sound_speed(const Number n, const Number p,
                                                             const DensityTerms<Number> &t) const
    {
      const Number T = (p - t.pf) / (n * t.Z);
      return lanes::any_sqrt((T < Number{} ? Number{} : T) * (t.Z + t.phi * t.dZ + (2. / 3.) * t.Z * t.Z) +
                             t.dpf);
    }

    /// Energy flux into a dissipative wall [scaled W/m^2] from the state of the cell at
    /// the wall (doc/physics.md 5.2, contact theorem, m = 1): (1 - eps_w) p_w sqrt(2 T/pi)
    /// with the collisional pressure and the granular temperature only - grains that
    /// rest on the wall in enduring contact (p_f) do not collide with it. The one copy
    /// the solver calls: GarzoDufty1999::wall_heat_flux_from_pressure (unit-tested).
    double wall_heat_flux(const State<dim> &U, const double eps_w) const
    {
      const double T = std::max(temperature(U), 0.);
      return GarzoDufty1999::wall_heat_flux_from_pressure(U[0] * T * model.Z(U[0] * phi_per_n), T, 1., eps_w);
    }

    double max_wave_speed(const State<dim> &U, const unsigned int d) const
    {
      return max_wave_speed(U, d, contact.active ? 0. : pressure(U));
    }

    /// the same with the state's pressure p = pressure(U) already evaluated (Riemann
    /// solvers that need p for the flux too; with the dense closure p is not used)
    template <class Number>
    __attribute__((always_inline)) inline Number max_wave_speed(const StateT<Number> &U, const unsigned int d,
                                                                const Number p) const
    {
      return max_wave_speed(U, d, p, density_terms(U[0]));
    }

    /// the same with the density's terms t = density_terms(U[0])
    template <class Number>
    __attribute__((always_inline)) inline Number max_wave_speed(const StateT<Number> &U, const unsigned int d,
                                                                const Number                p,
                                                                const DensityTerms<Number> &t) const
    {
      if (!contact.active)
        return lanes::abs(U[1 + d] / U[0]) + sound_speed(U[0], p > Number{} ? p : Number{}, t);
      // with the closure: the temperature from the state, p_f, n w and dp_f/dn from t
      const Number n = U[0], Z = t.Z;
      const Number Tn = temperature(U, t.W), T = Tn < Number{} ? Number{} : Tn;
      return lanes::abs(U[1 + d] / n) + lanes::any_sqrt(T * (Z + t.phi * t.dZ + (2. / 3.) * Z * Z) + t.dpf);
    }

    template <class Number>
    __attribute__((always_inline)) inline Number flux(const StateT<Number> &U, const unsigned int d,
                                                      StateT<Number> &F) const
    {
      const Number p = pressure(U);
      flux(U, p, d, F);
      return p;
    }

    /// the same with the state's pressure p = pressure(U) already evaluated
    template <class Number>
    __attribute__((always_inline)) inline void flux(const StateT<Number> &U, const Number p,
                                                    const unsigned int d, StateT<Number> &F) const
    {
      euler_flux<dim>(U, p, d, F);
    }

    /// With the dense closure, nE = KE + n w(n) + (3/2) n T holds the contact energy n w
    /// and a pile at rest under gravity: T -> 0 by cooling and is the small difference of
    /// large numbers. In each Strang step the source step gives the pile the velocity
    /// g dt and the convective step takes it back through the contact pressure, so the
    /// thermal energy per grain absorbs a splitting error of order (g dt)^2 that exceeds
    /// the pile's own (3/2) T; and a cold cell that is compressed receives its contact
    /// energy through fluxes that carry the contact enthalpy w + p_f/n of the face states,
    /// not of the cell, which leaves a deficit of a small fraction of w + p_f/n per grain
    /// (largest just above phi_min, where w << p_f/n). A state whose thermal-energy
    /// deficit per grain is at most temperature_repair_tolerance * (w + p_f/n) +
    /// repair_energy, the splitting allowance of the step (splitting_repair_energy(): 10
    /// (|g_eff| dt)^2, passed by the step to every test that lies inside it), is
    /// "repairable": admissible inside a step, and set to T = temperature_floor after each
    /// part of it (repair_temperature(), counted in the run summary). Outside a step (no
    /// allowance: repair_energy = 0) only the first share applies. Without the closure the
    /// test is e > 0 as before.
    static constexpr double temperature_repair_tolerance = 1e-4;

    /// the splitting allowance per grain (scaled) of a step in which the body force changes
    /// the velocity by g_dt = |g_eff| dt (scaled): 10 (g_dt)^2
    static double splitting_repair_energy(const double g_dt) { return 10 * std::pow(g_dt, 2); }
    /// scaled units (m g sigma, ~1e-8 J for 1 mm glass): 1e-12 of it, thermal speed ~1e-7 m/s
    static constexpr double temperature_floor = 1e-12;

    /// the largest thermal-energy deficit per volume that is repaired (see above): a share of
    /// the contact enthalpy per volume n w + p_f, plus the step's splitting allowance
    /// repair_energy per grain
    double repair_allowance(const double n, const double nw, const double repair_energy) const
    {
      return repair_allowance(n, nw, contact.pressure(n), repair_energy);
    }

    /// the same with p_f = ContactPressure::pressure(n) already evaluated (T = double or
    /// a vector of doubles)
    template <class Number>
    __attribute__((always_inline)) inline Number
    repair_allowance(const Number n, const Number nw, const Number pf, const double repair_energy) const
    {
      return temperature_repair_tolerance * (nw + pf) + n * repair_energy;
    }

    /// n > 0, phi < phi_c, finite energy and positive thermal energy (with the closure:
    /// a deficit up to repair_allowance() is admissible), outside a step (no splitting
    /// allowance). For a vector of states, a mask per lane, the closure's terms lane by lane.
    template <class Number>
    __attribute__((always_inline)) inline lanes::Mask<Number> admissible(const StateT<Number> &U) const
    {
      return admissible(U, density_terms(U[0]), 0.);
    }

    /// the same inside a step with the splitting allowance repair_energy per grain (scaled;
    /// splitting_repair_energy())
    template <class Number>
    __attribute__((always_inline)) inline lanes::Mask<Number> admissible(const StateT<Number> &U,
                                                                         const double repair_energy) const
    {
      return admissible(U, density_terms(U[0]), repair_energy);
    }

    /// the same inside a step with the splitting allowance repair_energy per grain (scaled;
    /// splitting_repair_energy()) and the density's terms t = density_terms(U[0]) (n w and
    /// p_f from there): MUSTA's test of its predictor states, the diffusion step's result
    template <class Number>
    __attribute__((always_inline)) inline lanes::Mask<Number>
    admissible(const StateT<Number> &U, const DensityTerms<Number> &t, const double repair_energy) const
    {
      const Number n    = U[0];
      const auto   base = (n > Number{}) & lanes::isfinite(U[energy]) & (n * phi_per_n < phi_c);
      const Number e    = U[energy] - physics::kinetic_energy<dim>(U);
      if (!contact.active)
        return base & (e > Number{}) & lanes::isfinite(e);
      return base & (e - t.W > -repair_allowance(n, t.W, t.pf_n2, repair_energy)) & lanes::isfinite(e);
    }

    /// the test inside the convective step (reconstructed face states, a-posteriori
    /// first-order fallback): n > 0, phi < phi_c and positive energy beyond the kinetic
    /// one. It leaves out the temperature test of admissible(): in a pile at T ~ 0 that
    /// test sits at the state itself and would switch reconstructions on round-off
    /// (1 rank and N ranks would part); the step's end check and the repair see T.
    bool convectively_admissible(const State<dim> &U) const
    {
      if (!(U[0] > 0.) || !std::isfinite(U[energy]) || !(U[0] * phi_per_n < phi_c))
        return false;
      const double e = U[energy] - kinetic_energy(U);
      return e > 0. && std::isfinite(e);
    }

    /// the same inside a convective step that carries the body force (well-balanced
    /// gravity): a forward-Euler stage gives a cell in free fall the kinetic energy
    /// n (g dt)^2 / 2 beyond the work g . m dt of its source, taken from its thermal
    /// energy (SSP-RK3's result is exact for a free fall; its stages are not), so a stage
    /// may leave a thermal-energy deficit up to the splitting allowance n repair_energy
    bool convectively_admissible(const State<dim> &U, const double repair_energy) const
    {
      if (!(U[0] > 0.) || !std::isfinite(U[energy]) || !(U[0] * phi_per_n < phi_c))
        return false;
      const double e = U[energy] - kinetic_energy(U);
      return e > -U[0] * repair_energy && std::isfinite(e);
    }

    /// admissible with T > 0 (no repair needed)
    bool strictly_admissible(const State<dim> &U) const
    {
      return admissible(U) && U[energy] - kinetic_energy(U) - contact.energy_density(U[0]) > 0.;
    }

    /// a state repairable in a step with the splitting allowance repair_energy (see
    /// admissible()) with T < temperature_floor gets T = temperature_floor; returns the
    /// thermal energy added (0: nothing to repair)
    double repair_temperature(State<dim> &U, const double repair_energy) const
    {
      if (!contact.active)
        return 0.;
      const double w = contact.energy_density(U[0]), ke = kinetic_energy(U);
      const double e = U[energy] - ke - w, e_min = 1.5 * U[0] * temperature_floor;
      if (e >= e_min || !(e > -repair_allowance(U[0], w, repair_energy)))
        return 0.;
      U[energy] = ke + w + e_min;
      return e_min - e;
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
