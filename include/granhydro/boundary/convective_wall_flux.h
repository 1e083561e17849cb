#pragma once
/**
 * @file convective_wall_flux.h
 * The convective flux through a wall face. The numerical flux between the cell and its
 * mirror ghost (boundary/ghost_state.h) is corrected: walls do not move normally, so the
 * mass and energy fluxes there are exactly 0 whatever the ghost state (at concave
 * corners of a mesh file the nearest-fluid ghost is not an exact mirror for every
 * stencil), and closed domains conserve mass to round-off. A no-slip wall with the
 * paper's pressure flux (Numerics/No-slip wall flux = pressure) carries no tangential
 * momentum flux either, only the wall pressure acts (paper eq. 6.1a). Cohesionless
 * grains: a wall pushes, never pulls - the normal momentum flux (wall pressure) is at
 * least 0 (a cell receding from the wall faster than the flux's wave speeds allow
 * cavitates instead of being sucked back).
 *
 * The kind of each face is decided once per mesh (convective_wall_kind()), the flux
 * corrected per face per stage (apply_convective_wall_flux(): inline).
 */
#include <granhydro/boundary/wall_settings.h>

namespace granhydro::boundary
{
  /// how the convective flux of a face is corrected (a char per face)
  enum ConvectiveWallKind : char
  {
    not_a_wall    = 0, ///< the numerical flux as it is
    mirror_wall   = 1, ///< mass and energy flux 0
    pressure_wall = 2  ///< mass, energy and tangential momentum flux 0: the wall pressure only
  };

  /// the kind of a face on the wall w (a slip or no-slip wall); pressure_flux: no-slip
  /// walls take the paper's pressure flux
  inline char convective_wall_kind(const WallSettings &w, const bool pressure_flux)
  {
    return pressure_flux && w.type == BoundaryType::no_slip_wall ? pressure_wall : mirror_wall;
  }

  /// corrects the flux F (dim + 2 values) of a wall face of the given kind (not 0) normal
  /// to d; with no_tension a negative normal momentum flux becomes 0. Returns true if it
  /// did (the wall pulled).
  template <int dim>
  inline bool apply_convective_wall_flux(const char kind, const unsigned int d, double *F,
                                         const bool no_tension)
  {
    constexpr unsigned int NC = dim + 2;
    F[0] = F[NC - 1] = 0.;
    if (kind == pressure_wall)
      for (unsigned int j = 0; j < dim; ++j)
        if (j != d)
          F[1 + j] = 0.;
    if (no_tension && F[1 + d] < 0)
      {
        F[1 + d] = 0.;
        return true;
      }
    return false;
  }
} // namespace granhydro::boundary
