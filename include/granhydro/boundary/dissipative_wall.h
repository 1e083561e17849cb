#pragma once
/**
 * @file dissipative_wall.h
 * The dissipative wall (doc/physics.md 5.2): a wall with grain-wall restitution
 * eps_w < 1 takes energy out of the grains next to it, the heat flux q_w into the wall
 * from the contact theorem (the physics formula: GranularGas::wall_heat_flux). Which
 * faces carry it is decided once per mesh (dissipative_wall_face()); the diffusion
 * operator adds it to the energy flux of those faces (add_wall_heat_flux(): inline).
 */
#include <granhydro/boundary/wall_settings.h>

namespace granhydro::boundary
{
  /// a face on a dissipative wall: eps_w and the sign of the wall's outward normal
  /// along d (-1 lower wall: interior on the right; +1 upper wall); sign 0: no wall
  struct DissipativeWallFace
  {
    double eps_w = 1;
    int    sign  = 0;
  };

  /// the face between a cell and a ghost behind the wall w: cell_low if the cell is on
  /// the low side (the wall's outward normal points up). The sign comes from the
  /// geometry (which side the cell is on), not from the boundary id (mesh files).
  inline DissipativeWallFace dissipative_wall_face(const WallSettings &w, const bool cell_low)
  {
    if (w.restitution < 1)
      return {w.restitution, cell_low ? +1 : -1};
    return DissipativeWallFace();
  }

  /// the energy into the wall (m = 1) added to the energy flux F_E of the face: the cell
  /// update is (F_e - F_w)/dx, so a loss through the upper wall (the cell's east face)
  /// needs F_E -= q_w, through the lower wall (west face) F_E += q_w. desc.wall_heat_flux()
  /// is the physics formula, U the state of the cell next to the wall.
  template <class Description, class State>
  inline void add_wall_heat_flux(const DissipativeWallFace &wall, const Description &desc, const State &U,
                                 double &F_E)
  {
    F_E -= wall.sign * desc.wall_heat_flux(U, wall.eps_w);
  }
} // namespace granhydro::boundary
