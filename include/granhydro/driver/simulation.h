#pragma once
/**
 * @file simulation.h
 * The composition root of a run: from the scene, the model, the mesh, the operators,
 * the output and the initial state, and the modules that run it - SplitStep (one time
 * step), TimeLoop (step size, retries, outputs, stop rules, history, the final report),
 * Checkpointing, RunReport - each with its own settings (run_settings.h). Only this class
 * reads the Scene.
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
  /// a run of a scene with the constitutive description Description
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
    double       start_time() const { return start_.time * units_.time(); }
    unsigned int start_step() const { return start_.step; }

    /// adapt the mesh to the state (Adaptivity section of the scene): refine where the
    /// indicator exceeds the refine threshold (plus a buffer), coarsen where it stays
    /// below the coarsen threshold (not when initial); true if the mesh changed
    bool adapt_mesh(const bool initial);

    /// number of mesh adaptations so far
    unsigned int n_adaptations() const { return adapted_.adaptations; }

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

    /// the scene: read here, in the composition root (simulation.cc) only; the parts of
    /// the run read their settings below (run_settings.h)
    scene::Scene               scene;
    TimeLoopSettings           loop;       ///< time_loop.cc
    RunFiles                   files;      ///< outputs, checkpoints, history, summary
    RunReportSettings          report;     ///< run_summary.cc, run_history.cc
    CheckpointIdentity         identity;   ///< simulation_checkpoint.cc
    AdaptationSettings         adaptation; ///< adapt_mesh.cc
    MPI_Comm                   comm;
    dealii::ConditionalOStream pcout;
    Units                      units_;
    Description                desc;
    /// the convective operator's copy of desc: without the dense closure when the implicit
    /// contact step applies it (the convective step then sees E without the contact energy)
    Description                                                       conv_desc;
    std::unique_ptr<mesh::CartesianPatch<dim>>                        patch_;
    std::unique_ptr<convection::ConvectionOperator<dim, Description>> conv;
    std::unique_ptr<io::Output<dim, Description>>                     output;
    std::unique_ptr<diffusion::DiffusionOperator<dim>>                diff;
    std::unique_ptr<diffusion::ImplicitIntegrator<dim>>               integrator;
    /// the implicit contact pressure and gravity ('Numerics/Contact pressure = implicit')
    std::unique_ptr<diffusion::ContactStep<dim>> contact;
    /// this rank's wall time in the sections convection, diffusion, adaptation and output
    /// (no barriers: TimerOutput without a communicator); measure_phases() reduces them
    dealii::TimerOutput timers_{pcout, dealii::TimerOutput::never, dealii::TimerOutput::wall_times};
    /// one time step: the splitting, the owed convective time, the repair counters
    std::unique_ptr<SplitStep<dim, Description>> split_;
    /// the run summary lines and <base>_summary.csv
    std::unique_ptr<RunReport> run_report_;
    /// what a checkpoint holds besides the state, and its checks on restart
    std::unique_ptr<Checkpointing<dim>> checkpoints_;
    Vector                              U;
    /// where the time loop starts: time and step (0 unless restarted from a checkpoint)
    /// and the record of the run's earlier segments read from that checkpoint (none: no
    /// segments, counted from step 0)
    TimeLoopStart start_ = [] {
      TimeLoopStart s;
      s.earlier.segments = 0;
      return s;
    }();
    AdaptationCounts adapted_;           ///< what the mesh adaptation did so far
    double           busy_at_adapt_ = 0; ///< conv->busy_seconds() at the last adaptation
    double           fixed_cost_    = 0; ///< set_cost_per_cell()
    /// what the next checkpoint carries of the run (io::CheckpointHeader::run_record)
    std::vector<std::pair<std::string, double>> record_;
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
