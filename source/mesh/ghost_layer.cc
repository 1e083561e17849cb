#include "ghost_layer.h"

#include <algorithm>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    /// separable Chebyshev dilation by r of a 0/1 box of bn points (x fastest) along
    /// the first dim directions, line by line
    void dilate_box(std::vector<char> &a, const std::array<long long, 3> &bn, const unsigned int dim,
                    const int r)
    {
      if (r <= 0)
        return;
      const std::array<std::size_t, 3> stride{{1, std::size_t(bn[0]), std::size_t(bn[0] * bn[1])}};
      std::vector<char>                out;
      for (unsigned int d = 0; d < dim; ++d)
        {
          out.assign(a.size(), 0);
          const long long n = bn[d];
          // the lines along d: every point whose coordinate along d is 0
          for (std::size_t base = 0; base < a.size(); ++base)
            {
              if ((base / stride[d]) % n != 0)
                continue;
              for (long long c = 0; c < n; ++c)
                if (a[base + c * stride[d]])
                  for (long long o = std::max(-c, -(long long)r); o <= r && c + o < n; ++o)
                    out[base + (c + o) * stride[d]] = 1;
            }
          a.swap(out);
        }
    }
  } // namespace

  template <int dim>
  FaceKeys face_neighbour_keys(const std::vector<OwnedCell> &owned, Lattice<dim> &lattice)
  {
    using Position = typename Lattice<dim>::Position;
    FaceKeys face_keys;
    face_keys.start.reserve(owned.size() * dim * 2 + 1);
    face_keys.keys.reserve(owned.size() * dim * 2 + owned.size());
    face_keys.start.push_back(0);
    auto &fk = face_keys.keys;
    for (std::size_t i = 0; i < owned.size(); ++i)
      {
        const unsigned int k = owned[i].level;
        const Position     p0{{owned[i].ijk[0], owned[i].ijk[1], owned[i].ijk[2]}};
        // faces: same level, one coarser leaf, or 2^(dim-1) finer leaves
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int side = 0; side < 2; ++side, face_keys.start.push_back(fk.size()))
            {
              Position q = p0;
              q[d] += side ? 1 : -1;
              const long long t = lattice.same_level(k, q);
              if (t != no_slot_key)
                {
                  fk.push_back(t);
                  continue;
                }
              const long long c = lattice.covering(k, q);
              AssertThrow(c != no_slot_key, ExcInternalError());
              const unsigned int l = c & 7;
              if (l < k)
                {
                  fk.push_back(c);
                  continue;
                }
              // q is refined (its corner may be finer still, away from the face): 2:1
              // balance puts level k+1 cells along the face
              lattice.wrap(k, q);
              const unsigned int t1 = (d + 1) % dim, t2 = (d + 2) % dim;
              const unsigned int n1 = dim > 1 ? 2 : 1, n2 = dim > 2 ? 2 : 1;
              for (unsigned int b = 0; b < n2; ++b) // t1 fastest
                for (unsigned int a = 0; a < n1; ++a)
                  {
                    Position f{{2 * q[0], 2 * q[1], 2 * q[2]}};
                    for (unsigned int e = dim; e < 3; ++e)
                      f[e] = 0;
                    f[d] += side ? 0 : 1;
                    if (dim > 1)
                      f[t1] += a;
                    if (dim > 2)
                      f[t2] += b;
                    const long long ft = lattice.same_level(k + 1, f);
                    AssertThrow(ft != no_slot_key, ExcMessage("the mesh is not 2:1 balanced"));
                    fk.push_back(ft);
                  }
            }
      }
    return face_keys;
  }

  namespace
  {
    /// one level of the reconstruction boxes of stencil_closure: the dense grid (lo, bn,
    /// positions with a virtual cell dilated by r) or the face cells' keys, sorted, and
    /// whether each one's box is full
    template <int dim>
    struct BoxLevel
    {
      using Position = typename Lattice<dim>::Position;
      Position          lo{{0, 0, 0}}, bn{{1, 1, 1}};
      std::vector<char> bad, full;
      bool              dense = false;
      std::size_t       idx(const Position &q) const
      {
        return std::size_t((q[0] - lo[0]) + bn[0] * ((q[1] - lo[1]) + bn[1] * (q[2] - lo[2])));
      }
    };

    /// the boxes of the face cells P of level k on the dense grid of L: each position of
    /// their union looked at once (a leaf or wall ghost is needed, else a virtual cell is
    /// made); L.bad: the positions with a virtual cell, dilated by r
    template <int dim, class Need>
    void mark_dense_level(BoxLevel<dim> &L, const std::vector<typename Lattice<dim>::Position> &P,
                          const unsigned int k, const int r, Lattice<dim> &lattice,
                          VirtualCells<dim> &virtuals, Need &need)
    {
      using Position        = typename Lattice<dim>::Position;
      const long long   vol = L.bn[0] * L.bn[1] * L.bn[2];
      std::vector<char> in(vol, 0);
      for (const auto &p : P)
        in[L.idx(p)] = 1;
      dilate_box(in, L.bn, dim, r);
      L.bad.assign(vol, 0);
      std::size_t i = 0;
      for (long long z = 0; z < L.bn[2]; ++z)
        for (long long y = 0; y < L.bn[1]; ++y)
          for (long long x = 0; x < L.bn[0]; ++x, ++i)
            if (in[i])
              {
                const Position  q{{L.lo[0] + x, L.lo[1] + y, L.lo[2] + z}};
                const long long t = lattice.same_level(k, q);
                if (t == no_slot_key)
                  {
                    virtuals.add(k, q);
                    L.bad[i] = 1;
                  }
                else
                  need(t); // periodic images repeat
              }
      dilate_box(L.bad, L.bn, dim, r);
    }

    /// the boxes of the face cells (keys, positions P) of level k one by one, in key
    /// order (the order of the virtual cells made); keys sorted on return, L.full per key
    template <int dim, class Need>
    void mark_boxes_in_key_order(BoxLevel<dim> &L, std::vector<long long> &keys,
                                 const std::vector<typename Lattice<dim>::Position> &P, const unsigned int k,
                                 const int r, Lattice<dim> &lattice, VirtualCells<dim> &virtuals, Need &need)
    {
      using Position = typename Lattice<dim>::Position;
      std::vector<std::size_t> order(keys.size());
      for (std::size_t c = 0; c < order.size(); ++c)
        order[c] = c;
      std::sort(order.begin(), order.end(),
                [&](const std::size_t a, const std::size_t b) { return keys[a] < keys[b]; });
      std::vector<long long> sorted_keys(keys.size());
      L.full.assign(keys.size(), 1);
      for (std::size_t c = 0; c < order.size(); ++c)
        {
          sorted_keys[c]     = keys[order[c]];
          const Position &p0 = P[order[c]];
          for (int z = (dim > 2 ? -r : 0); z <= (dim > 2 ? r : 0); ++z)
            for (int y = (dim > 1 ? -r : 0); y <= (dim > 1 ? r : 0); ++y)
              for (int x = -r; x <= r; ++x)
                {
                  const Position  q{{p0[0] + x, p0[1] + y, p0[2] + z}};
                  const long long t = lattice.same_level(k, q);
                  if (t == no_slot_key)
                    {
                      virtuals.add(k, q);
                      L.full[c] = 0;
                    }
                  else
                    need(t);
                }
        }
      keys.swap(sorted_keys);
    }
  } // namespace

  template <int dim>
  std::vector<long long> stencil_closure(const std::vector<OwnedCell> &owned, const FaceKeys &face_keys,
                                         Lattice<dim> &lattice, VirtualCells<dim> &virtuals, const int r,
                                         std::vector<char> &uniform)
  {
    using Position = typename Lattice<dim>::Position;
    // the keys found, each once: the face cells (owned cells and their face neighbours,
    // which need reconstruction boxes and gradient stencils; each face neighbour is met
    // from several cells), then what their stencils reach. A hash set drops the
    // repetitions as they come; only the distinct keys are kept and sorted
    FlatKeyMap<char>       seen;
    std::vector<long long> needed;
    seen.reserve(2 * owned.size());
    needed.reserve(2 * owned.size());
    auto need = [&](const long long t) {
      if (seen.insert(t, 1).second)
        needed.push_back(t);
    };
    for (const auto &o : owned)
      need(o.key);
    for (const long long t : face_keys.keys)
      need(t);
    const std::size_t n_face_cells = needed.size(); // needed[0, n_face_cells): the face cells
    // the gradient stencils of the face cells. An owned cell's gradient neighbours (the
    // same-level leaf or wall ghost, else a coarser leaf) are among its face neighbours
    // already: only the other face cells (after the owned ones, which are distinct) are
    // looked at
    for (std::size_t i = owned.size(); i < n_face_cells; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        for (const int o : {-1, 1})
          {
            const long long t = lattice.gradient_key(needed[i], j, o);
            if (t != no_slot_key)
              need(t);
          }
    // the reconstruction boxes (Chebyshev radius r of each face cell, at its level):
    // leaves, wall ghosts, virtual cells. The boxes overlap (each position lies in up to
    // (2 r + 1)^dim of them): per level, the union of the boxes is marked on a dense
    // grid over the face cells' bounding box (positions unwrapped, as the boxes have
    // them) and each of its positions is looked at once; where that grid would be much
    // larger than the boxes themselves (a scattered level), box by box, the face cells
    // in key order. A cell's box is full when it holds no virtual cell: the positions
    // with none, dilated by r.
    uniform.assign(owned.size(), 0);
    const unsigned int                  m = lattice.max_level();
    std::vector<std::vector<long long>> keys_at(m + 1);
    // a face neighbour that is another rank's leaf (after the owned cells, a key >= 0) gets
    // no box: its reconstructions come from its owner (the convective operator's halo
    // exchange), so the halo is the face neighbours, their gradient stencils and what the
    // boxes of the owned cells and wall ghosts reach
    for (std::size_t i = 0; i < n_face_cells; ++i)
      if (i < owned.size() || needed[i] < 0)
        keys_at[needed[i] >= 0 ? needed[i] & 7 : lattice.ghost(needed[i]).level].push_back(needed[i]);
    virtuals.reserve(n_face_cells / 8);
    long long box_volume = 1; // (2 r + 1)^dim
    for (unsigned int d = 0; d < dim; ++d)
      box_volume *= 2 * r + 1;
    std::vector<BoxLevel<dim>> levels(m + 1);
    std::vector<Position>      P;
    for (unsigned int k = 0; k <= m; ++k)
      {
        auto &keys = keys_at[k];
        if (keys.empty())
          continue;
        BoxLevel<dim> &L = levels[k];
        P.resize(keys.size());
        for (std::size_t c = 0; c < keys.size(); ++c)
          {
            unsigned int kk;
            lattice.decode(keys[c], kk, P[c]);
          }
        for (unsigned int d = 0; d < dim; ++d)
          {
            long long mn = P[0][d], mx = P[0][d];
            for (const auto &p : P)
              {
                mn = std::min(mn, p[d]);
                mx = std::max(mx, p[d]);
              }
            L.lo[d] = mn - r;
            L.bn[d] = mx - mn + 1 + 2 * r;
          }
        const long long vol = L.bn[0] * L.bn[1] * L.bn[2];
        if (vol <= 4 * box_volume * (long long)P.size() + 4096)
          {
            L.dense = true;
            mark_dense_level(L, P, k, r, lattice, virtuals, need);
            continue;
          }
        mark_boxes_in_key_order(L, keys, P, k, r, lattice, virtuals, need);
      }
    // the owned cells' flags
    for (std::size_t i = 0; i < owned.size(); ++i)
      {
        const BoxLevel<dim> &L = levels[owned[i].level];
        const Position       p{{owned[i].ijk[0], owned[i].ijk[1], owned[i].ijk[2]}};
        if (L.dense)
          uniform[i] = !L.bad[L.idx(p)];
        else
          {
            const auto &keys = keys_at[owned[i].level];
            const auto  it   = std::lower_bound(keys.begin(), keys.end(), owned[i].key);
            uniform[i]       = L.full[it - keys.begin()];
          }
      }
    for (const auto &v : virtuals.cells())
      for (const auto &[t, w] : v.sources)
        need(t);
    return needed;
  }

  template <int dim>
  DilatedMask<dim>::DilatedMask(const std::vector<OwnedCell> &owned, const unsigned int G)
  {
    for (unsigned int d = 0; d < dim; ++d)
      {
        int mn = 1 << 30, mx = -(1 << 30);
        for (const auto &o : owned)
          {
            mn = std::min(mn, o.ijk[d]);
            mx = std::max(mx, o.ijk[d]);
          }
        if (owned.empty())
          mn = mx = 0;
        box_lower[d] = mn - int(G);
        box_size[d]  = mx - mn + 1 + 2 * int(G);
      }
    const std::size_t nbox = std::size_t(box_size[0]) * box_size[1] * box_size[2];
    mask.assign(nbox, 0);
    for (const auto &o : owned)
      mask[std::size_t(o.ijk[0] - box_lower[0]) +
           std::size_t(box_size[0]) * (std::size_t(o.ijk[1] - box_lower[1]) +
                                       std::size_t(box_size[1]) * (o.ijk[2] - box_lower[2]))] = 1;
    dilate_box(mask, {{box_size[0], box_size[1], box_size[2]}}, dim, int(G));
  }

  template <int dim>
  bool DilatedMask<dim>::contains(const Position &p) const
  {
    for (unsigned int d = 0; d < 3; ++d)
      if (p[d] < box_lower[d] || p[d] >= box_lower[d] + box_size[d])
        return false;
    return mask[std::size_t(p[0] - box_lower[0]) +
                std::size_t(box_size[0]) *
                  (std::size_t(p[1] - box_lower[1]) + std::size_t(box_size[1]) * (p[2] - box_lower[2]))];
  }

  template <int dim>
  std::vector<long long> DilatedMask<dim>::keys(Lattice<dim> &lattice) const
  {
    std::vector<long long> needed;
    for (int k = box_lower[2]; k < box_lower[2] + box_size[2]; ++k)
      for (int j = box_lower[1]; j < box_lower[1] + box_size[1]; ++j)
        for (int i = box_lower[0]; i < box_lower[0] + box_size[0]; ++i)
          if (contains({{i, j, k}}))
            needed.push_back(lattice.same_level(0, {{i, j, k}}));
    return needed;
  }

  template <int dim>
  void add_wall_sources(std::vector<long long> &needed, const Lattice<dim> &lattice)
  {
    // the repetitions go through a hash set first: the list holds every key several
    // times, sorting the distinct ones only is cheaper
    auto make_unique = [&]() {
      FlatKeyMap<char> seen;
      seen.reserve(needed.size() / 8); // about the distinct keys: a smaller table misses the cache less
      std::size_t n = 0;
      for (const long long t : needed)
        if (seen.insert(t, 1).second)
          needed[n++] = t;
      needed.resize(n);
      std::sort(needed.begin(), needed.end());
    };
    make_unique();
    for (std::size_t i = 0, n = needed.size(); i < n; ++i)
      if (needed[i] < 0)
        needed.push_back(lattice.ghost(needed[i]).source_key);
    make_unique();
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                     \
  template FaceKeys               face_neighbour_keys(const std::vector<OwnedCell> &, Lattice<d> &); \
  template std::vector<long long> stencil_closure(const std::vector<OwnedCell> &, const FaceKeys &,  \
                                                  Lattice<d> &, VirtualCells<d> &, const int,        \
                                                  std::vector<char> &);                              \
  template class DilatedMask<d>;                                                                     \
  template void add_wall_sources(std::vector<long long> &, const Lattice<d> &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::mesh
