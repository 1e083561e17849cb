// Unit test of include/granhydro/physics/diffusive_flux.h (doc/physics.md 4.1-4.3,
// paper (2.2), (2.3), (5.1)-(5.9), (A1)-(A10)). Standalone, no framework:
//   g++ -std=c++17 -O2 -Wall -Wextra -I<repo>/include test_diffusive_flux.cc
// Exit status 0 on success; otherwise a message names the failing check.
//
// Tolerance. Every comparison below is between two evaluations of the same
// exact expression, so they differ only by floating-point round-off. Errors
// are measured relative to a *flux scale*: the sum of absolute values of all
// terms of the primitive formula (doc/physics.md 4.1), with each primitive
// gradient inflated by the magnitudes the chain rule of 4.1 combines to
// recover it from dU (the conditioning of conservative -> primitive, which can
// cancel heavily, e.g. d(nE) - E dn at small T). Standard error analysis bounds
// the round-off of such sums/products by c * eps * scale with c = O(number of
// operations) ~ 30, i.e. ~1e-14; we require 1e-12 (~4500 eps), leaving two
// orders of magnitude of margin while still catching any wrong term (a wrong
// coefficient or missing term gives O(1) relative errors).
#include <granhydro/physics/contact_pressure.h>
#include <granhydro/physics/diffusive_flux.h>
#include <granhydro/physics/garzo_dufty.h> // must coexist; its coefficients must be accepted

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

using namespace granhydro::physics;

namespace
{
  constexpr double tol = 1e-12;
  std::mt19937_64  rng(20240607);
  double           uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

  int failures = 0;
  void check(const bool ok, const std::string &what)
  {
    if (!ok)
      {
        ++failures;
        if (failures < 20)
          std::fprintf(stderr, "FAILED: %s\n", what.c_str());
      }
  }

  template <int dim>
  struct Sample
  {
    double                  n, T, m, E, u2;
    std::array<double, dim> u;
    State<dim>              U;
    PrimitiveGradients<dim> g;
    StateGradient<dim>      dU;
    DiffusiveCoefficients   c;
  };

  /// Conservative gradients from primitive ones (forward chain rule):
  /// d(n u_l) = u_l dn + n du_l, d(nE) = E dn + n (m u_k du_k + 3/2 dT).
  template <int dim>
  void build_dU(Sample<dim> &s)
  {
    for (int j = 0; j < dim; ++j)
      {
        const double dn = s.g.grad_n[j];
        double       dE = 1.5 * s.g.grad_T[j];
        s.dU[j][0]      = dn;
        for (int l = 0; l < dim; ++l)
          {
            s.dU[j][1 + l] = s.u[l] * dn + s.n * s.g.grad_u[j][l];
            dE += s.m * s.u[l] * s.g.grad_u[j][l];
          }
        s.dU[j][dim + 1] = s.E * dn + s.n * dE;
      }
  }

  template <int dim>
  void set_state(Sample<dim> &s)
  {
    s.u2 = 0;
    for (int l = 0; l < dim; ++l)
      s.u2 += s.u[l] * s.u[l];
    s.E    = 0.5 * s.m * s.u2 + 1.5 * s.T;
    s.U[0] = s.n;
    for (int l = 0; l < dim; ++l)
      s.U[1 + l] = s.n * s.u[l];
    s.U[dim + 1] = s.n * s.E;
  }

