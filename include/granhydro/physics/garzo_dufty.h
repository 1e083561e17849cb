#pragma once
/**
 * @file garzo_dufty.h
 * Garzó & Dufty (1999, Phys. Rev. E 59, 5895; "GD99") Navier–Stokes transport
 * coefficients of a granular gas of smooth inelastic hard spheres (d = 3),
 * revised-Enskog theory, standard first Sonine approximation, with the
 * fourth cumulant c* kept — exactly as specified in doc/physics.md section 3,
 * plus the equation of state and sound speed (doc/physics.md 1.1, 2) and the
 * dissipative-wall heat flux (doc/physics.md 5.2).
 *
 * The GD99 article itself was not available to the authors of doc/physics.md
 * (see its section 3.9), so the comments below cite the doc/physics.md section
 * and name the GD99 quantity rather than quote GD99 equation numbers.
 *
 * Units: every dimensional formula is dimensionally homogeneous and contains
 * no hidden constant (no k_B; T is an energy), so it holds in SI and in the
 * code's scaled units (sigma = m = 1) alike, provided all inputs use one
 * consistent unit system (doc/physics.md section 0).
 *
 * The dimensionless closures in (phi, chi) and their restitution-only constants are
 * in garzo_dufty/factors.h, the records and modes the model gives in
 * garzo_dufty/coefficients.h; this header includes both.
 *
 * Header only, standard library only, no virtual functions. The dimensionless
 * functions are templated on the number type of phi; the dimensional ones on
 * the number type of (n, T), with grain mass m and diameter sigma as double.
 */
