#pragma once
/**
 * @file run_summary.h
 * What a run reports at its end: steps, times, the operators' statistics, the mesh and
 * the memory, for the summary lines of the log and for <base>_summary.csv.
 */
#include <granhydro/base/units.h>
#include <granhydro/convection/convection_operator.h>
#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/driver/phase_times.h>

#include <string>
#include <utility>
#include <vector>

namespace granhydro::driver
{
  struct RunSummary
  {
    unsigned int steps = 0, rejected_steps = 0;
    /// wall_seconds: rank 0's; convection, adaptation (indicator, p4est, transfer, tables)
    /// and diffusion_seconds: the largest rank's (also in phases)
    double time_si = 0, wall_seconds = 0, convection_seconds = 0;
    double adaptation_seconds = 0;
    /// where the wall time went: min, avg, max over the ranks per phase (phase_times.h)
    std::vector<PhaseTime>           phases;
    convection::ConvectionStatistics convection;
    diffusion::IntegratorStatistics  diffusion;
    double                           diffusion_seconds = 0;
    bool                             diffusion_active  = false;
    bool                             steady            = false; ///< stopped at a steady state
    int                              interrupted_by    = 0;     ///< SIGTERM/SIGINT that stopped the run
    /// smallest and largest step taken [s] (the last step before an output time or the
    /// end time is cut short and is left out, unless it is the only one)
    double min_dt_si = 0, max_dt_si = 0;
    /// smallest convective CFL step [s] and the time it occurred [s]
    double min_cfl_dt_si = 0, min_cfl_dt_time_si = 0;
    /// relative change of the total mass over the run (|M_end - M_0| / M_0)
    double       mass_drift = 0;
    unsigned int cells = 0, ranks = 1;
    /// adaptive meshes: the most cells the mesh had, and how often it was adapted
    unsigned long long max_cells   = 0;
    unsigned int       adaptations = 0;
    /// cells flagged for refinement and coarsening over the run
    unsigned long long refined_cells = 0, coarsened_cells = 0;
    /// the mesh's cells summed over the steps (an adaptive mesh's work against a uniform one)
    unsigned long long cell_steps = 0;
    /// the fewest and most cells a rank owns at the end
    unsigned long long min_rank_cells = 0, max_rank_cells = 0;
    /// cell updates of a cooling dense pile set to the temperature floor, and the largest
    /// thermal-energy deficit repaired per grain (scaled)
    unsigned long long temperature_repairs = 0;
    /// cell updates that ended beyond phi_c - delta (linear continuations of chi and w)
    unsigned long long continuation_cells = 0;
    /// the implicit contact step ('Numerics/Contact pressure = implicit'): steps, Newton and
    /// GMRES iterations, failed solves (each rejected the step, which was retried)
    unsigned long long contact_steps = 0, contact_newton_iterations = 0, contact_linear_iterations = 0,
                       contact_failures = 0;
    /// the contact step's floors (counted, never silent): cell reads with negative thermal
    /// energy taken as T* = 0, wall faces whose extrapolated pressure was taken as 0
    unsigned long long contact_negative_thermal_cells = 0, contact_wall_pressure_floors = 0;
    double             max_temperature_repair = 0;
    /// SSP-RK3 steps taken by the convective part since the start of this run: 1 per step
    /// without the diffusion step, with it 2 per step with symmetric Strang splitting,
    /// about 1 with merged; retried steps included, and the owed half-step a stop between
    /// output times convects for its final output
    unsigned long long convective_steps = 0;
    /// peak resident memory of the process [bytes]: the largest over the ranks, and the
    /// sum over the ranks (at the end of the run; getrusage's ru_maxrss)
    double peak_memory_max = 0, peak_memory_total = 0;
    /// the run's segments: 1 + the restarts from a checkpoint that carried the record of
    /// the earlier ones (a checkpoint of format v5 carries none: the counts then start at
    /// counted_from_step, the step of that checkpoint)
    unsigned int       segments          = 1;
    unsigned long long counted_from_step = 0;
    /// the total number of grains at the start of the counted run (scaled; the mass drift
    /// is taken against it)
    double initial_grains = 0;
    /// the total mass [kg] and energy [J] of the final state (per m^(3 - dim) of the
    /// unresolved extent; the last row of <base>_history.csv has the same)
    double final_mass_si = 0, final_energy_si = 0;
  };

  /// the unit factors of a run record: a run restarted with other units (another
  /// material) converts the scaled values it carries
  struct RecordUnits
  {
    double time   = 1; ///< [s] per scaled time
    double energy = 1; ///< [J] per scaled energy (a grain's)
    double extent = 1; ///< length^(dim - 3) [m^(dim - 3)]: grains or energy per m^(3 - dim)
  };

  /// the unit factors of a run record of a run in `dim` dimensions with the units `units`
  RecordUnits record_units(const Units &units, const unsigned int dim);

  /// the whole run so far: the record of the earlier segments combined with this
  /// segment's figures (counts and wall times added, the extremes combined, steps and
  /// the end-of-run figures - cells, time, mass drift, memory of this process - from now)
  RunSummary combine_segments(const RunSummary &earlier, const RunSummary &now);

  /// what a checkpoint carries of the run (io::CheckpointHeader::run_record): every
  /// figure combine_segments() adds or combines, scaled values with the units to convert
  std::vector<std::pair<std::string, double>> to_run_record(const RunSummary &sum, const RecordUnits &units);
  /// the figures of a run record read back in the units `units` (keys it does not know
  /// are ignored, a missing one keeps its default); false if the record is empty (a
  /// checkpoint of format v5)
  bool from_run_record(const std::vector<std::pair<std::string, double>> &record, const RecordUnits &units,
                       RunSummary &sum);
} // namespace granhydro::driver
