#pragma once
/**
 * @file reconstruction.h
 * One-dimensional reconstructions from cell averages to points of a cell,
 * used dimension by dimension (paper section 4, Titarev & Toro 2004):
 * first along the face normal to the two faces (xi = -1/2, +1/2), then along
 * each transverse direction to the two Gauss points xi = -+sqrt(3)/6.
 *
 * Each class evaluates a *pair* of points from one stencil (so smoothness
 * indicators are computed once): pair 0 = faces, pair 1 = Gauss points.
 * The linear weights of WENO at arbitrary points are computed from the
 * exact polynomial reconstruction (point_coefficients) at construction.
 *
 * REFERENCES
 *  - G.-S. Jiang, C.-W. Shu, J. Comput. Phys. 126 (1996) 202 (WENO5 weights)
 *  - V. Titarev, E. Toro, J. Sci. Comput. 17 (2002); J. Comput. Phys. 201 (2004)
 *  - B. van Leer, J. Comput. Phys. 23 (1977) (MC-limited MUSCL)
 */
#include <array>
#include <cmath>
#include <vector>

namespace granhydro::convection
{
  /// points of pair p: xi(p, 0) < xi(p, 1), in units of the cell width
  double pair_point(const unsigned int pair, const unsigned int side);

  /**
   * Weights w_j such that sum_j w_j vbar_{first+j} is the value at xi of the
   * unique polynomial of degree n-1 with the given cell averages on cells
   * first .. first+n-1 (cell 0 = [-1/2, 1/2]).
   */
  std::vector<double> point_coefficients(const int first, const unsigned int n, const double xi);

  struct FirstOrder
  {
    static constexpr int r = 0;
    void   pair(const double *v, const unsigned int, double &lo, double &hi) const { lo = hi = v[0]; }
    double center(const double *v) const { return v[0]; }
  };

  /// MUSCL with the monotonized-central limiter: v0 + xi * slope
  struct Muscl
  {
    static constexpr int r = 1;
    void                 pair(const double *v, const unsigned int p, double &lo, double &hi) const
    {
      const double dm = v[1] - v[0], dp = v[2] - v[1];
      double       s = 0;
      if (dm * dp > 0)
        {
          const double a = std::abs(0.5 * (dm + dp)), b = 2 * std::abs(dm), c = 2 * std::abs(dp);
          s = std::copysign(std::min(a, std::min(b, c)), dm);
        }
      const double x = p == 0 ? 0.5 : 0.28867513459481287;
      lo             = v[1] - x * s;
      hi             = v[1] + x * s;
    }
    /// the linear reconstruction's value at the cell centre is the average
    double center(const double *v) const { return v[1]; }
  };

