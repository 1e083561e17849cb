#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace granhydro
{
  using namespace dealii;

  namespace
  {
    using Vector = LinearAlgebra::distributed::Vector<double>;

    /// per owned cell (W: the slot array) and direction d < dim the minmod slopes of all components (from the
    /// gradient neighbours) in carried[d], and the cell's level in carried[dim]
    template <int dim>
    void carry_slopes(const CartesianPatch<dim> &patch, const std::vector<double> &W,
                      std::vector<Vector> &carried)
    {
      constexpr unsigned int NC = CartesianPatch<dim>::n_components;
      for (unsigned int s = 0; s < patch.n_owned(); ++s)
        {
          for (unsigned int d = 0; d < dim; ++d)
            {
              const int m = patch.gradient_neighbor(s, d, 0), q = patch.gradient_neighbor(s, d, 1);
              for (unsigned int c = 0; c < NC; ++c)
                {
                  double sigma = 0;
                  if (m >= 0 && q >= 0)
                    {
                      const double u  = W[std::size_t(s) * NC + c];
                      const double sl = (u - W[std::size_t(m) * NC + c]) / -patch.gradient_offset(s, d, 0);
                      const double sr = (W[std::size_t(q) * NC + c] - u) / patch.gradient_offset(s, d, 1);
                      sigma = sl * sr > 0 ? (std::abs(sl) < std::abs(sr) ? sl : sr) : 0.;
                    }
                  carried[d].local_element(std::size_t(s) * NC + c) = sigma;
                }
            }
          for (unsigned int c = 0; c < NC; ++c)
            carried[dim].local_element(std::size_t(s) * NC + c) = patch.level(s);
        }
      for (auto &v : carried)
        v.update_ghost_values();
    }

    /// new children (their level is above the carried one) take the parent's value plus
    /// the carried slopes times their offset, when all 2^dim siblings pass admissible
    template <int dim>
    void prolong_linearly(const CartesianPatch<dim> &patch, const std::vector<Vector> &out, Vector &U,
                          const std::function<bool(const double *)> &admissible)
    {
      constexpr unsigned int NC = CartesianPatch<dim>::n_components;
      for (unsigned int s = 0; s < patch.n_owned(); ++s)
        {
          if (double(patch.level(s)) <= out[dim + 1].local_element(std::size_t(s) * NC))
            continue;
          // the value of sibling `sib` (bit d set: upper half along d); all 2^dim
          // siblings admissible, or the family keeps the parent's value
          double *u       = &U.local_element(std::size_t(s) * NC);
          auto    sibling = [&](const unsigned int sib, double *child) {
            for (unsigned int c = 0; c < NC; ++c)
              {
                child[c] = u[c];
                for (unsigned int d = 0; d < dim; ++d)
                  child[c] += out[1 + d].local_element(std::size_t(s) * NC + c) * 0.5 * patch.cell_size(s, d) *
                              ((sib >> d & 1u) ? 1. : -1.);
              }
          };
          double child[NC];
          bool   ok = true;
          for (unsigned int sib = 0; sib < (1u << dim) && ok; ++sib)
            {
              sibling(sib, child);
              ok = admissible(child);
            }
          if (!ok)
            continue;
          unsigned int mine = 0;
          for (unsigned int d = 0; d < dim; ++d)
            mine |= (patch.lattice(s)[d] & 1u) << d;
          sibling(mine, child);
          std::copy(child, child + NC, u);
        }
    }
  } // namespace

  template <int dim>
  bool CartesianPatch<dim>::adapt(const std::vector<signed char> &flags,
                                  LinearAlgebra::distributed::Vector<double> &U,
                                  const std::function<bool(const double *)> &admissible)
  {
    if constexpr (dim == 1)
      {
        (void)flags;
        (void)U;
        (void)admissible;
        AssertThrow(false, ExcMessage("adaptive meshes need 2 or 3 dimensions"));
        return false;
      }
    else
      {
        auto &ptria = dynamic_cast<parallel::distributed::Triangulation<dim> &>(*tria);
        AssertThrow(flags.size() == n_owned_, ExcMessage("one flag per owned cell"));
        std::vector<int> slot_of_active(tria->n_active_cells(), -1);
        for (unsigned int s = 0; s < n_owned_; ++s)
          slot_of_active[active_index_[s]] = s;
        unsigned int changes = 0;
        for (const auto &cell : tria->active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const int s = slot_of_active[cell->active_cell_index()];
              cell->clear_refine_flag();
              cell->clear_coarsen_flag();
              if (flags[s] > 0 && level_[s] < max_level_)
                {
                  cell->set_refine_flag();
                  ++changes;
                }
              else if (flags[s] < 0 && level_[s] > 0)
                {
                  cell->set_coarsen_flag();
                  ++changes;
                }
            }
        if (Utilities::MPI::sum(changes, comm) == 0)
          return false;
        // the state with the ghost values deal.II expects (locally relevant = one layer)
        IndexSet relevant;
        DoFTools::extract_locally_relevant_dofs(*dofh, relevant);
        LinearAlgebra::distributed::Vector<double> old(dofh->locally_owned_dofs(), relevant, comm);
        for (std::size_t i = 0; i < std::size_t(n_owned_) * n_components; ++i)
          old.local_element(i) = U.local_element(i);
        old.update_ghost_values();
        // (deal.II's execute_coarsening_and_refinement() makes the flags consistent, 2:1
        // balance included: the counts of refined and coarsened cells come from the
        // carried levels below, not from a second pass over the flags)
        //
        // limited linear prolongation: each cell carries, through the transfer, its
        // minmod slopes per direction (from the gradient neighbours, all components) and
        // its level; a child then knows it is new (its level is higher) and takes the
        // parent's value plus the slopes times its offset from the parent's centre. The
        // offsets of the 2^dim children sum to zero: conservative to round-off.
        constexpr unsigned int NC = n_components;
        const bool linear = bool(admissible);
        // carried[d < dim]: the slopes along d; carried[dim]: the level (in every component)
        std::vector<LinearAlgebra::distributed::Vector<double>> carried(dim + 1);
        {
          std::vector<double> W;
          gather(U, W);
          for (auto &v : carried)
            v.reinit(dofh->locally_owned_dofs(), relevant, comm);
          carry_slopes(*this, W, carried);
        }
        std::vector<const LinearAlgebra::distributed::Vector<double> *> in{&old};
        for (const auto &v : carried)
          in.push_back(&v);
        parallel::distributed::SolutionTransfer<dim, LinearAlgebra::distributed::Vector<double>> st(*dofh);
        st.prepare_for_coarsening_and_refinement(in);
        ptria.execute_coarsening_and_refinement();
        rebuild();
        std::vector<LinearAlgebra::distributed::Vector<double>> out(in.size());
        std::vector<LinearAlgebra::distributed::Vector<double> *> outp;
        for (auto &v : out)
          {
            v.reinit(dofh->locally_owned_dofs(), comm);
            outp.push_back(&v);
          }
        st.interpolate(outp);
        U.reinit(part);
        for (std::size_t i = 0; i < std::size_t(n_owned_) * NC; ++i)
          U.local_element(i) = out[0].local_element(i);
        // a new child's level is above the carried (its parent's); a new parent's below
        // the carried (the mean of its children's)
        unsigned long long nr = 0, nc = 0;
        for (unsigned int s = 0; s < n_owned_; ++s)
          {
            const double carried_level = out[dim + 1].local_element(std::size_t(s) * NC);
            nr += double(level_[s]) > carried_level ? 1 : 0;
            nc += double(level_[s]) < carried_level ? 1 : 0;
          }
        last_refined_   = Utilities::MPI::sum(nr, comm) >> dim;
        last_coarsened_ = Utilities::MPI::sum(nc, comm) << dim;
        if (linear)
          prolong_linearly(*this, out, U, admissible);
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
        // a leaf of the target at level l inside an active cell of level k < l: refine it
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
        rebuild();
      }
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                   \
  template bool CartesianPatch<d>::adapt(const std::vector<signed char> &, Vector &,               \
                                         const std::function<bool(const double *)> &);             \
  template void CartesianPatch<d>::refine_to(const std::vector<long long> &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro
