#pragma once
/**
 * @file boundary_conditions.h
 * The kinds of domain boundary. The ground floor of the boundary layer: mesh,
 * convection and the scene name them, none of them owns them.
 */
#include <granhydro/base/enum_names.h>

#include <array>

namespace granhydro::boundary
{
  enum class BoundaryType
  {
    periodic,
    slip_wall,
    no_slip_wall,
    outflow
  };
  /// Domain/Boundary x- ... z+
  constexpr auto enum_names(BoundaryType)
  {
    return enum_table(
      EnumName{BoundaryType::periodic, "periodic"}, EnumName{BoundaryType::slip_wall, "slip wall"},
      EnumName{BoundaryType::no_slip_wall, "no-slip wall"}, EnumName{BoundaryType::outflow, "outflow"});
  }
  static_assert(check_enum_names(enum_names(BoundaryType{})));

  /// a wall (slip or no-slip): the mass and energy fluxes through it are 0, its ghosts mirror
  constexpr bool is_wall(const BoundaryType t)
  {
    return t == BoundaryType::slip_wall || t == BoundaryType::no_slip_wall;
  }
} // namespace granhydro::boundary
