#include <granhydro/mesh/ghost_layer.h>

#include <algorithm>


namespace granhydro
{
  using namespace dealii;

  template <int dim>
  std::vector<std::vector<long long>> face_neighbour_keys(const std::vector<OwnedCell> &owned,
                                                          Lattice<dim>                 &lattice)
  {
    using Position = typename Lattice<dim>::Position;
    std::vector<std::vector<long long>> face_keys(owned.size() * dim * 2);
    for (std::size_t i = 0; i < owned.size(); ++i)
      {
        const unsigned int k = owned[i].level;
        const Position     p0{{owned[i].ijk[0], owned[i].ijk[1], owned[i].ijk[2]}};
        // faces: same level, one coarser leaf, or 2^(dim-1) finer leaves
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int side = 0; side < 2; ++side)
            {
              auto    &fk = face_keys[(i * dim + d) * 2 + side];
              Position q  = p0;
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

  template <int dim>
  std::vector<long long> stencil_closure(const std::vector<OwnedCell>              &owned,
                                         const std::vector<std::vector<long long>> &face_keys,
                                         Lattice<dim> &lattice, VirtualCells<dim> &virtuals,
                                         const int r)
  {
    using Position = typename Lattice<dim>::Position;
    std::vector<long long> needed;
    for (const auto &fk : face_keys)
      for (const long long t : fk)
        needed.push_back(t);
    // the face cells: owned cells and their face neighbours (they need reconstruction
    // boxes and gradient stencils)
    std::vector<long long> face_cells; // sorted, unique
    face_cells.reserve(owned.size() * 3);
    for (std::size_t i = 0; i < owned.size(); ++i)
      {
        face_cells.push_back(owned[i].key);
        for (unsigned int f = 0; f < dim * 2; ++f)
          for (const long long t : face_keys[i * dim * 2 + f])
            face_cells.push_back(t);
      }
    std::sort(face_cells.begin(), face_cells.end());
    face_cells.erase(std::unique(face_cells.begin(), face_cells.end()), face_cells.end());
    for (const long long c : face_cells)
      for (unsigned int j = 0; j < dim; ++j)
        for (const int o : {-1, 1})
          {
            const long long t = lattice.gradient_key(c, j, o);
            if (t != no_slot_key)
              needed.push_back(t);
          }
    // the reconstruction boxes: leaves, wall ghosts, virtual cells. The boxes overlap
    // (each leaf lies in up to 5^dim of them): a leaf is pushed once, marked at its fine
    // corner (leaves do not overlap)
    virtuals.reserve(4 * face_cells.size());
    FlatKeyMap<char> seen;
    seen.reserve(4 * face_cells.size());
    for (const long long u : face_cells)
      {
        unsigned int k;
        Position     p0;
        lattice.decode(u, k, p0);
        for (int z = (dim > 2 ? -r : 0); z <= (dim > 2 ? r : 0); ++z)
          for (int y = (dim > 1 ? -r : 0); y <= (dim > 1 ? r : 0); ++y)
            for (int x = -r; x <= r; ++x)
              {
                const Position  q{{p0[0] + x, p0[1] + y, p0[2] + z}};
                const long long t = lattice.same_level(k, q);
                if (t == no_slot_key)
                  virtuals.add(k, q);
                else if (t < 0)
                  needed.push_back(t);
                else if (seen.insert(t, 1).second)
                  needed.push_back(t);
              }
      }
    for (const auto &v : virtuals.cells())
      for (const auto &[t, w] : v.sources)
        needed.push_back(t);
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
        blo[d] = mn - int(G);
        bn[d]  = mx - mn + 1 + 2 * int(G);
      }
    const std::size_t nbox = std::size_t(bn[0]) * bn[1] * bn[2];
    mask.assign(nbox, 0);
    for (const auto &o : owned)
      mask[std::size_t(o.ijk[0] - blo[0]) +
           std::size_t(bn[0]) * (std::size_t(o.ijk[1] - blo[1]) + std::size_t(bn[1]) * (o.ijk[2] - blo[2]))] = 1;
    // separable Chebyshev dilation by G
    const std::array<std::size_t, 3> stride{{1, std::size_t(bn[0]), std::size_t(bn[0]) * bn[1]}};
    for (unsigned int d = 0; d < dim; ++d)
      {
        std::vector<char> out(nbox, 0);
        for (std::size_t p = 0; p < nbox; ++p)
          if (mask[p])
            {
              const int c = (p / stride[d]) % bn[d];
              for (int o = -int(G); o <= int(G); ++o)
                if (c + o >= 0 && c + o < bn[d])
                  out[p + std::ptrdiff_t(o) * std::ptrdiff_t(stride[d])] = 1;
            }
        mask.swap(out);
      }
  }

  template <int dim>
  bool DilatedMask<dim>::contains(const Position &p) const
  {
    for (unsigned int d = 0; d < 3; ++d)
      if (p[d] < blo[d] || p[d] >= blo[d] + bn[d])
        return false;
    return mask[std::size_t(p[0] - blo[0]) +
                std::size_t(bn[0]) * (std::size_t(p[1] - blo[1]) + std::size_t(bn[1]) * (p[2] - blo[2]))];
  }

  template <int dim>
  std::vector<long long> DilatedMask<dim>::keys(Lattice<dim> &lattice) const
  {
    std::vector<long long> needed;
    for (int k = blo[2]; k < blo[2] + bn[2]; ++k)
      for (int j = blo[1]; j < blo[1] + bn[1]; ++j)
        for (int i = blo[0]; i < blo[0] + bn[0]; ++i)
          if (contains({{i, j, k}}))
            needed.push_back(lattice.same_level(0, {{i, j, k}}));
    return needed;
  }

  template <int dim>
  void add_wall_sources(std::vector<long long> &needed, const Lattice<dim> &lattice)
  {
    auto make_unique = [&]() {
      std::sort(needed.begin(), needed.end());
      needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    };
    make_unique();
    for (std::size_t i = 0, n = needed.size(); i < n; ++i)
      if (needed[i] < 0)
        needed.push_back(lattice.ghost(needed[i]).source_key);
    make_unique();
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                   \
  template std::vector<std::vector<long long>> face_neighbour_keys(const std::vector<OwnedCell> &, \
                                                                   Lattice<d> &);                  \
  template std::vector<long long> stencil_closure(const std::vector<OwnedCell> &,                  \
                                                  const std::vector<std::vector<long long>> &,     \
                                                  Lattice<d> &, VirtualCells<d> &, const int);     \
  template class DilatedMask<d>;                                                                   \
  template void add_wall_sources(std::vector<long long> &, const Lattice<d> &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro
