#pragma once
/**
 * @file stencil_tables.h
 * The table builders of CartesianPatch and the slot numbering they share (an internal
 * part of the patch: source/mesh, not installed). CartesianPatch::rebuild() runs them in
 * turn on the lattice, the virtual cells and the keys the ghost layer needs; they fill
 * the patch's SlotTables (mesh/patch_tables.h), source/mesh/stencil_tables.cc.
 */
#include <granhydro/mesh/patch_tables.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/partitioner.h>

#include "ghost_layer.h"
#include "lattice.h"

#include <algorithm>
#include <memory>
#include <vector>

namespace granhydro::mesh
{
  /// slot of each key (lattice.h) and key of each slot (no_slot_key for virtual cells)
  struct SlotIndex
  {
    FlatKeyMap<unsigned int> slot_of;
    std::vector<long long>   keys;
    /// the first virtual cell's slot (virtual cells come last)
    unsigned int first_virtual = 0;
    /// the slot of a key, or -1
    int operator()(const long long key) const
    {
      if (key == no_slot_key)
        return -1;
      const unsigned int *s = slot_of.find(key);
      return s ? int(*s) : -1;
    }
  };

  /**
   * The slot at each position (level k, lattice coordinates at level k, periodic
   * directions wrapped): every slot has one such position, and a position without a
   * slot gives -1. Per level a dense grid over the bounding box of that level's slots,
   * or a hash map (Lattice::position_key) where that box would be much larger than the
   * slots (a scattered level).
   */
  template <int dim>
  class SlotGrid
  {
  public:
    using Position = typename Lattice<dim>::Position;
    struct Level
    {
      Position                 lower{{0, 0, 0}}, extent{{1, 1, 1}}; ///< the grid's box
      std::size_t              count = 0;
      std::vector<int>         dense;
      FlatKeyMap<unsigned int> sparse;
      std::size_t              idx(const Position &q) const
      {
        return std::size_t((q[0] - lower[0]) +
                           extent[0] * ((q[1] - lower[1]) + extent[1] * (q[2] - lower[2])));
      }
      bool inside(const Position &q) const
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (q[d] < lower[d] || q[d] >= lower[d] + extent[d])
            return false;
        return true;
      }
    };

    /// pos, level: each slot's position and level; a level's grid is dense when its box
    /// holds at most dense_factor x its slots + 4096 points (dense_factor < 0: never,
    /// for tests)
    SlotGrid(const Lattice<dim> &lattice, const std::vector<std::array<int, 3>> &pos,
             const std::vector<unsigned char> &level, const long long dense_factor = 8)
      : lattice(lattice)
      , levels(lattice.max_level() + 1)
    {
      std::vector<Position> hi(levels.size(), Position{{0, 0, 0}}); // the boxes' last points
      for (std::size_t s = 0; s < pos.size(); ++s)
        {
          Level &g = levels[level[s]];
          for (unsigned int d = 0; d < dim; ++d)
            {
              g.lower[d]      = g.count ? std::min<long long>(g.lower[d], pos[s][d]) : pos[s][d];
              hi[level[s]][d] = g.count ? std::max<long long>(hi[level[s]][d], pos[s][d]) : pos[s][d];
            }
          ++g.count;
        }
      for (std::size_t k = 0; k < levels.size(); ++k)
        {
          Level &g = levels[k];
          for (unsigned int d = 0; d < dim; ++d)
            g.extent[d] = hi[k][d] - g.lower[d] + 1;
          const long long vol = g.extent[0] * g.extent[1] * g.extent[2];
          if (g.count && dense_factor >= 0 && vol <= dense_factor * (long long)(g.count) + 4096)
            g.dense.assign(vol, -1);
          else
            g.sparse.reserve(g.count);
        }
      for (std::size_t s = 0; s < pos.size(); ++s)
        {
          Level         &g = levels[level[s]];
          const Position p{{pos[s][0], pos[s][1], pos[s][2]}};
          if (!g.dense.empty())
            g.dense[g.idx(p)] = s;
          else
            g.sparse.insert(lattice.position_key(level[s], p), s);
        }
    }
    /// the slot at q of level k (wrapped here), or -1
    int operator()(const unsigned int k, Position q) const
    {
      lattice.wrap(k, q);
      const Level &g = levels[k];
      if (!g.dense.empty())
        return g.inside(q) ? g.dense[g.idx(q)] : -1;
      const long long     pk = lattice.position_key(k, q);
      const unsigned int *t  = pk >= 0 ? g.sparse.find(pk) : nullptr;
      return t ? int(*t) : -1;
    }
    const Level &level(const unsigned int k) const { return levels[k]; }

  private:
    const Lattice<dim> &lattice;
    std::vector<Level>  levels;
  };

  /// the slots: owned cells in DoF order, MPI ghosts in DoF order, wall ghosts by key,
  /// virtual cells (tables: positions, levels, n_mpi_ghosts, boundary_ghosts,
  /// virtual_cells; active_index: of the owned cells; index); returns the state vector's
  /// partitioner with the MPI ghosts (collective). tables.n_owned is set
  template <int dim>
  std::shared_ptr<const dealii::Utilities::MPI::Partitioner>
  assign_slots(const std::vector<OwnedCell> &owned, const std::vector<long long> &needed,
               const Lattice<dim> &lattice, const VirtualCells<dim> &virtuals,
               const dealii::IndexSet &owned_dofs, const MPI_Comm comm, SlotTables &tables,
               std::vector<unsigned int> &active_index, SlotIndex &index);
  /// boundary ids of the real cells' faces (tables.face_boundary_ids)
  template <int dim>
  void make_face_ids(const Lattice<dim> &lattice, SlotTables &tables);
  /// neighbour table and uniform flags (grid: the slot at each position; mask: a mesh
  /// file's dilated mask, the positions whose rows exist, nullptr for all; full_box: the
  /// stencil closure's flags per owned cell, or empty to look)
  template <int dim>
  void make_neighbor_table(Lattice<dim> &lattice, const VirtualCells<dim> &virtuals, const SlotIndex &index,
                           const SlotGrid<dim> &grid, const DilatedMask<dim> *mask,
                           const std::vector<char> &full_box, const LatticeGeometry &geometry,
                           SlotTables &tables);
  /// gradient neighbours and offsets (rows: per slot, whether its row is read, i.e. owned
  /// cells and face cells; incomplete: per slot, 1 if a neighbour lies beyond the fetched
  /// blocks)
  template <int dim>
  void make_gradient_table(Lattice<dim> &lattice, const SlotIndex &index, const SlotGrid<dim> &grid,
                           const DilatedMask<dim> *mask, const std::vector<char> &rows,
                           const LatticeGeometry &geometry, SlotTables &tables,
                           std::vector<char> &incomplete);
  /// faces from each owned cell's face-neighbour lists per direction and side (start,
  /// slots: FaceKeys with the keys' slots)
  template <int dim>
  void make_faces(const std::vector<unsigned int> &start, const std::vector<unsigned int> &slots,
                  SlotTables &tables);
} // namespace granhydro::mesh
