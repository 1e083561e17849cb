/**
 * @file time_loop.cc
 * TimeLoop (driver/time_loop.h): CFL time step, rejected steps retried with half the
 * step, the output and checkpoint schedule, the steady-state test, the stop on a signal
 * or the wall time limit, the progress line, and the final output and summary.
 */
#include <granhydro/base/errors.h>
#include <granhydro/io/checkpoint.h>
#include <granhydro/io/diagnostics.h>
#include <granhydro/io/summary_csv.h>

#include <deal.II/base/mpi.h>

#include "time_loop_instances.h"
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <ctime>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <type_traits>

namespace granhydro::driver
{
  using namespace dealii;

  namespace
  {
    using clock = TimeLoopState::clock;

    /// halvings allowed to the first step of a run (see take_step)
    constexpr unsigned int first_step_retries = 30;

    double seconds_since(const clock::time_point t)
    {
      return std::chrono::duration<double>(clock::now() - t).count();
    }

    /// the wall-clock time in ISO 8601, UTC, to the second (2026-12-06T09:30:00Z)
    std::string utc_now()
    {
      const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
      std::tm           utc{};
      gmtime_r(&now, &utc);
      char text[32];
      std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
      return text;
    }

    std::string hms(double s)
    {
      const long         k = std::lround(std::max(0., s));
      std::ostringstream os;
      os << std::setfill('0') << std::setw(2) << k / 3600 << ':' << std::setw(2) << (k / 60) % 60 << ':'
         << std::setw(2) << k % 60;
      return os.str();
    }

    volatile std::sig_atomic_t stop_requested = 0;

    /// test hook (doc/developer.md, "Test hooks"): GRANHYDRO_SIGTERM_AT_STEP=K sends SIGTERM to
    /// every rank after step K, so that a test interrupts at a known step
    unsigned long sigterm_at_step()
    {
      static const unsigned long k = [] {
        const char *v = std::getenv("GRANHYDRO_SIGTERM_AT_STEP");
        return v ? std::strtoul(v, nullptr, 10) : 0UL;
      }();
      return k;
    }

    extern "C" void on_stop_signal(const int sig)
    {
      stop_requested = sig;
      std::signal(sig, SIG_DFL); // a second signal ends the process at once
    }
  } // namespace

  void install_stop_signal_handlers()
  {
    std::signal(SIGTERM, on_stop_signal);
    std::signal(SIGINT, on_stop_signal);
  }

  int stop_signal()
  {
    return stop_requested;
  }

  template <int dim, class Description>
  TimeLoop<dim, Description>::TimeLoop(const TimeLoopSettings &settings, const RunFiles &files,
                                       const std::string &integrator_name, const Units &units,
                                       const MPI_Comm comm, const dealii::ConditionalOStream &pcout,
                                       const TimeLoopParts<dim, Description> &parts,
                                       const TimeLoopHooks                   &hooks)
    : loop(settings)
    , files(files)
    , integrator_name(integrator_name)
    , units_(units)
    , comm(comm)
    , pcout(pcout)
    , U(parts.state)
    , patch(parts.patch)
    , desc(parts.desc)
    , conv(parts.convection)
    , integrator(parts.integrator)
    , split(parts.split)
    , output(parts.output)
    , report(parts.report)
    , adaptation(parts.adaptation)
    , timers(parts.timers)
    , hooks(hooks)
  {}

  template <int dim, class Description>
  TimeLoop<dim, Description>::~TimeLoop() = default;

  template <int dim, class Description>
  void TimeLoop<dim, Description>::write_output(const Vector &V, const double time_si,
                                                const unsigned int step)
  {
    const TimerOutput::Scope scope(timers, "output");
    output.write(V, time_si, step);
  }

