#pragma once
/**
 * @file phase_times.h
 * Where a run's wall time went: per phase (convection, its halo waits and admissibility
 * votes, diffusion, its Jacobians, preconditioner set-ups and GMRES, adaptation,
 * output) the least, mean and largest seconds over the ranks, for the table at the end
 * of the log and the <phase>_{min,avg,max}_seconds rows of <base>_summary.csv. Each
 * rank measures its own times without waiting for the others; one reduction at the end
 * of the run gives the statistics (deal.II's print_wall_time_statistics does the same).
 */
#include <granhydro/io/summary_csv.h>

#include <mpi.h>

#include <string>
#include <vector>

namespace granhydro::driver
{
  /// one phase of a run, its wall time over the ranks [s]
  struct PhaseTime
  {
    std::string key;   ///< the summary's rows are <key>_min_seconds, _avg_seconds, _max_seconds
    std::string label; ///< the name in the log's table
    /// 0: the whole run ("wall") or one of the phases that split it: on every rank they
    /// do not overlap, and "other" is what they leave; 1: a part of the phase above
    unsigned int depth = 0;
    double       min = 0, avg = 0, max = 0;
  };

  /// the phases of a run with this rank's seconds (`local`, in the order of
  /// phase_list()), reduced over the ranks of comm in one collective call
  std::vector<PhaseTime> reduce_phase_times(const std::vector<double> &local, const MPI_Comm comm);

  /// the phases in the order of the log and the summary: wall, convection, halo_wait,
  /// admissibility_vote, diffusion, jacobian, preconditioner, gmres, adaptation, output,
  /// other (times unset)
  std::vector<PhaseTime> phase_list();

  /// the table at the end of the log: phase, min, avg, max [s] and the mean's share of the
  /// mean wall time; phases that took no time on any rank are left out
  std::string phase_table(const std::vector<PhaseTime> &phases, const unsigned int ranks);

  /// the summary's rows <key>_min_seconds, <key>_avg_seconds, <key>_max_seconds of every
  /// phase (all of them, also those that took no time)
  void append_phase_entries(std::vector<io::SummaryEntry> &entries, const std::vector<PhaseTime> &phases);
} // namespace granhydro::driver
