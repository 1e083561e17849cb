#pragma once
/**
 * @file lanes.h
 * Helpers that let a physics formula be written once for a value type T that is
 * either double or a GCC vector of doubles (double __attribute__((vector_size(16|32))),
 * "lanes": independent states evaluated side by side, e.g. the Gauss points of a face).
 * Arithmetic on such vectors is element-wise IEEE arithmetic, so each lane is bit for
 * bit the double result (no contraction to FMA on the default or AVX2-without-FMA
 * targets). Comparisons of vectors give integer masks (-1 true, 0 false) and
 * `mask ? a : b` selects per lane; for double they are the usual bool and ?: .
 */
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace granhydro::physics::lanes
{
  /// number of doubles in T (1 for double)
  template <class T>
  constexpr unsigned int width = sizeof(T) / sizeof(double);

  /// the mask type of comparisons of T (bool for double)
  template <class T>
  using Mask = decltype(T() < T());

  __attribute__((always_inline)) inline double sqrt(const double x) { return std::sqrt(x); }
  __attribute__((always_inline)) inline double abs(const double x) { return std::abs(x); }
  __attribute__((always_inline)) inline bool   isfinite(const double x) { return std::isfinite(x); }

  /// correctly rounded square root per lane (as std::sqrt)
  template <class T, std::enable_if_t<!std::is_arithmetic_v<T>, int> = 0>
  __attribute__((always_inline)) inline T sqrt(const T x)
  {
#if defined(__SSE2__)
    typedef double v2 __attribute__((vector_size(16)));
    T r;
    for (unsigned int i = 0; i < width<T>; i += 2)
      {
        v2 h;
        std::memcpy(&h, reinterpret_cast<const double *>(&x) + i, sizeof h);
        h = __builtin_ia32_sqrtpd(h);
        std::memcpy(reinterpret_cast<double *>(&r) + i, &h, sizeof h);
      }
    return r;
#else
    T r;
    for (unsigned int i = 0; i < width<T>; ++i)
      r[i] = std::sqrt(x[i]);
    return r;
#endif
  }

  /// |x| per lane (clears the sign bit, as std::abs)
  template <class T, std::enable_if_t<!std::is_arithmetic_v<T>, int> = 0>
  __attribute__((always_inline)) inline T abs(const T x)
  {
    Mask<T> b;
    std::memcpy(&b, &x, sizeof b);
    b &= INT64_MAX;
    T r;
    std::memcpy(&r, &b, sizeof r);
    return r;
  }

  /// finite per lane (x - x is 0 for finite x, NaN for inf and NaN)
  template <class T, std::enable_if_t<!std::is_arithmetic_v<T>, int> = 0>
  __attribute__((always_inline)) inline Mask<T> isfinite(const T x)
  {
    return x - x == T();
  }

  /// lane i of x (x itself for double), to read and to write
  __attribute__((always_inline)) inline double get(const double x, const unsigned int) { return x; }
  __attribute__((always_inline)) inline double &ref(double &x, const unsigned int) { return x; }
  template <class T, std::enable_if_t<!std::is_arithmetic_v<T>, int> = 0>
  __attribute__((always_inline)) inline double get(const T &x, const unsigned int i)
  {
    return x[i];
  }
  template <class T, std::enable_if_t<!std::is_arithmetic_v<T>, int> = 0>
  __attribute__((always_inline)) inline double &ref(T &x, const unsigned int i)
  {
    return reinterpret_cast<double *>(&x)[i];
  }

  /// whether lane i of a mask is set
  __attribute__((always_inline)) inline bool set(const bool m, const unsigned int) { return m; }
  template <class M, std::enable_if_t<!std::is_same_v<M, bool>, int> = 0>
  __attribute__((always_inline)) inline bool set(const M m, const unsigned int i)
  {
    return m[i] != 0;
  }

  /// true if any lane of the mask is set
  __attribute__((always_inline)) inline bool any(const bool m) { return m; }
  template <class M, std::enable_if_t<!std::is_same_v<M, bool>, int> = 0>
  __attribute__((always_inline)) inline bool any(const M m)
  {
    bool r = false;
    for (unsigned int i = 0; i < sizeof(M) / sizeof(m[0]); ++i)
      r = r || m[i] != 0;
    return r;
  }
} // namespace granhydro::physics::lanes
