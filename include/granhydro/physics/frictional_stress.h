#pragma once
/**
 * @file frictional_stress.h
 * The frictional shear stress of a dense granular pile (the dense closure's 'Frictional
 * stress'), and the invariants of the strain rate it needs. Two laws:
 *
 *  - 'srivastava-sundaresan': Srivastava & Sundaresan, "Analysis of a
 *    frictional-kinetic model for gas-particle flow", Powder Technol. 129, 72 (2003), in
 *    the form MFIX codes as its Princeton friction model. With the critical-state pressure
 *    P_c (here the contact pressure p_f of the closure), the friction angle phi, the
 *    deviatoric strain rate S = D - (div u / 3) I and the grain diameter d,
 *
 *      zeta    = sqrt(S:S + Theta / d^2),  Theta = T/m          (fluctuations regularise)
 *      n       = sqrt(3) / (2 sin phi)  if div u >= 0 (dilation),  1.03 if div u < 0
 *      P_f/P_c = (1 - div u / (n sqrt(2) sin phi zeta))^(n - 1),   0 if the bracket is < 0
 *      mu_f    = sqrt(2) sin phi P_f (n - (n - 1)(P_f/P_c)^(1/(n - 1))) / (2 zeta),  >= 0
 *
 *    The deviatoric stress 2 mu_f S is rate-independent and Coulomb-bounded: in simple
 *    shear (div u = 0) it is P_c sin phi gamma_dot / sqrt(gamma_dot^2 + 2 Theta/d^2) <=
 *    P_c sin phi; in uniaxial dilation at Theta = 0 the bracket is exactly 0 and the stress
 *    vanishes (the choice of n for dilation makes it so).
 *  - 'newtonian' (the scene default, doc/physics.md 4.5 says why): mu_f = t_f sin(phi) P_c (OpenFOAM's JohnsonJackson, t_f = 0.5 s), a
 *    Newtonian viscosity whose stress grows without bound with the strain rate.
 *
 * The Srivastava–Sundaresan viscosity is bounded by the Newtonian law: mu_f <= t_f sin phi
 * P_c, i.e. below strain rates of about 1/(sqrt(2) t_f) a pile at rest whose granular
 * temperature has died out creeps instead of being rigid (a regularisation like MFIX's cap
 * on the solids viscosity, counted in the run summary where it acts). It keeps the
 * diffusion step never stiffer than with the Newtonian law: a larger bound (10 s) made the
 * implicit step's modified Newton iteration, whose Jacobian does not follow mu_f's
 * dependence on the strain rate, fail in a settling pile (140 000 retried steps in a 1D
 * collapse). t_f = 0 switches the frictional stress off in either law. The isotropic part of the model (P_f instead of P_c in the pressure) is not applied: the
 * contact pressure stays the conservative one of the contact potential (doc/physics.md 2.1).
 *
 * Units: any consistent set (the solver's scaled units: m = 1, d = sigma = 1, so
 * Theta / d^2 = T).
 */
#include <granhydro/base/enum_names.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace granhydro::physics
{
  enum class FrictionalLaw
  {
    newtonian,
    srivastava_sundaresan
  };
  /// Dense closure/Frictional stress
  constexpr auto enum_names(FrictionalLaw)
  {
    return enum_table(EnumName{FrictionalLaw::newtonian, "newtonian"},
                      EnumName{FrictionalLaw::srivastava_sundaresan, "srivastava-sundaresan"});
  }
  static_assert(check_enum_names(enum_names(FrictionalLaw{})));

  /// div u and S:S (S the deviatoric strain rate) from grad_u[j][l] = d u_l / d x_j over the
  /// resolved directions (unresolved components and derivatives are zero)
  template <int dim, class Number, class Gradient>
  inline void strain_rate_invariants(const Gradient &grad_u, Number &div, Number &SS)
  {
    div = Number{};
    for (int k = 0; k < dim; ++k)
      div += grad_u[k][k];
    Number DD{}; // D:D, D = (grad u + grad u^T)/2
    for (int j = 0; j < dim; ++j)
      for (int l = 0; l < dim; ++l)
        {
          const Number Djl = 0.5 * (grad_u[j][l] + grad_u[l][j]);
          DD += Djl * Djl;
        }
    SS = DD - div * div / 3.;
  }

  struct FrictionalStress
  {
    FrictionalLaw law     = FrictionalLaw::newtonian;
    double        sin_phi = 0; ///< sine of the friction angle
    double        t_f     = 0; ///< viscosity time (0: no frictional stress)

    static constexpr double n_compression = 1.03;

    bool active() const { return sin_phi > 0 && t_f > 0; }

    double n_dilation() const { return std::sqrt(3.) / (2. * sin_phi); }

    /// the exponent n of Srivastava & Sundaresan: dilation (div u >= 0) or compression
    double exponent(const double div) const { return div >= 0 ? n_dilation() : n_compression; }

    /// P_f / P_c of Srivastava & Sundaresan for div u and zeta = sqrt(S:S + Theta/d^2) > 0
    double pressure_ratio(const double div, const double zeta) const
    {
      const double n = exponent(div);
      const double b = 1. - div / (n * std::sqrt(2.) * sin_phi * zeta);
      return b > 0 ? std::pow(b, n - 1.) : 0.;
    }

    /// mu_f / P_c of Srivastava & Sundaresan, uncapped (theta_d2 = Theta / d^2)
    double srivastava_sundaresan_factor(const double div, const double SS, const double theta_d2) const
    {
      const double zeta = std::sqrt(std::max(SS, 0.) + std::max(theta_d2, 0.));
      if (!(zeta > 0))
        return std::numeric_limits<double>::infinity(); // a pile at rest with T = 0: rigid
      const double n = exponent(div);
      const double r = pressure_ratio(div, zeta);
      const double f =
        std::sqrt(2.) * sin_phi * r * (n - (n - 1.) * std::pow(r, 1. / (n - 1.))) / (2. * zeta);
      return f > 0 ? f : 0.; // compression far beyond the critical state: MFIX sets it to 0
    }

    /**
     * Frictional shear viscosity mu_f for the critical-state (contact) pressure pc, div u,
     * S:S and Theta/d^2. capped (optional) is set when the Srivastava–Sundaresan value was
     * held at its bound t_f sin phi P_c.
     */
    double viscosity(const double pc, const double div, const double SS, const double theta_d2,
                     bool *capped = nullptr) const
    {
      if (capped)
        *capped = false;
      if (!active() || !(pc > 0))
        return 0.;
      if (law == FrictionalLaw::newtonian)
        return t_f * sin_phi * pc;
      const double f = srivastava_sundaresan_factor(div, SS, theta_d2), bound = t_f * sin_phi;
      if (f > bound)
        {
          if (capped)
            *capped = true;
          return bound * pc;
        }
      return f * pc;
    }

    /// the largest mu_f / P_c the law can give: for stiffness bounds
    double max_factor() const { return active() ? t_f * sin_phi : 0.; }
  };
} // namespace granhydro::physics
