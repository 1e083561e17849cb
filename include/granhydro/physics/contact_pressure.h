#pragma once
/**
 * @file contact_pressure.h
 * Optional dense-regime closure (off by default; the paper has none): a contact
 * (frictional) pressure of Johnson–Jackson type, p_f ~ F (phi - phi_min)^r /
 * (phi_c - phi)^s, as MFIX and OpenFOAM use (F = 0.05 Pa, r = 2, s = 5: Johnson, Nott
 * & Jackson, J. Fluid Mech. 210, 501 (1990)), with phi_min = 0.62 for smooth spheres
 * (their enduring contacts form only next to random close packing; doc/user-guide.md,
 * 'Dense closure'), and a frictional shear stress (physics/frictional_stress.h: Srivastava &
 * Sundaresan's Coulomb-bounded law by default, or the Newtonian mu_f = t_f sin(theta_f) p_f)
 * whose work is dissipated, not turned into T.
 *
 * Why it is needed: kinetic theory alone gives no pressure to a pile at rest
 * (T -> 0). Under gravity the floor of a cooling column obeys, with
 * x = phi_c - phi, p = n T Z ~ C T / x = weight (so T ~ x) and
 * 3/2 n dT/dt = p dphi/dt / phi - cooling ~ -x^{1/2}: x' = -K sqrt(x), so the
 * pair-correlation pole is reached in *finite* time (the 1D sedimentation
 * column reaches phi_c at t = 0.118 s without a closure).
 *
 * How it stays consistent: p_f is derived from a contact potential energy per
 * grain w(phi) that is part of the energy density,
 *   nE = n |u|^2/2 + 3/2 n T + n w(phi),   p_f = n^2 dw/dn = n phi w'(phi),
 * so the work of p_f is stored in w and given back on expansion: the equation
 * for T is exactly the one without closure (no negative T on expansion, the
 * flaw of adding p_f to the momentum equation only), total energy stays
 * conserved, and the Euler system stays hyperbolic with
 *   c^2 = c_kinetic^2 + dp_f/dn    (per unit grain mass).
 * The potential is chosen in closed form,
 *   w(phi) = A (phi - a)^{r+1} / (c - phi)^{s-1},  A = v F / (c^2 (s - 1)(c - a)),
 * (a = phi_min, c = phi_c, v = grain volume), giving
 *   p_f = F (phi - a)^r / (c - phi)^s * (phi/c)^2 [(r+1)(c - phi) + (s-1)(phi - a)] / ((s-1)(c - a)),
 * i.e. Johnson–Jackson's law times a smooth factor that is 1 at phi_c and
 * (a/c)^2 (r+1)/(s-1) at phi_min (0.70 for the defaults, phi_min = 0.62). Beyond
 * phi_max = phi_c - delta, w is continued linearly (C1) so everything stays finite.
 *
 * Units: the code's scaled units (sigma = 1, m = 1, so v = pi/6 and phi = v n).
 */
#include <granhydro/physics/frictional_stress.h>

#include <cmath>

namespace granhydro::physics
{
  struct ContactPressure
  {
    bool             active  = false;
    double           F       = 0; ///< scaled pressure
    double           phi_min = 0.62;
    double           phi_c   = 0.64;
    double           r       = 2;
    double           s       = 5;
    double           delta   = 1e-3; ///< continuation beyond phi_c - delta
    FrictionalStress friction;       ///< the frictional shear stress (physics/frictional_stress.h)

    static constexpr double v = M_PI / 6.;

    ContactPressure() = default;
    ContactPressure(const double F, const double phi_min, const double phi_c, const double r, const double s,
                    const double delta, const FrictionalStress &friction)
      : active(F > 0)
      , F(F)
      , phi_min(phi_min)
      , phi_c(phi_c)
      , r(r)
      , s(s)
      , delta(delta)
      , friction(friction)
    {}

