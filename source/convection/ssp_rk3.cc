// ConvectionOperator: the SSP-RK3 time step of eq. (4.10), its stage update with the
// a-posteriori first-order fallback, the convective rate for the CFL condition and the
// admissibility check of a step's result (the operator L(U) is in convection_operator.cc)
#include <granhydro/convection/convection_operator.h>
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/models.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <sstream>

namespace granhydro::convection
{
  using namespace dealii;

  template <int dim, class Description>
  bool ConvectionOperator<dim, Description>::stage_update(Vector &U, const double a, const double b,
                                                          const double den, const double dt,
                                                          const double repair_energy) const
  {
    // candidate u_new = a U0 + b (u + dt L(u)); cells whose candidate is inadmissible
    // get first-order Rusanov fluxes (cell averages of this stage) on all their faces,
    // which is positivity preserving for CFL <= 1/2 (Perthame-Shu); their neighbours
    // see the changed face flux and are re-checked. Flags are exchanged between
    // ranks, so shared faces are recomputed identically on both sides.
    const unsigned int n_owned = patch.n_owned();
    const std::size_t  n       = std::size_t(n_owned) * NC;
    double            *u       = n ? &U.local_element(0) : nullptr;
    apply(W, rhs0, repair_energy);
    std::vector<char> low(patch.n_slots(), 0);
    for (unsigned int iter = 0;; ++iter)
      {
        for (std::size_t i = 0; i < n; ++i)
          cand[i] = (a * U0[i] + b * (u[i] + dt * rhs0[i])) / den;
        unsigned int new_flags = 0;
        for (unsigned int s = 0; s < n_owned; ++s)
          {
            physics::State<dim> S;
            std::copy(&cand[std::size_t(s) * NC], &cand[std::size_t(s + 1) * NC], S.begin());
            const bool bad =
              !(wb_any ? desc.convectively_admissible(S, repair_energy) : desc.convectively_admissible(S));
            flags.local_element(s) = bad || low[s] ? 1.f : 0.f;
            if (bad && !low[s])
              ++new_flags;
            if (bad && low[s])
              {
                new_flags += 1u << 20; // already first order: give up, the step is rejected
                if (last_failure.empty())
                  {
                    std::ostringstream os;
                    os << "convective stage at x = " << patch.center(s)
                       << " m even with first-order fluxes: packing fraction "
                       << physics::packing_fraction(S[0]) << ", T = " << desc.temperature(S)
                       << " (scaled units)";
                    last_failure = os.str();
                  }
              }
          }
        const auto         t0     = std::chrono::steady_clock::now();
        const unsigned int global = Utilities::MPI::sum(new_flags, patch.communicator());
        vote_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (global == 0)
          break;
        if (global >= (1u << 20) || iter > 8)
          return false;
        flags.update_ghost_values();
        for (unsigned int s = 0; s < n_owned + patch.n_mpi_ghosts(); ++s)
          if (flags.local_element(s) > 0 && !low[s])
            {
              low[s] = 1;
              if (s < n_owned)
                ++stats.fallback_cells;
            }
        for (unsigned int d = 0; d < dim; ++d)
          for (std::size_t k = 0; k < patch.faces(d).size(); ++k)
            if (const unsigned int sl = patch.faces(d)[k].l, sr = patch.faces(d)[k].r; low[sl] || low[sr])
              {
                // first-order face states: the cell averages, with gravity along d the
                // equilibrium's (a wall's ghost side the mirror of the cell's)
                physics::State<dim> UL, UR, F;
                first_order_face_state(W, sl, d, 1, UL);
                first_order_face_state(W, sr, d, 0, UR);
                if (wb_dir[d] && wb_wall_ghost[d][k] >= 0)
                  mirror_wall_face(d, k, UL.data(), UR.data());
                numflux.rusanov(UL, UR, d, F);
                if (wall[d][k])
                  wall_flux(wall[d][k], d, F.data(), owned_wall_face(d, k));
                std::copy(F.begin(), F.end(), &Fp[d][k * NC]);
              }
        assemble_rhs(rhs0);
      }
    std::copy(cand, cand + n, u);
    return true;
  }

  template <int dim, class Description>
  physics::State<dim> ConvectionOperator<dim, Description>::owned_state(const Vector &U, const unsigned int s,
                                                                        const double *energy_shift) const
  {
    physics::State<dim> S;
    for (unsigned int c = 0; c < NC; ++c)
      S[c] = U.local_element(std::size_t(s) * NC + c);
    if (energy_shift != nullptr)
      S[NC - 1] -= energy_shift[s];
    return S;
  }

