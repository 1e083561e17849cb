// Standalone self-test of tests/exact_riemann.h (no test framework).
// Build & run:  g++ -std=c++17 -O2 -Wall -Wextra -o /tmp/ers tests/unit/exact_riemann_selftest.cc && /tmp/ers
// Reference values: Toro, "Riemann Solvers and Numerical Methods for Fluid
// Dynamics", Tables 4.2/4.3 (gamma = 1.4); gamma = 5/3 Sod values as given.
// Returns 0 on success; prints every failed check to stderr and returns 1.
#include "common/exact_riemann.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

using granhydro::testing::ExactRiemannSolver;
using granhydro::testing::Primitive;

namespace
{
  int n_fail = 0;

  // |got - expected| <= tol * |expected| (tol_is_abs: <= tol).
  void check(const std::string &name, double got, double expected, double tol, bool tol_is_abs = false)
  {
    const double err = std::abs(got - expected);
    const double rel = expected != 0.0 ? err / std::abs(expected) : err;
    const bool   ok  = tol_is_abs ? err <= tol : rel <= tol;
    std::printf("%-4s %-44s got %.10g  expected %.10g  abs err %.2e  rel err %.2e\n", ok ? "ok" : "FAIL",
                name.c_str(), got, expected, err, rel);
    if (!ok)
      {
        std::fprintf(stderr, "FAILED: %s: got %.12g, expected %.12g (tol %.1e)\n", name.c_str(), got,
                     expected, tol);
        ++n_fail;
      }
  }

  void check_true(const std::string &name, bool cond)
  {
    std::printf("%-4s %s\n", cond ? "ok" : "FAIL", name.c_str());
    if (!cond)
      {
        std::fprintf(stderr, "FAILED: %s\n", name.c_str());
        ++n_fail;
      }
  }

  // Conservative variables and Euler flux of a primitive state.
  std::array<double, 3> cons(const Primitive &w, double g)
  {
    return {w.rho, w.rho * w.u, w.p / (g - 1.0) + 0.5 * w.rho * w.u * w.u};
  }
  std::array<double, 3> flux(const Primitive &w, double g)
  {
    const double E = cons(w, g)[2];
    return {w.rho * w.u, w.rho * w.u * w.u + w.p, w.u * (E + w.p)};
  }

  // Integral conservation on [-X, X] (x0 = 0) while no wave has reached +-X:
  // int U(x,t) dx = X (U_L + U_R) + t (F(U_L) - F(U_R)).  Exact identity, so the
  // only error is quadrature error (wave-aligned splitting makes it ~round-off);
  // tol is absolute for |exact| <= 1, relative otherwise.
  void check_conservation(const std::string &name, const Primitive &L, const Primitive &R, double g, double X,
                          double t, unsigned n_sub, double tol)
  {
    const ExactRiemannSolver rs(L, R, g);
    const auto               avg = rs.cell_average_conserved(-X, X, 0.0, t, n_sub);
    const auto               UL = cons(L, g), UR = cons(R, g), FL = flux(L, g), FR = flux(R, g);
    const char              *var[3] = {"mass", "momentum", "energy"};
    for (int k = 0; k < 3; ++k)
      {
        const double exact = (X * (UL[k] + UR[k]) + t * (FL[k] - FR[k])) / (2.0 * X);
        check(name + ": avg " + var[k], avg[k], exact, tol * std::max(1.0, std::abs(exact)), true);
      }
  }

  template <class F>
  void check_throws(const std::string &name, F &&f)
  {
    bool thrown = false;
    try
      {
        f();
      }
    catch (const std::runtime_error &e)
      {
        thrown = true;
        std::printf("     (message: %s)\n", e.what());
      }
    check_true(name + " throws std::runtime_error", thrown);
  }
} // namespace

