// unit.integrators: the coefficients of the diffusion-step integrators, checked as
// numbers against their defining properties (Hairer & Wanner, Solving ODEs II,
// IV.3 and IV.6; Meyer, Balsara & Aslam 2014 for RKL2):
//  - Butcher tables (Gauss-Legendre 2, implicit midpoint, SDIRK2): c = row sums of A;
//    every order condition up to the claimed order holds to 1e-15 (exact rationals,
//    round-off of sqrt(3), sqrt(2)), and the first condition of the next order fails
//    (so the claimed order is the order, not a lower bound);
//  - stability function R(z) = 1 + z b^T (I - z A)^-1 1: |R(iy)| <= 1 + 1e-14 on the
//    imaginary axis (A-stability, sampled) and R(-1e8): ~0 for SDIRK2 (L-stable), ~1
//    for Gauss-Legendre, ~-1 for midpoint (both only A-stable);
//  - RKL2: on y' = lambda y the s-stage recurrence is stable (|R| <= 1) over the
//    whole interval lambda dt in [-(s^2 + s - 2)/2, 0] (sampled; the step bound
//    dt <= dt_FE (s^2 + s - 2)/4 with the forward-Euler limit dt_FE = 2/|lambda|), and
//    unstable just beyond it (|R| > 1 at 1.01 times the end), is second order
//    (error vs exp(lambda dt) falls 8x when lambda dt halves, within 2 %), and the
//    stage count is the fewest that is stable.
#include <granhydro/diffusion/implicit_integrator.h>

#include "common/test_common.h"

#include <complex>
#include <iomanip>

using namespace granhydro;
using namespace granhydro::diffusion;
using granhydro::testing::Checker;
using cplx = std::complex<double>;

namespace
{
  // R(z) = 1 + z b^T (I - z A)^-1 1 for 1 or 2 stages (closed-form inverse)
  cplx stability(const ButcherTableau &t, const cplx z)
  {
    if (t.b.size() == 1)
      return 1. + z * t.b[0] / (1. - z * t.A[0][0]);
    const cplx m00 = 1. - z * t.A[0][0], m01 = -z * t.A[0][1], m10 = -z * t.A[1][0], m11 = 1. - z * t.A[1][1];
    const cplx det = m00 * m11 - m01 * m10;
    const cplx x0 = (m11 - m01) / det, x1 = (m00 - m10) / det; // (I - zA)^-1 (1, 1)
    return 1. + z * (t.b[0] * x0 + t.b[1] * x1);
  }

  // order conditions (trees up to order 4): residuals of sum b = 1, sum b c = 1/2, ...
  std::vector<std::vector<double>> order_conditions(const ButcherTableau &t)
  {
    const auto   s = t.b.size();
    auto         Av = [&](const std::vector<double> &v) {
      std::vector<double> r(s, 0.);
      for (std::size_t i = 0; i < s; ++i)
        for (std::size_t j = 0; j < s; ++j)
          r[i] += t.A[i][j] * v[j];
      return r;
    };
    auto bdot = [&](const std::vector<double> &v) {
      double r = 0;
      for (std::size_t i = 0; i < s; ++i)
        r += t.b[i] * v[i];
      return r;
    };
    auto pw = [&](const int k) {
      std::vector<double> r(s);
      for (std::size_t i = 0; i < s; ++i)
        r[i] = std::pow(t.c[i], k);
      return r;
    };
    std::vector<double> one(s, 1.), cAc(s);
    const auto          Ac = Av(t.c);
    for (std::size_t i = 0; i < s; ++i)
      cAc[i] = t.c[i] * Ac[i];
    return {{bdot(one) - 1},
            {bdot(t.c) - 0.5},
            {bdot(pw(2)) - 1. / 3, bdot(Ac) - 1. / 6},
            {bdot(pw(3)) - 0.25, bdot(cAc) - 1. / 8, bdot(Av(pw(2))) - 1. / 12, bdot(Av(Ac)) - 1. / 24},
            {bdot(pw(4)) - 0.2}};
  }
} // namespace