  template <int dim, class Description>
  RunSummary TimeLoop<dim, Description>::run(const TimeLoopStart &start)
  {
    start_  = start;
    L       = TimeLoopState();
    L.start = clock::now();
    start_run();
    while (L.t < L.t_end * (1 - 1e-12) && (loop.max_steps == 0 || L.step < loop.max_steps))
      {
        // adaptation on absolute step numbers: a restarted run adapts where the
        // uninterrupted one did
        if (loop.adapt_interval > 0 && L.step % loop.adapt_interval == 0 && L.step > 0)
          {
            const TimerOutput::Scope scope(timers, "adaptation");
            hooks.adapt_mesh();
          }
        double       dt_cfl   = 0;
        const double dt_uncut = step_size(dt_cfl);
        double       dt       = std::min(dt_uncut, L.t_end - L.t);
        dt                    = std::min(dt, L.next_output - L.t);
        unsigned int tries    = 0;
        dt                    = take_step(dt, dt_cfl, tries);
        const double t_before = L.t;
        L.t += dt;
        ++L.step;
        L.cell_steps += patch.n_global_cells();
        L.last_dt = dt;
        if (history_due(t_before))
          write_history_row(io::state_totals(patch, U, desc, units_.length, comm));
        // a step cut short to land on an output or end time says nothing about the
        // scheme's step; halved (retried) steps do and are kept
        if (tries == 0 && dt < dt_uncut)
          L.min_cut_dt = std::min(L.min_cut_dt, dt);
        else
          L.min_dt = std::min(L.min_dt, dt);
        L.max_dt = std::max(L.max_dt, dt);
        if (L.t >= L.next_output * (1 - 1e-12) && output_time())
          break;
        if (stop_requested())
          break;
        progress_line(dt);
      }
    // Time/Maximum steps reached before the end time: say so, not "completed"
    const bool step_limited =
      !L.sum.steady && !L.wall_limited && !L.interrupted_by && L.t < L.t_end * (1 - 1e-12);
    if (step_limited)
      pcout << "  step limit (Time/Maximum steps = " << loop.max_steps << ") reached at t = " << L.t * L.t0
            << " s of " << loop.end_time << " s\n";
    L.sum.interrupted_by = L.interrupted_by;
    finish(L.sum.steady ? "steady" :
           L.interrupted_by ?
                          (L.interrupted_by == SIGINT ? "interrupted (SIGINT)" : "interrupted (SIGTERM)") :
           L.wall_limited ? "wall time limit" :
           step_limited   ? "maximum steps" :
                            "completed");
    return L.sum;
  }

  template <int dim, class Description>
  void TimeLoop<dim, Description>::start_run()
  {
    report.set_start_time(utc_now()); // rank 0's clock gives the summary's start_time
    L.t0          = units_.time();
    L.t_end       = loop.end_time / L.t0;
    L.dt_fixed    = loop.fixed_time_step / L.t0;
    L.interval    = loop.output_interval / L.t0;
    L.t           = start_.time;
    L.next_output = L.interval > 0 ? L.interval : L.t_end;
    // the output times after a restart are the ones the uninterrupted run would have
    // chosen (same additions), so the time steps and results are identical
    while (L.interval > 0 && L.t >= L.next_output * (1 - 1e-12) && L.next_output < L.t_end)
      L.next_output = std::min(L.next_output + L.interval, L.t_end);
    timers.reset();
    split.reset_counters();
    L.step  = start_.step;
    L.merge = integrator && loop.convection && loop.merge_strang;
    if (split.owed() > 0 && !L.merge) // a checkpoint of a merged run restarted with symmetric steps
      {
        if (!split.convect(U, split.owed()))
          throw RunError("the convective half-step owed by the checkpoint failed");
        split.set_owed(0);
      }
    L.checkpoint    = files.file(".checkpoint");
    L.last_progress = L.start;
    std::string why;
    if (!split.admissible(U, &why))
      throw RunError("initial state is inadmissible (n <= 0 or T <= 0): " + why);
    if (files.summary && Utilities::MPI::this_mpi_process(comm) == 0)
      io::write_running_summary(files.file("_summary.csv"), report.record_entries());
    // a run from the scene's initial state writes it; a restart (even from the t = 0
    // checkpoint) has it already
    const bool fresh = L.step == 0 && !loop.from_checkpoint;
    if (fresh)
      {
        write_output(U, L.t * L.t0, 0);
        checkpoint_now();
      }
    L.backup.reinit(U.get_partitioner());
    L.backup                      = U;
    const io::StateTotals<dim> s0 = io::state_totals(patch, U, desc, units_.length, comm);
    // the mass drift is taken against the mass at the start of the counted run
    L.mass0 = start_.earlier.initial_grains > 0 ? start_.earlier.initial_grains : s0.n;
    start_history(fresh, s0);
  }

