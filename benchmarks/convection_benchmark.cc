/**
 * granhydro_benchmark: throughput of the convective solver (not a test).
 *
 * Runs Simulation<3> on a periodic box of N^3 cells (ideal gas; a smooth
 * density/velocity wave plus a spherical blast, i.e. smooth and shock data)
 * for K SSP-RK3 steps, R times, and prints
 *
 *   convective cell-updates per second per RK stage per core
 *     = (owned cells updated per RHS evaluation, summed over ranks, RK stages
 *        and steps: ConvectionStatistics::cell_updates)
 *       / (wall time spent in the SSP-RK3 steps, max over ranks; setup, CFL
 *          and admissibility checks excluded: RunSummary::convection_seconds)
 *       / (number of MPI ranks)
 *
 * as the median over the R repetitions (each repetition builds a fresh
 * Simulation; setup is not timed), together with the median seconds per step
 * and the mean number of MUSTA stages per face point.
 *
 *   granhydro_benchmark [--cells N] [--steps K]
 *                       [--reconstruction weno5|weno3|muscl|first order]
 *                       [--quadrature gauss|midpoint] [--flux musta|rusanov|hll]
 *                       [--repeat R]
 *
 * Defaults: N = 48, K = 10, weno5, gauss, musta, R = 3. "first order" may be
 * given as one quoted argument or as two words; first_order / first-order are
 * accepted too. Options may also be written --option=value.
 * Exit codes: 0 success, 2 bad command line or scene, 3 run failure.
 */
