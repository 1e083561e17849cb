#pragma once
/**
 * @file boundary_ghost.h
 * A boundary-ghost slot of a CartesianPatch (mesh/cartesian_patch.h): the slot
 * behind a wall or outflow face whose state is a mirror or a copy of an interior
 * cell's. The mirror rule (boundary/wall_mirror.h) fills in the walls it lies
 * behind, the ghost-state rules (boundary/ghost_state.h) make its state.
 */
#include <array>

namespace granhydro::boundary
{
  /// a boundary-ghost slot: copy of slot source, momentum components with bit d of
  /// flip_mask set change sign (mirror at a slip wall normal to d)
  struct BoundaryGhost
  {
    unsigned int slot, source, flip_mask;
    /// true if any wall this ghost lies behind is a no-slip wall
    bool no_slip = false;
    /// the walls this ghost lies behind (1 at a face, 2 at an edge, 3 at a corner),
    /// applied in turn: slip wall flips the normal velocity, no-slip wall mirrors the
    /// velocity about the wall velocity u -> 2 u_w - u (scaled units); n and the
    /// internal energy are copied (doc/physics.md 5.1). wall_dir is the geometric normal
    /// direction, wall_id the boundary id (index of the scene's Boundary entry)
    unsigned int                         n_walls = 0;
    std::array<unsigned int, 3>          wall_dir{{0, 0, 0}};
    std::array<unsigned int, 3>          wall_id{{0, 0, 0}};
    std::array<bool, 3>                  wall_no_slip{{false, false, false}};
    std::array<std::array<double, 3>, 3> wall_velocity{};
  };
} // namespace granhydro::boundary
