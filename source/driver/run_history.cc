/**
 * @file run_history.cc
 * The run's history <base>_history.csv (io/history.h): its columns, when a row is due
 * (Output/History interval) and the values of a row, from the state's totals
 * (io::state_totals) and the run's counts so far, the earlier segments' included.
 */
#include "time_loop_instances.h"

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace granhydro::driver
{
  template <int dim, class Description>
  void TimeLoop<dim, Description>::start_history(const bool fresh, const io::StateTotals<dim> &s0)
  {
    if (files.history_steps == 0 && files.history_seconds == 0)
      return;
    const char              *ax      = "xyz";
    std::vector<std::string> columns = {"time", "dt", "step", "mass"};
    for (unsigned int d = 0; d < dim; ++d)
      columns.push_back(std::string("momentum_") + ax[d]);
    for (const char *part : {"kinetic", "thermal", "contact", "total"})
      columns.push_back(std::string(part) + "_energy");
    for (unsigned int d = 0; d < dim; ++d)
      columns.push_back(std::string("centre_of_mass_") + ax[d]);
    for (const char *c : {"max_packing_fraction", "min_temperature", "max_speed", "rejected_steps",
                          "integrator", "convective_steps", "diffusion_steps", "rkl2_steps", "rkl2_stages",
                          "implicit_steps", "newton_iterations", "gmres_iterations"})
      columns.emplace_back(c);
    history_ = std::make_unique<io::HistoryFile>(files.directory, files.file("_history.csv"), columns, comm);
    if (fresh)
      {
        history_->start();
        write_history_row(s0);
      }
    else
      {
        // the rows up to the checkpoint's step stay, the ones a later part of a killed run
        // wrote are dropped; the row of this step is there already (or was not due)
        history_->resume(L.step);
        L.history_step = L.step;
      }
  }

  template <int dim, class Description>
  bool TimeLoop<dim, Description>::history_due(const double t_before) const
  {
    if (!history_)
      return false;
    if (files.history_steps > 0)
      return L.step % files.history_steps == 0;
    // after the first step at or past each multiple of the interval: a rule of the step's
    // own times, so that a restarted run writes the rows the uninterrupted one wrote
    const double h     = files.history_seconds / L.t0;
    const auto   index = [h](const double t) { return std::floor(t / h * (1 + 1e-12)); };
    return index(L.t) > index(t_before);
  }

  template <int dim, class Description>
  void TimeLoop<dim, Description>::write_history_row(const io::StateTotals<dim> &s)
  {
    L.history_step = L.step;
    using N        = unsigned long long;
    // extensive values per m^(3 - dim) of the unresolved extent
    const double                  extent = std::pow(units_.length, dim - 3.);
    const double                  energy = units_.energy() * extent;
    std::vector<io::HistoryValue> row = {L.t * L.t0, L.last_dt * L.t0, N(L.step), s.n * units_.mass * extent};
    for (unsigned int d = 0; d < dim; ++d)
      row.emplace_back(s.nu[d] * units_.mass * units_.velocity * extent);
    for (const double e : {s.kinetic, s.thermal, s.contact, s.energy})
      row.emplace_back(e * energy);
    for (unsigned int d = 0; d < dim; ++d)
      row.emplace_back(s.nx[d] / s.n);
    row.emplace_back(std::is_same_v<Description, physics::GranularGas<dim>> ?
                       s.max_packing_fraction :
                       std::numeric_limits<double>::quiet_NaN());
    row.emplace_back(s.min_temperature * units_.energy());
    row.emplace_back(s.max_speed * units_.velocity);
    // the counts of the whole run so far: the earlier segments' and this one's (the
    // integrator's counts are the same on every rank: no reduction)
    const auto                           &e = start_.earlier.diffusion;
    const diffusion::IntegratorStatistics none;
    const auto                           &d = integrator ? integrator->statistics() : none;
    row.emplace_back(N(start_.earlier.rejected_steps + L.sum.rejected_steps));
    row.emplace_back(integrator ? integrator_name : std::string("none"));
    row.emplace_back(N(start_.earlier.convective_steps + split.counters().convective_pieces));
    row.emplace_back(N(e.steps + d.steps));
    row.emplace_back(N(e.rkl2_steps + d.rkl2_steps));
    row.emplace_back(N(e.rkl2_stages + d.rkl2_stages));
    row.emplace_back(N(e.implicit_steps + d.implicit_steps));
    row.emplace_back(N(e.newton_iterations + d.newton_iterations));
    row.emplace_back(N(e.linear_iterations + d.linear_iterations));
    history_->write(row);
  }

  GRANHYDRO_TIME_LOOP_INSTANCES
} // namespace granhydro::driver
