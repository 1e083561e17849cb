#include "forest.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <cmath>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    template <int dim>
    using p4 = internal::p4est::functions<dim>;
    template <int dim>
    using quadrant_t = typename internal::p4est::types<dim>::quadrant;
    template <int dim>
    using tree_t = typename internal::p4est::types<dim>::tree;
    template <int dim>
    using topidx_t = typename internal::p4est::types<dim>::topidx;
    template <int dim>
    using p4forest = typename internal::p4est::types<dim>::forest;

    /// each quadrant carries n_values doubles and its flag (as a double) after them
    template <int dim>
    double *payload(quadrant_t<dim> *q)
    {
      return static_cast<double *>(q->p.user_data);
    }

    /// the number of doubles of a payload and the leaves' partition weight are in the
    /// forest's user pointer (ForestUserData)
    template <int dim>
    unsigned int payload_size(p4forest<dim> *f)
    {
      return static_cast<ForestUserData *>(f->user_pointer)->n_values;
    }

    template <int dim>
    int weigh_leaf(p4forest<dim> *f, topidx_t<dim>, quadrant_t<dim> *)
    {
      return static_cast<ForestUserData *>(f->user_pointer)->leaf_weight;
    }

    template <int dim>
    void init_zero(p4forest<dim> *f, topidx_t<dim>, quadrant_t<dim> *q)
    {
      std::fill_n(payload<dim>(q), payload_size<dim>(f) + 1, 0.);
    }

    template <int dim>
    int refine_flagged(p4forest<dim> *f, topidx_t<dim>, quadrant_t<dim> *q)
    {
      return payload<dim>(q)[payload_size<dim>(f)] > 0;
    }

    template <int dim>
    int coarsen_flagged(p4forest<dim> *f, topidx_t<dim>, quadrant_t<dim> *children[])
    {
      for (unsigned int c = 0; c < (1u << dim); ++c)
        if (!(payload<dim>(children[c])[payload_size<dim>(f)] < 0))
          return 0;
      return 1;
    }

    /// calls op(tree, quadrant) for the local quadrants in order
    template <int dim, class Op>
    void for_each_local(p4forest<dim> *f, const Op &op)
    {
      if (f->local_num_quadrants == 0)
        return;
      for (topidx_t<dim> t = f->first_local_tree; t <= f->last_local_tree; ++t)
        {
          tree_t<dim> *tree = static_cast<tree_t<dim> *>(sc_array_index(f->trees, t));
          for (std::size_t i = 0; i < tree->quadrants.elem_count; ++i)
            op(t, static_cast<quadrant_t<dim> *>(sc_array_index(&tree->quadrants, i)));
        }
    }

    template <int dim>
    int coordinate(const quadrant_t<dim> &q, const unsigned int d)
    {
      if constexpr (dim == 3)
        return d == 0 ? q.x : d == 1 ? q.y : q.z;
      else
        return d == 0 ? q.x : q.y;
    }
  } // namespace

  template <int dim>
  Forest<dim>::Forest(const parallel::distributed::Triangulation<dim> &tria, const unsigned int base_level,
                      const std::array<double, 3> &lower, const std::array<double, 3> &h,
                      const unsigned int n_values)
    : base_level(base_level)
    , user{n_values, 1}
  {
    forest = p4<dim>::copy_forest(const_cast<p4forest<dim> *>(tria.get_p4est()), /*copy_data=*/0);
    forest->user_pointer = &user;
    p4<dim>::reset_data(forest, sizeof(double) * (n_values + 1), &init_zero<dim>, &user);
    // each tree is a coarse cell of the box; its vertex 0 is its lower corner and its
    // axes are the box's (GridGenerator::subdivided_hyper_rectangle, checked against
    // deal.II's cells in CartesianPatch::sync_dealii())
    const auto &tree_to_cell = tria.get_p4est_tree_to_coarse_cell_permutation();
    tree_origin.resize(tree_to_cell.size());
    for (std::size_t t = 0; t < tree_to_cell.size(); ++t)
      {
        const typename Triangulation<dim>::cell_iterator cell(&tria, 0, tree_to_cell[t]);
        for (unsigned int d = 0; d < 3; ++d)
          tree_origin[t][d] = d < dim ? int(std::lround((cell->vertex(0)[d] - lower[d]) / h[d])) : 0;
      }
  }

  template <int dim>
  Forest<dim>::~Forest()
  {
    if (forest != nullptr)
      p4<dim>::destroy(forest);
  }

  template <int dim>
  unsigned long long Forest<dim>::first_global() const
  {
    return forest->global_first_quadrant[forest->mpirank];
  }

  template <int dim>
  unsigned long long Forest<dim>::n_global() const
  {
    return forest->global_first_quadrant[forest->mpisize];
  }

  template <int dim>
  std::vector<typename Forest<dim>::Leaf> Forest<dim>::leaves() const
  {
    std::vector<Leaf> out;
    out.reserve(forest->local_num_quadrants);
    constexpr int max_level = p4<dim>::max_level;
    for_each_local<dim>(forest, [&](const topidx_t<dim> t, const quadrant_t<dim> *q) {
      AssertThrow(q->level >= int(base_level), ExcInternalError());
      Leaf l;
      l.level = q->level - base_level;
      l.ijk   = {{0, 0, 0}};
      for (unsigned int d = 0; d < dim; ++d)
        l.ijk[d] = (tree_origin[t][d] << l.level) + (coordinate<dim>(*q, d) >> (max_level - q->level));
      out.push_back(l);
    });
    return out;
  }

  template <int dim>
  std::vector<double>
  Forest<dim>::adapt(const std::vector<signed char>                      &flags,
                     const std::function<void(const Source &, double *)> &fill, unsigned long long &refined,
                     unsigned long long &coarsened, const int leaf_weight,
                     const std::function<bool(const std::vector<signed char> &)> &balanced)
  {
    const unsigned int n_values = user.n_values;
    AssertThrow(leaf_weight >= 0, ExcMessage("leaf weights are positive (0: unweighted partition)"));
    AssertThrow(flags.size() == std::size_t(forest->local_num_quadrants),
                ExcMessage("one flag per local leaf"));
    // the leaves before, with their flags
    std::vector<std::pair<topidx_t<dim>, quadrant_t<dim>>> old;
    old.reserve(flags.size());
    for_each_local<dim>(forest, [&](const topidx_t<dim> t, quadrant_t<dim> *q) {
      payload<dim>(q)[n_values] = flags[old.size()];
      old.emplace_back(t, *q);
    });
    // deal.II's sequence (parallel::distributed::Triangulation::execute_coarsening_and_
    // refinement): refine and coarsen one level, then balance faces, edges and corners
    p4<dim>::refine(forest, /*recursive=*/0, &refine_flagged<dim>, &init_zero<dim>);
    p4<dim>::coarsen(forest, /*recursive=*/0, &coarsen_flagged<dim>, &init_zero<dim>);
    // walking the new leaves and the old ones together (both in forest order, covering the
    // same region): skip the old leaves before q that do not contain it
    auto skip_to = [&old](std::size_t &j, const topidx_t<dim> t, const quadrant_t<dim> *q) {
      while (j < old.size() &&
             (old[j].first < t || (old[j].first == t && p4<dim>::quadrant_compare(&old[j].second, q) < 0 &&
                                   !p4<dim>::quadrant_is_ancestor(&old[j].second, q))))
        ++j;
      AssertThrow(j < old.size() && old[j].first == t, ExcInternalError());
    };
    // the change of level of each former leaf (the leaves now are the former ones, their
    // children or their parents, in the same order): whoever knows the neighbourhoods
    // may prove that balance has nothing to do
    bool skip_balance = false;
    if (balanced)
      {
        std::vector<signed char> delta(old.size(), 0);
        std::size_t              j = 0;
        for_each_local<dim>(forest, [&](const topidx_t<dim> t, const quadrant_t<dim> *q) {
          skip_to(j, t, q);
          if (p4<dim>::quadrant_is_equal(&old[j].second, q))
            ++j;
          else if (p4<dim>::quadrant_is_ancestor(&old[j].second, q))
            delta[j] = 1; // a child (the next ones skip past the parent)
          else
            for (unsigned int c = 0; c < (1u << dim); ++c, ++j)
              {
                AssertThrow(j < old.size(), ExcInternalError());
                delta[j] = -1;
              }
        });
        skip_balance = balanced(delta);
      }
    if (skip_balance)
      ++n_balance_skipped;
    else
      {
        p4<dim>::balance(forest,
                         typename internal::p4est::types<dim>::balance_type(
                           dim == 2 ? int(P4EST_CONNECT_FULL) : int(P8EST_CONNECT_FULL)),
                         &init_zero<dim>);
        ++n_balance_run;
      }

    // each new leaf against the old ones (both in forest order, covering the same region:
    // refinement, coarsening and balance are local): the same, a child of one, or the
    // parent of a family
    refined = coarsened = 0;
    std::size_t j       = 0;
    for_each_local<dim>(forest, [&](const topidx_t<dim> t, quadrant_t<dim> *q) {
      skip_to(j, t, q);
      const quadrant_t<dim> &o = old[j].second;
      Source                 src{Source::same, unsigned(j), 0};
      if (p4<dim>::quadrant_is_equal(&o, q))
        ++j;
      else if (q->level == o.level + 1 && p4<dim>::quadrant_is_ancestor(&o, q))
        {
          src.kind  = Source::from_parent;
          src.child = p4<dim>::quadrant_ancestor_id(q, q->level);
          refined += src.child == 0 ? 1 : 0;
        }
      else
        {
          src.kind = Source::from_children;
          for (unsigned int c = 0; c < (1u << dim); ++c)
            AssertThrow(j + c < old.size() && old[j + c].first == t &&
                          old[j + c].second.level == q->level + 1 &&
                          p4<dim>::quadrant_is_ancestor(q, &old[j + c].second),
                        ExcMessage("adaptation changed a leaf by more than one level"));
          j += 1u << dim;
          coarsened += 1u << dim;
        }
      fill(src, payload<dim>(q));
    });

    // families stay on one rank (the next adaptation may coarsen them); p4est moves the
    // payloads along
    // (the weights are the same kind on every rank: all 0 or all > 0)
    user.leaf_weight = leaf_weight;
    p4<dim>::partition(forest, /*partition_for_coarsening=*/1, leaf_weight > 0 ? &weigh_leaf<dim> : nullptr);
    std::vector<double> values;
    values.reserve(std::size_t(forest->local_num_quadrants) * n_values);
    for_each_local<dim>(forest, [&](const topidx_t<dim>, quadrant_t<dim> *q) {
      const double *p = payload<dim>(q);
      values.insert(values.end(), p, p + n_values);
    });
    return values;
  }

  // 1D boxes are never adaptive (CartesianPatch<1> holds no forest)
  template <>
  Forest<1>::~Forest() = default;
  template <>
  unsigned long long Forest<1>::first_global() const
  {
    return 0;
  }
  template <>
  unsigned long long Forest<1>::n_global() const
  {
    return 0;
  }
  template <>
  std::vector<Forest<1>::Leaf> Forest<1>::leaves() const
  {
    return {};
  }

  template class Forest<2>;
  template class Forest<3>;
} // namespace granhydro::mesh
