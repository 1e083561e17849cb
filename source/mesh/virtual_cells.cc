#include "virtual_cells.h"

#include <algorithm>
#include <cmath>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    /// add w to key's weight in a short (key, weight) list, weights of equal keys summed
    /// in insertion order (a few entries: a linear search beats a map)
    void add_weight(std::vector<std::pair<long long, double>> &v, const long long key, const double w)
    {
      for (auto &e : v)
        if (e.first == key)
          {
            e.second += w;
            return;
          }
      v.emplace_back(key, w);
    }
  } // namespace

  template <int dim>
  long long VirtualCells<dim>::key_of(const unsigned int k, const Position &q, bool &inside,
                                      Position &w) const
  {
    // periodic directions wrapped also when q lies outside a wall: the same position
    // reached across a periodic side and from inside must have one key
    w      = q;
    inside = lattice.wrap(k, w);
    return lattice.position_key(k, w);
  }

  template <int dim>
  int VirtualCells<dim>::find(const unsigned int k, const Position &q) const
  {
    bool            inside;
    Position        w;
    const long long key = key_of(k, q, inside, w);
    if (key < 0) // farther out than any virtual cell
      return -1;
    const unsigned int *i = index.find(key);
    return i ? int(*i) : -1;
  }

  template <int dim>
  unsigned int VirtualCells<dim>::add(const unsigned int k, const Position &q)
  {
    bool            inside;
    Position        w;
    const long long key = key_of(k, q, inside, w);
    AssertThrow(key >= 0,
                ExcMessage("internal error: a virtual cell farther outside than the lattice keys reach"));
    if (const unsigned int *i = index.find(key))
      return *i;
    Virtual v;
    v.level = k;
    v.pos   = w;
    Position mq{{0, 0, 0}};
    if (inside)
      v.sources = region_sources(k, v.pos);
    else
      {
        v.ghost = true;
        mq      = lattice.mirror(k, v.pos, v.bg);
      }
    const unsigned int i = virtuals.size();
    virtuals.push_back(std::move(v));
    index.insert(key, i);
    if (!inside)
      {
        const unsigned int mi = add(k, mq);
        virtuals[i].mirror    = mi;
      }
    return i;
  }

  template <int dim>
  std::vector<std::pair<long long, double>> VirtualCells<dim>::region_sources(const unsigned int k,
                                                                              const Position    &q)
  {
    const unsigned int                        m = lattice.max_level();
    std::vector<std::pair<long long, double>> src;
    const long long                           c = lattice.covering(k, q);
    if (int(c & 7) <= int(k))
      {
        // prolongation: the coarse leaf's value plus its central-difference slope along
        // each direction with two leaf neighbours (same level or coarser), evaluated at
        // the virtual cell's centre (linear, exact for linear data; the transitions lie
        // where the indicator found the solution smooth)
        add_weight(src, c, 1.);
        const unsigned int l = c & 7;
        Position           pc;
        unsigned int       lc;
        lattice.decode(c, lc, pc);
        for (unsigned int j = 0; j < dim && l < k; ++j)
          {
            const long long tm = lattice.gradient_key(c, j, -1), tp = lattice.gradient_key(c, j, 1);
            if (tm < 0 || tp < 0) // a wall ghost or none: constant along j
              continue;
            const double hl = 1. / double(1u << l);
            const double om = -0.5 * (hl + 1. / double(1u << (tm & 7)));
            const double op = 0.5 * (hl + 1. / double(1u << (tp & 7)));
            // centre of the virtual cell relative to the coarse centre, in level-0 units
            // (positions wrap periodically: use the offset inside the coarse cell)
            const long long rel   = q[j] - (pc[j] << (k - l));
            const double    delta = (rel + 0.5) / double(1u << k) - 0.5 * hl;
            add_weight(src, tp, delta / (op - om));
            add_weight(src, tm, -(delta / (op - om)));
          }
      }
    else
      {
        const long long span = 1ll << (m - k);
        const double    w    = 1. / std::pow(double(span), double(dim));
        for (long long z = 0; z < (dim > 2 ? span : 1); ++z)
          for (long long y = 0; y < (dim > 1 ? span : 1); ++y)
            for (long long x = 0; x < span; ++x)
              add_weight(
                src,
                lattice.covering(m, {{(q[0] << (m - k)) + x, (q[1] << (m - k)) + y, (q[2] << (m - k)) + z}}),
                w);
      }
    std::sort(src.begin(), src.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
    return src;
  }

  template class VirtualCells<1>;
  template class VirtualCells<2>;
  template class VirtualCells<3>;
} // namespace granhydro::mesh
