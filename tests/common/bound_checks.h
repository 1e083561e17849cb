#pragma once
/**
 * @file bound_checks.h
 * The check of the standalone formula tests (no deal.II, no MPI): a value against its
 * bound, printed as "ok" or "FAIL" with both, failures counted; and the relative
 * difference they bound.
 */
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

namespace granhydro::testing
{
  /// failures of check() so far (the test's exit code)
  inline int failures = 0;

  /// prints the check with its value and bound; counts a failure
  inline void check(const bool ok, const std::string &what, const double value, const double bound)
  {
    std::cout << (ok ? "  ok    " : "  FAIL  ") << what << ": " << value << " (bound " << bound << ")\n";
    if (!ok)
      ++failures;
  }

  /// |a - b| / |b| (b = 0: relative to the smallest positive normal scale)
  inline double rel(const double a, const double b)
  {
    return std::abs(a - b) / std::max(std::abs(b), 1e-300);
  }
} // namespace granhydro::testing