  template <int dim, class Description>
  double ConvectionOperator<dim, Description>::max_rate(const Vector &U, const double *energy_shift) const
  {
    double m = 0;
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        const physics::State<dim> S    = owned_state(U, s, energy_shift);
        double                    rate = 0;
        for (unsigned int d = 0; d < dim; ++d)
          rate += desc.max_wave_speed(S, d) * inv_h[d][patch.level(s)];
        m = std::max(m, rate);
      }
    return Utilities::MPI::max(m, patch.communicator());
  }

  template <int dim, class Description>
  bool ConvectionOperator<dim, Description>::ssp_rk3_step(Vector &U, const double dt,
                                                          const double repair_energy) const
  {
    const std::size_t n = std::size_t(patch.n_owned()) * NC;
    last_failure.clear();
    // the step's work arrays (the patch's shared scratch)
    W         = patch.scratch(mesh::Scratch::slot_array, std::size_t(patch.n_slots()) * NC);
    U0        = patch.scratch(mesh::Scratch::owned_0, n);
    rhs0      = patch.scratch(mesh::Scratch::owned_1, n);
    cand      = patch.scratch(mesh::Scratch::owned_2, n);
    double *u = n ? &U.local_element(0) : nullptr;
    std::copy(u, u + n, U0);
    // eq. 4.10, each stage a convex combination of forward Euler steps, written with
    // integer weights and one division ((U0 + 2 v)/3, not U0/3 + 2v/3): the rounded
    // weights 1/3 and 2/3 sum to 1 - 5.6e-17, a systematic mass loss of that size per step
    patch.gather(U, W);
    if (!stage_update(U, 0., 1., 1., dt, repair_energy))
      return false;
    patch.gather(U, W);
    if (!stage_update(U, 3., 1., 4., dt, repair_energy))
      return false;
    patch.gather(U, W);
    if (!stage_update(U, 1., 2., 3., dt, repair_energy))
      return false;
    return true;
  }

  template <int dim, class Description>
  bool ConvectionOperator<dim, Description>::admissible(const Vector &U, std::string *what,
                                                        const double *energy_shift) const
  {
    int bad = -1;
    for (unsigned int s = 0; s < patch.n_owned() && bad < 0; ++s)
      if (!desc.admissible(owned_state(U, s, energy_shift)))
        bad = s;
    const bool ok = Utilities::MPI::min(bad < 0 ? 1 : 0, patch.communicator()) == 1;
    if (!ok && what != nullptr && bad >= 0)
      {
        std::ostringstream        os;
        const physics::State<dim> S = owned_state(U, bad, energy_shift);
        os << "cell at x = " << patch.center(bad) << " m: n*sigma^3 = " << S[0] << ", packing fraction "
           << physics::packing_fraction(S[0]) << ", T = " << desc.temperature(S) << " (scaled units)";
        *what = os.str();
      }
    return ok;
  }

  template <int dim, class Description>
  ConvectionStatistics ConvectionOperator<dim, Description>::global_statistics() const
  {
    ConvectionStatistics g;
    const MPI_Comm       comm = patch.communicator();
    g.flux.points             = Utilities::MPI::sum(stats.flux.points, comm);
    g.flux.stages             = Utilities::MPI::sum(stats.flux.stages, comm);
    g.flux.fallbacks          = Utilities::MPI::sum(stats.flux.fallbacks, comm);
    g.flux.early_stops        = Utilities::MPI::sum(stats.flux.early_stops, comm);
    g.limited_cells           = Utilities::MPI::sum(stats.limited_cells, comm);
    g.fallback_cells          = Utilities::MPI::sum(stats.fallback_cells, comm);
    g.cell_updates            = Utilities::MPI::sum(stats.cell_updates, comm);
    g.rhs_evaluations         = stats.rhs_evaluations;
    g.wall_tension_bounded    = Utilities::MPI::sum(stats.wall_tension_bounded, comm);
    g.gravity_point_sources   = Utilities::MPI::sum(stats.gravity_point_sources, comm);
    return g;
  }

#define GRANHYDRO_INSTANTIATE(d, D) template class ConvectionOperator<d, D>;
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_INSTANTIATE)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::convection
