#pragma once
/**
 * @file no_slip_ghost.h
 * The ghost state behind a no-slip wall (doc/physics.md 5.1): the walls the ghost lies
 * behind applied in turn, a no-slip wall mirroring the velocity about the wall velocity,
 * u -> 2 u_w - u, a slip wall negating its normal component; n and the internal energy
 * are copied (the total energy takes the ghost's kinetic energy). With the wall at rest
 * the velocity on the wall is 0, moving tangentially it is u_w (a shearing lid). Per
 * ghost slot per gather: inline.
 */
#include <granhydro/boundary/boundary_ghost.h>

namespace granhydro::boundary
{
  /// out = the no-slip ghost state of in (dim + 2 conserved values; g.no_slip)
  template <int dim>
  inline void no_slip_ghost_state(const BoundaryGhost &g, const double *in, double *out)
  {
    // compose the wall reflections; n and the internal energy are copied
    const double n    = in[0];
    double       u[3] = {0, 0, 0}, ke = 0, keg = 0;
    for (unsigned int k = 0; k < dim; ++k)
      {
        u[k] = in[1 + k] / n;
        ke += 0.5 * n * u[k] * u[k];
      }
    for (unsigned int w = 0; w < g.n_walls; ++w)
      if (g.wall_no_slip[w])
        for (unsigned int k = 0; k < dim; ++k)
          u[k] = 2 * g.wall_velocity[w][k] - u[k];
      else
        u[g.wall_dir[w]] = -u[g.wall_dir[w]];
    out[0] = n;
    for (unsigned int k = 0; k < dim; ++k)
      {
        out[1 + k] = n * u[k];
        keg += 0.5 * n * u[k] * u[k];
      }
    out[dim + 1] = in[dim + 1] - ke + keg;
  }

  /// the sign of each velocity component of the ghost relative to its source after all
  /// reflections (bit d set: negated; the derivative for walls at rest): a no-slip wall
  /// negates every component, a slip wall its normal one
  template <int dim>
  inline unsigned int no_slip_velocity_signs(const BoundaryGhost &g)
  {
    unsigned int m = 0;
    for (unsigned int w = 0; w < g.n_walls; ++w)
      m ^= g.wall_no_slip[w] ? (1u << dim) - 1 : 1u << g.wall_dir[w];
    return m;
  }
} // namespace granhydro::boundary
