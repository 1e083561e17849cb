#pragma once
/**
 * @file settings.h
 * What the mesh needs to know: the box or the mesh file, the refinement levels and the
 * boundaries (their kinds and wall velocities). scene/ fills it (Scene::mesh_settings());
 * the mesh never sees the scene.
 */
#include <granhydro/base/enum_names.h>
#include <granhydro/boundary/wall_settings.h>

#include <array>
#include <string>

namespace granhydro::mesh
{
  /// refinement levels a cell may have above the lattice: 0 .. max_levels - 1
  /// (Adaptivity/Maximum level <= max_levels - 1); the operators keep their geometry per level
  constexpr unsigned int max_levels = 8;

  struct MeshSettings
  {
    /// coarse mesh file (gmsh .msh or ucd .inp, resolved path; empty: the box below)
    std::string  mesh_file;
    unsigned int mesh_refinements = 0; ///< global refinements of the file's coarse mesh
    /// the box [m] and its level-0 cells (the first dim entries are used)
    std::array<double, 3>       lower{{0, 0, 0}}, upper{{1, 1, 1}};
    std::array<unsigned int, 3> cells{{1, 1, 1}};
    /// refinement levels above `cells` (adaptive boxes; 0 = uniform)
    unsigned int max_level = 0;
    /// walls[2 d] lower side, walls[2 d + 1] upper side of direction d; with a mesh file,
    /// walls[i] applies to the faces with boundary id i (the mesh reads the kinds and the
    /// wall velocities [m/s])
    boundary::WallSettingsTable walls{};
    /// the velocity unit [m/s] (wall velocities are stored scaled)
    double velocity_unit = 1;
  };

  /// Adaptivity/Indicator: what marks a cell for refinement
  enum class RefinementIndicator
  {
    jumps,              ///< relative jumps of density and pressure across its faces
    second_differences, ///< Loehner's normalised second differences of density and pressure
    packing_fraction    ///< absolute jumps of the packing fraction across its faces (granular)
  };
  constexpr auto enum_names(RefinementIndicator)
  {
    return enum_table(EnumName{RefinementIndicator::jumps, "jumps"},
                      EnumName{RefinementIndicator::second_differences, "second differences"},
                      EnumName{RefinementIndicator::packing_fraction, "packing fraction"});
  }
  static_assert(check_enum_names(enum_names(RefinementIndicator{})));

  /// Adaptivity/Refine threshold, Coarsen threshold, Buffer cells, Indicator
  struct RefinementIndicatorSettings
  {
    double              refine_threshold = 0, coarsen_threshold = 0;
    unsigned int        buffer    = 0; ///< cells marked around each refined one (passes)
    RefinementIndicator indicator = RefinementIndicator::jumps;
  };

} // namespace granhydro::mesh
