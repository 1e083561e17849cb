#include <granhydro/diffusion/butcher_tables.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace granhydro::diffusion
{
  ButcherTableau butcher_tableau(const ImplicitMethod method)
  {
    ButcherTableau t;
    const double   s3 = std::sqrt(3.) / 6., g = 1 - 1 / std::sqrt(2.);
    switch (method)
      {
        case ImplicitMethod::gauss_legendre:
          t.A = {{0.25, 0.25 - s3}, {0.25 + s3, 0.25}};
          t.b = {0.5, 0.5};
          break;
        case ImplicitMethod::implicit_midpoint:
          t.A = {{0.5}};
          t.b = {1.};
          break;
        case ImplicitMethod::sdirk2: // L-stable, stiffly accurate (b = last row of A)
          t.A = {{g, 0.}, {1 - g, g}};
          t.b = {1 - g, g};
          break;
        default:
          throw std::invalid_argument("butcher_tableau: not an implicit Runge-Kutta method");
      }
    for (const auto &row : t.A)
      {
        double c = 0;
        for (const double a : row)
          c += a;
        t.c.push_back(c);
      }
    return t;
  }

  RKL2Stage rkl2_stage(const unsigned int j, const unsigned int s)
  {
    // b_j = (j^2 + j - 2) / (2 j (j + 1)), b_0 = b_1 = b_2 = 1/3, a_j = 1 - b_j,
    // w1 = 4 / (s^2 + s - 2)
    auto         bj = [](const double k) { return k < 2.5 ? 1. / 3. : (k * k + k - 2) / (2 * k * (k + 1)); };
    const double w1 = 4. / (double(s) * s + s - 2);
    if (j == 1)
      return {1., 0., bj(1) * w1, 0.};
    const double mu = (2. * j - 1) / j * bj(j) / bj(j - 1), nu = -(j - 1.) / j * bj(j) / bj(j - 2);
    return {mu, nu, mu * w1, -(1 - bj(j - 1)) * mu * w1};
  }

  unsigned int rkl2_stages(const double ratio)
  {
    // (2s + 1)^2 = 9 + 16 ratio at the bound: the 1e-9 keeps a ratio exactly at the bound
    // of s stages from rounding up to s + 1
    return std::max(2u, unsigned(std::ceil((std::sqrt(9 + 16 * ratio) - 1) / 2 - 1e-9)));
  }
} // namespace granhydro::diffusion
