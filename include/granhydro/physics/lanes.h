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
#include <cstdlib>
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

  /// AVX2 paths (target("avx2") clones of the vector kernels, no FMA: the same IEEE
  /// operations) on x86 CPUs that have it; GRANHYDRO_NO_AVX2 (set, any value) forces the
  /// default-target vectors (testing: both paths give the same results bit for bit)
  inline bool use_avx2()
  {
#if defined(__x86_64__) || defined(__i386__)
    static const bool avx2 = __builtin_cpu_supports("avx2") && std::getenv("GRANHYDRO_NO_AVX2") == nullptr;
    return avx2;
#else
    return false;
#endif
  }

  /// true for GCC vectors of doubles (neither a class nor an arithmetic type); false for
  /// double and for class number types (autodiff), which keep their own operators
  template <class T>
  constexpr bool is_vector = !std::is_class_v<T> && !std::is_arithmetic_v<T>;

  /// the constant x in every lane; T(x) for scalar and class number types (a GCC vector
  /// cannot be constructed from a scalar, so formulas write constant<Number>(x))
  template <class T>
  __attribute__((always_inline)) inline T constant(const double x)
  {
    if constexpr (is_vector<T>)
      {
        T r;
        for (unsigned int i = 0; i < sizeof(T) / sizeof(double); ++i)
          reinterpret_cast<double *>(&r)[i] = x;
        return r;
      }
    else
      return T(x);
  }

  __attribute__((always_inline)) inline double sqrt(const double x)
  {
    return std::sqrt(x);
  }
  __attribute__((always_inline)) inline double abs(const double x)
  {
    return std::abs(x);
  }
  __attribute__((always_inline)) inline bool isfinite(const double x)
  {
    return std::isfinite(x);
  }

  /// correctly rounded square root per lane (as std::sqrt)
  template <class T, std::enable_if_t<!std::is_arithmetic_v<T>, int> = 0>
  __attribute__((always_inline)) inline T sqrt(const T x)
  {
#if defined(__SSE2__)
    typedef double v2 __attribute__((vector_size(16)));
    T              r;
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

  /// sqrt for any number type of a formula: the lane-wise sqrt for GCC vectors, std::sqrt
  /// for double, and the type's own sqrt (found by argument-dependent lookup) otherwise
  template <class T>
  __attribute__((always_inline)) inline T any_sqrt(const T x)
  {
    if constexpr (is_vector<T>)
      return lanes::sqrt(x);
    else
      {
        using std::sqrt;
        return sqrt(x);
      }
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
  __attribute__((always_inline)) inline double get(const double x, const unsigned int)
  {
    return x;
  }
  __attribute__((always_inline)) inline double &ref(double &x, const unsigned int)
  {
    return x;
  }
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
  __attribute__((always_inline)) inline bool set(const bool m, const unsigned int)
  {
    return m;
  }
  template <class M, std::enable_if_t<!std::is_same_v<M, bool>, int> = 0>
  __attribute__((always_inline)) inline bool set(const M m, const unsigned int i)
  {
    return m[i] != 0;
  }

  /// true if any lane of the mask is set
  __attribute__((always_inline)) inline bool any(const bool m)
  {
    return m;
  }
  template <class M, std::enable_if_t<!std::is_same_v<M, bool>, int> = 0>
  __attribute__((always_inline)) inline bool any(const M m)
  {
    auto r = m[0]; // the lanes or-ed without a branch per lane
    for (unsigned int i = 1; i < sizeof(M) / sizeof(m[0]); ++i)
      r |= m[i];
    return r != 0;
  }

  /// the number of lanes set in a mask (0 or 1 for bool)
  __attribute__((always_inline)) inline unsigned int count(const bool m)
  {
    return m;
  }
  template <class M, std::enable_if_t<!std::is_same_v<M, bool>, int> = 0>
  __attribute__((always_inline)) inline unsigned int count(const M m)
  {
    auto r = m[0]; // a set lane is -1
    for (unsigned int i = 1; i < sizeof(M) / sizeof(m[0]); ++i)
      r += m[i];
    return static_cast<unsigned int>(-r);
  }
} // namespace granhydro::physics::lanes
