#include <granhydro/mesh/cartesian_patch.h>

#include <granhydro/mesh/forest.h>

#include <deal.II/distributed/tria.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace granhydro
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
  bool CartesianPatch<dim>::adapt(const std::vector<signed char> &flags,
                                  LinearAlgebra::distributed::Vector<double> &U,
                                  const std::function<bool(const double *)> &admissible,
                                  const int leaf_weight)
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
        AssertThrow(flags.size() == n_owned_, ExcMessage("one flag per owned cell"));
        unsigned int changes = 0;
        std::vector<signed char> f(n_owned_, 0);
        for (unsigned int s = 0; s < n_owned_; ++s)
          if (flags[s] > 0 && level_[s] < max_level_)
            f[s] = 1;
          else if (flags[s] < 0 && level_[s] > 0)
            f[s] = -1;
        for (const signed char x : f)
          changes += x != 0;
        if (Utilities::MPI::sum(changes, comm) == 0)
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
            slopes.assign(std::size_t(n_owned_) * dim * NC, 0.);
            for (unsigned int s = 0; s < n_owned_; ++s)
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
              P[ch][c] = fe->get_prolongation_matrix(ch)(c, c);
              R[ch][c] = fe->get_restriction_matrix(ch)(c, c);
            }
        // (fill() runs inside the forest's adapt(), before rebuild(): level_ is still the
        // old leaves')
        auto fill = [&](const typename Forest<dim>::Source &src, double *out) {
          using Source = typename Forest<dim>::Source;
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
              const unsigned int k = level_[src.first] + 1;
              auto sibling = [&](const unsigned int sib, double *child) {
                for (unsigned int c = 0; c < NC; ++c)
                  {
                    child[c] = v[c];
                    for (unsigned int d = 0; d < dim; ++d)
                      child[c] += row(P[src.child][c], slopes[(std::size_t(src.first) * dim + d) * NC + c]) *
                                  0.5 * (h_[d] / double(1u << k)) * ((sib >> d & 1u) ? 1. : -1.);
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
        unsigned long long nr = 0, nc = 0;
        const std::vector<double> values = forest_->adapt(f, fill, nr, nc, leaf_weight);
        dealii_mesh_current_ = false;
        rebuild();
        U.reinit(part);
        AssertThrow(values.size() == std::size_t(n_owned_) * NC, ExcInternalError());
        for (std::size_t i = 0; i < values.size(); ++i)
          U.local_element(i) = values[i];
        last_refined_   = Utilities::MPI::sum(nr, comm);
        last_coarsened_ = Utilities::MPI::sum(nc, comm);
        return true;
      }
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
            for (const auto &cell : tria->active_cell_iterators())
              if (cell->is_locally_owned())
                {
                  // this cell's leaf key; refine unless it is a target leaf or contains none
                  const unsigned int k = cell->level() - base_tria_level_;
                  long long          key = 0;
                  bool               refine = false;
                  for (int d = dim - 1; d >= 0; --d)
                    key = key * ((long long)(N_[d]) << max_level_) +
                          ((long long)(std::floor((cell->center()[d] - lo_[d]) / (h_[d] / double(1u << k))))
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
            if (Utilities::MPI::sum(n, comm) == 0)
              break;
            tria->execute_coarsening_and_refinement();
          }
        if (forest_)
          make_forest();
        rebuild();
      }
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                   \
  template bool CartesianPatch<d>::adapt(const std::vector<signed char> &, Vector &,               \
                                         const std::function<bool(const double *)> &, int);        \
  template void CartesianPatch<d>::refine_to(const std::vector<long long> &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro
