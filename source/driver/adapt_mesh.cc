/**
 * @file adapt_mesh.cc
 * Adaptive meshes of Simulation: the refinement indicator (largest normalised jump of
 * n and p, or Loehner's second differences), the buffer around refined cells, and the
 * adaptation of the patch with the state.
 */
#include <granhydro/driver/simulation_instances.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace granhydro
{
  using namespace dealii;

  template <int dim, class Description>
  bool Simulation<dim, Description>::adapt_mesh(const bool initial)
  {
    constexpr unsigned int NC = dim + 2;
    const CartesianPatch<dim> &P = *patch_;
    const unsigned int n_owned = P.n_owned();
    std::vector<double> W;
    P.gather(U, W);
    // indicator: largest normalised jump of n and p across the cell's faces
    std::vector<double> n(P.n_slots()), p(P.n_slots());
    for (unsigned int s = 0; s < P.n_slots(); ++s)
      {
        State S;
        std::copy(&W[std::size_t(s) * NC], &W[std::size_t(s + 1) * NC], S.begin());
        n[s] = S[0];
        p[s] = desc.pressure(S);
      }
    auto jump = [](const double a, const double b) {
      const double lo = std::min(a, b);
      return lo > 0 ? std::abs(a - b) / lo : std::numeric_limits<double>::infinity();
    };
    // Loehner's indicator: the second difference over the first differences along each
    // direction (gradient neighbours: same level or coarser), in [0, 1], ~1 at
    // discontinuities and kinks, ~h |a''| / |a'| in smooth regions
    auto loehner = [&](const std::vector<double> &a, const unsigned int s, const unsigned int d) {
      const int m = P.gradient_neighbor(s, d, 0), q = P.gradient_neighbor(s, d, 1);
      if (m < 0 || q < 0)
        return 0.;
      // the neighbours' values at the distance h_s (linear along the line of centres)
      const double h = P.cell_size(s, d), dm = -P.gradient_offset(s, d, 0), dq = P.gradient_offset(s, d, 1);
      const double sm = (a[s] - a[m]) * h / dm, sq = (a[q] - a[s]) * h / dq;
      const double den = std::abs(sq) + std::abs(sm) + 0.05 * (std::abs(a[q]) + 2 * std::abs(a[s]) + std::abs(a[m]));
      return den > 0 ? std::abs(sq - sm) / den : 0.;
    };
    Vector mark(P.partitioner()); // component 0: 1 = refine
    std::vector<double> eta(n_owned, 0.);
    for (unsigned int s = 0; s < n_owned; ++s)
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (scene.adapt_indicator == RefinementIndicator::second_differences)
            eta[s] = std::max({eta[s], loehner(n, s, d), loehner(p, s, d)});
          else
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                {
                  const unsigned int t = P.across(d, *cf);
                  eta[s] = std::max({eta[s], jump(n[s], n[t]), jump(p[s], p[t])});
                }
            }
        mark.local_element(std::size_t(s) * NC) = eta[s] > scene.refine_threshold ? 1. : 0.;
      }
    // buffer: the refine mark spreads over face neighbours, one layer per pass
    for (unsigned int pass = 0; pass < scene.adapt_buffer; ++pass)
      {
        mark.update_ghost_values();
        std::vector<char> next(n_owned, 0);
        for (unsigned int s = 0; s < n_owned; ++s)
          for (unsigned int d = 0; d < dim && !next[s]; ++d)
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                if (const unsigned int t = P.across(d, *cf);
                    P.is_cell(t) && mark.local_element(std::size_t(t) * NC) > 0)
                  next[s] = 1;
            }
        mark.zero_out_ghost_values();
        for (unsigned int s = 0; s < n_owned; ++s)
          if (next[s])
            mark.local_element(std::size_t(s) * NC) = 1.;
      }
    std::vector<signed char> flags(n_owned, 0);
    for (unsigned int s = 0; s < n_owned; ++s)
      if (mark.local_element(std::size_t(s) * NC) > 0)
        flags[s] = 1;
      else if (!initial && eta[s] < scene.coarsen_threshold)
        flags[s] = -1;
    // new children: limited linear prolongation where all siblings stay admissible
    const auto admissible = [this](const double *u) {
      State S;
      std::copy(u, u + NC, S.begin());
      return desc.admissible(S);
    };
    // the partition (Adaptivity/Load balance): with the measured cost, each rank's cells
    // weigh its convective seconds per cell since the last adaptation (waits for other
    // ranks excluded) relative to the mean over the ranks, within 1/2 .. 2; p4est then
    // gives every rank the same sum of weights, so a rank that was slower per cell (a
    // busier core, more coarse/fine interfaces) hands cells to its neighbours. Until every
    // rank has measured (the first steps), equal numbers of cells.
    int                leaf_weight = 0;
    const unsigned int n_ranks     = Utilities::MPI::n_mpi_processes(comm);
    if (n_ranks > 1 && scene.balance_by_measured_cost(scene.diffusion_active()))
      {
        const double busy = conv ? conv->busy_seconds() - busy_at_adapt_ : 0.;
        const double cost = fixed_cost_ > 0 ? fixed_cost_ : (n_owned > 0 && busy > 0 ? busy / n_owned : 0.);
        const std::vector<double> costs = Utilities::MPI::all_gather(comm, cost); // O(ranks)
        if (std::all_of(costs.begin(), costs.end(), [](const double c) { return c > 0; }))
          {
            const double mean = std::accumulate(costs.begin(), costs.end(), 0.) / n_ranks;
            leaf_weight       = int(std::lround(1000. * std::clamp(cost / mean, 0.5, 2.)));
          }
      }
    if (!patch_->adapt(flags, U, admissible, leaf_weight))
      return false;
    busy_at_adapt_ = conv ? conv->busy_seconds() : 0.;
    mesh_changed();
    ++adaptations;
    refined_cells += patch_->last_refined();
    coarsened_cells += patch_->last_coarsened();
    max_cells = std::max<unsigned long long>(max_cells, patch_->n_global_cells());
    return true;
  }

  GRANHYDRO_SIMULATION_INSTANCES
} // namespace granhydro
