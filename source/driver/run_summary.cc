/**
 * @file run_summary.cc
 * What a run reports at its end (RunReport, driver/run_report.h): the run summary lines
 * of the log and the entries of <base>_summary.csv (written by io/summary_csv.h); and the
 * record of a run's figures that checkpoints carry (driver/run_summary.h).
 */
#include <granhydro/base/errors.h>
#include <granhydro/base/version.h>
#include <granhydro/driver/phase_times.h>
#include <granhydro/driver/run_report.h>
#include <granhydro/io/summary_csv.h>
#include <granhydro/physics/granular_gas.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace granhydro::driver
{
  using namespace dealii;

  namespace
  {
    /// how a figure of two segments combines, and the unit its scaled value is in
    enum class Rule
    {
      sum,
      min, ///< the smaller of the positive finite values (0 or infinity: none)
      max
    };
    enum class Unit
    {
      none,
      time,
      energy,
      extensive_energy, ///< energy per m^(3 - dim)
      grains            ///< grains per m^(3 - dim)
    };

    struct Field
    {
      const char                               *key;
      Rule                                      rule;
      Unit                                      unit;
      std::function<double(const RunSummary &)> get;
      std::function<void(RunSummary &, double)> set;
    };

#define GRANHYDRO_FIELD(key, member, rule, unit)                                           \
  Field                                                                                    \
  {                                                                                        \
    key, Rule::rule, Unit::unit, [](const RunSummary &s) { return double(s.member); },     \
      [](RunSummary &s, const double v) { s.member = static_cast<decltype(s.member)>(v); } \
  }

    /// every figure a checkpoint carries of the run; the keys are the run record's
    /// (a new figure is one more line; an older record without it reads as absent)
    const std::vector<Field> &fields()
    {
      static const std::vector<Field> f = {
        GRANHYDRO_FIELD("segments", segments, sum, none),
        GRANHYDRO_FIELD("rejected_steps", rejected_steps, sum, none),
        GRANHYDRO_FIELD("wall_seconds", wall_seconds, sum, none),
        GRANHYDRO_FIELD("convection_seconds", convection_seconds, sum, none),
        GRANHYDRO_FIELD("adaptation_seconds", adaptation_seconds, sum, none),
        GRANHYDRO_FIELD("diffusion_seconds", diffusion_seconds, sum, none),
        GRANHYDRO_FIELD("convective_steps", convective_steps, sum, none),
        GRANHYDRO_FIELD("temperature_repairs", temperature_repairs, sum, none),
        GRANHYDRO_FIELD("continuation_cells", continuation_cells, sum, none),
        GRANHYDRO_FIELD("contact_steps", contact_steps, sum, none),
        GRANHYDRO_FIELD("contact_newton_iterations", contact_newton_iterations, sum, none),
        GRANHYDRO_FIELD("contact_linear_iterations", contact_linear_iterations, sum, none),
        GRANHYDRO_FIELD("contact_failures", contact_failures, sum, none),
        GRANHYDRO_FIELD("contact_negative_thermal_cells", contact_negative_thermal_cells, sum, none),
        GRANHYDRO_FIELD("contact_wall_pressure_floors", contact_wall_pressure_floors, sum, none),
        GRANHYDRO_FIELD("max_temperature_repair", max_temperature_repair, max, energy),
        GRANHYDRO_FIELD("adaptations", adaptations, sum, none),
        GRANHYDRO_FIELD("refined_cells", refined_cells, sum, none),
        GRANHYDRO_FIELD("coarsened_cells", coarsened_cells, sum, none),
        GRANHYDRO_FIELD("cell_steps", cell_steps, sum, none),
        GRANHYDRO_FIELD("max_cells", max_cells, max, none),
        GRANHYDRO_FIELD("peak_memory_max", peak_memory_max, max, none),
        GRANHYDRO_FIELD("peak_memory_total", peak_memory_total, max, none),
        GRANHYDRO_FIELD("min_dt", min_dt_si, min, none), GRANHYDRO_FIELD("max_dt", max_dt_si, max, none),
        GRANHYDRO_FIELD("flux_points", convection.flux.points, sum, none),
        GRANHYDRO_FIELD("musta_stages", convection.flux.stages, sum, none),
        GRANHYDRO_FIELD("musta_fallbacks", convection.flux.fallbacks, sum, none),
        GRANHYDRO_FIELD("musta_early_stops", convection.flux.early_stops, sum, none),
        GRANHYDRO_FIELD("limited_reconstructions", convection.limited_cells, sum, none),
        GRANHYDRO_FIELD("first_order_fallbacks", convection.fallback_cells, sum, none),
        GRANHYDRO_FIELD("cell_updates", convection.cell_updates, sum, none),
        GRANHYDRO_FIELD("rhs_evaluations", convection.rhs_evaluations, sum, none),
        GRANHYDRO_FIELD("wall_tension_bounded_convective", convection.wall_tension_bounded, sum, none),
        GRANHYDRO_FIELD("gravity_point_sources", convection.gravity_point_sources, sum, none),
        GRANHYDRO_FIELD("diffusion_steps", diffusion.steps, sum, none),
        GRANHYDRO_FIELD("newton_iterations", diffusion.newton_iterations, sum, none),
        GRANHYDRO_FIELD("gmres_iterations", diffusion.linear_iterations, sum, none),
        GRANHYDRO_FIELD("newton_failures", diffusion.newton_failures, sum, none),
        GRANHYDRO_FIELD("gmres_failures", diffusion.linear_failures, sum, none),
        GRANHYDRO_FIELD("switches_to_midpoint", diffusion.switches_to_midpoint, sum, none),
        GRANHYDRO_FIELD("explicit_substeps", diffusion.explicit_substeps, sum, none),
        GRANHYDRO_FIELD("jacobians", diffusion.jacobians, sum, none),
        GRANHYDRO_FIELD("full_jacobian_retries", diffusion.full_jacobian_retries, sum, none),
        GRANHYDRO_FIELD("matrix_reuses", diffusion.matrix_reuses, sum, none),
        GRANHYDRO_FIELD("stale_matrix_retries", diffusion.stale_matrix_retries, sum, none),
        GRANHYDRO_FIELD("jacobian_seconds", diffusion.jacobian_seconds, sum, none),
        GRANHYDRO_FIELD("preconditioner_seconds", diffusion.preconditioner_seconds, sum, none),
        GRANHYDRO_FIELD("gmres_seconds", diffusion.linear_seconds, sum, none),
        GRANHYDRO_FIELD("rkl2_steps", diffusion.rkl2_steps, sum, none),
        GRANHYDRO_FIELD("rkl2_stages", diffusion.rkl2_stages, sum, none),
        GRANHYDRO_FIELD("rkl2_fallbacks", diffusion.rkl2_fallbacks, sum, none),
        GRANHYDRO_FIELD("implicit_steps", diffusion.implicit_steps, sum, none),
        GRANHYDRO_FIELD("rkl2_seconds", diffusion.rkl2_seconds, sum, none),
        GRANHYDRO_FIELD("implicit_seconds", diffusion.implicit_seconds, sum, none),
        GRANHYDRO_FIELD("max_dt_over_explicit", diffusion.max_dt_over_explicit, max, none),
        GRANHYDRO_FIELD("friction_dissipation", diffusion.friction_dissipation, sum, extensive_energy),
        GRANHYDRO_FIELD("diffusive_face_fluxes", diffusion.faces.faces, sum, none),
        GRANHYDRO_FIELD("tension_bounded_faces", diffusion.faces.tension_bounded, sum, none),
        GRANHYDRO_FIELD("tension_bounded_wall_faces", diffusion.faces.tension_bounded_walls, sum, none),
        GRANHYDRO_FIELD("friction_capped_faces", diffusion.faces.friction_capped, sum, none),
        GRANHYDRO_FIELD("negative_temperature_faces", diffusion.faces.negative_temperature, sum, none),
        // (the smallest steps with the time they occurred: combined by hand below)
        GRANHYDRO_FIELD("min_cfl_dt", min_cfl_dt_si, min, none),
        GRANHYDRO_FIELD("min_cfl_dt_time", min_cfl_dt_time_si, min, none),
        GRANHYDRO_FIELD("min_explicit_dt", diffusion.min_explicit_dt, min, time),
        GRANHYDRO_FIELD("min_explicit_dt_time", diffusion.min_explicit_dt_time, min, time),
        GRANHYDRO_FIELD("counted_from_step", counted_from_step, min, none),
        GRANHYDRO_FIELD("initial_grains", initial_grains, min, grains)};
      return f;
    }
#undef GRANHYDRO_FIELD

    double factor(const Unit u, const RecordUnits &r)
    {
      return u == Unit::time             ? r.time :
             u == Unit::energy           ? r.energy :
             u == Unit::extensive_energy ? r.energy * r.extent :
             u == Unit::grains           ? r.extent :
                                           1.;
    }

    bool present(const double v)
    {
      return std::isfinite(v) && v > 0;
    }
  } // namespace

  RunSummary combine_segments(const RunSummary &earlier, const RunSummary &now)
  {
    RunSummary all = now;
    for (const Field &f : fields())
      {
        const double a = f.get(earlier), b = f.get(now);
        if (f.rule == Rule::sum)
          f.set(all, a + b);
        else if (f.rule == Rule::max)
          f.set(all, std::max(a, b));
      }
    // the smallest step (0: none) and the smallest limits with the time they occurred
    if (present(earlier.min_dt_si) && (!present(now.min_dt_si) || earlier.min_dt_si < now.min_dt_si))
      all.min_dt_si = earlier.min_dt_si;
    if (present(earlier.min_cfl_dt_si) &&
        (!present(now.min_cfl_dt_si) || earlier.min_cfl_dt_si <= now.min_cfl_dt_si))
      {
        all.min_cfl_dt_si      = earlier.min_cfl_dt_si;
        all.min_cfl_dt_time_si = earlier.min_cfl_dt_time_si;
      }
    const auto &ed = earlier.diffusion, &nd = now.diffusion;
    if (present(ed.min_explicit_dt) &&
        (!present(nd.min_explicit_dt) || ed.min_explicit_dt <= nd.min_explicit_dt))
      {
        all.diffusion.min_explicit_dt      = ed.min_explicit_dt;
        all.diffusion.min_explicit_dt_time = ed.min_explicit_dt_time;
      }
    // where the counts start, and the grains they started with: the earlier segments'
    all.counted_from_step = earlier.counted_from_step;
    if (earlier.initial_grains > 0)
      all.initial_grains = earlier.initial_grains;
    return all;
  }

  RecordUnits record_units(const Units &units, const unsigned int dim)
  {
    RecordUnits r;
    r.time   = units.time();
    r.energy = units.energy();
    r.extent = std::pow(units.length, dim - 3.);
    return r;
  }

  std::vector<std::pair<std::string, double>> to_run_record(const RunSummary &sum, const RecordUnits &units)
  {
    std::vector<std::pair<std::string, double>> r;
    for (const Field &f : fields())
      r.emplace_back(f.key, f.get(sum) * factor(f.unit, units));
    return r;
  }

  bool from_run_record(const std::vector<std::pair<std::string, double>> &record, const RecordUnits &units,
                       RunSummary &sum)
  {
    for (const auto &[key, value] : record)
      for (const Field &f : fields())
        if (key == f.key)
          f.set(sum, value / factor(f.unit, units));
    return !record.empty();
  }

  RunReport::RunReport(const RunReportSettings &settings, const RunFiles &files, const TimeLoopSettings &loop,
                       const AdaptationSettings &adaptation, const Units &units, const unsigned int dim,
                       const MPI_Comm comm, const dealii::ConditionalOStream &pcout)
    : report(settings)
    , files(files)
    , loop(loop)
    , adaptation(adaptation)
    , units_(units)
    , dim(dim)
    , comm(comm)
    , pcout(pcout)
  {}

  double RunReport::friction_dissipation_si(const RunSummary &sum) const
  {
    return sum.diffusion.friction_dissipation * units_.energy() * std::pow(units_.length, dim - 3.);
  }

  void RunReport::print(const RunSummary                           &sum,
                        const std::pair<unsigned int, unsigned int> balance_counts) const
  {
    const double t0 = units_.time();
    const auto  &cs = sum.convection;
    const double nr = Utilities::MPI::n_mpi_processes(comm);
    pcout << "run summary: " << sum.steps << " steps to t = " << sum.time_si << " s, " << sum.rejected_steps
          << " rejected (retried with half dt)\n"
          << "  wall " << sum.wall_seconds << " s, convection " << sum.convection_seconds << " s, "
          << cs.cell_updates / std::max(sum.convection_seconds, 1e-30) / nr
          << " cell-updates/s per RK stage per core";
    if (sum.diffusion_active && loop.convection)
      pcout << ", " << sum.convective_steps << " SSP-RK3 steps ("
            << (loop.merge_strang ? "merged" : "symmetric") << " Strang splitting)";
    pcout << "\n"
          << "  flux points " << cs.flux.points;
    if (report.musta)
      pcout << ", MUSTA stages/point " << double(cs.flux.stages) / std::max<double>(cs.flux.points, 1)
            << ", MUSTA fallbacks to Rusanov " << cs.flux.fallbacks
            << ", early stops at an inadmissible stage state " << cs.flux.early_stops;
    if (cs.wall_tension_bounded)
      pcout << "\n  wall pressure: " << cs.wall_tension_bounded
            << " wall face fluxes pulled on a receding cell and were set to 0 (cohesionless grains)";
    if (cs.gravity_point_sources)
      pcout << "\n  well-balanced gravity: point source n g instead of the equilibrium (cell x direction x "
               "stage) "
            << cs.gravity_point_sources;
    pcout << "\n  positivity: reconstructions reset to the cell average (cell x direction x stage) "
          << cs.limited_cells << ", cell updates redone first order (a posteriori) " << cs.fallback_cells
          << "\n";
    if (sum.diffusion_active)
      {
        const auto &ds = sum.diffusion;
        pcout << "  diffusion step: " << sum.diffusion_seconds << " s, " << ds.steps << " steps, "
              << ds.newton_iterations << " Newton iterations ("
              << double(ds.newton_iterations) / std::max<double>(ds.steps, 1) << "/step), "
              << ds.linear_iterations << " GMRES iterations ("
              << double(ds.linear_iterations) / std::max<double>(ds.newton_iterations, 1) << "/Newton), "
              << ds.newton_failures << " Newton failures, " << ds.linear_failures << " GMRES failures, "
              << ds.switches_to_midpoint << " switches to implicit midpoint, " << ds.full_jacobian_retries
              << " retries with the fully coupled Jacobian";
        if (ds.explicit_substeps)
          pcout << ", " << ds.explicit_substeps << " explicit sub-steps";
        if (ds.rkl2_steps)
          pcout << "\n    RKL2: " << ds.rkl2_steps << " steps, " << ds.rkl2_stages << " stages ("
                << double(ds.rkl2_stages) / ds.rkl2_steps << "/step), " << ds.rkl2_seconds << " s ("
                << ds.rkl2_seconds / ds.rkl2_steps << " s/step); implicit: " << ds.implicit_steps
                << " steps, " << ds.implicit_seconds << " s ("
                << ds.implicit_seconds / std::max<double>(ds.implicit_steps, 1) << " s/step); "
                << ds.rkl2_fallbacks << " failed RKL2 steps redone implicitly";
        if (ds.jacobians)
          pcout << "\n    of which: " << ds.jacobian_seconds << " s in " << ds.jacobians
                << " Jacobians (finite differences + Newton matrix; kept for " << ds.matrix_reuses
                << " further steps, " << ds.stale_matrix_retries << " steps redone with a fresh one), "
                << ds.preconditioner_seconds << " s in preconditioner set-ups, " << ds.linear_seconds
                << " s in GMRES (largest rank)";
        pcout << "\n";
      }
    if (sum.diffusion_active && std::isfinite(sum.diffusion.min_explicit_dt))
      pcout << "  time step: " << sum.min_dt_si << " .. " << sum.max_dt_si
            << " s; explicit diffusive limit down to " << sum.diffusion.min_explicit_dt * t0
            << " s (at t = " << sum.diffusion.min_explicit_dt_time * t0 << " s); steps up to "
            << sum.diffusion.max_dt_over_explicit << " x that limit\n";
    pcout << "  mass drift " << sum.mass_drift << " (relative)\n";
    if (sum.segments > 1)
      pcout << "  the run in " << sum.segments << " segments (" << sum.segments - 1
            << " restart(s) from checkpoints): the figures above are of the whole run\n";
    if (sum.counted_from_step > 0)
      pcout << "  the figures above count from step " << sum.counted_from_step
            << " (the checkpoint the run restarted from there carries no counts of the steps before it)\n";
    pcout << "  memory: peak resident " << sum.peak_memory_max / 1048576. << " MiB (largest rank), "
          << sum.peak_memory_total / 1024. / std::max<double>(sum.max_cells, 1)
          << " KiB per cell (all ranks, at the most cells)\n";
    if (const auto &fc = sum.diffusion.faces;
        fc.tension_bounded + fc.friction_capped + fc.negative_temperature > 0)
      pcout << "  diffusive face fluxes: " << fc.faces
            << " evaluations; tensile normal stress bounded by the pressure "
            << "(cohesionless grains) in " << fc.tension_bounded << " (" << fc.tension_bounded_walls
            << " at walls); frictional viscosity held at the Newtonian bound t_f sin(theta_f) p_f in "
            << fc.friction_capped << "; T < 0 taken as 0 in the coefficients in " << fc.negative_temperature
            << "\n";
    if (sum.diffusion.friction_dissipation > 0)
      pcout << "  frictional dissipation (dense closure, work of mu_f lost to heat): "
            << friction_dissipation_si(sum)
            << (dim == 3 ? " J" :
                dim == 2 ? " J/m" :
                           " J/m^2")
            << "\n";
    if (const auto [balanced, balance_skipped] = balance_counts; report.adaptive)
      pcout << "  adaptive mesh: " << sum.adaptations << " adaptations, " << sum.refined_cells
            << " cells refined, " << sum.coarsened_cells << " coarsened; " << sum.cells
            << " cells at the end, at most " << sum.max_cells << "; " << sum.cell_steps
            << " cell-steps; 2:1 balance by p4est in " << balanced << " (skipped in " << balance_skipped
            << ": the changes kept it); adaptation " << sum.adaptation_seconds << " s\n";
    if (report.adaptive && sum.ranks > 1)
      pcout << "  partition: " << sum.min_rank_cells << " to " << sum.max_rank_cells
            << " cells per rank at the end, "
            << (adaptation.balance_by_cost ? "cells weighted by each rank's measured cost per cell" :
                                             "equal numbers of cells")
            << " (Adaptivity/Load balance = " << report.load_balance << ")\n";
    if (sum.continuation_cells > 0)
      pcout
        << "  close packing: " << sum.continuation_cells
        << " cell updates ended beyond phi_c - delta, in the linear continuations of chi and of the contact "
           "potential (doc/physics.md 2)\n";
    if (sum.contact_steps > 0)
      pcout << "  implicit contact step: " << sum.contact_steps << " steps, " << sum.contact_newton_iterations
            << " Newton iterations (" << sum.contact_linear_iterations << " GMRES), " << sum.contact_failures
            << " failed solves (each step retried with half dt); " << sum.contact_negative_thermal_cells
            << " cell reads with negative thermal energy taken as T = 0, " << sum.contact_wall_pressure_floors
            << " wall faces whose hydrostatically extrapolated pressure was taken as 0\n";
    if (sum.temperature_repairs > 0)
      pcout << "  temperature floor: " << sum.temperature_repairs
            << " cell updates of a cooling dense pile ended with T < "
            << physics::GranularGas<3>::temperature_floor
            << " (scaled) and were set to it; largest thermal-energy deficit "
            << sum.max_temperature_repair * units_.energy()
            << " J per grain (doc/user-guide.md, 'Dense closure')\n";
    pcout << phase_table(sum.phases, sum.ranks);
  }

  void RunReport::write(const RunSummary &sum, const std::string &status) const
  {
    if (Utilities::MPI::this_mpi_process(comm) != 0)
      return;
    const double t0                       = units_.time();
    const auto  &cs                       = sum.convection;
    const auto  &ds                       = sum.diffusion;
    using N                               = unsigned long long;
    std::vector<io::SummaryEntry> entries = {
      {"status", status},
      {"dimension", N(dim)},
      {"cells", N(sum.cells)},
      {"max_cells", sum.max_cells},
      {"adaptations", N(sum.adaptations)},
      {"refined_cells", sum.refined_cells},
      {"coarsened_cells", sum.coarsened_cells},
      {"cell_steps", sum.cell_steps},
      {"time", sum.time_si},
      {"steps", N(sum.steps)},
      {"rejected_steps", N(sum.rejected_steps)},
      {"steady", N(sum.steady ? 1 : 0)},
      {"wall_seconds", sum.wall_seconds},
      {"convection_seconds", sum.convection_seconds},
      {"convective_steps", sum.convective_steps},
      {"diffusion_seconds", sum.diffusion_seconds},
      {"min_dt", sum.min_dt_si},
      {"max_dt", sum.max_dt_si},
      {"min_cfl_dt", sum.min_cfl_dt_si},
      {"min_cfl_dt_time", sum.min_cfl_dt_time_si},
      {"mass_drift", sum.mass_drift},
      {"peak_memory_bytes_max_rank", sum.peak_memory_max},
      {"peak_memory_bytes_all_ranks", sum.peak_memory_total},
      {"temperature_repairs", sum.temperature_repairs},
      {"max_temperature_repair_J", sum.max_temperature_repair * units_.energy()},
      {"flux_points", cs.flux.points},
      {"musta_stages", cs.flux.stages},
      {"limited_reconstructions", cs.limited_cells},
      {"first_order_fallbacks", cs.fallback_cells},
      {"wall_tension_bounded_convective", cs.wall_tension_bounded},
      {"gravity_point_sources", cs.gravity_point_sources},
      {"diffusion_steps", ds.steps},
      {"newton_iterations", ds.newton_iterations},
      {"gmres_iterations", ds.linear_iterations},
      {"jacobians", ds.jacobians},
      {"matrix_reuses", ds.matrix_reuses},
      {"rkl2_steps", ds.rkl2_steps},
      {"rkl2_stages", ds.rkl2_stages},
      {"rkl2_fallbacks", ds.rkl2_fallbacks},
      {"rkl2_seconds", ds.rkl2_seconds},
      {"implicit_steps", ds.implicit_steps},
      {"implicit_seconds", ds.implicit_seconds},
      {"stale_matrix_retries", ds.stale_matrix_retries},
      {"jacobian_seconds", ds.jacobian_seconds},
      {"preconditioner_seconds", ds.preconditioner_seconds},
      {"gmres_seconds", ds.linear_seconds},
      {"newton_failures", ds.newton_failures},
      {"gmres_failures", ds.linear_failures},
      {"switches_to_midpoint", ds.switches_to_midpoint},
      {"full_jacobian_retries", ds.full_jacobian_retries},
      {"explicit_substeps", ds.explicit_substeps},
      {"min_explicit_dt", std::isfinite(ds.min_explicit_dt) ? ds.min_explicit_dt * t0 : 0},
      {"min_explicit_dt_time", ds.min_explicit_dt_time * t0},
      {"max_dt_over_explicit", ds.max_dt_over_explicit},
      {"friction_dissipation_J", friction_dissipation_si(sum)},
      {"diffusive_face_fluxes", ds.faces.faces},
      {"tension_bounded_faces", ds.faces.tension_bounded},
      {"tension_bounded_wall_faces", ds.faces.tension_bounded_walls},
      {"friction_capped_faces", ds.faces.friction_capped},
      {"negative_temperature_faces", ds.faces.negative_temperature},
      {"musta_early_stops", cs.flux.early_stops},
      {"continuation_cells", sum.continuation_cells},
      {"contact_steps", sum.contact_steps},
      {"contact_newton_iterations", sum.contact_newton_iterations},
      {"contact_linear_iterations", sum.contact_linear_iterations},
      {"contact_failures", sum.contact_failures},
      {"contact_negative_thermal_cells", sum.contact_negative_thermal_cells},
      {"contact_wall_pressure_floors", sum.contact_wall_pressure_floors},
      {"final_mass_kg", sum.final_mass_si},
      {"final_total_energy_J", sum.final_energy_si},
      {"segments", N(sum.segments)},
      {"counted_from_step", sum.counted_from_step}};
    append_phase_entries(entries, sum.phases);
    const auto records = record_entries();
    entries.insert(entries.end(), records.begin(), records.end());
    try
      {
        io::write_summary_csv(files.directory, files.file("_summary.csv"), entries);
      }
    catch (const OutputError &e)
      {
        throw RunError(e.what());
      }
  }

  std::vector<io::SummaryEntry> RunReport::record_entries() const
  {
    // the -p overrides as given, joined by ';' (for reading; a value may hold a ';' of its
    // own, e.g. a velocity "0; 0": <base>_parameters.prm is the exact record)
    std::string overrides;
    for (const auto &o : report.overrides)
      overrides += (overrides.empty() ? "" : ";") + o;
    using N = unsigned long long;
    return {{"version", std::string(version())},
            {"git_revision", std::string(git_revision())},
            {"scene", report.source},
            {"overrides", overrides},
            {"ranks", N(Utilities::MPI::n_mpi_processes(comm))},
            {"start_time", started_utc_}};
  }
} // namespace granhydro::driver
