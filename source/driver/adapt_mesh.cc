/**
 * @file adapt_mesh.cc
 * Adaptive meshes of Simulation: the refinement flags from n and p (mesh/adaptivity.h),
 * the partition's weights, and the adaptation of the patch with the state.
 */
#include <granhydro/mesh/adaptivity.h>

#include "simulation_instances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace granhydro::driver
{
  using namespace dealii;

  template <int dim, class Description>
  bool Simulation<dim, Description>::adapt_mesh(const bool initial)
  {
    constexpr unsigned int           NC      = dim + 2;
    const mesh::CartesianPatch<dim> &P       = *patch_;
    const unsigned int               n_owned = P.n_owned();
    std::vector<double>              W;
    P.gather(U, W);
    // the indicator's fields: n and p on every slot
    std::vector<double> n(P.n_slots()), p(P.n_slots());
    for (unsigned int s = 0; s < P.n_slots(); ++s)
      {
        State S;
        std::copy(&W[std::size_t(s) * NC], &W[std::size_t(s + 1) * NC], S.begin());
        n[s] = S[0];
        p[s] = desc.pressure(S);
      }
    const std::vector<signed char> flags = mesh::refinement_flags(P, n, p, adaptation.indicator, initial);
    // new children: limited linear prolongation where all siblings stay admissible
    // (with the splitting allowance of the last step, whose states they come from)
    const auto admissible = [this](const double *u) {
      State S;
      std::copy(u, u + NC, S.begin());
      return desc.admissible(S, split_->repair_energy());
    };
    // the partition (Adaptivity/Load balance): with the measured cost, each rank's cells
    // weigh its convective seconds per cell since the last adaptation (waits for other
    // ranks excluded) relative to the mean over the ranks, within 1/2 .. 2; p4est then
    // gives every rank the same sum of weights, so a rank that was slower per cell (a
    // busier core, more coarse/fine interfaces) hands cells to its neighbours. Until every
    // rank has measured (the first steps), equal numbers of cells.
    int                leaf_weight = 0;
    const unsigned int n_ranks     = Utilities::MPI::n_mpi_processes(comm);
    if (n_ranks > 1 && adaptation.balance_by_cost)
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
    ++adapted_.adaptations;
    adapted_.refined_cells += patch_->last_refined();
    adapted_.coarsened_cells += patch_->last_coarsened();
    adapted_.max_cells = std::max<unsigned long long>(adapted_.max_cells, patch_->n_global_cells());
    return true;
  }

  GRANHYDRO_SIMULATION_INSTANCES
} // namespace granhydro::driver
