#pragma once
/**
 * @file butcher_tables.h
 * The named time-integration methods of the diffusive step and their coefficients:
 * the Butcher tables of the implicit Runge-Kutta methods, the stage coefficients and
 * stage count of RKL2 super-time-stepping, and the cost model's price of an SDIRK2
 * step (ImplicitIntegrator, implicit_integrator.h, describes the methods).
 * Butcher tables (doc/physics.md P13; the paper's 5.14/5.15 are garbled):
 *   Gauss-Legendre 2: c = 1/2 -+ sqrt(3)/6, A = [[1/4, 1/4 - sqrt(3)/6], [1/4 + sqrt(3)/6, 1/4]], b = (1/2, 1/2)
 *   implicit midpoint: c = 1/2, A = [[1/2]], b = 1
 *   SDIRK2 (Alexander 1977; Hairer & Wanner II, IV.6): g = 1 - 1/sqrt(2),
 *     c = (g, 1), A = [[g, 0], [1 - g, g]], b = (1 - g, g): order 2, L-stable and
 *     stiffly accurate (U1 is the last stage value)
 */
#include <granhydro/base/enum_names.h>

#include <array>
#include <vector>

namespace granhydro::diffusion
{
  enum class ImplicitMethod
  {
    gauss_legendre,
    implicit_midpoint,
    sdirk2,
    rkl2,
    cost_based,
    automatic,
    explicit_euler
  };
  /// Diffusion step/Integrator
  constexpr auto enum_names(ImplicitMethod)
  {
    return enum_table(EnumName{ImplicitMethod::gauss_legendre, "gauss-legendre"},
                      EnumName{ImplicitMethod::implicit_midpoint, "implicit midpoint"},
                      EnumName{ImplicitMethod::sdirk2, "sdirk2"}, EnumName{ImplicitMethod::rkl2, "rkl2"},
                      EnumName{ImplicitMethod::cost_based, "cost-based"},
                      EnumName{ImplicitMethod::automatic, "automatic"},
                      EnumName{ImplicitMethod::explicit_euler, "explicit euler"});
  }
  static_assert(check_enum_names(enum_names(ImplicitMethod{})));

  /// Butcher table (A, b, c = row sums of A) of the implicit Runge-Kutta methods above
  struct ButcherTableau
  {
    std::vector<std::vector<double>> A;
    std::vector<double>              b, c;
  };
  /// gauss_legendre, implicit_midpoint or sdirk2 (throws for the others)
  ButcherTableau butcher_tableau(const ImplicitMethod method);

  /// RKL2 stage j (2 <= j <= s) of s: Y_j = mu Y_j-1 + nu Y_j-2 + (1 - mu - nu) Y_0
  /// + mu_tilde dt f(Y_j-1) + gamma_tilde dt f(Y_0); j = 1 gives Y_1 = Y_0 + mu_tilde dt f(Y_0)
  /// (mu = 1, nu = gamma_tilde = 0). Meyer, Balsara & Aslam 2014, eq. 16-17.
  struct RKL2Stage
  {
    double mu, nu, mu_tilde, gamma_tilde;
  };
  RKL2Stage rkl2_stage(const unsigned int j, const unsigned int s);

  /// the fewest RKL2 stages (>= 2) stable for dt = ratio x the forward-Euler limit:
  /// ratio <= (s^2 + s - 2) / 4
  unsigned int rkl2_stages(const double ratio);
  /// the cost model's price of one SDIRK2 step in evaluations of f, for NC unknowns per
  /// cell: the finite-difference Jacobian (2 NC + 1 face-flux sweeps), the preconditioner
  /// set-up, 12 Newton iterations (two stages; 12.3-14.3 per step measured on the three
  /// stiff benchmark scenes) of one f and GMRES each, and 3 for the final slopes.
  /// Calibrated on bouncing_bed-ci, 1 rank: block ILU(0) 2 for the set-up and 1 per Newton
  /// iteration for GMRES (1.3 ms and 0.9 ms against 0.84 ms per f); Trilinos' Ifpack ILU 15
  /// and 2.5. A constant, so that the choice depends on dt and the explicit limit alone.
  inline double sdirk2_cost(const double NC, const bool block_ilu)
  {
    return 2 * NC + 1 + (block_ilu ? 2. : 15.) + 12 * (1 + (block_ilu ? 1. : 2.5)) + 3;
  }
} // namespace granhydro::diffusion
