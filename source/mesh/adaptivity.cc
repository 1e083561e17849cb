#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/distributed/tria.h>

#include "forest.h"
#include "lattice.h"
#include "stencil_tables.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    using Vector = LinearAlgebra::distributed::Vector<double>;

    /// y = 0 + a x, as deal.II's FullMatrix::vmult forms one row of a diagonal matrix
    /// (a zero product is +0): the values equal those of deal.II's SolutionTransfer
    inline double row(const double a, const double x)
    {
      const double y = a * x;
      return y == 0 ? 0. : y;
    }
  } // namespace

  template <int dim>
  bool CartesianPatch<dim>::adapt(const std::vector<signed char>             &flags,
                                  LinearAlgebra::distributed::Vector<double> &U,
                                  const std::function<bool(const double *)>  &admissible,
                                  const int                                   leaf_weight)
  {
    if constexpr (dim == 1)
      {
        (void)flags;
        (void)U;
        (void)admissible;
        (void)leaf_weight;
        AssertThrow(false, ExcMessage("adaptive meshes need 2 or 3 dimensions"));
        return false;
      }
    else
      {
        AssertThrow(forest_, ExcMessage("adapt() needs an adaptive box mesh"));
        AssertThrow(flags.size() == tables_.n_owned, ExcMessage("one flag per owned cell"));
        unsigned int             changes = 0;
        std::vector<signed char> f(tables_.n_owned, 0);
        for (unsigned int s = 0; s < tables_.n_owned; ++s)
          if (flags[s] > 0 && tables_.levels[s] < max_level_)
            f[s] = 1;
          else if (flags[s] < 0 && tables_.levels[s] > 0)
            f[s] = -1;
        for (const signed char x : f)
          changes += x != 0;
        if (Utilities::MPI::sum(changes, communicator_) == 0)
          return false;

        // the transfer: a leaf that stays keeps its values; a parent takes the mean of its
        // children (restriction matrix of the DG0 element, children in z-order); a child
        // takes its parent's values (prolongation matrix) and, with `admissible`, the
        // parent's minmod slopes (from the gradient neighbours, all components) times its
        // offset from the parent's centre, when all 2^dim siblings' states pass. The
        // offsets of the 2^dim children sum to zero: conservative to round-off.
        constexpr unsigned int NC     = n_components;
        const bool             linear = bool(admissible);
        std::vector<double>    slopes; // per owned slot: dim x NC
        if (linear)
          {
            std::vector<double> W;
            gather(U, W);
            slopes.assign(std::size_t(tables_.n_owned) * dim * NC, 0.);
            for (unsigned int s = 0; s < tables_.n_owned; ++s)
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const int m = gradient_neighbor(s, d, 0), q = gradient_neighbor(s, d, 1);
                  if (m < 0 || q < 0)
                    continue;
                  for (unsigned int c = 0; c < NC; ++c)
                    {
                      const double u  = W[std::size_t(s) * NC + c];
                      const double sl = (u - W[std::size_t(m) * NC + c]) / -gradient_offset(s, d, 0);
                      const double sr = (W[std::size_t(q) * NC + c] - u) / gradient_offset(s, d, 1);
                      slopes[(std::size_t(s) * dim + d) * NC + c] =
                        sl * sr > 0 ? (std::abs(sl) < std::abs(sr) ? sl : sr) : 0.;
                    }
                }
          }
        // the DG0 element's interpolation matrices (diagonal, one entry per component)
        std::array<std::array<double, NC>, 1u << dim> P, R;
        for (unsigned int ch = 0; ch < (1u << dim); ++ch)
          for (unsigned int c = 0; c < NC; ++c)
            {
              P[ch][c] = finite_element_->get_prolongation_matrix(ch)(c, c);
              R[ch][c] = finite_element_->get_restriction_matrix(ch)(c, c);
            }
        // (fill() runs inside the forest's adapt(), before rebuild(): tables_.levels is still the
        // old leaves')
        auto fill = [&](const typename Forest<dim>::Source &src, double *out) {
          using Source    = typename Forest<dim>::Source;
          const double *u = &U.local_element(std::size_t(src.first) * NC);
          if (src.kind == Source::same)
            std::copy(u, u + NC, out);
          else if (src.kind == Source::from_children)
            for (unsigned int c = 0; c < NC; ++c)
              {
                double sum = 0;
                for (unsigned int ch = 0; ch < (1u << dim); ++ch)
                  sum += row(R[ch][c], U.local_element((std::size_t(src.first) + ch) * NC + c));
                out[c] = sum;
              }
          else
            {
              double v[NC];
              for (unsigned int c = 0; c < NC; ++c)
                v[c] = row(P[src.child][c], u[c]);
              std::copy(v, v + NC, out);
              if (!linear)
                return;
              const unsigned int k       = tables_.levels[src.first] + 1;
              auto               sibling = [&](const unsigned int sib, double *child) {
                for (unsigned int c = 0; c < NC; ++c)
                  {
                    child[c] = v[c];
                    for (unsigned int d = 0; d < dim; ++d)
                      child[c] += row(P[src.child][c], slopes[(std::size_t(src.first) * dim + d) * NC + c]) *
                                  0.5 * (geometry_.cell_size[d] / double(1u << k)) *
                                  ((sib >> d & 1u) ? 1. : -1.);
                  }
              };
              double child[NC];
              for (unsigned int sib = 0; sib < (1u << dim); ++sib)
                {
                  sibling(sib, child);
                  if (!admissible(child))
                    return;
                }
              sibling(src.child, out);
            }
        };
        unsigned long long        nr = 0, nc = 0;
        const std::vector<double> values =
          forest_->adapt(f, fill, nr, nc, leaf_weight,
                         [this](const std::vector<signed char> &delta) { return stays_balanced(delta); });
        dealii_mesh_current_ = false;
        rebuild();
        U.reinit(partitioner_);
        AssertThrow(values.size() == std::size_t(tables_.n_owned) * NC, ExcInternalError());
        for (std::size_t i = 0; i < values.size(); ++i)
          U.local_element(i) = values[i];
        last_refined_   = Utilities::MPI::sum(nr, communicator_);
        last_coarsened_ = Utilities::MPI::sum(nc, communicator_);
        return true;
      }
  }

  template <int dim>
  std::pair<unsigned int, unsigned int> CartesianPatch<dim>::balance_counts() const
  {
    if constexpr (dim == 1)
      return {0, 0};
    else
      return forest_ ? std::make_pair(forest_->balances_run(), forest_->balances_skipped()) :
                       std::make_pair(0u, 0u);
  }

  template <int dim>
  bool CartesianPatch<dim>::stays_balanced(const std::vector<signed char> &delta) const
  {
    // The leaves before were 2:1 balanced (faces, edges, corners). Afterwards a pair of
    // touching leaves can differ by two levels only if one of them changed: a refined
    // leaf s of level L next to a leaf that ends coarser than L, or a merged family
    // (children of level L, parent L - 1) next to a leaf that ends finer than L. Each
    // rank checks its own changed leaves against the 3^dim - 1 boxes of their level
    // around them, among the leaves it knows (owned and MPI ghosts, with the ghosts'
    // changes from their owners). Where it cannot tell (a neighbourhood beyond the
    // fetched part), it answers false: p4est then balances. (Only boxes are adaptive.)
    constexpr unsigned int                     NC = n_components;
    bool                                       ok = true;
    LinearAlgebra::distributed::Vector<double> change(partitioner_);
    for (unsigned int s = 0; s < tables_.n_owned; ++s)
      change.local_element(std::size_t(s) * NC) = delta[s];
    change.update_ghost_values();
    const unsigned int n_leaves = tables_.n_owned + tables_.n_mpi_ghosts;
    auto moved     = [&](const int t) { return int(std::lround(change.local_element(std::size_t(t) * NC))); };
    using Position = typename Lattice<dim>::Position;
    const Lattice<dim>                    lattice = make_lattice();
    const std::vector<std::array<int, 3>> pos(tables_.positions.begin(),
                                              tables_.positions.begin() + n_leaves);
    const std::vector<unsigned char>      lev(tables_.levels.begin(), tables_.levels.begin() + n_leaves);
    const SlotGrid<dim>                   grid(lattice, pos, lev);
    for (unsigned int s = 0; s < tables_.n_owned && ok; ++s)
      {
        if (delta[s] == 0)
          continue;
        const unsigned int L = tables_.levels[s];
        for (unsigned int e = 0; e < Utilities::pow(3u, dim) && ok; ++e)
          {
            Position     q{{0, 0, 0}};
            unsigned int code = e, zero = 0;
            for (unsigned int d = 0; d < dim; ++d, code /= 3)
              {
                q[d] = tables_.positions[s][d] + int(code % 3) - 1;
                zero += code % 3 == 1;
              }
            if (zero == dim || !lattice.wrap(L, q)) // s itself; beyond a wall
              continue;
            // the box q of level L: a leaf of level L, inside a leaf of level L - 1,
            // or split into leaves of level L + 1 (the former leaves were balanced)
            const int same   = grid(L, q);
            Position  parent = q;
            for (unsigned int d = 0; d < dim; ++d)
              parent[d] >>= 1;
            const int coarser = same < 0 && L > 0 ? grid(L - 1, parent) : -1;
            int       finer = 0, finer_staying = 0; // children of the box found; those not merged
            if (same < 0 && coarser < 0 && L < max_level_)
              for (unsigned int c = 0; c < (1u << dim); ++c)
                {
                  Position child = q;
                  for (unsigned int d = 0; d < dim; ++d)
                    child[d] = 2 * q[d] + (c >> d & 1u);
                  if (const int t = grid(L + 1, child); t >= 0)
                    {
                      ++finer;
                      finer_staying += moved(t) >= 0;
                    }
                }
            if (delta[s] > 0) // children of level L + 1: the neighbour must end at L or finer
              ok = same >= 0 ? moved(same) >= 0 : (coarser >= 0 ? moved(coarser) > 0 : finer > 0);
            else // the parent of level L - 1: the neighbour must end at L or coarser
              ok =
                same >= 0 ? moved(same) <= 0 : (coarser >= 0 || (finer == (1 << dim) && finer_staying == 0));
          }
      }
    return Utilities::MPI::min(ok ? 1 : 0, communicator_) == 1;
  }

  template <int dim>
  void CartesianPatch<dim>::refine_to(const std::vector<long long> &cells)
  {
    if constexpr (dim == 1)
      {
        AssertThrow(cells.empty() || max_level_ == 0, ExcMessage("adaptive meshes need 2 or 3 dimensions"));
      }
    else
      {
        // on deal.II's mesh (brought up to date first), then copied to the forest:
        // a leaf of the target at level l inside an active cell of level k < l: refine it
        sync_dealii();
        std::set<long long> target(cells.begin(), cells.end());
        for (unsigned int pass = 0; pass < max_level_; ++pass)
          {
            unsigned int n = 0;
            for (const auto &cell : triangulation_->active_cell_iterators())
              if (cell->is_locally_owned())
                {
                  // this cell's leaf key; refine unless it is a target leaf or contains none
                  const unsigned int k      = cell->level() - geometry_.base_level;
                  long long          key    = 0;
                  bool               refine = false;
                  for (int d = dim - 1; d >= 0; --d)
                    key = key * ((long long)(geometry_.cells[d]) << max_level_) +
                          ((long long)(std::floor((cell->center()[d] - geometry_.lower[d]) /
                                                  (geometry_.cell_size[d] / double(1u << k))))
                           << (max_level_ - k));
                  if (k < max_level_ && !target.count(key * 8 + k))
                    {
                      // is any target leaf of a finer level at this corner? (leaves of a
                      // refined cell include one at its lower corner)
                      for (unsigned int l = k + 1; l <= max_level_ && !refine; ++l)
                        refine = target.count(key * 8 + l) > 0;
                    }
                  if (refine)
                    {
                      cell->set_refine_flag();
                      ++n;
                    }
                }
            if (Utilities::MPI::sum(n, communicator_) == 0)
              break;
            triangulation_->execute_coarsening_and_refinement();
          }
        if (forest_)
          make_forest();
        rebuild();
      }
  }

#define GRANHYDRO_INSTANTIATE(d)                                                            \
  template bool CartesianPatch<d>::adapt(const std::vector<signed char> &, Vector &,        \
                                         const std::function<bool(const double *)> &, int); \
  template void CartesianPatch<d>::refine_to(const std::vector<long long> &);               \
  template std::pair<unsigned int, unsigned int> CartesianPatch<d>::balance_counts() const;
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::mesh