  /// Random admissible state, coefficients (mu of either sign, P5), gradients.
  template <int dim>
  Sample<dim> random_sample(const double m)
  {
    Sample<dim> s;
    s.m = m;
    s.n = std::exp(uni(std::log(0.01), std::log(2.)));
    s.T = uni(0.1, 5.);
    do
      for (int l = 0; l < dim; ++l)
        s.u[l] = uni(-3., 3.);
    while (std::sqrt([&] { double a = 0; for (double v : s.u) a += v * v; return a; }()) > 3.);
    set_state(s);
    s.c = {std::exp(uni(std::log(1e-2), std::log(10.))), uni(0., 5.), uni(1e-2, 5.), uni(-5., 5.)};
    const bool relative = uni(0, 1) < 0.5; // relative (dn ~ n) or absolute gradients
    for (int j = 0; j < dim; ++j)
      {
        s.g.grad_n[j] = relative ? s.n * uni(-5, 5) : uni(-2, 2);
        s.g.grad_T[j] = relative ? s.T * uni(-5, 5) : uni(-2, 2);
        for (int l = 0; l < dim; ++l)
          s.g.grad_u[j][l] = uni(-3, 3);
      }
    build_dU(s);
    return s;
  }

  /// Flux scale per row for face i (see the header comment).
  template <int dim>
  State<dim> flux_scale(const Sample<dim> &s, const unsigned int i)
  {
    double Au[dim][dim], AT[dim];
    for (int j = 0; j < dim; ++j)
      {
        const auto &d = s.dU[j];
        double      t = std::abs(d[dim + 1]) + (s.m * s.u2 + std::abs(s.E)) * std::abs(d[0]);
        for (int l = 0; l < dim; ++l)
          {
            Au[j][l] = std::abs(s.g.grad_u[j][l]) + (std::abs(d[1 + l]) + std::abs(s.u[l] * d[0])) / s.n;
            t += s.m * std::abs(s.u[l] * d[1 + l]);
          }
        AT[j] = std::abs(s.g.grad_T[j]) + 2. / (3. * s.n) * t;
      }
    const double L   = std::abs(s.c.gamma) + 2. / 3. * std::abs(s.c.eta);
    double       div = 0;
    for (int l = 0; l < dim; ++l)
      div += Au[l][l];
    State<dim> S{};
    S[dim + 1] = std::abs(s.c.kappa) * AT[i] + std::abs(s.c.mu) * std::abs(s.g.grad_n[i]);
    for (int k = 0; k < dim; ++k)
      {
        const double tau = std::abs(s.c.eta) * (Au[k][i] + Au[i][k]) + (k == int(i) ? L * div : 0.);
        S[1 + k]         = tau / s.m;
        S[dim + 1] += tau * std::abs(s.u[k]);
      }
    return S;
  }

  template <int dim>
  double rel_dev(const State<dim> &a, const State<dim> &b, const State<dim> &scale)
  {
    double r = 0;
    for (int k = 0; k < dim + 2; ++k)
      {
        const double d = std::abs(a[k] - b[k]);
        r = std::max(r, scale[k] > 0 ? d / scale[k] : (d > 0 ? HUGE_VAL : 0.));
      }
    return r;
  }