#include <granhydro/driver/simulation.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
  struct Options
  {
    unsigned int cells = 48, steps = 10, repeat = 3;
    std::string  reconstruction = "weno5", quadrature = "gauss", flux = "musta";
  };

  struct UsageError
  {
    std::string message;
  };

  const char *usage_text =
    "usage: granhydro_benchmark [--cells N] [--steps K]\n"
    "                           [--reconstruction weno5|weno3|muscl|first order]\n"
    "                           [--quadrature gauss|midpoint] [--flux musta|rusanov|hll]\n"
    "                           [--repeat R]\n"
    "defaults: --cells 48 --steps 10 --reconstruction weno5 --quadrature gauss --flux musta "
    "--repeat 3\n";

  unsigned int parse_positive(const std::string &option, const std::string &value, const unsigned long max)
  {
    std::size_t   pos = 0;
    unsigned long v   = 0;
    bool          ok  = !value.empty() && value[0] != '-' && value[0] != '+';
    if (ok)
      try
        {
          v  = std::stoul(value, &pos);
          ok = pos == value.size() && v >= 1 && v <= max;
        }
      catch (const std::exception &)
        {
          ok = false;
        }
    if (!ok)
      throw UsageError{"option '" + option + "' needs a whole number between 1 and " + std::to_string(max) +
                       ", got '" + value + "'"};
    return static_cast<unsigned int>(v);
  }

  std::string parse_choice(const std::string &option, const std::string &value,
                           const std::vector<std::string> &allowed)
  {
    if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
      {
        std::string list;
        for (const auto &a : allowed)
          list += (list.empty() ? "" : "|") + a;
        throw UsageError{"option '" + option + "' must be one of " + list + ", got '" + value + "'"};
      }
    return value;
  }

  /// throws UsageError; returns false if --help was given
  bool parse_command_line(int argc, char **argv, Options &o)
  {
    for (int i = 1; i < argc; ++i)
      {
        std::string a = argv[i], value;
        if (a == "--help" || a == "-h")
          return false;
        bool has_value = false;
        if (const auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos)
          {
            value     = a.substr(eq + 1);
            a         = a.substr(0, eq);
            has_value = true;
          }
        const bool known = a == "--cells" || a == "--steps" || a == "--repeat" || a == "--reconstruction" ||
                           a == "--quadrature" || a == "--flux";
        if (!known)
          throw UsageError{"unknown option '" + std::string(argv[i]) + "'"};
        if (!has_value)
          {
            if (i + 1 >= argc)
              throw UsageError{"option '" + a + "' needs a value"};
            value = argv[++i];
          }
        if (a == "--cells")
          o.cells = parse_positive(a, value, 368); // 368^3 < 5e7, the scene limit
        else if (a == "--steps")
          o.steps = parse_positive(a, value, 1000000);
        else if (a == "--repeat")
          o.repeat = parse_positive(a, value, 1000);
        else if (a == "--reconstruction")
          {
            // "first order" as two words, or first_order / first-order
            if (value == "first" && !has_value && i + 1 < argc && std::string(argv[i + 1]) == "order")
              {
                value = "first order";
                ++i;
              }
            if (value == "first_order" || value == "first-order")
              value = "first order";
            o.reconstruction = parse_choice(a, value, {"weno5", "weno3", "muscl", "first order"});
          }
        else if (a == "--quadrature")
          o.quadrature = parse_choice(a, value, {"gauss", "midpoint"});
        else
          o.flux = parse_choice(a, value, {"musta", "rusanov", "hll"});
      }
    return true;
  }

  /// the benchmark scene: periodic box of side 0.1 m, ideal gas, a smooth
  /// density and velocity wave plus a spherical blast (pressure ratio ~40)
  std::string scene_text(const Options &o)
  {
    const std::string  N = std::to_string(o.cells);
    std::ostringstream s;
    s << "set Dimension = 3\n"
         "subsection Domain\n"
         "  set Lower corner = 0, 0, 0\n"
         "  set Upper corner = 0.1, 0.1, 0.1\n"
      << "  set Cells = " << N << ", " << N << ", " << N << "\n"
      << "  set Boundary x- = periodic\n"
         "  set Boundary x+ = periodic\n"
         "  set Boundary y- = periodic\n"
         "  set Boundary y+ = periodic\n"
         "  set Boundary z- = periodic\n"
         "  set Boundary z+ = periodic\n"
         "end\n"
         "subsection Material\n"
         "  set Model = ideal gas\n"
         "  set Grain diameter = 1e-3\n"
         "  set Material density = 2600\n"
         "end\n"
         "subsection Initial state\n"
         "  set Constants = L=0.1, cx=0.04, cy=0.05, cz=0.06, R=0.02\n"
         "  set Packing fraction = 0.01*(1 + 0.2*sin(2*pi*x/L) + 0.1*sin(2*pi*(y+z)/L)) "
         "+ if((x-cx)^2 + (y-cy)^2 + (z-cz)^2 < R^2, 0.01, 0)\n"
         "  set Velocity = 0.02*sin(2*pi*z/L); 0.02*sin(2*pi*x/L); 0.02*sin(2*pi*y/L)\n"
         "  set Temperature = if((x-cx)^2 + (y-cy)^2 + (z-cz)^2 < R^2, 2e-7, 1e-8)\n"
         "  set Quadrature points = 2\n"
         "end\n"
         "subsection Numerics\n"
      << "  set Reconstruction = " << o.reconstruction << "\n"
      << "  set Face quadrature = " << o.quadrature << "\n"
      << "  set Flux = " << o.flux << "\n"
      << "end\n"
         "subsection Time\n"
         "  set End time = 1e6\n"
      << "  set Maximum steps = " << o.steps << "\n"
      << "end\n"
         "subsection Output\n"
         "  set Write VTU = false\n"
         "  set Write profiles = false\n  set Write checkpoint = false\n"
         "  set Progress interval = 1e9\n"
         "  set Verbose = false\n"
         "end\n";
    return s.str();
  }

  double median(std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }

  std::string config_name(const Options &o)
  {
    std::string r = o.reconstruction == "first order" ? "first_order" : o.reconstruction;
    return r + "/" + o.quadrature + "/" + o.flux;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm   = MPI_COMM_WORLD;
  const bool                               root   = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  const unsigned int                       nranks = dealii::Utilities::MPI::n_mpi_processes(comm);

  Options o;
  try
    {
      if (!parse_command_line(argc, argv, o))
        {
          if (root)
            std::cout << usage_text;
          return 0;
        }
    }
  catch (const UsageError &e)
    {
      if (root)
        std::cerr << "granhydro_benchmark: error: " << e.message << "\n" << usage_text;
      return 2;
    }

  try
    {
      const granhydro::scene::Scene scene = granhydro::scene::parse_scene(scene_text(o), "<benchmark scene>");

      std::vector<double> rate, seconds_per_step, musta_stages;
      unsigned long long  rejected = 0, fallbacks = 0, limited = 0;
      for (unsigned int rep = 0; rep < o.repeat; ++rep)
        {
          granhydro::driver::Simulation<3> sim(scene, comm, std::cout);
          sim.setup(); // not timed
          MPI_Barrier(comm);
          const granhydro::driver::RunSummary s = sim.run();
          if (s.steps != o.steps)
            throw granhydro::RunError("run stopped after " + std::to_string(s.steps) + " of " +
                                      std::to_string(o.steps) + " steps");
          const double secs = std::max(s.convection_seconds, 1e-30); // already max over ranks
          rate.push_back(double(s.convection.cell_updates) / secs / nranks);
          seconds_per_step.push_back(secs / s.steps);
          musta_stages.push_back(double(s.convection.flux.stages) /
                                 std::max<double>(double(s.convection.flux.points), 1.));
          rejected += s.rejected_steps;
          fallbacks += s.convection.flux.fallbacks;
          limited += s.convection.limited_cells;
        }

      if (root)
        {
          char line[256];
          std::cout << "# granhydro convection benchmark: 3D periodic box, ideal gas, density wave "
                       "+ blast, SSP-RK3, "
                    << o.steps << " steps, median of " << o.repeat << (o.repeat == 1 ? " run\n" : " runs\n");
          std::snprintf(line, sizeof line, "%-8s %5s  %-30s %22s %12s %14s\n", "cells", "ranks", "config",
                        "updates/s/stage/core", "s/step", "MUSTA_st/point");
          std::cout << line;
          const std::string cells = std::to_string(o.cells) + "^3";
          char              musta[32];
          if (o.flux == "musta")
            std::snprintf(musta, sizeof musta, "%.3f", median(musta_stages));
          else
            std::snprintf(musta, sizeof musta, "-");
          std::snprintf(line, sizeof line, "%-8s %5u  %-30s %22.4e %12.4e %14s\n", cells.c_str(), nranks,
                        config_name(o).c_str(), median(rate), median(seconds_per_step), musta);
          std::cout << line << std::flush;
          if (rejected > 0 || fallbacks > 0 || limited > 0)
            std::cerr << "granhydro_benchmark: note (all runs): " << rejected << " rejected (retried) steps, "
                      << fallbacks << " MUSTA fallbacks to Rusanov, " << limited
                      << " positivity fallbacks to first order\n";
        }
      return 0;
    }
  catch (const granhydro::SceneError &e)
    {
      if (root)
        std::cerr << "granhydro_benchmark: error: " << e.what() << std::endl;
      return 2;
    }
  catch (const granhydro::RunError &e)
    {
      if (root)
        std::cerr << "granhydro_benchmark: run stopped: " << e.what() << std::endl;
      return 3;
    }
  catch (const std::exception &e)
    {
      std::cerr << "granhydro_benchmark: internal error: " << e.what() << std::endl;
      MPI_Abort(comm, 1);
      return 1;
    }
}