#include <granhydro/physics/garzo_dufty/coefficients.h>
#include <granhydro/physics/garzo_dufty/factors.h>
#include <granhydro/physics/pair_correlation.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace granhydro::physics
{
  /**
   * Garzó–Dufty (1999) constitutive model for d = 3 hard spheres with
   * restitution eps (GD99's alpha) and the Torquato pair correlation
   * (doc/physics.md sections 2 and 3).
   */
  class GarzoDufty1999 : private GarzoDuftyFactors
  {
  public:
    /**
     * @param eps      normal restitution, 0.5 <= eps <= 1 (doc/physics.md 3.4: totals
     *                 eta, kappa > 0 are verified only on this range)
     * @param pair_correlation  chi(phi) with its guard (doc/physics.md 2)
     * @param T_floor  >= 0; T is replaced by max(T, T_floor) inside the
     *                 transport-coefficient formulas only (doc/physics.md 2, item 3)
     * @param zeta_u_mode  first-order cooling (doc/physics.md 3.6), off by default
     * @throws std::invalid_argument naming the parameter and its allowed range.
     */
    explicit GarzoDufty1999(const double eps, const PairCorrelationTorquato &pair_correlation,
                            const double T_floor = 0., const ZetaUMode zeta_u_mode = ZetaUMode::off)
      : chi_(pair_correlation)
    {
      initialize(eps, T_floor, zeta_u_mode);
    }

    /**
     * Same, constructing the pair correlation from (phi_f, phi_c, delta)
     * (defaults 0.49, 0.64, 1e-3; default eps = 1, elastic); refuses phi_f >= phi_c (and the other
     * invalid choices listed at PairCorrelationTorquato) with
     * std::invalid_argument.
     */
    explicit GarzoDufty1999(const double eps = 1., const double phi_f = 0.49, const double phi_c = 0.64,
                            const double delta = 1.e-3, const double T_floor = 0.,
                            const ZetaUMode zeta_u_mode = ZetaUMode::off)
      : chi_(phi_f, phi_c, delta)
    {
      initialize(eps, T_floor, zeta_u_mode);
    }

    /** @name Parameters */
    ///@{
    double                         eps() const { return a_; }
    double                         T_floor() const { return T_floor_; }
    ZetaUMode                      zeta_u_mode() const { return zeta_u_mode_; }
    const PairCorrelationTorquato &pair_correlation() const { return chi_; }

    /// Change the temperature floor (>= 0), doc/physics.md 2 item 3.
    void set_T_floor(const double T_floor)
    {
      if (!(T_floor >= 0.) || !std::isfinite(T_floor))
        fail("T_floor", T_floor, "[0, inf)");
      T_floor_ = T_floor;
    }
    void set_zeta_u_mode(const ZetaUMode mode) { zeta_u_mode_ = mode; }

    /**
     * Frictional grains (Coulomb friction coefficient mu >= 0 between grains), after
     * Chialvo & Sundaresan, "A modified kinetic theory for frictional granular flows in
     * dense and dilute regimes", Phys. Fluids 25, 070603 (2013): the collisional
     * dissipation of rough, frictional spheres is that of smooth spheres with the
     * effective restitution e_eff = e - (3/2) mu exp(-3 mu) (their fit to DEM of sheared
     * frictional spheres). Only the cooling rate zeta0 (the energy sink) uses e_eff; the
     * pressure, the transport coefficients and zeta_U keep e, as in their model. mu = 0 is
     * the smooth model bit for bit (e_eff = e exactly). doc/physics.md 3.10.
     */
    void set_friction(const double mu)
    {
      if (!(mu >= 0. && mu <= 1.))
        fail("mu (friction coefficient)", mu, "[0, 1]");
      friction_mu_ = mu;
      e_eff_       = effective_restitution(a_, mu);
      cooling_fac_ = cooling_factor(e_eff_, c_star_);
    }
    /// the friction coefficient mu (0: smooth spheres)
    double friction() const { return friction_mu_; }
    /// e_eff of the cooling rate (= eps() for mu = 0)
    double effective_restitution() const { return e_eff_; }
    /// Chialvo & Sundaresan (2013): e_eff = e - (3/2) mu exp(-3 mu)
    static double effective_restitution(const double e, const double mu)
    {
      return e - 1.5 * mu * std::exp(-3. * mu);
    }
    ///@}

    // ------------------------------------------------------------------------
    /** @name Dimensionless factors (functions of phi; eps fixed by the object) */
    ///@{

    /**
     * c*(eps) = 32 (1 - a)(1 - 2a^2)/[81 - 17a + 30 a^2 (1 - a)], doc/physics.md 3.2
     * (van Noije–Ernst fourth cumulant of the homogeneous cooling state, as
     * used in GD99; independent of phi in Enskog theory).
     */
    double c_star() const { return c_star_; }

    /// c* for an arbitrary eps (doc/physics.md 3.2); c_star() is this at eps().
    static double c_star(const double a) { return fourth_cumulant(a); }

    /// chi(phi), doc/physics.md 2 (forwarded to the pair correlation).
    template <typename Number>
    __attribute__((always_inline)) inline Number chi(const Number phi) const
    {
      return chi_.chi(phi);
    }

    /// Z = p/(n T) = 1 + 2(1 + a) phi chi, doc/physics.md 2 (GD99 pressure, d = 3).
    template <typename Number>
    __attribute__((always_inline)) inline Number Z(const Number phi) const
    {
      return Z_(phi, chi_.chi(phi));
    }

    /// dZ/dphi = 2(1 + a)(chi + phi dchi/dphi), doc/physics.md 1.1.
    template <typename Number>
    __attribute__((always_inline)) inline Number dZ_dphi(const Number phi) const
    {
      Number c, dc;
      chi_.chi_and_derivative(phi, c, dc);
      return dZ_(phi, c, dc);
    }

    /// Z and dZ/dphi from one evaluation of chi and dchi/dphi: bit for bit Z(phi) and
    /// dZ_dphi(phi) (chi_and_derivative()'s chi is chi())
    template <typename Number>
    __attribute__((always_inline)) inline void Z_and_derivative(const Number phi, Number &Zv,
                                                                Number &dZ) const
    {
      Number c, dc;
      chi_.chi_and_derivative(phi, c, dc);
      Zv = Z_(phi, c);
      dZ = dZ_(phi, c, dc);
    }

    /// zeta* = (5/12) chi (1 - a^2)(1 + 3c*/32), doc/physics.md 3.3 (GD99 zeroth-order cooling rate / nu0).
    template <typename Number>
    Number zeta_star(const Number phi) const
    {
      return lanes::constant<Number>(zeta_fac_) * chi_.chi(phi);
    }

    /// nu_eta* = chi (1 - (1 - a)^2/4)(1 - c*/64), doc/physics.md 3.3.
    template <typename Number>
    Number nu_eta_star(const Number phi) const
    {
      return lanes::constant<Number>(nu_eta_fac_) * chi_.chi(phi);
    }

    /// nu_kappa* = nu_mu* = (chi/3)(1 + a)[1 + (33/16)(1 - a) + (19 - 3a)c*/1024], doc/physics.md 3.3.
    template <typename Number>
    Number nu_kappa_star(const Number phi) const
    {
      return lanes::constant<Number>(nu_kap_fac_) * chi_.chi(phi);
    }

    /// gamma* = (128/(5 pi)) phi^2 chi (1 + a)(1 - c*/32), doc/physics.md 3.4 (GD99 bulk viscosity / eta0).
    template <typename Number>
    Number gamma_star(const Number phi) const
    {
      return gamma_(phi, chi_.chi(phi));
    }

    /**
     * eta* = eta_k* [1 + (4/5) phi chi (1 + a)] + (3/5) gamma*, with
     * eta_k* = [1 - (2/5)(1 + a)(1 - 3a) phi chi]/(nu_eta* - zeta* /2),
     * doc/physics.md 3.4 (GD99 shear viscosity / eta0).
     */
    template <typename Number>
    Number eta_star(const Number phi) const
    {
      const Number c = chi_.chi(phi);
      return eta_(phi, c, eta_k_(phi, c));
    }

    /**
     * kappa* = kappa_k* [1 + (6/5) phi chi (1 + a)] + (256/(25 pi)) phi^2 chi (1 + a)(1 + 7c* /32),
     * kappa_k* = (2/3)[1 + c* + (3/5) phi chi (1 + a)^2 (2a - 1 + (1 + a)c* /2)]/(nu_kappa* - 2 zeta*),
     * doc/physics.md 3.4 (GD99 thermal conductivity / kappa0, compact numerator).
     */
    template <typename Number>
    Number kappa_star(const Number phi) const
    {
      const Number c = chi_.chi(phi);
      return kappa_(phi, c, kappa_k_(phi, c));
    }

    /**
     * mu* = mu_k* [1 + (6/5) phi chi (1 + a)], with
     * mu_k* = [(1 + g) zeta* kappa_k* + c* /3 - (4/5) phi chi (1 + a)(1 + g/2)
     *          (a(1 - a) - (c* /12)(16 - 3a + 3a^2))]/(nu_mu* - (3/2) zeta*),
     * g = phi d ln chi/d phi; doc/physics.md 3.4 and 3.9 (D1) (GD99 coefficient of
     * grad n in the heat flux, / (T kappa0/n)). Not sign-definite (P5).
     */
    template <typename Number>
    Number mu_star(const Number phi) const
    {
      Number c, dc;
      chi_.chi_and_derivative(phi, c, dc);
      return mu_(phi, c, mu_k_(phi, c, dc, kappa_k_(phi, c)));
    }

    /// zeta_U in the object's mode (0 when off), doc/physics.md 3.6; dimensionless, multiplies div u.
    template <typename Number>
    Number zeta_U(const Number phi) const
    {
      return zeta_U(phi, zeta_u_mode_);
    }

    /**
     * zeta_U in a given mode, doc/physics.md 3.6 (GD99 first-order cooling rate,
     * dimensionless):
     *   leading: -(1 - a)(Z - 1) = -2 (1 - a^2) phi chi;
     *   full:    leading + (5/32)(1 - a^2)(1 + 3c* /64) chi c_D (MFIX GD_99 form,
     *            c_D, nu_gamma*, lambda as printed in doc/physics.md 3.6).
     */
    template <typename Number>
    Number zeta_U(const Number phi, const ZetaUMode mode) const
    {
      if (mode == ZetaUMode::off)
        return lanes::constant<Number>(0.);
      return zeta_U_(phi, chi_.chi(phi), mode);
    }

    /**
     * Every dimensionless factor at once (doc/physics.md 3.2–3.6), chi and
     * dchi/dphi evaluated once: the function for hot loops.
     */
    template <typename Number>
    DimensionlessCoefficientsT<Number> dimensionless(const Number phi) const
    {
      DimensionlessCoefficientsT<Number> r;
      Number                             c, dc;
      chi_.chi_and_derivative(phi, c, dc);
      r.phi           = phi;
      r.chi           = c;
      r.dchi_dphi     = dc;
      r.g             = phi * dc / c;
      r.c_star        = lanes::constant<Number>(c_star_);
      r.Z             = Z_(phi, c);
      r.dZ_dphi       = dZ_(phi, c, dc);
      r.zeta_star     = lanes::constant<Number>(zeta_fac_) * c;
      r.nu_eta_star   = lanes::constant<Number>(nu_eta_fac_) * c;
      r.nu_kappa_star = lanes::constant<Number>(nu_kap_fac_) * c;
      r.gamma_star    = gamma_(phi, c);
      r.eta_k_star    = eta_k_(phi, c);
      r.eta_star      = eta_(phi, c, r.eta_k_star, r.gamma_star);
      r.kappa_k_star  = kappa_k_(phi, c);
      r.kappa_star    = kappa_(phi, c, r.kappa_k_star);
      r.mu_k_star     = mu_k_(phi, c, dc, r.kappa_k_star);
      r.mu_star       = mu_(phi, c, r.mu_k_star);
      r.zeta_U = zeta_u_mode_ == ZetaUMode::off ? lanes::constant<Number>(0.) : zeta_U_(phi, c, zeta_u_mode_);
      return r;
    }

    /// Same as dimensionless(); the name used in the brief's interface.
    template <typename Number>
    DimensionlessCoefficientsT<Number> coefficients(const Number phi) const
    {
      return dimensionless(phi);
    }
    ///@}

    // ------------------------------------------------------------------------
    /** @name Dimensional functions of (n, T, m, sigma)
     *
     * n number density, T granular temperature in energy units, m grain mass,
     * sigma grain diameter, in any consistent unit system (doc/physics.md 0).
     * Inside the transport-coefficient formulas (eta0, kappa0, nu0, eta, gamma,
     * kappa, mu, zeta0) T is replaced by max(T, T_floor) (doc/physics.md 2 item 3);
     * pressure, sound speed and wall heat flux use T as given (they are parts
     * of the flux and must stay consistent with the state; T >= 0 expected).
     * n and T must have the same number type (write 1., not 1).
     */
    ///@{

    /// phi = n pi sigma^3/6, doc/physics.md 0.
    template <typename Number>
    static Number packing_fraction(const Number n, const double sigma)
    {
      return n * lanes::constant<Number>(pi_ / 6. * sigma * sigma * sigma);
    }

    /// n = 6 phi/(pi sigma^3), doc/physics.md 0.
    template <typename Number>
    static Number number_density(const Number phi, const double sigma)
    {
      return phi * lanes::constant<Number>(6. / (pi_ * sigma * sigma * sigma));
    }

    /// grain mass m = rho_s pi sigma^3/6, doc/physics.md 0.
    static double grain_mass(const double sigma, const double rho_s)
    {
      return rho_s * pi_ * sigma * sigma * sigma / 6.;
    }

    /// p = n T Z(phi), doc/physics.md 2 (GD99 hydrostatic pressure, d = 3). m unused (uniform signature).
    template <typename Number>
    Number pressure(const Number n, const Number T, const double /*m*/, const double sigma) const
    {
      return n * T * Z(packing_fraction(n, sigma));
    }

    /**
     * Sound speed c = sqrt((T/m)[Z + phi dZ/dphi + (2/3) Z^2]), doc/physics.md 1.1
     * (Euler eigenvalues u.e -+ c of the convective system with p = n T Z and
     * internal energy 3T/2 per particle). Uses T as given.
     */
    template <typename Number>
    Number sound_speed(const Number n, const Number T, const double m, const double sigma) const
    {
      using std::sqrt;
      const Number phi = packing_fraction(n, sigma);
      Number       c, dc;
      chi_.chi_and_derivative(phi, c, dc);
      const Number Zv = Z_(phi, c);
      const Number dZ = dZ_(phi, c, dc);
      return sqrt(T / lanes::constant<Number>(m) *
                  (Zv + phi * dZ + lanes::constant<Number>(2. / 3.) * Zv * Zv));
    }

    /// eta0 = 5/(16 sigma^2) sqrt(m T/pi) [Pa s], doc/physics.md 3.1 (elastic Boltzmann viscosity). n unused.
    template <typename Number>
    Number eta0(const Number /*n*/, const Number T, const double m, const double sigma) const
    {
      return lanes::constant<Number>(5. / (16. * sigma * sigma)) *
             lanes::any_sqrt(lanes::constant<Number>(m / pi_) * floored(T));
    }

    /// kappa0 = 15/(4m) eta0 = 75/(64 sigma^2) sqrt(T/(pi m)) [1/(m s)], doc/physics.md 3.1. n unused.
    template <typename Number>
    Number kappa0(const Number /*n*/, const Number T, const double m, const double sigma) const
    {
      return lanes::constant<Number>(75. / (64. * sigma * sigma)) *
             lanes::any_sqrt(floored(T) / lanes::constant<Number>(pi_ * m));
    }

    /// nu0 = n T/eta0 = (16/5) n sigma^2 sqrt(pi T/m) [1/s], doc/physics.md 3.1.
    template <typename Number>
    Number nu0(const Number n, const Number T, const double m, const double sigma) const
    {
      return lanes::constant<Number>(16. / 5. * sigma * sigma) * n *
             lanes::any_sqrt(lanes::constant<Number>(pi_ / m) * floored(T));
    }

    /// Shear viscosity eta = eta0 eta*(phi) [Pa s], doc/physics.md 3.4.
    template <typename Number>
    Number eta(const Number n, const Number T, const double m, const double sigma) const
    {
      return eta0(n, T, m, sigma) * eta_star(packing_fraction(n, sigma));
    }

    /// Bulk viscosity gamma = eta0 gamma*(phi) [Pa s], doc/physics.md 3.4.
    template <typename Number>
    Number gamma(const Number n, const Number T, const double m, const double sigma) const
    {
      return eta0(n, T, m, sigma) * gamma_star(packing_fraction(n, sigma));
    }

    /// Thermal conductivity kappa = kappa0 kappa*(phi) [1/(m s)] (multiplies grad T, T in J), doc/physics.md 3.4.
    template <typename Number>
    Number kappa(const Number n, const Number T, const double m, const double sigma) const
    {
      return kappa0(n, T, m, sigma) * kappa_star(packing_fraction(n, sigma));
    }

    /// mu = (T kappa0/n) mu*(phi) [J m^2/s] (multiplies grad n; q = -kappa grad T - mu grad n), doc/physics.md 3.4.
    template <typename Number>
    Number mu(const Number n, const Number T, const double m, const double sigma) const
    {
      return floored(T) * kappa0(n, T, m, sigma) / n * mu_star(packing_fraction(n, sigma));
    }

    /**
     * Zeroth-order cooling rate zeta0 = nu0 zeta* = (4/3)(1 - a^2)(1 + 3c* /32)
     * chi n sigma^2 sqrt(pi T/m) [1/s], doc/physics.md 3.5 (dT/dt = -zeta0 T in the
     * homogeneous cooling state; energy sink -(3/2) n T zeta0).
     */
    template <typename Number>
    Number zeta0(const Number n, const Number T, const double m, const double sigma) const
    {
      return nu0(n, T, m, sigma) * cooling_star(packing_fraction(n, sigma));
    }

    /// zeta* of the cooling rate: zeta*(phi) with e_eff for frictional grains (set_friction),
    /// (5/12) chi (1 - e_eff^2)(1 + 3c*/32); zeta*(phi) itself for smooth ones
    template <typename Number>
    Number cooling_star(const Number phi) const
    {
      return lanes::constant<Number>(cooling_fac_) * chi_.chi(phi);
    }

    /// Mean free path lambda = 1/(sqrt(2) pi n sigma^2 chi) = sigma/(6 sqrt(2) phi chi), doc/physics.md 3.8.
    template <typename Number>
    Number mean_free_path(const Number n, const double sigma) const
    {
      return lanes::constant<Number>(1.) / (lanes::constant<Number>(std::sqrt(2.) * pi_ * sigma * sigma) * n *
                                            chi_.chi(packing_fraction(n, sigma)));
    }

    /**
     * p, c, eta, gamma, kappa, mu, zeta0 and zeta_U at one state with a single
     * chi evaluation (doc/physics.md 1.1, 2, 3.1–3.6); for hot loops. T_floor as
     * in the individual functions (not in p and c).
     */
    template <typename Number>
    TransportCoefficientsT<Number> transport(const Number n, const Number T, const double m,
                                             const double sigma) const
    {
      TransportCoefficientsT<Number> r;
      r.star          = dimensionless(packing_fraction(n, sigma));
      const auto  &s  = r.star;
      const Number Tc = floored(T);
      const Number e0 = lanes::constant<Number>(5. / (16. * sigma * sigma)) *
                        lanes::any_sqrt(lanes::constant<Number>(m / pi_) * Tc);
      const Number k0 = lanes::constant<Number>(15. / (4. * m)) * e0;
      r.p             = n * T * s.Z;
      r.c             = lanes::any_sqrt(T / lanes::constant<Number>(m) *
                                        (s.Z + s.phi * s.dZ_dphi + lanes::constant<Number>(2. / 3.) * s.Z * s.Z));
      r.eta           = e0 * s.eta_star;
      r.gamma         = e0 * s.gamma_star;
      r.kappa         = k0 * s.kappa_star;
      r.mu            = Tc * k0 / n * s.mu_star;
      r.zeta0  = n * Tc / e0 * (lanes::constant<Number>(cooling_fac_) * s.chi); // = s.zeta_star when smooth
      r.zeta_U = s.zeta_U;
      return r;
    }
    ///@}

    // ------------------------------------------------------------------------
    /** @name Dissipative wall (doc/physics.md 5.2, replaces paper eq. 6.2, P11) */
    ///@{

    /**
     * Energy flux into a wall with grain–wall restitution eps_w [W/m^2],
     * doc/physics.md 5.2:
     *   q_w = (1 - eps_w^2) n_c T sqrt(T/(2 pi m)),
     * contact_theorem (default): n_c = 2 p_w/((1 + eps_w) T), i.e.
     *   q_w = (1 - eps_w) p_w sqrt(2T/(pi m)), p_w = n T Z (this object's EOS);
     * dilute: n_c = n;  n_chi: n_c = n chi(phi).
     * (n, T) is the wall state; T used as given (T >= 0), 0 <= eps_w <= 1.
     */
    template <typename Number>
    Number wall_heat_flux(const Number n, const Number T, const double m, const double sigma,
                          const double            eps_w,
                          const WallHeatFluxModel model = WallHeatFluxModel::contact_theorem) const
    {
      using std::sqrt;
      switch (model)
        {
          case WallHeatFluxModel::dilute:
            return lanes::constant<Number>(1. - eps_w * eps_w) * n * T *
                   sqrt(T / lanes::constant<Number>(2. * pi_ * m));
          case WallHeatFluxModel::n_chi:
            return lanes::constant<Number>(1. - eps_w * eps_w) * n * chi_.chi(packing_fraction(n, sigma)) *
                   T * sqrt(T / lanes::constant<Number>(2. * pi_ * m));
          case WallHeatFluxModel::contact_theorem:
          default:
            return wall_heat_flux_from_pressure(pressure(n, T, m, sigma), T, m, eps_w);
        }
    }

    /// Contact-theorem wall heat flux from a given wall pressure p_w: (1 - eps_w) p_w sqrt(2T/(pi m)), doc/physics.md 5.2.
    template <typename Number>
    static Number wall_heat_flux_from_pressure(const Number p_w, const Number T, const double m,
                                               const double eps_w)
    {
      using std::sqrt;
      return lanes::constant<Number>(1. - eps_w) * p_w * sqrt(lanes::constant<Number>(2. / (pi_ * m)) * T);
    }

    /**
     * d q_w/dT at fixed n = (3/2) q_w/T, doc/physics.md 5.2 (all three models are
     * proportional to T^{3/2} at fixed n; with p_w proportional to T for the
     * contact theorem). Returns 0 for T <= 0.
     */
    template <typename Number>
    Number wall_heat_flux_dT(const Number n, const Number T, const double m, const double sigma,
                             const double            eps_w,
                             const WallHeatFluxModel model = WallHeatFluxModel::contact_theorem) const
    {
      if (!(T > lanes::constant<Number>(0.)))
        return lanes::constant<Number>(0.);
      return lanes::constant<Number>(1.5) * wall_heat_flux(n, T, m, sigma, eps_w, model) / T;
    }
    ///@}

  private:
    void initialize(const double eps, const double T_floor, const ZetaUMode zeta_u_mode)
    {
      if (!(eps >= 0.5 && eps <= 1.))
        fail("eps (normal coefficient of restitution)", eps,
             "[0.5, 1] (doc/physics.md 3.4: positivity of eta and kappa is verified only there)");
      set_T_floor(T_floor);
      zeta_u_mode_ = zeta_u_mode;
      a_           = eps;
      set_factors(eps);
      friction_mu_ = 0.;
      e_eff_       = eps;
      cooling_fac_ = zeta_fac_;
    }

    template <typename Number>
    Number floored(const Number T) const
    {
      // NaN propagates (comparison false -> T returned)
      return T < lanes::constant<Number>(T_floor_) ? lanes::constant<Number>(T_floor_) : T;
    }

    static std::string str(const double x)
    {
      std::ostringstream s;
      s.precision(17);
      s << x;
      return s.str();
    }

    [[noreturn]] static void fail(const std::string &name, const double value, const std::string &range)
    {
      throw std::invalid_argument("GarzoDufty1999: parameter " + name + " = " + str(value) +
                                  " is outside the allowed range " + range);
    }

    PairCorrelationTorquato chi_;
    double                  a_           = 1.;
    double                  T_floor_     = 0.;
    ZetaUMode               zeta_u_mode_ = ZetaUMode::off;
    double                  friction_mu_ = 0., e_eff_ = 1., cooling_fac_ = 0.; ///< friction (set_friction)
  };
} // namespace granhydro::physics