  /// The paper's Appendix A matrices (A1)-(A10), transcribed literally, with (A4).
  using M5 = std::array<std::array<double, 5>, 5>;
  M5 printed(const State<3> &U, const DiffusiveCoefficients &c, const double m, const int i, const int j)
  {
    const double n = U[0], ux = U[1] / n, uy = U[2] / n, uz = U[3] / n, E = U[4] / n;
    const double u2 = ux * ux + uy * uy + uz * uz, im = 1. / m;
    const double al = 2. * c.kappa / (3. * c.eta), be = n * c.mu / c.eta, la = al * (m * u2 - E) + be;
    const double h1 = c.gamma / c.eta + 4. / 3., h2 = c.gamma / c.eta + 1. / 3., h3 = c.gamma / c.eta - 2. / 3.;
    const double ma = m * al;
    M5 A;
    switch (3 * i + j)
      {
        case 0: A = {{{0, 0, 0, 0, 0}, {-im * h1 * ux, im * h1, 0, 0, 0}, {-uy * im, 0, im, 0, 0}, {-uz * im, 0, 0, im, 0}, {-u2 - h2 * ux * ux + la, (h1 - ma) * ux, (1 - ma) * uy, (1 - ma) * uz, al}}}; break; // (A1)
        case 1: A = {{{0, 0, 0, 0, 0}, {-im * h3 * uy, 0, im * h3, 0, 0}, {-im * ux, im, 0, 0, 0}, {0, 0, 0, 0, 0}, {-h2 * ux * uy, uy, h3 * ux, 0, 0}}}; break; // (A2)
        case 2: A = {{{0, 0, 0, 0, 0}, {-im * h3 * uz, 0, 0, im * h3, 0}, {0, 0, 0, 0, 0}, {-im * ux, im, 0, 0, 0}, {-h2 * ux * uz, uz, 0, h3 * ux, 0}}}; break; // (A3)
        case 3: A = {{{0, 0, 0, 0, 0}, {-uy * im, 0, im, 0, 0}, {-im * h3 * ux, im * h3, 0, 0, 0}, {0, 0, 0, 0, 0}, {-h2 * ux * uy, h3 * uy, ux, 0, 0}}}; break; // (A5)
        case 4: A = {{{0, 0, 0, 0, 0}, {-ux * im, im, 0, 0, 0}, {-im * h1 * uy, 0, im * h1, 0, 0}, {-im * uz, 0, 0, im, 0}, {-u2 - h2 * uy * uy + la, (1 - ma) * ux, (h1 - ma) * uy, (1 - ma) * uz, al}}}; break; // (A6)
        case 5: A = {{{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}, {-im * h3 * uz, 0, 0, im * h3, 0}, {-uy * im, 0, im, 0, 0}, {-h2 * uy * uz, 0, uz, h3 * uy, 0}}}; break; // (A7)
        case 6: A = {{{0, 0, 0, 0, 0}, {-im * uz, 0, 0, im, 0}, {0, 0, 0, 0, 0}, {-im * h3 * ux, im * h3, 0, 0, 0}, {-h2 * ux * uz, h3 * uz, 0, ux, 0}}}; break; // (A8)
        case 7: A = {{{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}, {-im * uz, 0, 0, im, 0}, {-im * h3 * uy, 0, im * h3, 0, 0}, {-h2 * uy * uz, 0, h3 * uz, uy, 0}}}; break; // (A9)
        default: A = {{{0, 0, 0, 0, 0}, {-im * ux, im, 0, 0, 0}, {-im * uy, 0, im, 0, 0}, {-im * h1 * uz, 0, 0, im * h1, 0}, {-u2 - h2 * uz * uz + la, (1 - ma) * ux, (1 - ma) * uy, (h1 - ma) * uz, al}}}; break; // (A10)
      }
    for (auto &row : A)
      for (auto &v : row)
        v *= c.eta / n;
    // entry scale: bound of every entry's constituents (A1-A10 all <= this)
    const double S = c.eta / n * ((1 + std::abs(h1) + std::abs(h2)) * (1 + u2) / std::min(1., m)
                                  + std::abs(al) * (m * u2 + std::abs(E) + m * std::sqrt(u2) + 1) + std::abs(be));
    A[0][0] = S; // mass row is zero in both; slot 0,0 carries the scale out
    return A;
  }

  struct Stats
  {
    double a = 0, b = 0, c = 0, c_exact = 0, d = 0, f = 0, f_energy_xx = 0, e = 0;
  };

  /// Hand case: expected flux Fe on face i from hand-made dU; all routes agree.
  template <int dim>
  void hand(const char *name, const State<dim> &U, const StateGradient<dim> &dU, const DiffusiveCoefficients &c,
            const double m, const unsigned int i, const State<dim> &Fe, Stats &st)
  {
    double scale = 0;
    for (double v : Fe)
      scale = std::max(scale, std::abs(v));
    scale = std::max(scale, 1e-300);
    const State<dim> F[3] = {viscous_flux<dim>(U, dU, c, m, i), flux_from_matrices<dim>(U, dU, c, m, i, false),
                             viscous_flux_primitive<dim>(U, primitive_gradients<dim>(U, dU, m), c, m, i)};
    for (const auto &f : F)
      for (int k = 0; k < dim + 2; ++k)
        {
          const double r = std::abs(f[k] - Fe[k]) / scale;
          st.e           = std::max(st.e, r);
          check(r <= tol, std::string("(e) ") + name + " dim=" + std::to_string(dim) + " face " + std::to_string(i));
        }
  }

