#pragma once
/**
 * @file run_report.h
 * What a run reports about itself: the run summary lines at the end of the log, the
 * entries of <base>_summary.csv, and the rows that say which run it was (also in the
 * running summary written at the start).
 */
#include <granhydro/base/units.h>
#include <granhydro/driver/run_settings.h>
#include <granhydro/driver/run_summary.h>
#include <granhydro/io/summary_csv.h>

#include <deal.II/base/conditional_ostream.h>

#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace granhydro::driver
{
  class RunReport
  {
  public:
    /// of the time loop's settings it reads the splitting, of the adaptation's the partition
    RunReport(const RunReportSettings &settings, const RunFiles &files, const TimeLoopSettings &loop,
              const AdaptationSettings &adaptation, const Units &units, const unsigned int dim,
              const MPI_Comm comm, const dealii::ConditionalOStream &pcout);

    /// when the run started, ISO 8601 UTC (rank 0's clock): the summary's start_time
    void set_start_time(const std::string &utc) { started_utc_ = utc; }

    /// the run summary lines of the log; balance_counts: the adaptations in which p4est's
    /// 2:1 balance ran and in which it was skipped (CartesianPatch::balance_counts())
    void print(const RunSummary &sum, const std::pair<unsigned int, unsigned int> balance_counts) const;

    /// <base>_summary.csv in the output directory (rank 0; written to .tmp, then renamed);
    /// a failure throws RunError
    void write(const RunSummary &sum, const std::string &status) const;

    /// the rows of the summary that say which run it was (also in the running summary):
    /// version, git_revision, scene, overrides, ranks, start_time
    std::vector<io::SummaryEntry> record_entries() const;

    /// the frictional dissipation of the run in J (per m^(3 - dim) of the unresolved extent)
    double friction_dissipation_si(const RunSummary &sum) const;

  private:
    const RunReportSettings          &report;
    const RunFiles                   &files;
    const TimeLoopSettings           &loop;
    const AdaptationSettings         &adaptation;
    const Units                      &units_;
    const unsigned int                dim;
    const MPI_Comm                    comm;
    const dealii::ConditionalOStream &pcout;
    std::string                       started_utc_;
  };
} // namespace granhydro::driver
