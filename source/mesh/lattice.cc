#include <granhydro/mesh/lattice.h>
#include <granhydro/mesh/mesh_file.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>

namespace granhydro
{
  using namespace dealii;

  std::vector<long long> all_gather(const std::vector<long long> &mine, const MPI_Comm comm)
  {
    const int        nranks = Utilities::MPI::n_mpi_processes(comm);
    std::vector<int> counts(nranks), displs(nranks);
    int              mycount = mine.size();
    MPI_Allgather(&mycount, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
    long long total = 0;
    for (int r = 0; r < nranks; ++r)
      {
        displs[r] = total;
        total += counts[r];
      }
    std::vector<long long> all(total);
    MPI_Allgatherv(mine.data(), mycount, MPI_LONG_LONG, all.data(), counts.data(),
                   displs.data(), MPI_LONG_LONG, comm);
    return all;
  }

  template <int dim>
  Lattice<dim>::Lattice(const std::array<unsigned int, 3> &N, const std::array<bool, 3> &periodic,
                        const unsigned int max_level, const unsigned int ghost_width,
                        const WallTable &walls, const bool subset)
    : N(N)
    , periodic(periodic)
    , m(max_level)
    , G(ghost_width)
    , walls(walls)
    , subset_(subset)
    , E(2 * ghost_width + 2)
  {
    for (unsigned int d = 0; d < dim; ++d)
      Nf[d] = (long long)(N[d]) << m;
  }

  template <int dim>
  std::vector<OwnedCell> Lattice<dim>::owned_cells(const DoFHandler<dim> &dofh,
                                                   const std::array<double, 3> &lo,
                                                   const std::array<double, 3> &h,
                                                   const unsigned int base_level,
                                                   std::vector<long long> *boundary_faces) const
  {
    const unsigned int nc = dofh.get_fe().n_components();
    std::vector<OwnedCell> owned;
    std::vector<types::global_dof_index> dofs(nc);
    for (const auto &cell : dofh.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int c = 1; c < nc; ++c)
            AssertThrow(dofs[c] == dofs[0] + c, ExcMessage("DG0 DoFs of a cell must be consecutive"));
          const unsigned int k = cell->level() - base_level;
          AssertThrow(k <= m, ExcMessage("cell above the maximum level"));
          const Point<dim>   x = cell->center();
          std::array<int, 3> ijk{{0, 0, 0}};
          Position           corner{{0, 0, 0}};
          for (unsigned int d = 0; d < dim; ++d)
            {
              ijk[d]    = static_cast<int>(std::floor((x[d] - lo[d]) / (h[d] / double(1u << k))));
              corner[d] = (long long)(ijk[d]) << (m - k);
            }
          const long long fk = fine_key(corner);
          owned.push_back({dofs[0], fk * 8 + k, cell->active_cell_index(), k, ijk});
          if (boundary_faces)
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary() && !cell->has_periodic_neighbor(f))
                {
                  const auto [d, upper]        = face_direction(cell, f);
                  const types::boundary_id id = cell->face(f)->boundary_id();
                  AssertThrow(id < 2 * dim, ExcMessage("boundary id out of range"));
                  boundary_faces->push_back((fk * 2 * dim + 2 * d + upper) * 8 + id);
                }
        }
    std::sort(owned.begin(), owned.end(),
              [](const OwnedCell &a, const OwnedCell &b) { return a.first < b.first; });
    return owned;
  }

  template <int dim>
  void Lattice<dim>::cover(const std::vector<long long> &all, const unsigned long long n_global)
  {
    AssertThrow(all.size() == 2 * n_global,
                ExcMessage(subset_ ? "mesh is not the expected lattice" : "mesh is not the expected octree"));
    const long long n_fine = Nf[0] * Nf[1] * Nf[2];
    cover_first.assign(n_fine, -1);
    cover_level.assign(n_fine, -1);
    for (std::size_t i = 0; i < all.size(); i += 2)
      {
        const long long    fk   = all[i] >> 3;
        const unsigned int k    = all[i] & 7;
        const long long    span = 1ll << (m - k);
        const Position     c{{fk % Nf[0], (fk / Nf[0]) % Nf[1], fk / (Nf[0] * Nf[1])}};
        for (long long z = 0; z < (dim > 2 ? span : 1); ++z)
          for (long long y = 0; y < (dim > 1 ? span : 1); ++y)
            for (long long x = 0; x < span; ++x)
              {
                const long long q = fine_key({{c[0] + x, c[1] + y, c[2] + z}});
                AssertThrow(all[i] >= 0 && q < n_fine && cover_first[q] < 0,
                            ExcMessage("two cells on one lattice point"));
                cover_first[q] = all[i + 1];
                cover_level[q] = k;
              }
      }
  }

  template <int dim>
  void Lattice<dim>::set_boundary_faces(std::vector<long long> all)
  {
    bfaces = std::move(all);
    std::sort(bfaces.begin(), bfaces.end());
  }

  template <int dim>
  long long Lattice<dim>::corner_key(const unsigned int k, const Position &p) const
  {
    Position c{{0, 0, 0}};
    for (unsigned int d = 0; d < dim; ++d)
      c[d] = p[d] << (m - k);
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
      if (e[d] < 0 || e[d] >= Nf[d])
        return false;
    return cover_level[fine_key(e)] >= 0;
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
    const int R = int(std::ceil(std::sqrt(double(dim)) * G));
    long long best_d2 = -1, best_key = 0;
    int       best_nnz = 0;
    Position  lo{{0, 0, 0}}, hi{{0, 0, 0}};
    for (unsigned int d = 0; d < dim; ++d)
      {
        lo[d] = std::max(e[d] - R, 0ll);
        hi[d] = std::min(e[d] + R, Nf[d] - 1);
      }
    for (long long z = lo[2]; z <= hi[2]; ++z)
      for (long long y = lo[1]; y <= hi[1]; ++y)
        for (long long x = lo[0]; x <= hi[0]; ++x)
          {
            const Position  c{{x, y, z}};
            const long long ck = fine_key(c);
            if (cover_level[ck] < 0)
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
    Position       q = mirror_across_walls<dim>(
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
  long long Lattice<dim>::same_level(const unsigned int k, Position p)
  {
    if (wrap(k, p))
      {
        const long long fk = corner_key(k, p);
        if (cover_level[fk] == int(k))
          return fk * 8 + k;
        if (cover_level[fk] >= 0)
          return no_slot_key;
      }
    // outside the lattice or a solid point: a wall (or outflow) ghost, the mirror (copy)
    // of the same-level cell inside
    long long ek = 0;
    for (int d = dim - 1; d >= 0; --d)
      ek = ek * (n(k, d) + 2 * E) + (p[d] + E);
    const long long key = -1 - (ek * 8 + k);
    if (ghosts.count(key))
      return key;
    WallGhost       gi;
    const Position  q  = mirror(k, p, gi.bg);
    const long long qk = corner_key(k, q);
    if (cover_level[qk] != int(k))
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
        p                  = {{fk % Nf[0], (fk / Nf[0]) % Nf[1], fk / (Nf[0] * Nf[1])}};
        for (unsigned int d = 0; d < dim; ++d)
          p[d] >>= (m - k);
      }
    else
      {
        const auto &gi = ghosts.at(key);
        k              = gi.level;
        p              = {{gi.pos[0], gi.pos[1], gi.pos[2]}};
      }
  }

  template <int dim>
  long long Lattice<dim>::covering(const unsigned int k, Position p) const
  {
    if (!wrap(k, p))
      return no_slot_key;
    const long long    fk = corner_key(k, p);
    const unsigned int l  = cover_level[fk];
    Position           c{{fk % Nf[0], (fk / Nf[0]) % Nf[1], fk / (Nf[0] * Nf[1])}};
    for (unsigned int d = 0; d < dim; ++d)
      c[d] = (c[d] >> (m - l)) << (m - l);
    return fine_key(c) * 8 + l;
  }

  template <int dim>
  long long Lattice<dim>::gradient_key(const long long key, const unsigned int j, const int o)
  {
    unsigned int k;
    Position     p;
    decode(key, k, p);
    p[j] += o;
    const long long t = same_level(k, p);
    if (t != no_slot_key)
      return t;
    const long long c = covering(k, p);
    return (c != no_slot_key && int(c & 7) < int(k)) ? c : no_slot_key;
  }

  template <int dim>
  int Lattice<dim>::face_id(const unsigned int k, const Position &p, const unsigned int lf) const
  {
    if (subset_)
      {
        // the boundary faces of the mesh file (level 0: the corner key is the cell's key)
        const long long code = (corner_key(k, p) * 2 * dim + lf) * 8;
        const auto      it   = std::lower_bound(bfaces.begin(), bfaces.end(), code);
        return (it != bfaces.end() && *it < code + 8) ? int(*it - code) : -1;
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
} // namespace granhydro