  template <int dim>
  void hand_cases(const double m, Stats &st)
  {
    const DiffusiveCoefficients c{1.3, 0.7, 2.1, -0.9};
    const double                n = 0.8, T = 1.4, gdot = 0.37, y0 = 2.5;
    constexpr int               eE = dim + 1;
    auto state = [&](const std::array<double, dim> &u) {
      State<dim> U;
      double     u2 = 0;
      U[0]          = n;
      for (int l = 0; l < dim; ++l)
        U[1 + l] = n * u[l], u2 += u[l] * u[l];
      U[eE] = n * (0.5 * m * u2 + 1.5 * T);
      return U;
    };
    if constexpr (dim >= 2)
      { // pure shear u = (gdot y, 0, 0) at y = y0: tau_xy = eta gdot
        std::array<double, dim> u{};
        u[0]                = gdot * y0;
        const State<dim>    U = state(u);
        StateGradient<dim>  dU{};
        dU[1][1]            = n * gdot;             // d_y(n u_x)
        dU[1][eE]           = n * m * u[0] * gdot; // d_y(nE)
        State<dim> Fy{}, Fx{};
        Fy[1]  = c.eta * gdot / m, Fy[eE] = c.eta * gdot * u[0]; // y-face: tau_xy/m, tau_xy u_x
        Fx[2]  = c.eta * gdot / m;                                // x-face: tau_yx/m, tau_xx u_x = 0
        hand<dim>("pure shear", U, dU, c, m, 1, Fy, st);
        hand<dim>("pure shear", U, dU, c, m, 0, Fx, st);
        // diagonal-only loses the whole x-face shear stress (P8), = cross term
        const State<dim> Fd = flux_from_matrices<dim>(U, dU, c, m, 0, true);
        const State<dim> X  = cross_terms<dim>(U, dU, c, m, 0);
        check(Fd[2] == 0. && std::abs(X[2] - c.eta * gdot / m) <= tol * c.eta * gdot / m, "(e) shear x-face diag/cross");
      }
    { // pure heat conduction, u = 0: T = T0 + G x -> kappa G; then n gradient -> mu dn
      const State<dim>   U = state({});
      const double       G = 0.9, Gn = -0.6;
      StateGradient<dim> dU{};
      dU[0][eE] = 1.5 * n * G;
      State<dim> F{};
      F[eE] = c.kappa * G;
      hand<dim>("heat conduction", U, dU, c, m, 0, F, st);
      dU[0][0] = Gn, dU[0][eE] += 1.5 * T * Gn; // d(nE) = E dn + n 3/2 dT
      F[eE] += c.mu * Gn;
      hand<dim>("heat conduction + dn", U, dU, c, m, 0, F, st);
    }
    { // uniaxial compression u = (-a x, 0, 0) at x0: tau_xx = (gamma - 2eta/3 + 2eta) d_x u_x
      const double            a = 0.45, x0 = -1.7, lam = c.gamma - 2. / 3. * c.eta;
      std::array<double, dim> u{};
      u[0]               = -a * x0;
      const State<dim>   U = state(u);
      StateGradient<dim> dU{};
      dU[0][1]  = -n * a;
      dU[0][eE] = n * m * u[0] * (-a);
      State<dim> Fx{};
      Fx[1] = (lam + 2 * c.eta) * (-a) / m, Fx[eE] = (lam + 2 * c.eta) * (-a) * u[0];
      hand<dim>("uniaxial compression", U, dU, c, m, 0, Fx, st);
      if constexpr (dim >= 2)
        { // y-face: tau_yy = lam d_x u_x, tau_yx = 0, energy tau_yy u_y = 0
          State<dim> Fy{};
          Fy[2] = lam * (-a) / m;
          hand<dim>("uniaxial compression", U, dU, c, m, 1, Fy, st);
        }
    }
    { // isotropic compression u_l = -a x_l: tau_ii = (2 eta + dim lam) (-a); 3D: 3 gamma (-a)
      const double            a = 0.3, lam = c.gamma - 2. / 3. * c.eta;
      std::array<double, dim> u{}, x{};
      for (int l = 0; l < dim; ++l)
        x[l] = 0.4 - 0.9 * l, u[l] = -a * x[l];
      const State<dim>   U = state(u);
      StateGradient<dim> dU{};
      for (int l = 0; l < dim; ++l)
        dU[l][1 + l] = -n * a, dU[l][eE] = n * m * u[l] * (-a);
      const double tii = dim == 3 ? 3 * c.gamma * (-a) : (2 * c.eta + dim * lam) * (-a);
      for (unsigned int i = 0; i < unsigned(dim); ++i)
        {
          State<dim> F{};
          F[1 + i] = tii / m, F[eE] = tii * u[i];
          hand<dim>("isotropic compression", U, dU, c, m, i, F, st);
        }
    }
  }

