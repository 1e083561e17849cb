#pragma once
/**
 * @file time_loop.h
 * What the time loop of a run (Simulation::run()) carries from step to step: time and
 * step, the output schedule, the record of the step sizes, the steady-state reference
 * and why the loop stopped.
 */
#include <granhydro/driver/run_summary.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <chrono>
#include <limits>
#include <string>

namespace granhydro::driver
{
  struct TimeLoopState
  {
    using clock = std::chrono::steady_clock;
    clock::time_point start, last_progress;
    RunSummary        sum;
    double            t0    = 1;                             ///< the time unit [s]
    double            t_end = 0, dt_fixed = 0, interval = 0; ///< scaled
    double            t = 0, next_output = 0;                ///< scaled
    unsigned int      step = 0;
    /// Numerics/Strang splitting = merged: adjacent convective half-steps of the
    /// splitting are taken as one (Simulation::advance())
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
    /// largest body force per unit mass [m/s^2]: gravity plus the container's acceleration
    double g_eff = 0;
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
} // namespace granhydro::driver
