#pragma once
/**
 * @file wall_mirror.h
 * The wall mirror rule: where a ghost cell takes its state from.
 *
 * A lattice position e without a cell (outside the lattice, or a solid point of a
 * mesh file) takes the state of the fluid cell f nearest to it, mirrored across
 * each face of f that faces e: along every direction d with e_d != f_d, a wall
 * (slip or no-slip) reflects, src_d = 2 f_d - sign(f_d - e_d) - e_d, and an
 * outflow face copies, src_d = f_d. The boundary id of that face names the
 * wall. For a box, f is e clamped into the box, and the rule is the composed
 * reflection at faces, edges and corners.
 */
#include <granhydro/boundary/wall_settings.h>

#include <deal.II/base/exceptions.h>

#include <array>

namespace granhydro::boundary
{
  /**
   * The mirror point of e across the faces of the fluid cell f towards e (src above).
   * face_id(lf) is the boundary id of f's lattice face lf = 2 d + upper. The walls
   * crossed are recorded in ghost (a BoundaryGhost) in the order of the
   * directions (boundary/boundary_ghost.h): n_walls, wall_dir, wall_id, wall_no_slip, wall_velocity (scaled), no_slip
   * and flip_mask.
   */
  template <int dim, typename Ghost, typename FaceId>
  std::array<long long, 3> mirror_across_walls(const std::array<long long, 3> &e,
                                               const std::array<long long, 3> &f, const FaceId &face_id,
                                               const WallTable &walls, Ghost &ghost)
  {
    std::array<long long, 3> src  = e;
    unsigned int             flip = 0;
    for (unsigned int d = 0; d < dim; ++d)
      {
        const long long delta = f[d] - e[d];
        if (delta == 0)
          continue;
        const int sgn = delta > 0 ? 1 : -1;
        const int id  = face_id(2 * d + (delta > 0 ? 0 : 1));
        AssertThrow(id >= 0, dealii::ExcMessage("a boundary ghost faces a cell face without boundary id"));
        const BoundaryType t = walls.settings[id].type;
        if (t == BoundaryType::slip_wall || t == BoundaryType::no_slip_wall)
          {
            src[d] = 2 * f[d] - sgn - e[d];
            flip |= 1u << d;
            const unsigned int w  = ghost.n_walls++;
            ghost.wall_dir[w]     = d;
            ghost.wall_id[w]      = id;
            ghost.wall_no_slip[w] = t == BoundaryType::no_slip_wall;
            if (t == BoundaryType::no_slip_wall)
              {
                ghost.no_slip = true;
                for (unsigned int k = 0; k < 3; ++k)
                  ghost.wall_velocity[w][k] = walls.settings[id].velocity[k] / walls.velocity_unit;
              }
          }
        else
          src[d] = f[d]; // outflow: copy
      }
    ghost.flip_mask = flip;
    return src;
  }
} // namespace granhydro::boundary
