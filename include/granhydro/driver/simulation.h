#pragma once
/**
 * @file simulation.h
 * The time loop of a scene: mesh and state from the scene, CFL time step on
 * the maximal convective wave speed, SSP-RK3 convection, rejected-step
 * handling (an inadmissible result is retried with half the step, counted,
 * and stops the run with a clear message when retries run out), output
 * schedule, progress line and run summary.
 */
#include <granhydro/base/errors.h>
#include <granhydro/convection/convection_operator.h>
#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/driver/checkpointing.h>
#include <granhydro/driver/run_report.h>
#include <granhydro/driver/run_settings.h>
#include <granhydro/driver/run_summary.h>
#include <granhydro/driver/split_step.h>
#include <granhydro/driver/time_loop.h>
#include <granhydro/io/diagnostics.h>
#include <granhydro/io/history.h>
#include <granhydro/io/output.h>
#include <granhydro/io/summary_csv.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/ideal_gas.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace granhydro::driver
{
  /// the time loop of a scene with the constitutive description Description
  /// (physics::IdealGas<dim> or physics::GranularGas<dim>)
  template <int dim, class Description = physics::IdealGas<dim>>
  class Simulation
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;
    using State  = physics::State<dim>;

    Simulation(const scene::Scene &scene, const MPI_Comm comm, std::ostream &log);
    ~Simulation();

    /// mesh, operators, initial state from the scene's expressions
    void setup();

    /// replace the initial state: f(x) returns the conservative state in SI
    /// units at a point x [m]; cell averages by Gauss quadrature (nq points per direction)
    void set_initial_state(const std::function<State(const dealii::Point<dim> &)> &f, const unsigned int nq);

    /// run to the scene's end time (or max steps)
    RunSummary run();

    /// one time step of size dt (scaled) from time t (SplitStep::advance(), split_step.h;
    /// with Numerics/Strang splitting = merged and no sync the closing convective half is
    /// owed to the next step: convection_owed())
    bool advance(const double t_scaled, const double dt_scaled, const bool sync = true,
                 const double max_convective_step = 0)
    {
      return split_->advance(U, t_scaled, dt_scaled, sync, max_convective_step);
    }

    /// scaled convective time the state still owes (0 after a synchronised step)
    double convection_owed() const { return split_->owed(); }
    void   set_convection_owed(const double h) { split_->set_owed(h); }

    /// the state with the owed convective time applied (a copy: U is not changed); false
    /// (and the unsynchronised state) if that convective step fails
    bool synchronised_state(Vector &V) { return split_->synchronised_state(U, V); }

    const mesh::CartesianPatch<dim>                        &patch() const { return *patch_; }
    const Vector                                           &state() const { return U; }
    const Units                                            &units() const { return units_; }
    const Description                                      &description() const { return desc; }
    const convection::ConvectionOperator<dim, Description> &convection() const { return *conv; }

    /// conservative SI state of owned slot s
    State state_si(const unsigned int s) const;

    /// global sums of the conserved variables times the cell volume (scaled units)
    State totals() const;

    /// write the state, time (scaled) and step to file (rank 0 writes all cells, sorted by
    /// lattice key, atomically and verified: io/checkpoint.h). with_history: also the
    /// implicit step's history (a checkpoint between output times, where restart_point()
    /// was not called). A failure throws io::OutputError on every rank.
    void write_checkpoint(const std::string &file, const double t, const unsigned int step,
                          const bool with_history = false) const;

    /// read a checkpoint of this mesh (any number of ranks wrote it): state, time, step
    void read_checkpoint(const std::string &file);

    /// time [s] and step the run starts from (0 unless restarted from a checkpoint)
    double       start_time() const { return start_time_ * units_.time(); }
    unsigned int start_step() const { return start_step_; }

    /// adapt the mesh to the state (Adaptivity section of the scene): refine where the
    /// indicator exceeds the refine threshold (plus a buffer), coarsen where it stays
    /// below the coarsen threshold (not when initial); true if the mesh changed
    bool adapt_mesh(const bool initial);

    /// number of mesh adaptations so far
    unsigned int n_adaptations() const { return adaptations; }

    /// for tests: the cost per cell this rank reports at each adaptation instead of the
    /// measured one, when the partition weighs the ranks' cells by their cost
    /// (Adaptivity/Load balance); 0 = measure
    void set_cost_per_cell(const double c) { fixed_cost_ = c; }

  private:
    /// gravity and the container's inertial force in scaled units
    physics::BodyForce body_force() const;
    /// rebuild the operators' tables after the patch changed
    void mesh_changed();
    void print_header() const;

    // the time loop (time_loop.cc)
    /// the schedule, the counters, the owed half-step of a merged checkpoint restarted
    /// with symmetric steps, the running summary and the initial output
    void start_run(TimeLoopState &L);
    /// the step size (scaled) from the CFL limit (dt_cfl, 0 without convection), the
    /// fixed step and the merged splitting's owed time, before the cut to the next
    /// output or end time
    double step_size(TimeLoopState &L, double &dt_cfl);
    /// one step of at most dt from L.t: retried with half the step while inadmissible
    /// (tries counts the retries); returns the step taken. After all retries the run
    /// ends with the last admissible state and throws RunError
    double take_step(TimeLoopState &L, double dt, const double dt_cfl, unsigned int &tries);
    /// at an output time: output and checkpoint (not at the end time), the next output
    /// time, the steady-state test; true if the run is steady
    bool output_time(TimeLoopState &L);
    /// total kinetic energy and centre of mass changed by less than the tolerance over
    /// one output interval (the first call only takes the reference)
    bool steady_state(TimeLoopState &L);
    /// SIGTERM/SIGINT or the wall time limit: true if the run stops after this step
    bool stop_requested(TimeLoopState &L);
    /// the progress line, at most every Output/Progress interval
    void progress_line(TimeLoopState &L, const double dt);
    /// a checkpoint (a restart starts here: the integrator forgets its history too,
    /// unless the run was interrupted), carrying the record of the whole run so far
    /// (`whole`, or computed now); with Output/Keep checkpoints > 1 also its numbered copy
    void checkpoint_now(const TimeLoopState &L, const RunSummary *whole = nullptr);
    /// this segment's figures so far (collective): what finish() reports, before it is
    /// combined with the earlier segments' record (combine_segments())
    RunSummary segment_summary(const TimeLoopState &L) const;
    /// the unit factors of the run record
    RecordUnits record_units() const;
    // the history (run_history.cc)
    /// <base>_history.csv with Output/History interval: started with the row of the
    /// initial state (totals s0) by a fresh run, continued by a restarted one
    void start_history(TimeLoopState &L, const bool fresh, const io::StateTotals<dim> &s0);
    /// a row of <base>_history.csv is due after the step that ended at L.t, begun at t_before
    bool history_due(const TimeLoopState &L, const double t_before) const;
    /// a row of <base>_history.csv from the totals s of the state (collective through s)
    void write_history_row(TimeLoopState &L, const io::StateTotals<dim> &s);
    /// final output and checkpoint, the run summary lines and summary.csv: at the end
    /// time, at a steady state, or (status failed/overpacking) with the last admissible
    /// state
    void finish(TimeLoopState &L, const std::string &status);

    /// output->write(V, time_si, step), timed as the section "output"
    void write_output(const Vector &V, const double time_si, const unsigned int step)
    {
      const dealii::TimerOutput::Scope scope(timers_, "output");
      output->write(V, time_si, step);
    }
    /// the phases' wall times over the ranks into sum.phases and the *_seconds rows
    /// (phase_times.cc; collective, after sum.wall_seconds is set)
    void measure_phases(RunSummary &sum) const;
    /// empty unless the state is near close packing (max phi >= 0.99 phi_c, granular
    /// model): then where, how dense and how much mass sits in the near-close-packed cells
    std::string overpacking_report(const Vector &U) const;

    /// the scene: read here, in the composition root (simulation.cc) only; the parts of
    /// the run read their settings below (run_settings.h)
    scene::Scene                               scene;
    TimeLoopSettings                           loop;       ///< time_loop.cc
    RunFiles                                   files;      ///< outputs, checkpoints, history, summary
    RunReportSettings                          report;     ///< run_summary.cc, run_history.cc
    CheckpointIdentity                         identity;   ///< simulation_checkpoint.cc
    AdaptationSettings                         adaptation; ///< adapt_mesh.cc
    MPI_Comm                                   comm;
    dealii::ConditionalOStream                 pcout;
    Units                                      units_;
    Description                                desc;
    std::unique_ptr<mesh::CartesianPatch<dim>> patch_;
    std::unique_ptr<convection::ConvectionOperator<dim, Description>> conv;
    std::unique_ptr<io::Output<dim, Description>>                     output;
    std::unique_ptr<diffusion::DiffusionOperator<dim>>                diff;
    std::unique_ptr<diffusion::ImplicitIntegrator<dim>>               integrator;
    /// this rank's wall time in the sections convection, diffusion, adaptation and output
    /// (no barriers: TimerOutput without a communicator); measure_phases() reduces them
    dealii::TimerOutput timers_{pcout, dealii::TimerOutput::never, dealii::TimerOutput::wall_times};
    /// one time step: the splitting, the owed convective time, the repair counters
    std::unique_ptr<SplitStep<dim, Description>> split_;
    /// the run summary lines and <base>_summary.csv
    std::unique_ptr<RunReport> run_report_;
    /// what a checkpoint holds besides the state, and its checks on restart
    std::unique_ptr<Checkpointing<dim>> checkpoints_;
    double                              start_time_ = 0; ///< scaled
    unsigned int                        start_step_ = 0;
    Vector                              U;
    unsigned int                        adaptations    = 0;
    double                              busy_at_adapt_ = 0; ///< conv->busy_seconds() at the last adaptation
    double                              fixed_cost_    = 0; ///< set_cost_per_cell()
    unsigned long long                  max_cells = 0, refined_cells = 0, coarsened_cells = 0;
    /// the record of the run's earlier segments, read from the checkpoint it restarted
    /// from (none: no segments, counted from step 0)
    RunSummary earlier_ = [] {
      RunSummary none;
      none.segments = 0;
      return none;
    }();
    /// what the next checkpoint carries of the run (io::CheckpointHeader::run_record)
    std::vector<std::pair<std::string, double>> record_;
    std::unique_ptr<io::HistoryFile>            history_; ///< <base>_history.csv, when written
  };

  class RunRecords;

  /// read the scene's dimension and run it; returns the process exit code: 0, or
  /// 128 + the signal number when SIGTERM/SIGINT stopped it (143 / 130)
  int run_scene(const scene::Scene &scene, const MPI_Comm comm, std::ostream &log);
  /// the same with the run's records (driver/run_records.h): it prints to records.log(),
  /// and records.start() writes them once the scene is set up
  int run_scene(const scene::Scene &scene, const MPI_Comm comm, RunRecords &records);

  /// SIGTERM and SIGINT make a run finish its current step, write the final output, a
  /// checkpoint (with the implicit step's history, so a restart continues exactly as the
  /// uninterrupted run) and the summary (status "interrupted (SIGTERM)"), and end with
  /// exit code 128 + signal; a second signal ends the process at once
  void install_stop_signal_handlers();
  /// the signal received since install_stop_signal_handlers() (0: none)
  int stop_signal();
} // namespace granhydro::driver
