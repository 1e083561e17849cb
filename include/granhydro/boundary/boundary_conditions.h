#pragma once
/**
 * @file boundary_conditions.h
 * The kinds of domain boundary. The ground floor of the boundary layer: mesh,
 * convection and the scene name them, none of them owns them.
 */

namespace granhydro
{
  enum class BoundaryType
  {
    periodic,
    slip_wall,
    no_slip_wall,
    outflow
  };
} // namespace granhydro
