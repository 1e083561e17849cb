#include "lattice.h"

#include <granhydro/mesh/mesh_file.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>

namespace granhydro::mesh
{
  using namespace dealii;

  template <int dim>
  Lattice<dim>::Lattice(const std::array<unsigned int, 3> &N, const std::array<bool, 3> &periodic,
                        const unsigned int max_level, const unsigned int ghost_width,
                        const boundary::WallTable &walls, const bool subset)
    : cells_(N)
    , periodic(periodic)
    , max_level_(max_level)
    , ghost_width_(ghost_width)
    , walls(walls)
    , subset_(subset)
    , margin_(2 * ghost_width + 2)
  {
    for (unsigned int d = 0; d < dim; ++d)
      fine_cells_[d] = (long long)(cells_[d]) << max_level_;
  }

  template <int dim>
  std::vector<OwnedCell>
  Lattice<dim>::owned_cells(const DoFHandler<dim> &dofh, const std::array<double, 3> &lo,
                            const std::array<double, 3> &h, const unsigned int base_level) const
  {
    const unsigned int                   nc = dofh.get_fe().n_components();
    std::vector<OwnedCell>               owned;
    std::vector<types::global_dof_index> dofs(nc);
    for (const auto &cell : dofh.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int c = 1; c < nc; ++c)
            AssertThrow(dofs[c] == dofs[0] + c, ExcMessage("DG0 DoFs of a cell must be consecutive"));
          const unsigned int k = cell->level() - base_level;
          AssertThrow(k <= max_level_, ExcMessage("cell above the maximum level"));
          const Point<dim>   x = cell->center();
          std::array<int, 3> ijk{{0, 0, 0}};
          Position           corner{{0, 0, 0}};
          for (unsigned int d = 0; d < dim; ++d)
            {
              ijk[d]    = static_cast<int>(std::floor((x[d] - lo[d]) / (h[d] / double(1u << k))));
              corner[d] = (long long)(ijk[d]) << (max_level_ - k);
            }
          const long long fk    = fine_key(corner);
          int             faces = 0;
          if (subset_)
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary() && !cell->has_periodic_neighbor(f))
                {
                  const auto [d, upper]       = face_direction(cell, f);
                  const types::boundary_id id = cell->face(f)->boundary_id();
                  AssertThrow(id < 2 * dim, ExcMessage("boundary id out of range"));
                  faces |= int(id + 1) << (3 * (2 * d + upper));
                }
          owned.push_back({dofs[0], fk * 8 + k, cell->active_cell_index(), k, ijk, faces});
        }
    std::sort(owned.begin(), owned.end(),
              [](const OwnedCell &a, const OwnedCell &b) { return a.first < b.first; });
    return owned;
  }

  template <int dim>
  unsigned int Lattice<dim>::reach() const
  {
    return subset_ ? ghost_width_ + 2 * (unsigned int)(std::ceil(std::sqrt(double(dim)) * ghost_width_)) + 2 :
                     2 * ghost_width_ + 4;
  }

  template <int dim>
  long long Lattice<dim>::block_of(const long long fk) const
  {
    const Position c = fine_position(fk);
    return (c[0] >> max_level_) +
           (long long)(cells_[0]) * ((c[1] >> max_level_) + (long long)(cells_[1]) * (c[2] >> max_level_));
  }

  template <int dim>
  long long Lattice<dim>::window_index(const Position &c) const
  {
    return (c[0] - window_lo[0]) +
           window_n[0] * ((c[1] - window_lo[1]) + window_n[1] * (c[2] - window_lo[2]));
  }

  template <int dim>
  int Lattice<dim>::window_at(const long long fk, bool *missing) const
  {
    return window_at_point(fine_position(fk), missing);
  }

  template <int dim>
  int Lattice<dim>::window_at_point(const Position &c, bool *missing) const
  {
    bool inside = true;
    for (unsigned int d = 0; d < 3; ++d)
      inside = inside && c[d] >= window_lo[d] && c[d] < window_lo[d] + window_n[d];
    const int l = inside ? window_level[window_index(c)] : -2;
    if (l == -2 && missing)
      {
        *missing = true;
        return -2;
      }
    AssertThrow(l != -2, ExcMessage("internal error: a lattice point beyond the part of the mesh this rank "
                                    "fetched (Lattice::reach() too small)"));
    AssertThrow(l >= 0 || subset_, ExcMessage("mesh is not the expected octree"));
    return l;
  }

  template <int dim>
  int Lattice<dim>::level_from(const long long fk, const unsigned int k, bool *missing) const
  {
    if (!window_level.empty())
      return window_at(fk, missing);
    const Leaf *e = leaves.find(fk * 8 + k);
    if (e)
      {
        if (e->first >= 0)
          return k;
        // refined: the finer leaf at the same corner
        for (unsigned int l = k + 1; l <= max_level_; ++l)
          if ((e = leaves.find(fk * 8 + l)) && e->first >= 0)
            return l;
        AssertThrow(false, ExcMessage("mesh is not the expected octree"));
      }
    // a coarser leaf, or a solid point
    const Position c = fine_position(fk);
    for (int l = int(k) - 1; l >= 0; --l)
      {
        Position a = c;
        for (unsigned int d = 0; d < dim; ++d)
          a[d] = (c[d] >> (max_level_ - l)) << (max_level_ - l);
        if ((e = leaves.find(fine_key(a) * 8 + l)))
          {
            AssertThrow(e->first >= 0, ExcMessage("mesh is not the expected octree"));
            return l;
          }
      }
    if (missing && !blocks.count(block_of(fk)))
      {
        *missing = true;
        return -2;
      }
    AssertThrow(blocks.count(block_of(fk)),
                ExcMessage("internal error: a lattice point beyond the part of the mesh this rank "
                           "fetched (Lattice::reach() too small)"));
    AssertThrow(subset_, ExcMessage("mesh is not the expected octree"));
    return -1;
  }

  template <int dim>
  const typename Lattice<dim>::Leaf &Lattice<dim>::leaf(const long long key) const
  {
    const Leaf *l = key >= 0 ? leaves.find(key) : nullptr;
    AssertThrow(l != nullptr && l->first >= 0,
                ExcMessage("internal error: a leaf beyond the part of the mesh this rank fetched"));
    return *l;
  }

  template <int dim>
  long long Lattice<dim>::corner_key(const unsigned int k, const Position &p) const
  {
    Position c{{0, 0, 0}};
    for (unsigned int d = 0; d < dim; ++d)
      c[d] = p[d] << (max_level_ - k);
    return fine_key(c);
  }

  template <int dim>
  bool Lattice<dim>::wrap(const unsigned int k, Position &p) const
  {
    bool inside = true;
    for (unsigned int d = 0; d < dim; ++d)
      {
        const long long nk = n(k, d);
        if (periodic[d])
          {
            // positions lie a few cells outside at most: cheaper than a division
            while (p[d] < 0)
              p[d] += nk;
            while (p[d] >= nk)
              p[d] -= nk;
          }
        else if (p[d] < 0 || p[d] >= nk)
          inside = false;
      }
    return inside;
  }

  template <int dim>
  bool Lattice<dim>::fluid(const Position &e) const
  {
    for (unsigned int d = 0; d < 3; ++d)
      if (e[d] < 0 || e[d] >= fine_cells_[d])
        return false;
    return level_from(fine_key(e), max_level_) >= 0;
  }

  template <int dim>
  typename Lattice<dim>::Position Lattice<dim>::nearest_fluid(const unsigned int k, const Position &e) const
  {
    Position f = e;
    if (!subset_)
      {
        // a box: e clamped into it (periodic directions are never outside)
        for (unsigned int d = 0; d < dim; ++d)
          if (!periodic[d])
            f[d] = std::min(std::max(e[d], 0ll), n(k, d) - 1);
        return f;
      }
    // a lattice subset (level 0): smallest squared lattice distance; ties: fewest
    // nonzero offset components, then smallest key. Any position looked at has fluid
    // within R.
    const int R       = int(std::ceil(std::sqrt(double(dim)) * ghost_width_));
    long long best_d2 = -1, best_key = 0;
    int       best_nnz = 0;
    Position  lo{{0, 0, 0}}, hi{{0, 0, 0}};
    for (unsigned int d = 0; d < dim; ++d)
      {
        lo[d] = std::max(e[d] - R, 0ll);
        hi[d] = std::min(e[d] + R, fine_cells_[d] - 1);
      }
    for (long long z = lo[2]; z <= hi[2]; ++z)
      for (long long y = lo[1]; y <= hi[1]; ++y)
        for (long long x = lo[0]; x <= hi[0]; ++x)
          {
            const Position  c{{x, y, z}};
            const long long ck = fine_key(c);
            if (level_from(ck, max_level_) < 0)
              continue;
            long long d2  = 0;
            int       nnz = 0;
            for (unsigned int d = 0; d < dim; ++d)
              {
                d2 += (c[d] - e[d]) * (c[d] - e[d]);
                nnz += c[d] != e[d];
              }
            if (best_d2 < 0 || d2 < best_d2 ||
                (d2 == best_d2 && (nnz < best_nnz || (nnz == best_nnz && ck < best_key))))
              {
                best_d2  = d2;
                best_nnz = nnz;
                best_key = ck;
                f        = c;
              }
          }
    AssertThrow(best_d2 > 0, ExcMessage("no fluid cell near a boundary ghost"));
    return f;
  }

  template <int dim>
  typename Lattice<dim>::Position Lattice<dim>::mirror(const unsigned int k, const Position &p,
                                                       BoundaryGhost &bg) const
  {
    const Position f = nearest_fluid(k, p);
    Position       q = boundary::mirror_across_walls<dim>(
      p, f, [&](const unsigned int lf) { return face_id(k, f, lf); }, walls, bg);
    // the mirror point may lie beyond the lattice (a box thinner than the ghost layer:
    // clamp it) or be solid (a concave corner of a lattice subset: f itself)
    if (subset_)
      {
        if (!fluid(q))
          q = f;
      }
    else
      for (unsigned int d = 0; d < dim; ++d)
        if (!periodic[d])
          q[d] = std::min(std::max(q[d], 0ll), n(k, d) - 1);
    return q;
  }

  template <int dim>
  long long Lattice<dim>::same_level(const unsigned int k, Position p, bool *missing)
  {
    if (wrap(k, p))
      {
        if (!window_level.empty())
          {
            // the fine corner, without decoding a key (the hot path of the tables)
            Position c{{0, 0, 0}};
            for (unsigned int d = 0; d < dim; ++d)
              c[d] = p[d] << (max_level_ - k);
            const int l = window_at_point(c, missing);
            if (l == -2)
              return no_slot_key; // beyond the fetched blocks (*missing set)
            if (l == int(k))
              return fine_key(c) * 8 + k;
            if (l >= 0)
              return no_slot_key; // refined or coarser; l < 0: solid, a wall ghost below
          }
        else
          {
            const long long fk = corner_key(k, p);
            if (const Leaf *e = leaves.find(fk * 8 + k))
              return e->first >= 0 ? fk * 8 + k : no_slot_key; // a leaf, or refined
            const int l = level_from(fk, k, missing);
            if (l >= 0 || l == -2) // coarser, or beyond the fetched blocks (*missing set)
              return no_slot_key;
          }
      }
    // outside the lattice or a solid point: a wall (or outflow) ghost, the mirror (copy)
    // of the same-level cell inside
    const long long pk = position_key(k, p);
    AssertThrow(pk >= 0,
                ExcMessage("internal error: a wall ghost farther outside than the lattice keys reach"));
    const long long key = -1 - pk;
    if (ghosts.count(key))
      return key;
    WallGhost       gi;
    const Position  q  = mirror(k, p, gi.bg);
    const long long qk = corner_key(k, q);
    if (level_from(qk, k, missing) != int(k)) // beyond the fetched blocks: throws or sets *missing
      return no_slot_key;
    gi.source_key = qk * 8 + k;
    for (unsigned int d = 0; d < 3; ++d)
      gi.pos[d] = p[d];
    gi.level    = k;
    ghosts[key] = gi;
    return key;
  }

  template <int dim>
  void Lattice<dim>::decode(const long long key, unsigned int &k, Position &p) const
  {
    if (key >= 0)
      {
        k                  = key & 7;
        const long long fk = key >> 3;
        p                  = fine_position(fk);
        for (unsigned int d = 0; d < dim; ++d)
          p[d] >>= (max_level_ - k);
      }
    else
      {
        const auto &gi = ghosts.at(key);
        k              = gi.level;
        p              = {{gi.pos[0], gi.pos[1], gi.pos[2]}};
      }
  }

  template <int dim>
  long long Lattice<dim>::covering(const unsigned int k, Position p, bool *missing) const
  {
    if (!wrap(k, p))
      return no_slot_key;
    const long long fk = corner_key(k, p);
    const int       lv = level_from(fk, k, missing);
    if (lv < 0)
      return no_slot_key;
    const unsigned int l = lv;
    Position           c = fine_position(fk);
    for (unsigned int d = 0; d < dim; ++d)
      c[d] = (c[d] >> (max_level_ - l)) << (max_level_ - l);
    return fine_key(c) * 8 + l;
  }

  template <int dim>
  long long Lattice<dim>::gradient_key(const long long key, const unsigned int j, const int o, bool *missing)
  {
    unsigned int k;
    Position     p;
    decode(key, k, p);
    p[j] += o;
    const long long t = same_level(k, p, missing);
    if (t != no_slot_key || (missing && *missing))
      return t;
    const long long c = covering(k, p, missing);
    return (c != no_slot_key && int(c & 7) < int(k)) ? c : no_slot_key;
  }

  template <int dim>
  int Lattice<dim>::face_id(const unsigned int k, const Position &p, const unsigned int lf) const
  {
    if (subset_)
      {
        // the boundary faces of the mesh file (level 0: the corner key is the cell's key)
        return ((leaf(corner_key(k, p) * 8 + k).faces >> (3 * lf)) & 7) - 1;
      }
    // box faces are colorized: id 2 d + upper
    const unsigned int d = lf / 2;
    if (periodic[d])
      return -1;
    if (lf % 2 == 0)
      return p[d] == 0 ? int(lf) : -1;
    return p[d] == n(k, d) - 1 ? int(lf) : -1;
  }

  template class Lattice<1>;
  template class Lattice<2>;
  template class Lattice<3>;
} // namespace granhydro::mesh