  /// WENO3 (two 2-cell candidates), Jiang-Shu type weights
  struct Weno3
  {
    static constexpr int r = 1;
    Weno3();
    double c[2][2][2][2]; // [pair][side][candidate][j]
    double d[2][2][2];    // linear weights [pair][side][candidate]
    double eps = 1e-6;    ///< relative to the stencil's mean square (see Weno5::scaled_eps)
    void   pair(const double *v, const unsigned int p, double &lo, double &hi) const
    {
      const double b0  = (v[1] - v[0]) * (v[1] - v[0]);
      const double b1  = (v[2] - v[1]) * (v[2] - v[1]);
      const double eps = this->eps * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) / 3. + 1e-100;
      double       out[2];
      for (unsigned int s = 0; s < 2; ++s)
        {
          const double a0 = d[p][s][0] / ((eps + b0) * (eps + b0));
          const double a1 = d[p][s][1] / ((eps + b1) * (eps + b1));
          const double q0 = c[p][s][0][0] * v[0] + c[p][s][0][1] * v[1];
          const double q1 = c[p][s][1][0] * v[1] + c[p][s][1][1] * v[2];
          out[s]          = (a0 * q0 + a1 * q1) / (a0 + a1);
        }
      lo = out[0];
      hi = out[1];
    }
    /// both candidates are linear with value v0 at the centre (second-order point value)
    double center(const double *v) const { return v[1]; }
  };

  /// WENO5 (three 3-cell candidates), Jiang-Shu smoothness indicators and weights.
  /// The centre point (midpoint quadrature) has negative linear weights; they are
  /// split into two positive sets (Shi, Hu & Shu, J. Comput. Phys. 175 (2002) 108).
  struct Weno5
  {
    static constexpr int r = 2;
    Weno5();
    double cc[3][3];       // centre: candidate coefficients
    double gp[3], gm[3];   // centre: split positive weights, normalised
    double sp = 1, sm = 0; // centre: their sums
    /// epsilon of the Jiang-Shu weights relative to the stencil's mean square, so the
    /// weights do not depend on the internal units: the smoothness indicators scale as
    /// v^2, and a fixed 1e-6 made results depend on 'Numerics/Reference velocity'
    /// (L1 error of Sod 2.825e-3 / 2.997e-3 / 2.936e-3 for three reference velocities)
    double eps = 1e-6;
    double scaled_eps(const double *v) const { return scaled_eps_v<double>(v[0], v[1], v[2], v[3], v[4]); }
    template <class T>
    __attribute__((always_inline)) inline T scaled_eps_v(const T v0, const T v1, const T v2, const T v3,
                                                         const T v4) const
    {
      return eps * (v0 * v0 + v1 * v1 + v2 * v2 + v3 * v3 + v4 * v4) / 5. +
             1e-100; // 1e-100: (eps + b)^2 must not underflow for v = 0
    }
    double center(const double *v) const
    {
      const double eps = scaled_eps(v);
      const double t0 = v[0] - 2 * v[1] + v[2], t1 = v[1] - 2 * v[2] + v[3], t2 = v[2] - 2 * v[3] + v[4];
      const double s0 = v[0] - 4 * v[1] + 3 * v[2], s1 = v[1] - v[3], s2 = 3 * v[2] - 4 * v[3] + v[4];
      const double b[3] = {13. / 12. * t0 * t0 + 0.25 * s0 * s0, 13. / 12. * t1 * t1 + 0.25 * s1 * s1,
                           13. / 12. * t2 * t2 + 0.25 * s2 * s2};
      double       q[3], ap = 0, am = 0, up = 0, um = 0;
      for (unsigned int k = 0; k < 3; ++k)
        {
          q[k]           = cc[k][0] * v[k] + cc[k][1] * v[k + 1] + cc[k][2] * v[k + 2];
          const double i = 1. / ((eps + b[k]) * (eps + b[k]));
          ap += gp[k] * i;
          am += gm[k] * i;
          up += gp[k] * i * q[k];
          um += gm[k] * i * q[k];
        }
      return sp * up / ap - (sm > 0 ? sm * um / am : 0.);
    }
    void pair(const double *v, const unsigned int p, double &lo, double &hi) const
    {
      pair_v<double>(v[0], v[1], v[2], v[3], v[4], p, lo, hi);
    }
    /// pair() for a value type T that is double or a GCC vector of doubles (lanes: independent
    /// stencils, e.g. the components of a cell): the same operations in the same order as the
    /// scalar version, so every lane is bit for bit what pair() gives for it
    template <class T>
    __attribute__((always_inline)) inline void pair_v(const T v0, const T v1, const T v2, const T v3,
                                                      const T v4, const unsigned int p, T &lo, T &hi) const
    {
      if (p == 0)
        pair_k<T, 0>(v0, v1, v2, v3, v4, lo, hi);
      else
        pair_k<T, 1>(v0, v1, v2, v3, v4, lo, hi);
    }
    /// the candidates' coefficients [pair][side][candidate][j] and linear weights
    /// [pair][side][candidate] as compile-time constants: the values the constructor derives
    /// from the exact polynomial reconstruction (point_coefficients()), checked there bit
    /// for bit. As
    /// constants they are operands the compiler folds into the multiplications (14 % fewer
    /// instructions in the reconstruction, see doc/performance.md)
    static constexpr double kc[2][2][3][3] = {
      {{{-0.16666666666666663, 0.83333333333333326, 0.33333333333333343},
        {0.33333333333333337, 0.83333333333333326, -0.16666666666666666},
        {1.8333333333333335, -1.1666666666666667, 0.33333333333333337}},
       {{0.33333333333333331, -1.1666666666666667, 1.8333333333333333},
        {-0.16666666666666666, 0.83333333333333326, 0.33333333333333337},
        {0.33333333333333337, 0.83333333333333326, -0.16666666666666666}}},
      {{{-0.14433756729740646, 0.57735026918962573, 0.5669872981077807},
        {0.14433756729740643, 1, -0.14433756729740643},
        {1.4330127018922192, -0.57735026918962573, 0.14433756729740643}},
       {{0.14433756729740643, -0.57735026918962573, 1.4330127018922192},
        {-0.14433756729740643, 1, 0.14433756729740643},
        {0.5669872981077807, 0.57735026918962573, -0.14433756729740643}}}};
    static constexpr double kd[2][2][3] = {{{0.30000000000000027, 0.59999999999999964, 0.10000000000000003},
                                            {0.099999999999999964, 0.6000000000000002, 0.29999999999999982}},
                                           {{0.19604819519219352, 0.61111111111111094, 0.19284069369669557},
                                            {0.19284069369669543, 0.61111111111111116, 0.19604819519219338}}};
    /// pair_v() for the pair P known at compile time
    template <class T, unsigned int P>
    __attribute__((always_inline)) inline void pair_k(const T v0, const T v1, const T v2, const T v3,
                                                      const T v4, T &lo, T &hi) const
    {
      const T t0 = v0 - 2 * v1 + v2, t1 = v1 - 2 * v2 + v3, t2 = v2 - 2 * v3 + v4;
      const T s0 = v0 - 4 * v1 + 3 * v2, s1 = v1 - v3, s2 = 3 * v2 - 4 * v3 + v4;
      const T b0  = 13. / 12. * t0 * t0 + 0.25 * s0 * s0;
      const T b1  = 13. / 12. * t1 * t1 + 0.25 * s1 * s1;
      const T b2  = 13. / 12. * t2 * t2 + 0.25 * s2 * s2;
      const T eps = scaled_eps_v<T>(v0, v1, v2, v3, v4);
      const T i0 = 1. / ((eps + b0) * (eps + b0)), i1 = 1. / ((eps + b1) * (eps + b1)),
              i2 = 1. / ((eps + b2) * (eps + b2));
      T out[2];
      for (unsigned int s = 0; s < 2; ++s)
        {
          const auto &cc = kc[P][s];
          const T     a0 = kd[P][s][0] * i0, a1 = kd[P][s][1] * i1, a2 = kd[P][s][2] * i2;
          const T     q0 = cc[0][0] * v0 + cc[0][1] * v1 + cc[0][2] * v2;
          const T     q1 = cc[1][0] * v1 + cc[1][1] * v2 + cc[1][2] * v3;
          const T     q2 = cc[2][0] * v2 + cc[2][1] * v3 + cc[2][2] * v4;
          out[s]         = (a0 * q0 + a1 * q1 + a2 * q2) / (a0 + a1 + a2);
        }
      lo = out[0];
      hi = out[1];
    }
  };
} // namespace granhydro::convection
