/**
 * @file exact_riemann.h
 * Exact Riemann solver for the 1D Euler equations of an ideal (polytropic)
 * gas with adiabatic index gamma > 1, following E. F. Toro, "Riemann Solvers
 * and Numerical Methods for Fluid Dynamics", 3rd ed., Springer 2009, ch. 4:
 * pressure functions f_K(p) (sec. 4.2), Newton iteration for p* (sec. 4.3),
 * wave speeds / star densities (sec. 4.4), sampling of the self-similar solution
 * (sec. 4.5) and the vacuum-generation case (sec. 4.6). Equation references
 * below are to sections, not equation numbers.
 *
 * Purpose: reference solution for verifying granhydro's convective (Euler)
 * solver in the ideal-gas limit (no inelastic cooling, no transport terms).
 * Header-only, standard library only.
 */
#ifndef GRANHYDRO_TESTS_EXACT_RIEMANN_H
#define GRANHYDRO_TESTS_EXACT_RIEMANN_H

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace granhydro::testing {

/// Primitive state: density, velocity, pressure.
struct Primitive { double rho, u, p; };

class ExactRiemannSolver {
public:
  /// Solves the Riemann problem; throws std::runtime_error on invalid input
  /// (rho <= 0, p <= 0, non-finite data, gamma <= 1) or Newton failure.
  ExactRiemannSolver(const Primitive &left, const Primitive &right, double gamma)
      : L_(left), R_(right), g_(gamma) {
    if (!(gamma > 1.0) || !std::isfinite(gamma))
      throw std::runtime_error("ExactRiemannSolver: gamma must be > 1");
    check_state(left, "left");
    check_state(right, "right");
    cL_ = std::sqrt(g_ * L_.p / L_.rho);
    cR_ = std::sqrt(g_ * R_.p / R_.rho);
    // Vacuum generation (Toro sec. 4.6): pressure positivity condition violated.
    if (2.0 / (g_ - 1.0) * (cL_ + cR_) <= R_.u - L_.u) {
      vacuum_ = true;
      p_star_ = rho_sL_ = rho_sR_ = 0.0;
      u_star_ = std::numeric_limits<double>::quiet_NaN(); // undefined
      return;
    }
    solve_p_star();
    u_star_ = 0.5 * (L_.u + R_.u) + 0.5 * (f(p_star_, R_, cR_) - f(p_star_, L_, cL_));
    rho_sL_ = rho_star(L_);
    rho_sR_ = rho_star(R_);
  }

  /// Star-region pressure / velocity (0 and NaN in the vacuum case).
  double p_star() const { return p_star_; }
  double u_star() const { return u_star_; }
  /// Densities left and right of the contact (0 in the vacuum case).
  double rho_star_left() const { return rho_sL_; }
  double rho_star_right() const { return rho_sR_; }
  /// True if the data generate a vacuum between two rarefactions.
  bool vacuum() const { return vacuum_; }

  /// Point value of the self-similar solution at xi = (x - x0)/t (Toro sec. 4.5).
  /// Inside a vacuum, rho = p = 0 and u is set to xi (the continuous extension
  /// of the velocity at both vacuum fronts).
  Primitive sample(double xi) const {
    if (vacuum_) {
      const double sL = L_.u + 2.0 * cL_ / (g_ - 1.0); // left vacuum front
      const double sR = R_.u - 2.0 * cR_ / (g_ - 1.0); // right vacuum front
      if (xi <= sL) return sample_left(xi);
      if (xi >= sR) return sample_right(xi);
      return {0.0, xi, 0.0};
    }
    return xi <= u_star_ ? sample_left(xi) : sample_right(xi);
  }

  /// Averages over [a, b] of (rho, rho u, E = p/(gamma-1) + rho u^2/2) at time
  /// t > 0, initial discontinuity at x0. [a, b] is first split at every wave
  /// position (shocks, contact, fan edges, vacuum fronts), so the solution is
  /// smooth on each piece; constant pieces are integrated exactly, pieces inside
  /// a rarefaction fan by composite 5-point Gauss-Legendre on n_sub uniform
  /// sub-intervals (error ~ round-off for moderate gamma, since the fan profile
  /// is a power 2/(gamma-1) of a linear function of x).
  std::array<double, 3> cell_average_conserved(double a, double b, double x0, double t,
                                               unsigned int n_sub = 64) const {
    if (!(b > a) || !(t > 0.0) || n_sub == 0)
      throw std::runtime_error("ExactRiemannSolver::cell_average_conserved: need b > a, t > 0, n_sub > 0");
    std::vector<double> pts{a, b};
    for (double s : wave_speeds()) {
      const double x = x0 + s * t;
      if (x > a && x < b) pts.push_back(x);
    }
    std::sort(pts.begin(), pts.end());
    // 5-point Gauss-Legendre nodes/weights on [-1, 1].
    static const double xg[5] = {0.0, -0.5384693101056831, 0.5384693101056831,
                                 -0.9061798459386640, 0.9061798459386640};
    static const double wg[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                 0.2369268850561891, 0.2369268850561891};
    std::array<double, 3> sum{{0.0, 0.0, 0.0}};
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      if (!(pts[i + 1] > pts[i])) continue;
      bool fan = false; // is this piece inside a rarefaction fan?
      const double xi_mid = (0.5 * (pts[i] + pts[i + 1]) - x0) / t;
      for (const auto &f : fans()) fan = fan || (xi_mid > f[0] && xi_mid < f[1]);
      const unsigned int n = fan ? n_sub : 1;
      const double h = (pts[i + 1] - pts[i]) / double(n);
      for (unsigned int k = 0; k < n; ++k) {
        const double m = pts[i] + (double(k) + 0.5) * h;
        for (int q = 0; q < 5; ++q) {
          const Primitive w = sample((m + 0.5 * h * xg[q] - x0) / t);
          const double wq = 0.5 * h * wg[q];
          sum[0] += wq * w.rho;
          sum[1] += wq * w.rho * w.u;
          sum[2] += wq * (w.p / (g_ - 1.0) + 0.5 * w.rho * w.u * w.u);
        }
      }
    }
    for (double &s : sum) s /= (b - a);
    return sum;
  }

private:
  static void check_state(const Primitive &s, const char *side) {
    if (!(s.rho > 0.0) || !(s.p > 0.0) || !std::isfinite(s.rho) || !std::isfinite(s.p) ||
        !std::isfinite(s.u)) {
      std::ostringstream os;
      os << "ExactRiemannSolver: invalid " << side << " state (rho=" << s.rho << ", u=" << s.u
         << ", p=" << s.p << "); need finite data with rho > 0 and p > 0";
      throw std::runtime_error(os.str());
    }
  }

  /// Pressure function f_K(p) (Toro sec. 4.2) and its derivative (sec. 4.3).
  double f(double p, const Primitive &K, double cK, double *df = nullptr) const {
    if (p > K.p) { // shock
      const double A = 2.0 / ((g_ + 1.0) * K.rho), B = (g_ - 1.0) / (g_ + 1.0) * K.p;
      const double q = std::sqrt(A / (p + B));
      if (df) *df = q * (1.0 - 0.5 * (p - K.p) / (p + B));
      return (p - K.p) * q;
    }
    const double r = std::pow(p / K.p, (g_ - 1.0) / (2.0 * g_)); // rarefaction
    if (df) *df = r / (K.rho * cK) * (K.p / p);
    return 2.0 * cK / (g_ - 1.0) * (r - 1.0);
  }

  /// Solves F(p) = f_L(p) + f_R(p) + (uR - uL) = 0 (Toro sec. 4.3). F is monotone
  /// increasing and concave. If F(pmin) >= 0, both waves are rarefactions and the
  /// two-rarefaction formula (Toro sec. 4.3) is exact, also arbitrarily close to
  /// vacuum. Otherwise p* > pmin and Newton's method (Toro sec. 4.3) is started from
  /// the PVRS or two-shock guess, floored at pmin > 0; from
  /// below the root the concave F makes the iterates increase monotonically.
  void solve_p_star() {
    const double du = R_.u - L_.u, pmin = std::min(L_.p, R_.p), pmax = std::max(L_.p, R_.p);
    const double eps = std::numeric_limits<double>::epsilon();
    if (f(pmin, L_, cL_) + f(pmin, R_, cR_) + du >= 0.0) { // two rarefactions
      const double z = (g_ - 1.0) / (2.0 * g_);
      p_star_ = std::pow((cL_ + cR_ - 0.5 * (g_ - 1.0) * du) /
                             (cL_ / std::pow(L_.p, z) + cR_ / std::pow(R_.p, z)), 1.0 / z);
      return;
    }
    const double ppv = 0.5 * (L_.p + R_.p) - 0.125 * du * (L_.rho + R_.rho) * (cL_ + cR_);
    double p;
    if (pmax / pmin <= 2.0 && ppv >= pmin && ppv <= pmax) {
      p = ppv; // PVRS
    } else { // two-shock, evaluated at max(ppv, pmin)
      const double p0 = std::max(ppv, pmin), G6 = (g_ - 1.0) / (g_ + 1.0);
      const double gL = std::sqrt(2.0 / ((g_ + 1.0) * L_.rho) / (p0 + G6 * L_.p));
      const double gR = std::sqrt(2.0 / ((g_ + 1.0) * R_.rho) / (p0 + G6 * R_.p));
      p = (gL * L_.p + gR * R_.p - du) / (gL + gR);
    }
    p = std::max(p, pmin);
    for (int it = 0; it < 100; ++it) {
      double dL, dR;
      const double fL = f(p, L_, cL_, &dL), fR = f(p, R_, cR_, &dR), F = fL + fR + du;
      // Residual at round-off level (cancellation in fL + fR + du): done.
      if (std::abs(F) <= 16.0 * eps * (std::abs(fL) + std::abs(fR) + std::abs(du))) break;
      const double p_new = std::max(p - F / (dL + dR), pmin);
      const double change = 2.0 * std::abs(p_new - p) / (p_new + p);
      p = p_new;
      if (change < 1e-14) break;
      if (it == 99)
        throw std::runtime_error("ExactRiemannSolver: Newton iteration for p* did not converge in 100 iterations");
    }
    p_star_ = p;
  }

  /// Density behind the left/right wave: shock or isentrope (Toro sec. 4.4).
  double rho_star(const Primitive &K) const {
    const double r = p_star_ / K.p, G6 = (g_ - 1.0) / (g_ + 1.0);
    return p_star_ > K.p ? K.rho * (r + G6) / (G6 * r + 1.0) : K.rho * std::pow(r, 1.0 / g_);
  }

  /// Left half of the wave pattern (xi left of the contact / left vacuum front).
  Primitive sample_left(double xi) const {
    const double G = g_;
    if (!vacuum_ && p_star_ > L_.p) { // left shock speed S_L (sec. 4.4)
      const double sL = L_.u - cL_ * std::sqrt((G + 1.0) / (2.0 * G) * p_star_ / L_.p + (G - 1.0) / (2.0 * G));
      return xi <= sL ? L_ : Primitive{rho_sL_, u_star_, p_star_};
    }
    const double head = L_.u - cL_;
    const double tail = vacuum_ ? L_.u + 2.0 * cL_ / (G - 1.0)
                                : u_star_ - cL_ * std::pow(p_star_ / L_.p, (G - 1.0) / (2.0 * G));
    if (xi <= head) return L_;
    if (xi >= tail) return Primitive{rho_sL_, u_star_, p_star_};
    // inside the left fan (sec. 4.5)
    const double c = 2.0 / (G + 1.0) + (G - 1.0) / ((G + 1.0) * cL_) * (L_.u - xi);
    const double rho = L_.rho * std::pow(c, 2.0 / (G - 1.0));
    return {rho, 2.0 / (G + 1.0) * (cL_ + 0.5 * (G - 1.0) * L_.u + xi), L_.p * std::pow(c, 2.0 * G / (G - 1.0))};
  }

  /// Right half of the wave pattern (mirror image of sample_left).
  Primitive sample_right(double xi) const {
    const double G = g_;
    if (!vacuum_ && p_star_ > R_.p) { // right shock speed S_R (sec. 4.4)
      const double sR = R_.u + cR_ * std::sqrt((G + 1.0) / (2.0 * G) * p_star_ / R_.p + (G - 1.0) / (2.0 * G));
      return xi >= sR ? R_ : Primitive{rho_sR_, u_star_, p_star_};
    }
    const double head = R_.u + cR_;
    const double tail = vacuum_ ? R_.u - 2.0 * cR_ / (G - 1.0)
                                : u_star_ + cR_ * std::pow(p_star_ / R_.p, (G - 1.0) / (2.0 * G));
    if (xi >= head) return R_;
    if (xi <= tail) return Primitive{rho_sR_, u_star_, p_star_};
    // inside the right fan (sec. 4.5)
    const double c = 2.0 / (G + 1.0) - (G - 1.0) / ((G + 1.0) * cR_) * (R_.u - xi);
    const double rho = R_.rho * std::pow(c, 2.0 / (G - 1.0));
    return {rho, 2.0 / (G + 1.0) * (-cR_ + 0.5 * (G - 1.0) * R_.u + xi), R_.p * std::pow(c, 2.0 * G / (G - 1.0))};
  }

  /// Rarefaction fans as xi-intervals [head/front, tail/front] (sorted, left to right).
  std::vector<std::array<double, 2>> fans() const {
    const double G = g_, z = (G - 1.0) / (2.0 * G);
    std::vector<std::array<double, 2>> r;
    if (vacuum_ || p_star_ <= L_.p)
      r.push_back({{L_.u - cL_, vacuum_ ? L_.u + 2.0 * cL_ / (G - 1.0) : u_star_ - cL_ * std::pow(p_star_ / L_.p, z)}});
    if (vacuum_ || p_star_ <= R_.p)
      r.push_back({{vacuum_ ? R_.u - 2.0 * cR_ / (G - 1.0) : u_star_ + cR_ * std::pow(p_star_ / R_.p, z), R_.u + cR_}});
    return r;
  }

  /// All wave positions xi (discontinuities of the solution or its derivative).
  std::vector<double> wave_speeds() const {
    const double G = g_, z = (G - 1.0) / (2.0 * G);
    std::vector<double> s;
    for (const auto &f : fans()) { s.push_back(f[0]); s.push_back(f[1]); }
    if (vacuum_) return s;
    s.push_back(u_star_);
    if (p_star_ > L_.p) s.push_back(L_.u - cL_ * std::sqrt((G + 1.0) / (2.0 * G) * p_star_ / L_.p + z));
    if (p_star_ > R_.p) s.push_back(R_.u + cR_ * std::sqrt((G + 1.0) / (2.0 * G) * p_star_ / R_.p + z));
    return s;
  }

  Primitive L_, R_;
  double g_, cL_ = 0.0, cR_ = 0.0;
  double p_star_ = 0.0, u_star_ = 0.0, rho_sL_ = 0.0, rho_sR_ = 0.0;
  bool vacuum_ = false;
};

} // namespace granhydro::testing

#endif // GRANHYDRO_TESTS_EXACT_RIEMANN_H