  template <int dim, class Description>
  double TimeLoop<dim, Description>::step_size(double &dt_cfl)
  {
    double dt = L.dt_fixed;
    if (loop.convection) // the convective CFL limits the step; diffusion never does
      {
        const double rate = split.max_rate(U);
        if (!(rate > 0) || !std::isfinite(rate))
          throw RunError("no finite wave speed at t = " + std::to_string(L.t * L.t0) + " s");
        dt_cfl = loop.cfl / rate;
        dt     = L.dt_fixed > 0 ? std::min(dt_cfl, L.dt_fixed) : dt_cfl;
        if (dt_cfl < L.min_cfl)
          {
            L.min_cfl   = dt_cfl;
            L.min_cfl_t = L.t;
          }
        // merged splitting: the step's convective part is the owed half plus dt/2;
        // keep it within the CFL limit by shortening dt (the step after is then back
        // at the limit). Where the limit fell by more than that allows, the
        // convective part is split into pieces instead (advance())
        const double owed = split.owed();
        const double room = 2 * (dt_cfl - owed); // the longest dt with owed + dt/2 <= dt_cfl
        if (L.merge && owed > 0 && room >= 0.5 * dt)
          dt = std::min(dt, room);
      }
    return dt;
  }

  template <int dim, class Description>
  double TimeLoop<dim, Description>::take_step(double dt, const double dt_cfl, unsigned int &tries)
  {
    const double t0 = L.t0;
    // merged Strang splitting: the closing C(dt/2) is owed to the next step, except
    // at output and end times and before the step limit (a checkpoint between output
    // times stores the owed time, so a restart continues exactly)
    const bool last_step = loop.max_steps > 0 && L.step + 1 >= loop.max_steps;
    auto       sync_at   = [&](const double h) {
      return !L.merge || last_step || L.t + h >= L.next_output * (1 - 1e-12);
    };
    if (L.backup.get_partitioner() != U.get_partitioner())
      L.backup.reinit(U.get_partitioner()); // the mesh changed
    L.backup = U;
    std::string why;
    while (true)
      {
        // a retried step (halved dt) also halves its convective pieces
        if (split.advance(U, L.t, dt, sync_at(dt), tries == 0 ? dt_cfl : dt) && split.admissible(U, &why))
          break;
        why.clear();
        split.admissible(U, &why); // where and what, for the message
        if (why.empty())
          why = conv.failure();
        if (why.empty() && integrator)
          why = integrator->failure();
        ++L.sum.rejected_steps;
        // the first step's CFL limit comes from the initial state alone, which can be far
        // out of proportion with the implicit step's stiffness: a no-slip wall at 1e4 m/s
        // against a gas at rest with T = 1e-8 J (CFL step 2.5e-3 s) heats it so fast
        // that Newton needs 2^-20 of that step. Once the gas has heated, its sound speed
        // brings the CFL step into proportion (3 halvings at the second step). So the
        // first step may halve down to 2^-30 ~ 1e-9 of its CFL step; every later step
        // keeps 'Maximum step retries'
        const unsigned int max_retries =
          L.step == 0 ? std::max(loop.max_step_retries, first_step_retries) : loop.max_step_retries;
        if (++tries > max_retries)
          {
            const std::string details = io::inadmissible_step_message(
              L.step, L.t * t0, max_retries, dt * t0, why,
              integrator ? std::optional<unsigned long long>(integrator->statistics().newton_failures) :
                           std::nullopt);
            // the run ends cleanly: the last admissible state (no mass lost) is written
            // as the final output, checkpoint and summary, then the run stops
            U                         = L.backup;
            const std::string packing = overpacking_report(U);
            const std::string message =
              packing.empty() ? details : io::overpacking_message(L.t * t0, packing, details);
            finish(packing.empty() ? "failed" : "overpacking");
            pcout << "  the last admissible state (t = " << L.t * t0 << " s) is the final output\n";
            throw RunError(message);
          }
        pcout << "  step " << L.step << ": inadmissible state, retrying with dt = " << dt * t0 / 2 << " s"
              << (why.empty() ? std::string() : " (" + why + ")") << "\n";
        U  = L.backup;
        dt = dt / 2;
      }
    split.set_owed(sync_at(dt) ? 0 : 0.5 * dt);
    return dt;
  }

