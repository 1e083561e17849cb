#pragma once
/**
 * @file garzo_dufty/factors.h
 * The dimensionless Garzó–Dufty (1999) closures of smooth inelastic hard spheres
 * (d = 3, first Sonine approximation with the fourth cumulant c* kept), doc/physics.md
 * 3.2–3.6: the constants that depend on the restitution a alone, computed once, and
 * the formulas in (phi, chi) built from them - each formula once. GarzoDufty1999
 * (garzo_dufty.h) evaluates chi(phi) and calls these; they are its building block
 * and not used on their own.
 *
 * Header only, standard library only, no virtual functions; the formulas are
 * templated on the number type (double, or a GCC vector of doubles whose lanes are
 * independent states, physics/lanes.h).
 */
#include <granhydro/physics/garzo_dufty/coefficients.h>
#include <granhydro/physics/lanes.h>

namespace granhydro::physics
{
  /**
   * The restitution-only constants of GD99 (doc/physics.md 3.2–3.6) and the
   * dimensionless formulas at a given chi (and dchi/dphi): Z_, gamma_, eta_k_, eta_,
   * kappa_k_, kappa_, mu_k_, mu_ and zeta_U_ are the formulas of GarzoDufty1999's
   * functions of the same name without the underscore, where they are documented.
   */
  class GarzoDuftyFactors
  {
  protected:
    static constexpr double pi_ = 3.14159265358979323846264338327950288;

    /// c*(a) = 32 (1 - a)(1 - 2a^2)/[81 - 17a + 30 a^2 (1 - a)], doc/physics.md 3.2
    static double fourth_cumulant(const double a)
    {
      return 32. * (1. - a) * (1. - 2. * (a * a)) / (81. - 17. * a + 30. * (a * a) * (1. - a)) + 0.;
    }

    /// zeta*/chi = (5/12)(1 - e^2)(1 + 3c*/32), doc/physics.md 3.3
    static double cooling_factor(const double e, const double cs)
    {
      return 5. / 12. * (1. - e * e) * (1. + 3. * cs / 32.);
    }

    /// the constants for restitution a (0.5 <= a <= 1, checked by the caller)
    void set_factors(const double a)
    {
      c_star_        = fourth_cumulant(a);
      const double cs = c_star_;
      two_1pa_       = 2. * (1. + a);
      // doc/physics.md 3.3
      zeta_fac_   = cooling_factor(a, cs);
      nu_eta_fac_ = (1. - 0.25 * (1. - a) * (1. - a)) * (1. - cs / 64.);
      nu_kap_fac_ = (1. + a) / 3. * (1. + 33. / 16. * (1. - a) + (19. - 3. * a) / 1024. * cs);
      // doc/physics.md 3.4
      gamma_fac_     = 128. / (5. * pi_) * (1. + a) * (1. - cs / 32.);
      eta_num_fac_   = 0.4 * (1. + a) * (1. - 3. * a);
      eta_den_fac_   = nu_eta_fac_ - 0.5 * zeta_fac_;
      eta_tr_fac_    = 0.8 * (1. + a);
      kap_num0_      = 1. + cs;
      kap_num1_      = 0.6 * (1. + a) * (1. + a) * (2. * a - 1. + 0.5 * (1. + a) * cs);
      kap_den_fac_   = nu_kap_fac_ - 2. * zeta_fac_;
      kap_tr_fac_    = 1.2 * (1. + a);
      kap_coll_fac_  = 256. / (25. * pi_) * (1. + a) * (1. + 7. / 32. * cs);
      mu_c_fac_      = cs / 3.;
      mu_tr_num_fac_ = 0.8 * (1. + a) * (a * (1. - a) - cs / 12. * (16. - 3. * a + 3. * a * a));
      mu_den_fac_    = nu_kap_fac_ - 1.5 * zeta_fac_;
      // doc/physics.md 3.6 (MFIX GD_99 form of zeta_U)
      zu_lead_fac_ = -(1. - a) * two_1pa_;
      const double nu_gam_fac =
        (1. + a) / 48. *
        (128. - 96. * a + 15. * a * a - 15. * a * a * a +
         cs / 64. * (15. * a * a * a - 15. * a * a + 498. * a - 434.));
      const double lam = 3. / 8. *
                         ((1. - a) * (5. * a * a + 4. * a - 1.) +
                          cs / 12. * (159. * a + 3. * a * a - 19. * a - 15. * a * a * a)) *
                         (1. + a);
      zu_cd_num1_ = 4. / 15. * lam;
      zu_cd_num2_ = (2. / 3. - a) * cs;
      zu_cd_den_  = 0.5 * zeta_fac_ + nu_gam_fac + 5. * cs / 64. * (1. + 3. * cs / 64.) * (1. - a * a);
      zu_corr_fac_ = 5. / 32. * (1. - a * a) * (1. + 3. * cs / 64.);
    }

