#pragma once
/**
 * @file euler_flux.h
 * The parts of the convective system (paper eqs. 2.5-2.6, scaled units m = 1) that do
 * not depend on the equation of state, shared by every description
 * (IdealGas, GranularGas): kinetic energy density and the physical flux F_d(U)
 * for a given pressure.
 */
#include <array>

namespace granhydro::physics
{
  template <int dim>
  using State = std::array<double, dim + 2>;

  /// n |u|^2 / 2 from U = (n, n u, nE); T: double or a vector of doubles (physics/lanes.h)
  template <int dim, class T = double>
  inline T kinetic_energy(const std::array<T, dim + 2> &U)
  {
    T m2{};
    for (int d = 0; d < dim; ++d)
      m2 += U[1 + d] * U[1 + d];
    return 0.5 * m2 / U[0];
  }

  /// F_d(U) = (n u_d, n u u_d + p e_d, (nE + p) u_d) (paper 2.6 with m = 1)
  template <int dim, class T = double>
  inline void euler_flux(const std::array<T, dim + 2> &U, const T p, const unsigned int d,
                         std::array<T, dim + 2> &F)
  {
    const T ud = U[1 + d] / U[0];
    F[0]       = U[1 + d];
    for (int k = 0; k < dim; ++k)
      F[1 + k] = U[1 + k] * ud;
    F[1 + d] += p;
    F[dim + 1] = (U[dim + 1] + p) * ud;
  }
} // namespace granhydro::physics