int main()
{
  Checker chk;
  struct Case
  {
    ImplicitMethod method;
    std::string    name;
    unsigned int   order;
    double         r_inf; // R(-infinity)
  };
  for (const Case &c : {Case{ImplicitMethod::gauss_legendre, "Gauss-Legendre 2", 4, 1.},
                        Case{ImplicitMethod::implicit_midpoint, "implicit midpoint", 2, -1.},
                        Case{ImplicitMethod::sdirk2, "SDIRK2", 2, 0.}})
    {
      const auto t = butcher_tableau(c.method);
      double     rowsum = 0;
      for (std::size_t i = 0; i < t.c.size(); ++i)
        {
          double r = 0;
          for (const double a : t.A[i])
            r += a;
          rowsum = std::max(rowsum, std::abs(r - t.c[i]));
        }
      const auto cond = order_conditions(t);
      double     worst = 0, next = 0;
      for (unsigned int q = 0; q < c.order; ++q)
        for (const double r : cond[q])
          worst = std::max(worst, std::abs(r));
      for (const double r : cond[c.order])
        next = std::max(next, std::abs(r));
      std::ostringstream os;
      os << c.name << ": order conditions 1.." << c.order << " hold to " << std::scientific
         << std::setprecision(1) << worst << ", order " << c.order + 1 << " misses by " << next;
      chk.check(rowsum <= 1e-15 && worst <= 1e-15 && next >= 1e-3, os.str());

      double maxabs = 0;
      for (double y = 1e-3; y < 1e6; y *= 1.3)
        maxabs = std::max(maxabs, std::abs(stability(t, cplx(0, y))));
      const cplx rinf = stability(t, -1e8);
      std::ostringstream os2;
      os2 << c.name << ": max |R(iy)| = " << std::setprecision(16) << maxabs << ", R(-1e8) = "
          << std::setprecision(3) << rinf.real();
      chk.check(maxabs <= 1 + 1e-14 && std::abs(rinf - c.r_inf) <= 1e-6, os2.str());
    }

  // RKL2 on the scalar test equation
  auto rkl2 = [](const unsigned int s, const double z) { // amplification of one step, z = lambda dt
    const auto st1 = rkl2_stage(1, s);
    double     y0 = 1, ym2 = 1, ym1 = 1 + st1.mu_tilde * z;
    for (unsigned int j = 2; j <= s; ++j)
      {
        const auto   st = rkl2_stage(j, s);
        const double y  = st.mu * ym1 + st.nu * ym2 + (1 - st.mu - st.nu) * y0 + st.mu_tilde * z * ym1 +
                         st.gamma_tilde * z * y0;
        ym2 = ym1;
        ym1 = y;
      }
    return ym1;
  };
  for (const unsigned int s : {2u, 3u, 5u, 10u, 40u})
    {
      // the stage count's bound in units of the forward-Euler limit (rkl2_stages' ratio)...
      const double zmax = (double(s) * s + s - 2) / 4;
      // ...and in lambda dt: twice that (forward Euler is stable for lambda dt >= -2)
      const double beta  = 2 * zmax;
      double       worst = 0;
      for (unsigned int k = 0; k <= 20000; ++k)
        worst = std::max(worst, std::abs(rkl2(s, -beta * k / 20000.)));
      const double beyond = std::abs(rkl2(s, -1.01 * beta));
      // second order: local error ~ C z^3
      const double e1 = std::abs(rkl2(s, -0.02) - std::exp(-0.02)), e2 = std::abs(rkl2(s, -0.01) - std::exp(-0.01));
      const double ratio = e1 / e2;
      const unsigned int fewest = rkl2_stages(zmax), fewer = rkl2_stages(zmax * 1.001);
      std::ostringstream os;
      os << "RKL2 s = " << s << ": max |R| over [-" << beta << ", 0] = " << std::setprecision(15) << worst
         << ", |R| at 1.01 x the end " << beyond
         << ", local error ratio " << std::setprecision(4) << ratio << " (8 for order 2), stages for ratio "
         << zmax << ": " << fewest << ", just above: " << fewer;
      // 1e-12: the recurrence's round-off (measured 5e-15 at s = 40); beyond the interval
      // |R| exceeds 1 except for s = 3, 5 (whose polynomials stay small just past the end)
      chk.check(worst <= 1 + 1e-12 && (s == 3 || s == 5 || beyond > 1) && std::abs(ratio / 8 - 1) < 0.02 &&
                  fewest == s && fewer == s + 1,
                os.str());
    }
  return chk.failed != 0;
}
