#pragma once
/**
 * @file mirror_ghost.h
 * The ghost state behind slip walls and outflow faces: a copy of the source cell's
 * conserved variables, the momentum component normal to each slip wall crossed
 * negated (the reflection), an outflow face copying unchanged. Per ghost slot per
 * gather: inline.
 */
#include <granhydro/boundary/boundary_ghost.h>

namespace granhydro::boundary
{
  /// out = in with the momentum components of the bits of g.flip_mask negated (dim + 2 values)
  template <int dim>
  inline void mirror_ghost_state(const BoundaryGhost &g, const double *in, double *out)
  {
    constexpr unsigned int NC = dim + 2;
    for (unsigned int c = 0; c < NC; ++c)
      {
        double v = in[c];
        if (c >= 1 && c <= dim && (g.flip_mask >> (c - 1) & 1u))
          v = -v;
        out[c] = v;
      }
  }

  /// the sign of each velocity component of the ghost relative to its source (bit d set:
  /// negated), the reflections of the slip walls
  inline unsigned int mirror_velocity_signs(const BoundaryGhost &g)
  {
    return g.flip_mask;
  }
} // namespace granhydro::boundary
