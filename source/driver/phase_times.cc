/**
 * @file phase_times.cc
 * Where a run's wall time went (driver/phase_times.h): the phases' seconds of each rank
 * (deal.II TimerOutput sections of the driver, plain sums inside the operators), their
 * least, mean and largest over the ranks in one reduction at the end, the log's table
 * and the summary's rows.
 */
#include <granhydro/driver/phase_times.h>

#include <deal.II/base/mpi.h>

#include "time_loop_instances.h"

#include <algorithm>
#include <cstdio>

namespace granhydro::driver
{
  using namespace dealii;

  std::vector<PhaseTime> phase_list()
  {
    return {{"wall", "wall (whole run)", 0},
            {"convection", "convection (SSP-RK3 steps)", 0},
            {"halo_wait", "halo waits", 1},
            {"admissibility_vote", "admissibility votes", 1},
            {"diffusion", "diffusion step", 0},
            {"jacobian", "Jacobians", 1},
            {"preconditioner", "preconditioner set-ups", 1},
            {"gmres", "GMRES", 1},
            {"adaptation", "mesh adaptation", 0},
            {"output", "output and checkpoints", 0},
            {"other", "other (step size, checks)", 0}};
  }

  std::vector<PhaseTime> reduce_phase_times(const std::vector<double> &local, const MPI_Comm comm)
  {
    std::vector<PhaseTime> phases = phase_list();
    AssertThrow(local.size() == phases.size(), ExcMessage("one time per phase"));
    const auto stats = Utilities::MPI::min_max_avg(local, comm); // the one collective call
    for (std::size_t i = 0; i < phases.size(); ++i)
      {
        phases[i].min = stats[i].min;
        phases[i].max = stats[i].max;
        // sum / ranks may round outside [min, max] when all ranks agree
        phases[i].avg = std::clamp(stats[i].avg, stats[i].min, stats[i].max);
      }
    return phases;
  }

  std::string phase_table(const std::vector<PhaseTime> &phases, const unsigned int ranks)
  {
    const double wall = phases.empty() ? 0 : phases.front().avg;
    char         line[160];
    std::snprintf(line, sizeof line,
                  "  wall time by phase over %u rank%s [s]:\n    %-32s %10s %10s %10s %10s\n", ranks,
                  ranks == 1 ? "" : "s", "phase", "min", "avg", "max", "% of wall");
    std::string table = line;
    for (const auto &p : phases)
      if (p.max > 0 || p.min < 0 || p.key == "wall")
        {
          const std::string name = std::string(2 * p.depth, ' ') + p.label;
          std::snprintf(line, sizeof line, "    %-32s %10.4g %10.4g %10.4g %10.1f\n", name.c_str(), p.min,
                        p.avg, p.max, wall > 0 ? 100 * p.avg / wall : 0.);
          table += line;
        }
    return table;
  }

  void append_phase_entries(std::vector<io::SummaryEntry> &entries, const std::vector<PhaseTime> &phases)
  {
    for (const auto &p : phases)
      {
        entries.push_back({p.key + "_min_seconds", p.min});
        entries.push_back({p.key + "_avg_seconds", p.avg});
        entries.push_back({p.key + "_max_seconds", p.max});
      }
  }

  template <int dim, class Description>
  void TimeLoop<dim, Description>::measure_phases(RunSummary &sum) const
  {
    // this rank's seconds; the driver's sections do not overlap and lie within the wall
    // time (from the start of run() to now), so "other" is what they leave (never < 0)
    const auto section = [times = timers.get_summary_data(TimerOutput::total_wall_time)](const char *name) {
      const auto it = times.find(name);
      return it == times.end() ? 0. : it->second;
    };
    const double convection = section("convection"), diffusion = section("diffusion"),
                 adaptation = section("adaptation"), out = section("output");
    const diffusion::IntegratorStatistics ds =
      integrator ? integrator->statistics() : diffusion::IntegratorStatistics();
    const std::vector<double> local = {sum.wall_seconds,
                                       convection,
                                       conv.halo_wait_seconds(),
                                       conv.vote_seconds(),
                                       diffusion,
                                       ds.jacobian_seconds,
                                       ds.preconditioner_seconds,
                                       ds.linear_seconds,
                                       adaptation,
                                       out,
                                       sum.wall_seconds - convection - diffusion - adaptation - out};
    sum.phases                      = reduce_phase_times(local, comm);
    const auto largest              = [&](const char *key) {
      return std::find_if(sum.phases.begin(), sum.phases.end(),
                                       [&](const PhaseTime &p) { return p.key == key; })
        ->max;
    };
    // the rows scripts read (the largest rank, as before; the Jacobian, preconditioner and
    // GMRES rows were rank 0's)
    sum.convection_seconds = largest("convection");
    sum.adaptation_seconds = largest("adaptation");
    if (integrator)
      {
        sum.diffusion_seconds                = largest("diffusion");
        sum.diffusion.jacobian_seconds       = largest("jacobian");
        sum.diffusion.preconditioner_seconds = largest("preconditioner");
        sum.diffusion.linear_seconds         = largest("gmres");
      }
  }

  GRANHYDRO_TIME_LOOP_INSTANCES
} // namespace granhydro::driver
