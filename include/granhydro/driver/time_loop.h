#pragma once
/**
 * @file time_loop.h
 * The time loop of a run: the CFL step size, rejected steps retried with half the step,
 * the output and checkpoint schedule, the steady-state test, the stop on a signal or the
 * wall time limit, the progress line, the history and the final output and summary. It
 * drives the parts of the run (TimeLoopParts) that the composition root (Simulation)
 * owns, and asks it for the two things that change the run's mesh or files beyond the
 * loop (TimeLoopHooks: the mesh adaptation, the checkpoint).
 */
#include <granhydro/base/units.h>
#include <granhydro/convection/convection_operator.h>
#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/driver/run_report.h>
#include <granhydro/driver/run_settings.h>
#include <granhydro/driver/run_summary.h>
#include <granhydro/driver/split_step.h>
#include <granhydro/io/diagnostics.h>
#include <granhydro/io/history.h>
#include <granhydro/io/output.h>
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <chrono>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::driver
{
  /// what the loop carries from step to step: time and step, the output schedule, the
  /// record of the step sizes, the steady-state reference and why the loop stopped
  struct TimeLoopState
  {
    using clock = std::chrono::steady_clock;
    clock::time_point start, last_progress;
    RunSummary        sum;
    double            t0    = 1;                             ///< the time unit [s]
    double            t_end = 0, dt_fixed = 0, interval = 0; ///< scaled
    double            t = 0, next_output = 0;                ///< scaled
    unsigned int      step = 0;
    /// the mesh's cells summed over the steps taken (the work of an adaptive mesh)
    unsigned long long cell_steps = 0;
    /// Numerics/Strang splitting = merged: adjacent convective half-steps of the
    /// splitting are taken as one (SplitStep::advance())
    bool        merge = false;
    std::string checkpoint; ///< the checkpoint file
    /// the SIGTERM/SIGINT that stopped the run: its checkpoint keeps the integrator's
    /// history instead (between output times the uninterrupted run keeps it too)
    int    interrupted_by        = 0;
    bool   wall_limited          = false;
    bool   have_steady_reference = false;
    double steady_ke = 0, steady_com = 0;
    /// the state before the step (a rejected step starts again from it)
    dealii::LinearAlgebra::distributed::Vector<double> backup;
    double                                             mass0 = 0; ///< total mass at the start (scaled)
    /// smallest and largest step, smallest step cut short to land on an output or end time
    double min_dt = std::numeric_limits<double>::infinity(), max_dt = 0,
           min_cut_dt = std::numeric_limits<double>::infinity();
    /// the last step taken (scaled; 0 before the first) and the step of the last row of
    /// <base>_history.csv (-1: none yet)
    double    last_dt      = 0;
    long long history_step = -1;
    /// smallest convective CFL step and the time it occurred (scaled)
    double min_cfl = std::numeric_limits<double>::infinity(), min_cfl_t = 0;
  };

  /// what the mesh adaptation did so far (the run summary's counts)
  struct AdaptationCounts
  {
    unsigned int       adaptations = 0;
    unsigned long long max_cells = 0, refined_cells = 0, coarsened_cells = 0;
  };

  /// where the loop starts: time (scaled) and step (0 unless restarted from a checkpoint),
  /// and the record of the run's earlier segments read from that checkpoint
  struct TimeLoopStart
  {
    double       time = 0;
    unsigned int step = 0;
    RunSummary   earlier;
  };

  /// the parts of the run the loop drives (owned by the composition root; they outlive
  /// the loop; the mesh adaptation changes the patch and the state in place)
  template <int dim, class Description>
  struct TimeLoopParts
  {
    dealii::LinearAlgebra::distributed::Vector<double>     &state;
    const mesh::CartesianPatch<dim>                        &patch;
    const Description                                      &desc;
    const convection::ConvectionOperator<dim, Description> &convection;
    diffusion::ImplicitIntegrator<dim>                     *integrator; ///< null: no diffusion step
    SplitStep<dim, Description>                            &split;
    io::Output<dim, Description>                           &output;
    RunReport                                              &report;
    const AdaptationCounts                                 &adaptation;
    /// the sections "convection", "diffusion", "adaptation" and "output"
    dealii::TimerOutput &timers;
  };

  /// what the loop asks of the composition root
  struct TimeLoopHooks
  {
    /// adapt the mesh to the state (not the initial adaptation)
    std::function<void()> adapt_mesh;
    /// write a checkpoint of the state at time t (scaled) and step carrying the record of
    /// the run (io::CheckpointHeader::run_record); with_history: also the implicit step's
    /// history
    std::function<void(const std::string &file, double t, unsigned int step, bool with_history,
                       const std::vector<std::pair<std::string, double>> &record)>
      write_checkpoint;
  };

  template <int dim, class Description>
  class TimeLoop
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    TimeLoop(const TimeLoopSettings &settings, const RunFiles &files, const std::string &integrator_name,
             const Units &units, const MPI_Comm comm, const dealii::ConditionalOStream &pcout,
             const TimeLoopParts<dim, Description> &parts, const TimeLoopHooks &hooks);
    ~TimeLoop();

    /// run from `start` to the end time (or the step limit, a steady state, a signal, the
    /// wall time limit); throws RunError after a step failed all its retries (the last
    /// admissible state then is the final output)
    RunSummary run(const TimeLoopStart &start);

  private:
    /// the schedule, the counters, the owed half-step of a merged checkpoint restarted
    /// with symmetric steps, the running summary and the initial output
    void start_run();
    /// the step size (scaled) from the CFL limit (dt_cfl, 0 without convection), the
    /// fixed step and the merged splitting's owed time, before the cut to the next
    /// output or end time
    double step_size(double &dt_cfl);
    /// one step of at most dt from L.t: retried with half the step while inadmissible
    /// (tries counts the retries); returns the step taken. After all retries the run
    /// ends with the last admissible state and throws RunError
    double take_step(double dt, const double dt_cfl, unsigned int &tries);
    /// at an output time: output and checkpoint (not at the end time), the next output
    /// time, the steady-state test; true if the run is steady
    bool output_time();
    /// total kinetic energy and centre of mass changed by less than the tolerance over
    /// one output interval (the first call only takes the reference)
    bool steady_state();
    /// SIGTERM/SIGINT or the wall time limit: true if the run stops after this step
    bool stop_requested();
    /// the progress line, at most every Output/Progress interval
    void progress_line(const double dt);
    /// a checkpoint (a restart starts here: the integrator forgets its history too,
    /// unless the run was interrupted), carrying the record of the whole run so far
    /// (`whole`, or computed now); with Output/Keep checkpoints > 1 also its numbered copy
    void checkpoint_now(const RunSummary *whole = nullptr);
    /// this segment's figures so far (collective): what finish() reports, before it is
    /// combined with the earlier segments' record (combine_segments())
    RunSummary segment_summary() const;
    /// the phases' wall times over the ranks into sum.phases and the *_seconds rows
    /// (phase_times.cc; collective, after sum.wall_seconds is set)
    void measure_phases(RunSummary &sum) const;
    /// empty unless the state is near close packing (max phi >= 0.99 phi_c, granular
    /// model): then where, how dense and how much mass sits in the near-close-packed cells
    std::string overpacking_report(const Vector &U) const;
    /// output.write(V, time_si, step), timed as the section "output"
    void write_output(const Vector &V, const double time_si, const unsigned int step);
    // the history (run_history.cc)
    /// <base>_history.csv with Output/History interval: started with the row of the
    /// initial state (totals s0) by a fresh run, continued by a restarted one
    void start_history(const bool fresh, const io::StateTotals<dim> &s0);
    /// a row of <base>_history.csv is due after the step that ended at L.t, begun at t_before
    bool history_due(const double t_before) const;
    /// a row of <base>_history.csv from the totals s of the state (collective through s)
    void write_history_row(const io::StateTotals<dim> &s);
    /// final output and checkpoint, the run summary lines and summary.csv: at the end
    /// time, at a steady state, or (status failed/overpacking) with the last admissible
    /// state
    void finish(const std::string &status);

    const TimeLoopSettings           &loop;
    const RunFiles                   &files;
    const std::string                 integrator_name; ///< the history's integrator column
    const Units                      &units_;
    const MPI_Comm                    comm;
    const dealii::ConditionalOStream &pcout;
    // the parts (TimeLoopParts)
    Vector                                                 &U;
    const mesh::CartesianPatch<dim>                        &patch;
    const Description                                      &desc;
    const convection::ConvectionOperator<dim, Description> &conv;
    diffusion::ImplicitIntegrator<dim>                     *integrator;
    SplitStep<dim, Description>                            &split;
    io::Output<dim, Description>                           &output;
    RunReport                                              &report;
    const AdaptationCounts                                 &adaptation;
    dealii::TimerOutput                                    &timers;
    TimeLoopHooks                                           hooks;
    TimeLoopStart                                           start_;
    TimeLoopState                    L;        ///< the loop's state (the step, the schedule, the records)
    std::unique_ptr<io::HistoryFile> history_; ///< <base>_history.csv, when written
  };
} // namespace granhydro::driver
