#pragma once
/**
 * @file wall_settings.h
 * What one boundary is: its kind, the velocity of a moving (no-slip) wall and the
 * grain-wall restitution of a dissipative wall. One struct per boundary id (2 d +
 * upper for a box; a mesh file's ids); scene/ fills them (Scene::wall_settings()),
 * the mesh and both operators read the parts they need.
 */
#include <granhydro/boundary/boundary_conditions.h>

#include <array>

namespace granhydro::boundary
{
  struct WallSettings
  {
    BoundaryType          type = BoundaryType::periodic;
    std::array<double, 3> velocity{{0, 0, 0}}; ///< [m/s]; no-slip walls, tangential
    double                restitution = 1;     ///< grain-wall; < 1: dissipative wall heat flux
  };

  /// the settings of boundary ids 0 .. 5
  using WallSettingsTable = std::array<WallSettings, 6>;

  /// the walls as the mesh's mirror rule reads them (boundary/wall_mirror.h): the settings
  /// per boundary id and the velocity unit the wall velocities are scaled with
  struct WallTable
  {
    WallSettingsTable settings{};
    double            velocity_unit = 1; ///< [m/s]
  };
} // namespace granhydro::boundary
