#pragma once
/**
 * @file body_force.h
 * The body force per unit mass and its source (paper eq. 2.5 with m = 1, scaled
 * units): gravity g, to which a vibrated container, solved in the container's frame,
 * adds the inertial force of its motion (boundary/moving_frame.h, doc/physics.md 5.3):
 *
 *   g_eff(t) = g - s''(t),
 *   S(U) = (0, n g_eff, n u . g_eff).
 *
 * The diffusion step evaluates it at its stage times (source of the implicit step).
 */
#include <array>

namespace granhydro::physics
{
  struct BodyForce
  {
    std::array<double, 3> gravity{{0, 0, 0}}; ///< scaled units g L0 / V0^2

    bool active() const { return gravity[0] != 0 || gravity[1] != 0 || gravity[2] != 0; }

    /// adds S(U) = (0, n g, n u . g) for the force g (g_eff at a time) to S (U, S: dim + 2 values)
    template <int dim, class T = double>
    static void add_source(const std::array<double, 3> &g, const T *U, T *S)
    {
      for (unsigned int d = 0; d < dim; ++d)
        {
          S[1 + d] += U[0] * g[d];       // n g (m = 1)
          S[dim + 1] += U[1 + d] * g[d]; // m n u . g
        }
    }
  };
} // namespace granhydro::physics
