#pragma once
/**
 * @file garzo_dufty/coefficients.h
 * What the Garzó–Dufty (1999) constitutive model (garzo_dufty.h) gives: its
 * modes (first-order cooling zeta_U, density at contact of the dissipative-wall heat
 * flux) and the records of its dimensionless factors and of its dimensional
 * coefficients at one state, with the doc/physics.md section of each value.
 * Templated on the number type: double, or a GCC vector of doubles (physics/lanes.h).
 */
namespace granhydro::physics
{
  /// First-order cooling coefficient zeta_U (doc/physics.md 3.6); off by default.
  enum class ZetaUMode
  {
    off,     ///< zeta = zeta0 (the paper's source term; default)
    leading, ///< zeta_U = -(1 - eps)(Z - 1) = -2 (1 - eps^2) phi chi
    full     ///< leading term + the c_D correction as coded in MFIX GD_99
  };

  /// Density at contact used in the dissipative-wall heat flux (doc/physics.md 5.2).
  enum class WallHeatFluxModel
  {
    contact_theorem, ///< n_c = 2 p_w/((1 + eps_w) T): q_w = (1 - eps_w) p_w sqrt(2T/(pi m)) (default)
    dilute,          ///< n_c = n
    n_chi            ///< n_c = n chi (Enskog-style)
  };

  /**
   * All dimensionless GD99 factors at one packing fraction (doc/physics.md
   * 3.2–3.6), filled by GarzoDufty1999::dimensionless() with a single chi
   * evaluation. Dimensional values: eta = eta0 eta_star, gamma = eta0
   * gamma_star, kappa = kappa0 kappa_star, mu = (T kappa0/n) mu_star,
   * zeta0 = nu0 zeta_star (doc/physics.md 3.4).
   */
  template <typename Number>
  struct DimensionlessCoefficientsT
  {
    Number phi;           ///< packing fraction the values belong to
    Number chi;           ///< pair correlation at contact (doc/physics.md 2)
    Number dchi_dphi;     ///< dchi/dphi
    Number g;             ///< phi d ln chi/d phi (doc/physics.md 3.4)
    Number c_star;        ///< fourth cumulant c*(eps) (3.2)
    Number Z;             ///< p* = p/(n T) (2)
    Number dZ_dphi;       ///< dZ/dphi (1.1)
    Number zeta_star;     ///< zeroth-order cooling rate / nu0 (3.3)
    Number nu_eta_star;   ///< (3.3)
    Number nu_kappa_star; ///< (3.3), equal to nu_mu*
    Number eta_k_star;    ///< kinetic part of eta* (3.4)
    Number eta_star;      ///< eta / eta0 (3.4)
    Number gamma_star;    ///< gamma / eta0 (3.4)
    Number kappa_k_star;  ///< kinetic part of kappa* (3.4)
    Number kappa_star;    ///< kappa / kappa0 (3.4)
    Number mu_k_star;     ///< kinetic part of mu* (3.4)
    Number mu_star;       ///< mu n/(T kappa0) (3.4)
    Number zeta_U;        ///< first-order cooling coefficient in the object's ZetaUMode (3.6)
  };

  using DimensionlessCoefficients = DimensionlessCoefficientsT<double>;

  /// Dimensional values at one state (n, T), see GarzoDufty1999::transport().
  template <typename Number>
  struct TransportCoefficientsT
  {
    Number p;      ///< pressure n T Z                       [Pa]
    Number c;      ///< sound speed (doc/physics.md 1.1)          [m/s]
    Number eta;    ///< shear viscosity                       [Pa s]
    Number gamma;  ///< bulk viscosity                        [Pa s]
    Number kappa;  ///< thermal conductivity (T-based)        [1/(m s)]
    Number mu;     ///< heat-flux coefficient of grad n       [J m^2/s]
    Number zeta0;  ///< zeroth-order cooling rate             [1/s]
    Number zeta_U; ///< dimensionless, multiplies div u in zeta = zeta0 + zeta_U div u
    DimensionlessCoefficientsT<Number> star; ///< the dimensionless factors used
  };

  using TransportCoefficients = TransportCoefficientsT<double>;
} // namespace granhydro::physics