int main()
{
  try
    {
      // 1. Sod, gamma = 1.4 (Toro Table 4.3, test 1): 5 printed digits.
      {
        const ExactRiemannSolver rs({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4);
        check("Sod 1.4: p*", rs.p_star(), 0.30313, 2e-5);
        check("Sod 1.4: u*", rs.u_star(), 0.92745, 2e-5);
        check("Sod 1.4: rho*L", rs.rho_star_left(), 0.42632, 2e-5);
        check("Sod 1.4: rho*R", rs.rho_star_right(), 0.26557, 2e-5);
        check_true("Sod 1.4: no vacuum", !rs.vacuum());
      }
      // 2. Sod, gamma = 5/3: 6 printed digits, plus wave positions by sampling.
      {
        const ExactRiemannSolver rs({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 5.0 / 3.0);
        check("Sod 5/3: p*", rs.p_star(), 0.293945, 2e-6);
        check("Sod 5/3: u*", rs.u_star(), 0.841195, 2e-6);
        check("Sod 5/3: rho*L", rs.rho_star_left(), 0.479689, 2e-6);
        check("Sod 5/3: rho*R", rs.rho_star_right(), 0.229806, 2e-6);
        const double eps = 1e-6, sS = 1.844473, sH = -1.290994, sT = -0.169401, sC = 0.841195;
        // Shock: star state behind, undisturbed state ahead.
        check("Sod 5/3: rho left of shock", rs.sample(sS - eps).rho, rs.rho_star_right(), 0.0, true);
        check("Sod 5/3: rho right of shock", rs.sample(sS + eps).rho, 0.125, 0.0, true);
        // Fan head: undisturbed left state before it, fan (u > 0, rho -> 1) after it.
        check("Sod 5/3: rho left of fan head", rs.sample(sH - eps).rho, 1.0, 0.0, true);
        check_true("Sod 5/3: inside fan right of head (u > 0)", rs.sample(sH + eps).u > 0.0);
        check("Sod 5/3: rho right of fan head (continuity)", rs.sample(sH + eps).rho, 1.0, 1e-5, true);
        // Fan tail: fan before it (rho -> rho*L), star state after it.
        check_true("Sod 5/3: inside fan left of tail", rs.sample(sT - eps).rho > rs.rho_star_left());
        check("Sod 5/3: rho left of fan tail (continuity)", rs.sample(sT - eps).rho, rs.rho_star_left(), 1e-5,
              true);
        check("Sod 5/3: rho right of fan tail", rs.sample(sT + eps).rho, rs.rho_star_left(), 0.0, true);
        // Contact: density jumps, pressure and velocity continuous.
        check("Sod 5/3: rho left of contact", rs.sample(sC - eps).rho, rs.rho_star_left(), 0.0, true);
        check("Sod 5/3: rho right of contact", rs.sample(sC + eps).rho, rs.rho_star_right(), 0.0, true);
        check("Sod 5/3: p at contact", rs.sample(sC + eps).p, rs.p_star(), 0.0, true);
      }
      // 3. Toro test 2, "123 problem": two strong rarefactions, p* = 0.00189 (3 digits).
      {
        const ExactRiemannSolver rs({1.0, -2.0, 0.4}, {1.0, 2.0, 0.4}, 1.4);
        check("123: p*", rs.p_star(), 0.00189, 0.5e-5 / 0.00189 * 1.01);
        check("123: u* (= 0 by symmetry)", rs.u_star(), 0.0, 1e-12, true);
        check_true("123: no vacuum", !rs.vacuum());
      }
      // 4. Toro test 3: left half of the Woodward-Colella blast wave (strong right shock).
      {
        const ExactRiemannSolver rs({1.0, 0.0, 1000.0}, {1.0, 0.0, 0.01}, 1.4);
        check("Toro 3: p*", rs.p_star(), 460.894, 2e-6);
        check("Toro 3: u*", rs.u_star(), 19.5975, 3e-6);
        check("Toro 3: rho*L", rs.rho_star_left(), 0.57506, 1e-5);
        check("Toro 3: rho*R", rs.rho_star_right(), 5.99924, 2e-6);
      }
      // 5. Vacuum generation: 2/(gamma-1)(cL+cR) = 7.48 <= uR - uL = 8.
      {
        const ExactRiemannSolver rs({1.0, -4.0, 0.4}, {1.0, 4.0, 0.4}, 1.4);
        check_true("vacuum: vacuum() is true", rs.vacuum());
        check_true("vacuum: sample(0).rho == 0 and p == 0",
                   rs.sample(0.0).rho == 0.0 && rs.sample(0.0).p == 0.0);
        check_true("vacuum: far field untouched", rs.sample(-10.0).rho == 1.0 && rs.sample(10.0).u == 4.0);
      }
      // 5b. Near vacuum (just below the vacuum threshold 7.483): tiny p* > 0 from
      //     the exact two-rarefaction formula; Newton round-off regression case
      //     (residual stagnates at 1e-15 because of cancellation in fL + fR + du).
      {
        const ExactRiemannSolver rs({1.0, -3.7, 0.4}, {1.0, 3.7, 0.4}, 1.4);
        check_true("near vacuum: no vacuum, 0 < p* < 1e-12",
                   !rs.vacuum() && rs.p_star() > 0.0 && rs.p_star() < 1e-12);
        check("near vacuum: u*", rs.u_star(), 0.0, 1e-12, true);
        const ExactRiemannSolver rr({0x1.76d16837bede8p+4, -0x1.116ec7e61c4b9p+4, 0x1.95a6c90a38b49p-8},
                                    {0x1.f3a0c5480014ep+4, -0x1.045cf69a1267p+3, 0x1.fbee46aa64f4ep+8},
                                    0x1.2c7409fb2ffe6p+1);
        check_true("Newton round-off stagnation case converges", rr.p_star() > 0.0);
      }
      // 6. Cell averages: uniform state, and exact integral conservation laws.
      {
        const Primitive          w{0.7, -0.3, 2.5};
        const ExactRiemannSolver rs(w, w, 1.4);
        const auto               avg = rs.cell_average_conserved(-0.37, 0.81, 0.1, 0.2, 7);
        const auto               U   = cons(w, 1.4);
        check("uniform: avg rho", avg[0], U[0], 1e-14);
        check("uniform: avg rho u", avg[1], U[1], 1e-14);
        check("uniform: avg E", avg[2], U[2], 1e-14);
        // Sod over [-1, 1], t = 0.1: mean rho = (1 + 0.125)/2, momentum gains
        // t (pL - pR), energy unchanged (zero energy flux at untouched ends).
        check_conservation("Sod 1.4", {1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4, 1.0, 0.1, 64, 1e-12);
        check_conservation("Sod 1.4 (n_sub=1)", {1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4, 1.0, 0.1, 1, 1e-12);
        check_conservation("Sod 5/3", {1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 5.0 / 3.0, 1.0, 0.1, 64, 1e-12);
        check_conservation("123", {1.0, -2.0, 0.4}, {1.0, 2.0, 0.4}, 1.4, 1.0, 0.1, 64, 1e-12);
        check_conservation("Toro 3", {1.0, 0.0, 1000.0}, {1.0, 0.0, 0.01}, 1.4, 1.0, 0.012, 64, 1e-12);
        check_conservation("vacuum", {1.0, -4.0, 0.4}, {1.0, 4.0, 0.4}, 1.4, 2.0, 0.1, 64, 1e-12);
        check_conservation("vacuum gamma=1.2", {1.0, -4.0, 0.4}, {0.5, 25.0, 0.4}, 1.2, 5.0, 0.1, 64, 1e-12);
        check_conservation("near vacuum", {1.0, -3.7, 0.4}, {1.0, 3.7, 0.4}, 1.4, 2.0, 0.1, 64, 1e-12);
        check_conservation("gamma=1.05 shock+fan", {3.0, 1.0, 5.0}, {0.2, -2.0, 0.01}, 1.05, 1.0, 0.02, 64,
                           1e-12);
      }
      // 7. Invalid input.
      check_throws("rho <= 0", [] { ExactRiemannSolver({0.0, 0.0, 1.0}, {1.0, 0.0, 1.0}, 1.4); });
      check_throws("p <= 0", [] { ExactRiemannSolver({1.0, 0.0, 1.0}, {1.0, 0.0, -1.0}, 1.4); });
      check_throws("gamma <= 1", [] { ExactRiemannSolver({1.0, 0.0, 1.0}, {1.0, 0.0, 1.0}, 1.0); });
    }
  catch (const std::exception &e)
    {
      std::fprintf(stderr, "FAILED: unexpected exception: %s\n", e.what());
      return 1;
    }
  if (n_fail > 0)
    {
      std::fprintf(stderr, "%d check(s) FAILED\n", n_fail);
      return 1;
    }
  std::printf("all checks passed\n");
  return 0;
}