    double A() const { return v * F / (phi_c * phi_c * (s - 1) * (phi_c - phi_min)); }

    /// x^e: products for whole exponents 1..8 (Johnson–Jackson's r = 2, s = 5: no pow in the
    /// flux's hot loop; within a few ulp of std::pow), std::pow otherwise
    static double power(const double x, const double e)
    {
      if (e >= 1 && e <= 8 && e == static_cast<int>(e))
        {
          double p = x;
          for (int k = static_cast<int>(e); k > 1; --k)
            p *= x;
          return p;
        }
      return std::pow(x, e);
    }

    /// w(phi), w'(phi), w''(phi) (energy per grain), continued linearly beyond phi_c - delta
    void potential(double phi, double &w, double &w1, double &w2) const
    {
      w = w1 = w2 = 0;
      if (!active || !(phi > phi_min))
        return;
      const double pm = phi_c - delta;
      const double ph = std::min(phi, pm);
      const double y = ph - phi_min, x = phi_c - ph, a = A();
      const double g = (r + 1) * x + (s - 1) * y, gp = s - r - 2;
      // y^r / x^s (y > 0, x >= delta > 0 here), the rest by products
      const double q = a * power(y, r) / power(x, s); // a y^r / x^s
      w              = q * y * x;
      w1             = q * g;
      w2             = q * (r * g / y + gp + s * g / x);
      if (phi > pm)
        {
          w += w1 * (phi - pm);
          w2 = 0;
        }
    }

    /// contact potential energy per volume n w(phi)
    double energy_density(const double n) const
    {
      if (!active)
        return 0;
      double w, w1, w2;
      potential(n * v, w, w1, w2);
      return n * w;
    }

    /// p_f = n phi w'(phi)
    double pressure(const double n) const
    {
      if (!active)
        return 0;
      double w, w1, w2;
      potential(n * v, w, w1, w2);
      return n * n * v * w1;
    }

    /// dw/dn = v w'(phi) = p_f / n^2: how the contact energy per grain changes with n. The
    /// chain rule from conservative to primitive gradients subtracts it (physics: the
    /// temperature gradient never contains the contact energy), see diffusive_flux.h
    double dw_dn(const double n) const
    {
      if (!active)
        return 0;
      double w, w1, w2;
      potential(n * v, w, w1, w2);
      return v * w1;
    }

    /// dp_f/dn = 2 phi w' + phi^2 w''
    double dpressure_dn(const double n) const
    {
      if (!active)
        return 0;
      const double phi = n * v;
      double       w, w1, w2;
      potential(phi, w, w1, w2);
      return 2 * phi * w1 + phi * phi * w2;
    }

    /// n w, p_f and dp_f/dn from one evaluation of the potential (the flux hot loop)
    void evaluate(const double n, double &energy, double &p, double &dp_dn) const
    {
      double p_n2;
      evaluate(n, energy, p, dp_dn, p_n2);
    }

    /// the same and p_f as pressure() rounds it (n^2 v w' in that order; evaluate()'s p is
    /// n phi w'): everything the convective formulas of one state read, from one
    /// evaluation of the potential (each keeps its own rounding)
    void evaluate(const double n, double &energy, double &p, double &dp_dn, double &p_n2) const
    {
      energy = p = dp_dn = p_n2 = 0;
      if (!active)
        return;
      const double phi = n * v;
      double       w, w1, w2;
      potential(phi, w, w1, w2);
      energy = n * w;
      p      = n * phi * w1;
      dp_dn  = 2 * phi * w1 + phi * phi * w2;
      p_n2   = n * n * v * w1;
    }

    /// the largest frictional shear viscosity at n, t_f sin(theta_f) p_f (the Newtonian law,
    /// which bounds the Srivastava–Sundaresan one)
    double viscosity(const double n) const
    {
      return friction.active() ? friction.max_factor() * pressure(n) : 0.;
    }
  };
} // namespace granhydro::physics
