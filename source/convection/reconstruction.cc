#include <granhydro/convection/reconstruction.h>

#include <stdexcept>

namespace granhydro::convection
{
  double pair_point(const unsigned int pair, const unsigned int side)
  {
    const double x = pair == 0 ? 0.5 : std::sqrt(3.) / 6.;
    return side == 0 ? -x : x;
  }

  std::vector<double> point_coefficients(const int first, const unsigned int n, const double xi)
  {
    // A_{ij} = average of x^j over cell first+i; solve A^T w = (xi^j)_j
    std::vector<std::vector<double>> M(n, std::vector<double>(n + 1));
    for (unsigned int j = 0; j < n; ++j) // row j: moment j
      {
        for (unsigned int i = 0; i < n; ++i)
          {
            const double a = first + int(i) - 0.5, b = first + int(i) + 0.5;
            M[j][i] = (std::pow(b, j + 1) - std::pow(a, j + 1)) / (j + 1);
          }
        M[j][n] = std::pow(xi, j);
      }
    for (unsigned int k = 0; k < n; ++k) // Gauss elimination with partial pivoting
      {
        unsigned int piv = k;
        for (unsigned int r = k + 1; r < n; ++r)
          if (std::abs(M[r][k]) > std::abs(M[piv][k]))
            piv = r;
        std::swap(M[k], M[piv]);
        for (unsigned int r = 0; r < n; ++r)
          if (r != k)
            {
              const double f = M[r][k] / M[k][k];
              for (unsigned int c = k; c <= n; ++c)
                M[r][c] -= f * M[k][c];
            }
      }
    std::vector<double> w(n);
    for (unsigned int i = 0; i < n; ++i)
      w[i] = M[i][n] / M[i][i];
    return w;
  }

  Weno3::Weno3()
  {
    for (unsigned int p = 0; p < 2; ++p)
      for (unsigned int s = 0; s < 2; ++s)
        {
          const double xi = pair_point(p, s);
          const auto   c3 = point_coefficients(-1, 3, xi);
          for (unsigned int k = 0; k < 2; ++k)
            {
              const auto ck = point_coefficients(int(k) - 1, 2, xi);
              for (unsigned int j = 0; j < 2; ++j)
                c[p][s][k][j] = ck[j];
            }
          d[p][s][0] = c3[0] / c[p][s][0][0];
          d[p][s][1] = 1 - d[p][s][0];
          if (!(d[p][s][0] > 0 && d[p][s][1] > 0))
            throw std::logic_error("WENO3: non-positive linear weights");
        }
  }

  Weno5::Weno5()
  {
    for (unsigned int p = 0; p < 2; ++p)
      for (unsigned int s = 0; s < 2; ++s)
        {
          // the candidates' coefficients c and linear weights d at the pair's point: pair_k()
          // multiplies by the tables kc, kd, which must be these values, bit for bit
          const double xi = pair_point(p, s);
          const auto   c5 = point_coefficients(-2, 5, xi);
          double       c[3][3], d[3];
          for (unsigned int k = 0; k < 3; ++k)
            {
              const auto ck = point_coefficients(int(k) - 2, 3, xi);
              for (unsigned int j = 0; j < 3; ++j)
                c[k][j] = ck[j];
            }
          d[0] = c5[0] / c[0][0];
          d[2] = c5[4] / c[2][2];
          d[1] = 1 - d[0] - d[2];
          for (unsigned int k = 0; k < 3; ++k)
            {
              if (!(d[k] > 0))
                throw std::logic_error("WENO5: non-positive linear weights");
              if (d[k] != kd[p][s][k])
                throw std::logic_error("WENO5: the linear weights table kd differs from its derivation");
              for (unsigned int j = 0; j < 3; ++j)
                if (c[k][j] != kc[p][s][k][j])
                  throw std::logic_error("WENO5: the coefficient table kc differs from its derivation");
            }
        }
    // centre point: linear weights (-9/80, 49/40, -9/80), split after Shi-Hu-Shu
    const auto c5 = point_coefficients(-2, 5, 0.);
    double     g[3];
    for (unsigned int k = 0; k < 3; ++k)
      {
        const auto ck = point_coefficients(int(k) - 2, 3, 0.);
        for (unsigned int j = 0; j < 3; ++j)
          cc[k][j] = ck[j];
      }
    g[0] = c5[0] / cc[0][0];
    g[2] = c5[4] / cc[2][2];
    g[1] = 1 - g[0] - g[2];
    sp = sm = 0;
    for (unsigned int k = 0; k < 3; ++k)
      {
        gp[k] = 0.5 * (g[k] + 3 * std::abs(g[k]));
        gm[k] = gp[k] - g[k];
        sp += gp[k];
        sm += gm[k];
      }
    for (unsigned int k = 0; k < 3; ++k)
      {
        gp[k] /= sp;
        gm[k] = sm > 0 ? gm[k] / sm : 0;
      }
  }
} // namespace granhydro::convection
