#pragma once
/**
 * @file run_settings.h
 * What the parts of a run read of the scene, one struct per part: the time loop
 * (time_loop.cc, split_step.cc), the files it writes (outputs, checkpoints, history,
 * summary), the run report (run_summary.cc, run_records.cc) and a checkpoint's identity
 * (simulation_checkpoint.cc). The composition root (simulation.cc, run_settings())
 * fills them once from the Scene; no other part of the driver reads the Scene, so what
 * a part depends on is written here. SI units.
 */
#include <granhydro/io/settings.h>
#include <granhydro/mesh/settings.h>

#include <array>
#include <string>
#include <vector>

namespace granhydro::scene
{
  struct Scene;
}

namespace granhydro::driver
{

  /// the time loop: end, step size, retries, stop rules, when to adapt
  struct TimeLoopSettings
  {
    double       end_time          = 0; ///< [s]
    double       fixed_time_step   = 0; ///< [s]; 0: the CFL limit
    double       output_interval   = 0; ///< [s]; 0: outputs only at the start and the end
    double       cfl               = 0;
    double       steady_tolerance  = 0; ///< 0: no steady-state stop
    double       max_wall_seconds  = 0; ///< 0: no wall-time limit
    double       progress_interval = 5; ///< wall seconds between progress lines
    unsigned int max_steps         = 0; ///< 0: no step limit
    unsigned int max_step_retries  = 6;
    /// steps between mesh adaptations (Adaptivity/Interval); 0: the mesh is not adaptive
    unsigned int adapt_interval = 0;
    /// the direction of the steady-state test's centre of mass (the profiles' direction)
    unsigned int profile_direction = 0;
    bool         convection        = false; ///< the convective step runs
    bool         merge_strang      = false; ///< Numerics/Strang splitting = merged
    bool         from_checkpoint   = false; ///< the run starts from Initial state/Checkpoint
    /// the largest body force per unit mass [m/s^2]: |g| plus the amplitude of the
    /// container's acceleration A (2 pi f)^2
    double max_body_acceleration = 0;
  };

  /// the files of a run: <directory>/<base name><suffix>, which are written and how often
  struct RunFiles
  {
    std::string  directory = "output", base_name = "solution";
    bool         vtu = true, profiles = true, summary = true, checkpoint = true;
    unsigned int keep_checkpoints = 1;
    /// a row of <base>_history.csv every history_steps steps or history_seconds [s] of
    /// simulated time; both 0: no history file
    unsigned int history_steps   = 0;
    double       history_seconds = 0;

    std::string file(const std::string &suffix) const { return io::run_file(directory, base_name, suffix); }
  };

  /// what the run report and the run records say about the run
  struct RunReportSettings
  {
    std::string              source;        ///< the scene file
    std::vector<std::string> overrides;     ///< the -p overrides
    std::string              expanded_text; ///< the scene as read (includes expanded)
    bool                     verbose = true;
    std::string              integrator;       ///< Diffusion step/Integrator
    bool                     musta    = false; ///< Numerics/Flux = musta
    bool                     adaptive = false;
    /// Adaptivity/Load balance as given (what it means: AdaptationSettings::balance_by_cost)
    std::string load_balance;
  };

  /// what a checkpoint of this run is matched against
  struct CheckpointIdentity
  {
    std::array<unsigned int, 3> cells{{1, 1, 1}};
    std::array<double, 3>       lower{{0, 0, 0}}, upper{{0, 0, 0}};
    std::string                 model;
    std::string                 source; ///< the scene file, for messages
    bool                        adaptive = false;
  };

  /// the mesh adaptation (adapt_mesh.cc): the indicator's thresholds and the partition
  struct AdaptationSettings
  {
    mesh::RefinementIndicatorSettings indicator; ///< where to refine and coarsen
    bool balance_by_cost = false;                ///< the partition weighs cells by measured cost
  };

  /// every part's settings
  struct RunSettings
  {
    TimeLoopSettings   loop;
    RunFiles           files;
    RunReportSettings  report;
    CheckpointIdentity identity;
    AdaptationSettings adaptation;
  };

  /// the parts' settings from the scene (dim: the profiles' default direction is the last)
  RunSettings run_settings(const scene::Scene &scene, const unsigned int dim);
} // namespace granhydro::driver
