#pragma once
/**
 * @file ghost_state.h
 * Which ghost-state rule a boundary ghost follows: the no-slip rule
 * (boundary/no_slip_ghost.h) if any wall it lies behind is a no-slip wall, else the
 * mirror (boundary/mirror_ghost.h; slip walls reflect, outflow faces copy). The mesh
 * fills its ghost slots with ghost_state() (CartesianPatch::gather); the diffusion
 * Jacobian maps a ghost's derivatives to its source with ghost_velocity_signs().
 */
#include <granhydro/boundary/mirror_ghost.h>
#include <granhydro/boundary/no_slip_ghost.h>

namespace granhydro::boundary
{
  /// out = the state of ghost g from its source's state in (dim + 2 conserved values)
  template <int dim>
  inline void ghost_state(const BoundaryGhost &g, const double *in, double *out)
  {
    if (g.no_slip)
      no_slip_ghost_state<dim>(g, in, out);
    else
      mirror_ghost_state<dim>(g, in, out);
  }

  /// the sign of each velocity component of ghost g relative to its source (bit d set:
  /// negated; exact for walls at rest)
  template <int dim>
  inline unsigned int ghost_velocity_signs(const BoundaryGhost &g)
  {
    return g.no_slip ? no_slip_velocity_signs<dim>(g) : mirror_velocity_signs(g);
  }
} // namespace granhydro::boundary
