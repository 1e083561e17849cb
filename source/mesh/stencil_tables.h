#pragma once
/**
 * @file stencil_tables.h
 * The slot numbering shared by the table builders of CartesianPatch (an internal part
 * of the patch; the builders are its private members, source/mesh/stencil_tables.cc).
 */
#include "lattice.h"

#include <algorithm>
#include <vector>

namespace granhydro
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
      Position                 lo{{0, 0, 0}}, n{{1, 1, 1}};
      std::size_t              count = 0;
      std::vector<int>         dense;
      FlatKeyMap<unsigned int> sparse;
      std::size_t idx(const Position &q) const
      {
        return std::size_t((q[0] - lo[0]) + n[0] * ((q[1] - lo[1]) + n[1] * (q[2] - lo[2])));
      }
      bool inside(const Position &q) const
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (q[d] < lo[d] || q[d] >= lo[d] + n[d])
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
              g.lo[d]            = g.count ? std::min<long long>(g.lo[d], pos[s][d]) : pos[s][d];
              hi[level[s]][d] = g.count ? std::max<long long>(hi[level[s]][d], pos[s][d]) : pos[s][d];
            }
          ++g.count;
        }
      for (std::size_t k = 0; k < levels.size(); ++k)
        {
          Level &g = levels[k];
          for (unsigned int d = 0; d < dim; ++d)
            g.n[d] = hi[k][d] - g.lo[d] + 1;
          const long long vol = g.n[0] * g.n[1] * g.n[2];
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
} // namespace granhydro