  template <int dim>
  void run(Stats &st)
  {
    for (const double m : {1., 1.7})
      {
        hand_cases<dim>(m, st);
        for (int sample = 0; sample < 1000; ++sample)
          {
            Sample<dim> s = random_sample<dim>(m);
            for (unsigned int i = 0; i < unsigned(dim); ++i)
              {
                const State<dim> S    = flux_scale(s, i);
                const State<dim> ref  = viscous_flux_primitive<dim>(s.U, s.g.grad_u, s.g.grad_T, s.g.grad_n, s.c, m, i);
                const State<dim> full = flux_from_matrices<dim>(s.U, s.dU, s.c, m, i, false);
                const State<dim> diag = flux_from_matrices<dim>(s.U, s.dU, s.c, m, i, true);
                const State<dim> cr   = cross_terms<dim>(s.U, s.dU, s.c, m, i);
                State<dim>       fmd;
                for (int k = 0; k < dim + 2; ++k)
                  fmd[k] = full[k] - diag[k];
                const double ra = rel_dev<dim>(full, ref, S);
                const double rb = rel_dev<dim>(viscous_flux<dim>(s.U, s.dU, s.c, m, i), ref, S);
                const double rd = rel_dev<dim>(fmd, cr, S);
                st.a = std::max(st.a, ra), st.b = std::max(st.b, rb), st.d = std::max(st.d, rd);
                check(ra <= tol, "(a) full matrix flux vs primitive, dim " + std::to_string(dim));
                check(rb <= tol, "(b) chain-rule flux vs primitive, dim " + std::to_string(dim));
                check(rd <= tol, "(d) full - diagonal vs cross_terms, dim " + std::to_string(dim));

                // (c) gradients only along direction i
                Sample<dim> t = s;
                for (int j = 0; j < dim; ++j)
                  if (j != int(i))
                    {
                      t.g.grad_n[j] = t.g.grad_T[j] = 0;
                      t.g.grad_u[j].fill(0.);
                    }
                build_dU(t);
                const State<dim> St = flux_scale(t, i);
                const State<dim> tf = flux_from_matrices<dim>(t.U, t.dU, t.c, m, i, false);
                const State<dim> td = flux_from_matrices<dim>(t.U, t.dU, t.c, m, i, true);
                const State<dim> tr = viscous_flux_primitive<dim>(t.U, t.g, t.c, m, i);
                const double     rc = std::max(rel_dev<dim>(td, tf, St), rel_dev<dim>(td, tr, St));
                st.c = std::max(st.c, rc), st.c_exact = std::max(st.c_exact, rel_dev<dim>(td, tf, St));
                check(rc <= tol, "(c) 1D gradients: diagonal == full, dim " + std::to_string(dim));

                // (f) printed (A1)-(A10); dim < 3 against the 3D matrix with zero unresolved velocity
                State<3> U3{{s.U[0], 0, 0, 0, s.U[dim + 1]}};
                for (int l = 0; l < dim; ++l)
                  U3[1 + l] = s.U[1 + l];
                auto idx = [](int r) { return r == dim + 1 ? 4 : r; };
                for (unsigned int j = 0; j < unsigned(dim); ++j)
                  {
                    const M5                   P = printed(U3, s.c, m, i, j);
                    const DiffusionMatrix<dim> D = diffusion_matrix<dim>(s.U, s.c, m, i, j);
                    for (int r = 0; r < dim + 2; ++r)
                      for (int q = 0; q < dim + 2; ++q)
                        {
                          const double ref_v = (r == 0 && q == 0) ? 0. : P[idx(r)][idx(q)];
                          const double dev   = std::abs(D[r][q] - ref_v) / P[0][0];
                          st.f               = std::max(st.f, dev);
                          if (dim == 3 && i == 0 && j == 0 && r == dim + 1)
                            st.f_energy_xx = std::max(st.f_energy_xx, dev);
                          check(dev <= tol, "(f) D_ij vs paper (A1)-(A10), dim " + std::to_string(dim) + " i=" +
                                              std::to_string(i) + " j=" + std::to_string(j));
                        }
                  }
              }
          }
      }
  }