  template <int dim, class Description>
  bool TimeLoop<dim, Description>::output_time()
  {
    if (L.t < L.t_end * (1 - 1e-12))
      {
        write_output(U, L.t * L.t0, L.step);
        checkpoint_now();
      }
    if (history_)
      history_->check(); // a failed history write stops every rank here
    L.next_output = L.interval > 0 ? std::min(L.next_output + L.interval, L.t_end) : L.t_end;
    return loop.steady_tolerance > 0 && L.interval > 0 && steady_state();
  }

  template <int dim, class Description>
  bool TimeLoop<dim, Description>::steady_state()
  {
    // steady state: total kinetic energy and centre of mass along the profile
    // direction both change by less than the tolerance over one output interval
    const unsigned int pd   = loop.profile_direction;
    double             v[3] = {0, 0, 0}; // kinetic energy, n x_pd, n
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        const double *u   = &U.local_element(std::size_t(s) * (dim + 2));
        const double  vol = patch.cell_volume(s);
        double        m2  = 0;
        for (unsigned int d = 0; d < dim; ++d)
          m2 += u[1 + d] * u[1 + d];
        v[0] += 0.5 * m2 / u[0] * vol;
        v[1] += u[0] * patch.center(s)[pd] * vol;
        v[2] += u[0] * vol;
      }
    Utilities::MPI::sum(ArrayView<const double>(v, 3), comm, ArrayView<double>(v, 3));
    const double ke = v[0], com = v[1] / v[2];
    const double L_pd = patch.cell_size(pd) * patch.cells(pd);
    if (L.have_steady_reference && std::abs(ke - L.steady_ke) <= loop.steady_tolerance * ke &&
        std::abs(com - L.steady_com) <= loop.steady_tolerance * L_pd)
      {
        pcout << "  steady state at t = " << L.t * L.t0 << " s: kinetic energy and centre of mass "
              << "changed by " << std::abs(ke - L.steady_ke) / ke << " and "
              << std::abs(com - L.steady_com) / L_pd << " (relative) over the last " << loop.output_interval
              << " s (Time/Steady state tolerance = " << loop.steady_tolerance << ")\n";
        L.sum.steady = true;
        return true;
      }
    L.have_steady_reference = true;
    L.steady_ke             = ke;
    L.steady_com            = com;
    return false;
  }

  template <int dim, class Description>
  bool TimeLoop<dim, Description>::stop_requested()
  {
    // SIGTERM / SIGINT (every rank stops after the same step)
    if (sigterm_at_step() > 0 && L.step == sigterm_at_step())
      std::raise(SIGTERM);
    L.interrupted_by = Utilities::MPI::max(int(stop_signal()), comm);
    if (L.interrupted_by)
      {
        pcout << "  " << (L.interrupted_by == SIGINT ? "SIGINT" : "SIGTERM")
              << " received: stopping at t = " << L.t * L.t0 << " s, step " << L.step
              << " (final output, checkpoint and summary follow)\n";
        return true;
      }
    if (loop.max_wall_seconds > 0 &&
        Utilities::MPI::max(seconds_since(L.start), comm) > loop.max_wall_seconds)
      {
        pcout << "  wall time limit (Time/Maximum wall time = " << loop.max_wall_seconds
              << " s) reached at t = " << L.t * L.t0 << " s, step " << L.step << "\n";
        L.wall_limited = true;
        return true;
      }
    return false;
  }

  template <int dim, class Description>
  void TimeLoop<dim, Description>::progress_line(const double dt)
  {
    const auto now = clock::now();
    if (std::chrono::duration<double>(now - L.last_progress).count() < loop.progress_interval)
      return;
    L.last_progress   = now;
    const double wall = std::chrono::duration<double>(now - L.start).count();
    const double frac = L.t / L.t_end;
    // rate and ETA from this run's own steps and time (a restart starts mid-way);
    // with Time/Maximum steps the run ends at whichever comes first
    const double done = (L.t - start_.time) / std::max(L.t_end - start_.time, 1e-300);
    const double rate = (L.step - start_.step) / std::max(wall, 1e-12);
    double       eta  = wall * (1 - done) / std::max(done, 1e-12);
    if (loop.max_steps > 0 && rate > 0)
      eta = std::min(eta, (double(loop.max_steps) - L.step) / rate);
    pcout << "  t = " << std::scientific << std::setprecision(4) << L.t * L.t0 << " s (" << std::fixed
          << std::setprecision(1) << 100 * frac << " %)  dt = " << std::scientific << std::setprecision(3)
          << dt * L.t0 << " s  step " << L.step << "  " << std::fixed << std::setprecision(1) << rate
          << " steps/s  ETA " << hms(eta) << std::defaultfloat << std::setprecision(6) << "\n";
  }

  template <int dim, class Description>
  void TimeLoop<dim, Description>::checkpoint_now(const RunSummary *whole)
  {
    if (integrator && !L.interrupted_by) // a restart starts here: the integrator forgets its history too
      integrator->restart_point();
    if (!files.checkpoint)
      return;
    const TimerOutput::Scope scope(timers, "output");
    hooks.write_checkpoint(L.checkpoint, L.t, L.step, L.interrupted_by != 0,
                           to_run_record(whole ? *whole : combine_segments(start_.earlier, segment_summary()),
                                         record_units(units_, dim)));
    if (files.keep_checkpoints > 1)
      {
        // the numbered copy and the deletion of the oldest: rank 0, now that every rank
        // has verified its part of the new checkpoint
        std::string error;
        if (Utilities::MPI::this_mpi_process(comm) == 0)
          error = io::keep_recent_checkpoints(L.checkpoint, L.step, files.keep_checkpoints);
        error = io::first_error(error, comm);
        if (!error.empty())
          throw io::OutputError(error + " (Output/Keep checkpoints)");
      }
  }

  template <int dim, class Description>
  RunSummary TimeLoop<dim, Description>::segment_summary() const
  {
    const double t0  = L.t0;
    RunSummary   sum = L.sum; // rejected steps, steady, interrupted_by
    sum.steps        = L.step;
    sum.min_dt_si =
      (std::isfinite(L.min_dt) ? L.min_dt : (std::isfinite(L.min_cut_dt) ? L.min_cut_dt : 0)) * t0;
    sum.max_dt_si                      = L.max_dt * t0;
    sum.min_cfl_dt_si                  = std::isfinite(L.min_cfl) ? L.min_cfl * t0 : 0;
    sum.min_cfl_dt_time_si             = L.min_cfl_t * t0;
    sum.cells                          = patch.n_global_cells();
    sum.max_cells                      = std::max<unsigned long long>(adaptation.max_cells, sum.cells);
    sum.adaptations                    = adaptation.adaptations;
    sum.refined_cells                  = adaptation.refined_cells;
    sum.coarsened_cells                = adaptation.coarsened_cells;
    sum.cell_steps                     = L.cell_steps;
    sum.min_rank_cells                 = Utilities::MPI::min<unsigned long long>(patch.n_owned(), comm);
    sum.max_rank_cells                 = Utilities::MPI::max<unsigned long long>(patch.n_owned(), comm);
    const SplitStepCounters &c         = split.counters();
    sum.temperature_repairs            = Utilities::MPI::sum(c.temperature_repairs, comm);
    sum.continuation_cells             = Utilities::MPI::sum(c.continuation_cells, comm);
    const auto cc                      = split.contact_counts(); // the same on every rank
    sum.contact_steps                  = cc.steps;
    sum.contact_newton_iterations      = cc.newton_iterations;
    sum.contact_linear_iterations      = cc.linear_iterations;
    sum.contact_failures               = cc.failures;
    sum.contact_negative_thermal_cells = Utilities::MPI::sum(cc.negative_thermal_cells, comm);
    sum.contact_wall_pressure_floors   = Utilities::MPI::sum(cc.wall_pressure_floors, comm);
    sum.convective_steps               = c.convective_pieces; // the same on every rank
    sum.max_temperature_repair         = Utilities::MPI::max(c.max_repair, comm);
    sum.ranks                          = Utilities::MPI::n_mpi_processes(comm);
    {
      rusage usage{};
      getrusage(RUSAGE_SELF, &usage);
      const double bytes    = 1024. * usage.ru_maxrss; // Linux: kilobytes
      sum.peak_memory_max   = Utilities::MPI::max(bytes, comm);
      sum.peak_memory_total = Utilities::MPI::sum(bytes, comm);
    }
    sum.time_si          = L.t * t0;
    sum.wall_seconds     = seconds_since(L.start);
    sum.convection       = conv.global_statistics();
    sum.diffusion_active = integrator != nullptr;
    if (integrator)
      {
        sum.diffusion = integrator->global_statistics();
      }
    measure_phases(sum); // this segment's phases (one reduction); sets the *_seconds rows
    sum.segments          = 1;
    sum.counted_from_step = 0;
    sum.initial_grains    = L.mass0;
    return sum;
  }

  template <int dim, class Description>
  void TimeLoop<dim, Description>::finish(const std::string &status)
  {
    const double t0 = L.t0;
    if (!(status == "steady" && L.t < L.t_end * (1 - 1e-12))) // a steady stop has just written its output
      {
        // the checkpoint's record of the run: taken before the owed half-step below,
        // which the restarted run takes (and counts) itself
        const RunSummary whole = combine_segments(start_.earlier, segment_summary());
        // stopped between output times (signal, wall time, failure) with convective
        // time owed: the output shows the synchronised state, the checkpoint keeps the
        // state and the owed time, so that a restart continues exactly
        if (split.owed() > 0)
          {
            Vector V;
            if (!split.synchronised_state(U, V))
              pcout << "  the convective half-step owed at the stop failed: the final output "
                       "shows the state before it\n";
            write_output(V, L.t * t0, L.step);
          }
        else
          write_output(U, L.t * t0, L.step);
        checkpoint_now(&whole);
      }
    // the whole run: the earlier segments' record and this segment
    RunSummary sum = combine_segments(start_.earlier, segment_summary());
    // the final state's totals, once: the summary's and the history's last row (the state
    // the checkpoint holds)
    const io::StateTotals<dim> s = io::state_totals(patch, U, desc, units_.length, comm);
    sum.mass_drift               = std::abs(s.n - L.mass0) / L.mass0;
    sum.final_mass_si            = s.n * units_.mass * std::pow(units_.length, dim - 3.);
    sum.final_energy_si          = s.energy * units_.energy() * std::pow(units_.length, dim - 3.);
    if (history_)
      {
        if (L.history_step != (long long)L.step)
          write_history_row(s);
        history_->check();
      }
    L.sum = sum;
    report.print(sum, patch.balance_counts());
    if (files.summary)
      report.write(sum, status);
    if (files.vtu || files.profiles || files.summary)
      {
        pcout << "  output in " << files.directory << "/:";
        if (files.vtu)
          pcout << " " << files.base_name << ".pvd (ParaView)";
        if (files.profiles)
          pcout << " " << files.base_name << "_profiles.csv";
        if (files.summary)
          pcout << " " << files.base_name << "_summary.csv";
        if (history_)
          pcout << " " << files.base_name << "_history.csv";
        pcout << "\n";
      }
  }

  template <int dim, class Description>
  std::string TimeLoop<dim, Description>::overpacking_report(const Vector &V) const
  {
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      return io::overpacking_report(patch, V, desc.phi_c, comm);
    else
      {
        (void)V;
        return {};
      }
  }

  GRANHYDRO_TIME_LOOP_INSTANCES
} // namespace granhydro::driver
