#include "stencil_tables.h"

#include "flat_key_map.h"
#include "ghost_layer.h"

#include <map>

namespace granhydro::mesh
{
  using namespace dealii;

  template <int dim>
  std::shared_ptr<const Utilities::MPI::Partitioner>
  assign_slots(const std::vector<OwnedCell> &owned, const std::vector<long long> &needed,
               const Lattice<dim> &lattice, const VirtualCells<dim> &virtuals, const IndexSet &owned_dofs,
               const MPI_Comm comm, SlotTables &tables, std::vector<unsigned int> &active_index,
               SlotIndex &index)
  {
    constexpr unsigned int n_components = dim + 2;
    // owned cells in DoF order, MPI ghosts in DoF order, wall ghosts by key, virtual cells
    tables.positions.clear();
    tables.levels.clear();
    active_index.clear();
    index.slot_of.clear();
    index.keys.clear();
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        index.slot_of[owned[i].key] = i;
        index.keys.push_back(owned[i].key);
        tables.positions.push_back(owned[i].ijk);
        tables.levels.push_back(owned[i].level);
        active_index.push_back(owned[i].active);
      }
    std::vector<std::pair<long long, long long>> mpi_ghosts; // (first dof, key)
    for (const long long t : needed)
      if (t >= 0 && !index.slot_of.count(t))
        mpi_ghosts.emplace_back(lattice.first_dof(t), t);
    std::sort(mpi_ghosts.begin(), mpi_ghosts.end());
    IndexSet ghost_dofs(owned_dofs.size());
    for (const auto &[first, key] : mpi_ghosts)
      {
        index.slot_of[key] = tables.positions.size();
        unsigned int                    k;
        typename Lattice<dim>::Position p;
        lattice.decode(key, k, p);
        tables.positions.push_back({{int(p[0]), int(p[1]), int(p[2])}});
        tables.levels.push_back(k);
        index.keys.push_back(key);
        ghost_dofs.add_range(first, first + n_components);
      }
    tables.n_mpi_ghosts = mpi_ghosts.size();
    ghost_dofs.compress();
    const auto partitioner =
      std::make_shared<const Utilities::MPI::Partitioner>(owned_dofs, ghost_dofs, comm);
    tables.boundary_ghosts.clear();
    for (const long long t : needed)
      if (t < 0)
        {
          const auto &gi   = lattice.ghost(t);
          index.slot_of[t] = tables.positions.size();
          tables.positions.push_back(gi.pos);
          tables.levels.push_back(gi.level);
          index.keys.push_back(t);
        }
    for (const long long t : needed)
      if (t < 0)
        {
          boundary::BoundaryGhost bg = lattice.ghost(t).bg;
          bg.slot                    = index.slot_of.at(t);
          bg.source                  = index.slot_of.at(lattice.ghost(t).source_key);
          tables.boundary_ghosts.push_back(bg);
        }
    index.first_virtual = tables.positions.size();
    const auto &vcells  = virtuals.cells();
    for (const auto &v : vcells)
      {
        tables.positions.push_back({{int(v.pos[0]), int(v.pos[1]), int(v.pos[2])}});
        tables.levels.push_back(v.level);
        index.keys.push_back(no_slot_key);
      }
    tables.virtual_cells.clear();
    for (unsigned int i = 0; i < vcells.size(); ++i)
      if (vcells[i].ghost)
        {
          boundary::BoundaryGhost bg = vcells[i].bg;
          bg.slot                    = index.first_virtual + i;
          bg.source                  = index.first_virtual + vcells[i].mirror;
          tables.boundary_ghosts.push_back(bg);
        }
      else
        {
          VirtualSlot vc;
          vc.slot = index.first_virtual + i;
          for (const auto &[t, w] : vcells[i].sources)
            vc.sources.emplace_back(index.slot_of.at(t), w);
          tables.virtual_cells.push_back(vc);
        }
    // push_back's growth leaves up to half of the capacity unused
    tables.positions.shrink_to_fit();
    tables.levels.shrink_to_fit();
    tables.boundary_ghosts.shrink_to_fit();
    active_index.shrink_to_fit();
    return partitioner;
  }

  template <int dim>
  void make_face_ids(const Lattice<dim> &lattice, SlotTables &tables)
  {
    tables.face_boundary_ids.assign(std::size_t(tables.n_owned + tables.n_mpi_ghosts) * 2 * dim, -1);
    for (unsigned int s = 0; s < tables.n_owned + tables.n_mpi_ghosts; ++s)
      for (unsigned int lf = 0; lf < 2 * dim; ++lf)
        tables.face_boundary_ids[std::size_t(s) * 2 * dim + lf] = lattice.face_id(
          tables.levels[s], {{tables.positions[s][0], tables.positions[s][1], tables.positions[s][2]}}, lf);
  }

  template <int dim>
  void make_neighbor_table(Lattice<dim> &lattice, const VirtualCells<dim> &virtuals, const SlotIndex &index,
                           const SlotGrid<dim> &grid, const DilatedMask<dim> *mask,
                           const std::vector<char> &full_box, const LatticeGeometry &geometry,
                           SlotTables &tables)
  {
    const unsigned int G  = tables.ghost_width;
    using Position        = typename Lattice<dim>::Position;
    const unsigned int ns = tables.positions.size();
    // the slot at position q of level k: a leaf or wall ghost of that level, or a virtual
    // cell. Every slot gets a row, also the far ones (the sources of virtual cells, MPI
    // ghosts reached by gradients) whose rows no stencil reads; their entries beyond the
    // lattice blocks this rank fetched are -1 (a stencil that needs one stops the
    // convection operator's setup with an internal error, it is never read silently).
    // The slots are found by position (SlotGrid): what the lattice and the virtual
    // cells would answer (a leaf or wall ghost without a slot, a position beyond the
    // fetched blocks, a refined or coarser neighbourhood without a virtual cell: -1).
    auto slot_at = [&](const unsigned int k, Position q) -> int {
      if (mask) // a mesh file: the lattice and the index (rows within the dilated mask)
        {
          bool            missing = false;
          const long long t       = lattice.same_level(k, q, &missing);
          if (missing)
            return -1;
          if (t != no_slot_key)
            return index(t);
          const int v = virtuals.find(k, q);
          return v < 0 ? -1 : int(index.first_virtual + v);
        }
      return grid(k, q);
    };
    const int          r = int(G) - 1;
    const unsigned int W = 2 * G + 1;
    if (mask)
      tables.neighbors.assign(std::size_t(ns) * dim * W, -1);
    else
      tables.neighbors.resize(std::size_t(ns) * dim * W); // every entry is written below
    tables.uniform.assign(ns, 0);
    for (unsigned int s = 0; s < ns; ++s)
      {
        const unsigned int k = tables.levels[s];
        const Position     p0{{tables.positions[s][0], tables.positions[s][1], tables.positions[s][2]}};
        const bool         row = !mask || mask->contains(p0);
        const auto        &g   = grid.level(k);
        for (unsigned int d = 0; d < dim && row; ++d)
          {
            int            *out = &tables.neighbors[(std::size_t(s) * dim + d) * W];
            const long long a = p0[d] - int(G), b = p0[d] + int(G);
            if (!mask && !g.dense.empty() && a >= g.lower[d] && b < g.lower[d] + g.extent[d] &&
                (!geometry.periodic[d] || (a >= 0 && b < lattice.n(k, d))))
              {
                // the whole row inside the grid and nothing to wrap: a strided copy
                const long long stride = d == 0 ? 1 : d == 1 ? g.extent[0] : g.extent[0] * g.extent[1];
                const int      *in     = &g.dense[g.idx(p0) - std::size_t(G * stride)];
                for (unsigned int o = 0; o < W; ++o)
                  out[o] = in[o * stride];
                continue;
              }
            for (int o = -int(G); o <= int(G); ++o)
              {
                Position q = p0;
                q[d] += o;
                if (!mask || mask->contains(q))
                  out[o + int(G)] = slot_at(k, q);
              }
          }
        bool ok = s < tables.n_owned; // the flag is for owned cells (output) only
        if (ok && !full_box.empty())
          ok = full_box[s] != 0; // slots of owned cells are in owned order
        else
          for (int z = (dim > 2 ? -r : 0); z <= (dim > 2 ? r : 0) && ok; ++z)
            for (int y = (dim > 1 ? -r : 0); y <= (dim > 1 ? r : 0) && ok; ++y)
              for (int x = -r; x <= r && ok; ++x)
                ok = index(lattice.same_level(k, {{p0[0] + x, p0[1] + y, p0[2] + z}})) >= 0;
        tables.uniform[s] = ok ? 1 : 0;
      }
  }

  template <int dim>
  void make_gradient_table(Lattice<dim> &lattice, const SlotIndex &index, const SlotGrid<dim> &grid,
                           const DilatedMask<dim> *mask, const std::vector<char> &rows,
                           const LatticeGeometry &geometry, SlotTables &tables, std::vector<char> &incomplete)
  {
    using Position        = typename Lattice<dim>::Position;
    const unsigned int ns = tables.positions.size();
    incomplete.assign(ns, 0);
    std::vector<std::array<double, 3>> size(lattice.max_level() + 1); // cell_size() per level
    for (unsigned int k = 0; k <= lattice.max_level(); ++k)
      for (unsigned int j = 0; j < dim; ++j)
        size[k][j] = geometry.cell_size[j] / double(1u << k);
    tables.gradient_neighbors.assign(std::size_t(ns) * dim * 2, -1);
    tables.gradient_offsets.assign(std::size_t(ns) * dim * 2, 0.);
    for (unsigned int s = 0; s < index.first_virtual; ++s)
      for (unsigned int j = 0; j < dim && rows[s]; ++j)
        for (unsigned int side = 0; side < 2; ++side)
          {
            if (mask)
              {
                Position p{{tables.positions[s][0], tables.positions[s][1], tables.positions[s][2]}};
                if (!mask->contains(p))
                  continue;
                p[j] += side ? 1 : -1;
                if (!mask->contains(p))
                  continue;
              }
            // the same-level leaf or wall ghost: the slot at that position (a virtual
            // cell is none); else the lattice's answer (a coarser leaf, or none). Only
            // the rows that are read (rows[s]: owned and face cells) are made; rebuild()
            // checks that none of them reaches beyond the fetched blocks
            int t = -1;
            if (!mask)
              {
                Position q{{tables.positions[s][0], tables.positions[s][1], tables.positions[s][2]}};
                q[j] += side ? 1 : -1;
                t = grid(tables.levels[s], q);
                if (t >= int(index.first_virtual))
                  t = -1;
              }
            if (t < 0)
              {
                bool missing = false;
                t            = index(lattice.gradient_key(index.keys[s], j, side ? 1 : -1, &missing));
                if (missing)
                  incomplete[s] = 1;
              }
            tables.gradient_neighbors[(std::size_t(s) * dim + j) * 2 + side] = t;
            if (t >= 0)
              tables.gradient_offsets[(std::size_t(s) * dim + j) * 2 + side] =
                (side ? 0.5 : -0.5) * (size[tables.levels[s]][j] + size[tables.levels[t]][j]);
          }
  }

  template <int dim>
  void make_faces(const std::vector<unsigned int> &start, const std::vector<unsigned int> &slots,
                  SlotTables &tables)
  {
    const double sub = 1. / double(1u << (dim - 1)); // share of a fine sub-face
    // a face is made where its (left, right) pair is met first (owned cells in order,
    // lower side first); met again from an owned cell t it already visited (t < s, or
    // s itself across a periodic side one cell wide), the face is the one t's list
    // entry on the opposite side got
    std::vector<unsigned int> face_of(slots.size());
    for (unsigned int d = 0; d < dim; ++d)
      {
        tables.faces[d].clear();
        tables.cell_faces[d].clear();
        tables.cell_face_start[d].assign(tables.n_owned + 1, 0);
        for (unsigned int s = 0; s < tables.n_owned; ++s)
          {
            tables.cell_face_start[d][s] = tables.cell_faces[d].size();
            for (unsigned int side = 0; side < 2; ++side)
              for (unsigned int e = (std::size_t(s) * dim + d) * 2 + side, i = start[e]; i < start[e + 1];
                   ++i)
                {
                  const unsigned int t = slots[i];
                  const unsigned int l = side ? s : t, r = side ? t : s;
                  if (t < s || (t == s && side == 1))
                    {
                      const unsigned int e2 = (std::size_t(t) * dim + d) * 2 + (1 - side);
                      unsigned int       j  = start[e2];
                      while (j < start[e2 + 1] && slots[j] != s)
                        ++j;
                      AssertThrow(j < start[e2 + 1],
                                  ExcMessage("internal error: face neighbours not mutual"));
                      face_of[i] = face_of[j];
                    }
                  else
                    {
                      face_of[i]      = tables.faces[d].size();
                      const double fl = tables.levels[l] < tables.levels[r] ? sub : 1.;
                      const double fr = tables.levels[r] < tables.levels[l] ? sub : 1.;
                      // a hanging face: the fine cell's quadrant of the coarse face, which
                      // holds the coarse face's Gauss point of the same index
                      int q = -1;
                      if (tables.levels[l] != tables.levels[r])
                        {
                          const auto &pf = tables.positions[tables.levels[l] > tables.levels[r] ? l : r];
                          const int   a  = dim > 1 ? pf[(d + 1) % dim] & 1 : 0;
                          const int   b  = dim > 2 ? pf[(d + 2) % dim] & 1 : 0;
                          q              = dim == 3 ? 2 * a + b : a;
                        }
                      tables.faces[d].push_back({l, r, float(fl), float(fr), q});
                    }
                  tables.cell_faces[d].push_back({face_of[i], side == 1});
                }
          }
        tables.cell_face_start[d][tables.n_owned] = tables.cell_faces[d].size();
        // push_back's growth leaves up to half of the capacity unused
        tables.faces[d].shrink_to_fit();
        tables.cell_faces[d].shrink_to_fit();
      }
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                            \
  template std::shared_ptr<const Utilities::MPI::Partitioner> assign_slots(                                 \
    const std::vector<OwnedCell> &, const std::vector<long long> &, const Lattice<d> &,                     \
    const VirtualCells<d> &, const IndexSet &, const MPI_Comm, SlotTables &, std::vector<unsigned int> &,   \
    SlotIndex &);                                                                                           \
  template void make_face_ids(const Lattice<d> &, SlotTables &);                                            \
  template void make_neighbor_table(Lattice<d> &, const VirtualCells<d> &, const SlotIndex &,               \
                                    const SlotGrid<d> &, const DilatedMask<d> *, const std::vector<char> &, \
                                    const LatticeGeometry &, SlotTables &);                                 \
  template void make_gradient_table(Lattice<d> &, const SlotIndex &, const SlotGrid<d> &,                   \
                                    const DilatedMask<d> *, const std::vector<char> &,                      \
                                    const LatticeGeometry &, SlotTables &, std::vector<char> &);            \
  template void make_faces<d>(const std::vector<unsigned int> &, const std::vector<unsigned int> &,         \
                              SlotTables &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::mesh