    /// dZ/dphi = 2(1 + a)(chi + phi dchi/dphi), doc/physics.md 1.1
    template <typename Number>
    __attribute__((always_inline)) inline Number dZ_(const Number phi, const Number c, const Number dc) const
    {
      return lanes::constant<Number>(two_1pa_) * (c + phi * dc);
    }

    template <typename Number>
    __attribute__((always_inline)) inline Number Z_(const Number phi, const Number c) const
    {
      return lanes::constant<Number>(1.) + lanes::constant<Number>(two_1pa_) * phi * c;
    }

    template <typename Number>
    Number gamma_(const Number phi, const Number c) const
    {
      return lanes::constant<Number>(gamma_fac_) * phi * phi * c;
    }

    template <typename Number>
    Number eta_k_(const Number phi, const Number c) const
    {
      return (lanes::constant<Number>(1.) - lanes::constant<Number>(eta_num_fac_) * phi * c) / (lanes::constant<Number>(eta_den_fac_) * c);
    }

    template <typename Number>
    Number eta_(const Number phi, const Number c, const Number eta_k) const
    {
      return eta_(phi, c, eta_k, gamma_(phi, c));
    }

    template <typename Number>
    Number eta_(const Number phi, const Number c, const Number eta_k, const Number gamma_s) const
    {
      return eta_k * (lanes::constant<Number>(1.) + lanes::constant<Number>(eta_tr_fac_) * phi * c) + lanes::constant<Number>(0.6) * gamma_s;
    }

    template <typename Number>
    Number kappa_k_(const Number phi, const Number c) const
    {
      return lanes::constant<Number>(2. / 3.) * (lanes::constant<Number>(kap_num0_) + lanes::constant<Number>(kap_num1_) * phi * c) /
             (lanes::constant<Number>(kap_den_fac_) * c);
    }

    template <typename Number>
    Number kappa_(const Number phi, const Number c, const Number kappa_k) const
    {
      return kappa_k * (lanes::constant<Number>(1.) + lanes::constant<Number>(kap_tr_fac_) * phi * c) +
             lanes::constant<Number>(kap_coll_fac_) * phi * phi * c;
    }

    template <typename Number>
    Number mu_k_(const Number phi, const Number c, const Number dc, const Number kappa_k) const
    {
      const Number g = phi * dc / c; // phi d ln chi / d phi (doc/physics.md 3.9, D1)
      return ((lanes::constant<Number>(1.) + g) * lanes::constant<Number>(zeta_fac_) * c * kappa_k + lanes::constant<Number>(mu_c_fac_) -
              lanes::constant<Number>(mu_tr_num_fac_) * phi * c * (lanes::constant<Number>(1.) + lanes::constant<Number>(0.5) * g)) /
             (lanes::constant<Number>(mu_den_fac_) * c);
    }

    template <typename Number>
    Number mu_(const Number phi, const Number c, const Number mu_k) const
    {
      return mu_k * (lanes::constant<Number>(1.) + lanes::constant<Number>(kap_tr_fac_) * phi * c);
    }

    template <typename Number>
    Number zeta_U_(const Number phi, const Number c, const ZetaUMode mode) const
    {
      const Number lead = lanes::constant<Number>(zu_lead_fac_) * phi * c; // -(1 - a)(Z - 1)
      if (mode != ZetaUMode::full)
        return lead;
      const Number Zm1 = lanes::constant<Number>(two_1pa_) * phi * c;       // Z - 1
      const Number c_D = (lanes::constant<Number>(zu_cd_num1_) * phi * c + Zm1 * lanes::constant<Number>(zu_cd_num2_)) /
                         (lanes::constant<Number>(zu_cd_den_) * c);
      return lead + lanes::constant<Number>(zu_corr_fac_) * c * c_D;
    }

    // a-only constants, set in set_factors()
    double c_star_ = 0., two_1pa_ = 0.;
    double zeta_fac_ = 0., nu_eta_fac_ = 0., nu_kap_fac_ = 0.;
    double gamma_fac_ = 0., eta_num_fac_ = 0., eta_den_fac_ = 0., eta_tr_fac_ = 0.;
    double kap_num0_ = 0., kap_num1_ = 0., kap_den_fac_ = 0., kap_tr_fac_ = 0., kap_coll_fac_ = 0.;
    double mu_c_fac_ = 0., mu_tr_num_fac_ = 0., mu_den_fac_ = 0.;
    double zu_lead_fac_ = 0., zu_cd_num1_ = 0., zu_cd_num2_ = 0., zu_cd_den_ = 0., zu_corr_fac_ = 0.;
  };
} // namespace granhydro::physics