  void report(const int dim, const Stats &s)
  {
    std::printf("dim %d: (a) full D vs primitive %.2e  (b) chain rule vs primitive %.2e  (c) 1D grads diag vs full/prim "
                "%.2e (diag vs full %.2e)\n       (d) full-diag vs cross_terms %.2e  (e) hand cases %.2e  (f) D vs "
                "(A1)-(A10) %.2e%s\n",
                dim, s.a, s.b, s.c, s.c_exact, s.d, s.e, s.f, dim == 3 ? "" : " (restricted)");
    if (dim == 3)
      std::printf("       (f) D_xx energy row (alpha/beta/lambda/h1/h2 form) %.2e\n", s.f_energy_xx);
  }
} // namespace

int main()
{
  Stats s1, s2, s3;
  run<1>(s1), run<2>(s2), run<3>(s3);
  report(1, s1), report(2, s2), report(3, s3);

  // Garzo-Dufty coefficients (garzo_dufty.h) are accepted as-is and give the same flux.
  {
    const GarzoDufty1999 gd(0.8);
    const auto           tc = gd.transport(0.5, 1.2, 1., 1.);
    Sample<3>            s  = random_sample<3>(1.);
    const DiffusiveCoefficients plain{tc.eta, tc.gamma, tc.kappa, tc.mu};
    s.c = plain;
    for (unsigned int i = 0; i < 3; ++i)
      {
        const State<3> a = viscous_flux<3>(s.U, s.dU, tc, 1., i), b = viscous_flux<3>(s.U, s.dU, plain, 1., i);
        const State<3> x = flux_from_matrices<3>(s.U, s.dU, tc, 1., i, false);
        check(a == b && rel_dev<3>(x, b, flux_scale(s, i)) <= tol, "Garzo-Dufty TransportCoefficients pass-through");
      }
  }

  // Dense closure (doc/physics.md 4.5): the contact potential energy n w(n) is part of nE but
  // not thermal, so the temperature gradient recovered from dU must not contain it.
  // Default Johnson-Jackson closure in scaled units (1 mm glass grains: F = 0.05 Pa is
  // 3.7e-3 m g / sigma^2), phi_min 0.5, phi_c 0.64, across 0.5 < phi < 0.63.
  {
    const ContactPressure cp(3.7e-3, 0.5, 0.64, 2, 5, 1e-3, FrictionalStress{});
    double                worst_uniform = 0, worst_random[2] = {0, 0}, worst_matrix = 0;
    for (int k = 0; k < 400; ++k)
      {
        Sample<3> s = random_sample<3>(1.);
        const bool uniform_T = k < 200; // first half: T uniform, only n (and u) vary
        s.n              = uni(0.5001, 0.63) / ContactPressure::v;
        set_state(s);
        for (int j = 0; j < 3; ++j)
          {
            if (uniform_T)
              s.g.grad_T[j] = 0;
            s.g.grad_n[j] = s.n * uni(-0.3, 0.3); // phi varies by up to 30 % over a unit length
          }
        build_dU(s);
        // the closure: nE += n w, d(nE) += (w + n dw/dn) dn (forward chain rule)
        const double nw = cp.energy_density(s.n), w = nw / s.n, wn = cp.dw_dn(s.n);
        s.U[4] += nw;
        s.E += w;
        for (int j = 0; j < 3; ++j)
          s.dU[j][4] += (w + s.n * wn) * s.g.grad_n[j];
        // the scale of the recovered dT includes the contact terms the chain rule cancels
        // (|d(nE)| and |E dn| already hold them, plus n |dw/dn dn|): round-off is eps times it
        State<3> scale_ref[3];
        for (unsigned int i = 0; i < 3; ++i)
          {
            scale_ref[i] = flux_scale(s, i);
            scale_ref[i][4] += 2. / 3. * std::abs(s.c.kappa) * std::abs(wn * s.g.grad_n[i]);
          }
        for (unsigned int i = 0; i < 3; ++i)
          {
            const State<3> F   = viscous_flux<3>(s.U, s.dU, s.c, 1., i, wn);
            const State<3> ref = viscous_flux_primitive<3>(s.U, s.g, s.c, 1., i); // true T gradient
            const State<3> FM  = flux_from_matrices<3>(s.U, s.dU, s.c, 1., i, false, wn);
            if (uniform_T)
              {
                // grad T = 0: the heat flux is exactly the mu grad n part; kappa grad T must
                // vanish to round-off of the chain rule
                const PrimitiveGradients<3> g = primitive_gradients<3>(s.U, s.dU, 1., wn);
                worst_uniform = std::max(worst_uniform, std::abs(s.c.kappa * g.grad_T[i]) / scale_ref[i][4]);
              }
            worst_random[uniform_T ? 0 : 1] = std::max(worst_random[uniform_T ? 0 : 1], rel_dev<3>(F, ref, scale_ref[i]));
            worst_matrix = std::max(worst_matrix, rel_dev<3>(FM, ref, scale_ref[i]));
          }
        // without the correction (dw_dn = 0) heat would be conducted along grad(T + 2w/3):
        // the check above must be able to fail
        if (k == 0)
          {
            const State<3> bad = viscous_flux<3>(s.U, s.dU, s.c, 1., 0, 0.);
            const State<3> ref = viscous_flux_primitive<3>(s.U, s.g, s.c, 1., 0);
            check(rel_dev<3>(bad, ref, scale_ref[0]) > 1e-3, "dense closure: the test detects a missing dw/dn");
          }
      }
    // uniform T: a handful of operations on the chain-rule terms, so a few eps of their
    // scale (1e-14 = 45 eps); the full flux: the file's tolerance
    std::printf("dense closure: uniform T, |kappa grad T| / scale <= %.2e; flux vs true-T primitive flux "
                "%.2e (uniform T), %.2e (random T); matrices %.2e\n",
                worst_uniform, worst_random[0], worst_random[1], worst_matrix);
    check(worst_uniform <= 1e-14, "dense closure: kappa grad T vanishes for uniform T");
    check(worst_random[0] <= tol && worst_random[1] <= tol, "dense closure: flux from the true T gradient");
    check(worst_matrix <= tol, "dense closure: diffusion matrices with the contact term");
  }

  if (failures)
    {
      std::fprintf(stderr, "test_diffusive_flux: %d check(s) failed (tolerance %.0e relative to the flux scale)\n",
                   failures, tol);
      return 1;
    }
  std::printf("test_diffusive_flux: all checks passed (tolerance %.0e relative to the flux scale)\n", tol);
  return 0;
}
