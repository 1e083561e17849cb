#include <granhydro/scene/output.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  namespace
  {
    /// a whole number lo..hi; anything else is refused naming the parameter (not deal.II's
    /// pattern text)
    long long whole_number(const std::string &v, const std::string &name, const long long lo,
                           const long long hi, const std::string &meaning)
    {
      std::size_t end = 0;
      long long   k   = -1;
      try
        {
          k = std::stoll(v, &end);
        }
      catch (const std::exception &)
        {
          end = 0;
        }
      while (end < v.size() && std::isspace(static_cast<unsigned char>(v[end])))
        ++end;
      if (v.empty() || end != v.size() || k < lo || k > hi)
        throw SceneError("parameter '" + name + "' = '" + v + "': expected a whole number " +
                         std::to_string(lo) + ".." + std::to_string(hi) + " (" + meaning + ")");
      return k;
    }
  } // namespace

  void OutputParameters::declare_parameters(ParameterHandler &prm)
  {
    const OutputParameters defaults;
    prm.enter_subsection("Output");
    {
      prm.declare_entry("Directory", default_text(defaults.output_directory), Patterns::Anything(),
                        "Directory for VTU/PVTU/PVD and CSV files (created if missing).");
      prm.declare_entry("Base name", default_text(defaults.base_name), Patterns::FileName(),
                        "Base name of the output files: <Base name>.pvd, <Base name>_summary.csv, ...");
      prm.declare_entry("Interval", default_text(defaults.output_interval),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Simulated time between outputs [s]; 0 = initial and final state only.");
      prm.declare_entry("Write VTU", default_text(defaults.write_vtu), Patterns::Bool(),
                        "Write <Base name>_NNNN.pvtu with its .vtu files at every output time, "
                        "and <Base name>.pvd, the time series for ParaView.");
      prm.declare_entry("VTU files per output", default_text(defaults.vtu_files_per_output),
                        Patterns::Anything(),
                        "Bound on the .vtu files of one output time: 0 = one file per MPI "
                        "rank; K = one file per rank on up to K ranks, and on more ranks K "
                        "files, file k holding the pieces of ranks k, k+K, k+2K, ... "
                        "(written collectively with MPI-IO). A whole number 0..1000000.");
      prm.declare_entry("Write checkpoint", default_text(defaults.write_checkpoint), Patterns::Bool(),
                        "Write <Directory>/<Base name>.checkpoint at every output time and at "
                        "the end (replaced atomically), for 'granhydro --resume' and 'Initial "
                        "state/Checkpoint'.");
      prm.declare_entry("Keep checkpoints", default_text(defaults.keep_checkpoints), Patterns::Anything(),
                        "How many checkpoints to keep, a whole number 1..1000. 1: only the latest, "
                        "<Base name>.checkpoint (and the one before it as <Base name>.checkpoint.bak). "
                        "N > 1: also the N most recent as <Base name>_checkpoint_<step>.checkpoint "
                        "(<step>: the step, 8 or more digits; hard links to the same file where "
                        "the file system allows, so the latest takes no extra space); older "
                        "ones are deleted once a new checkpoint is written and verified.");
      prm.declare_entry("History interval", "10 steps", Patterns::Anything(),
                        "How often a row of <Base name>_history.csv is written (time, step, mass, "
                        "momentum, energies, centre of mass, extremes and the run's counts; "
                        "doc/user-guide.md, 'Output'): 'N steps' = after every step whose "
                        "number is a multiple of N (N >= 1); 'T s' = after the first step at or "
                        "past each multiple of T seconds of simulated time (T > 0; the steps are "
                        "not shortened to land on it); 'off' or 0 = no history file. There is "
                        "always a row of the initial state and one of the final state.");
      prm.declare_entry("Write summary", default_text(defaults.write_summary), Patterns::Bool(),
                        "Write <Base name>_summary.csv at the end of the run: one 'key,value' "
                        "line per figure of the run summary (cells, steps, wall times, smallest "
                        "and largest time step, the explicit diffusive limit, Newton/GMRES "
                        "iterations, mass drift, version, git revision, scene, overrides, "
                        "ranks, start time), for scripts such as tools/work_precision.py; "
                        "and at the start the run records <Base name>_parameters.prm (the "
                        "scene as it runs, every parameter: a scene file that runs it again) "
                        "and <Base name>.log (what the run prints, with Verbose).");
      prm.declare_entry("Write profiles", default_text(defaults.write_profiles), Patterns::Bool(),
                        "Write <Base name>_profiles.csv: averages over the directions other "
                        "than the profile direction.");
      prm.declare_entry("Profile direction", "auto", Patterns::Selection("auto|x|y|z"),
                        "Direction of the profiles; auto = the last resolved direction.");
      prm.declare_entry("Cross-section direction", "none", Patterns::Selection("none|x|y|z"),
                        "3D scenes: also write <Base name>_cross_section.csv, the averages "
                        "along this direction as a map over the other two (e.g. x for the "
                        "chute: the velocity field across the channel, paper fig. 8).");
      prm.declare_entry("Progress interval", default_text(defaults.progress_interval),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Wall-clock seconds between progress lines (0 = every step).");
      prm.declare_entry("Verbose", default_text(defaults.verbose), Patterns::Bool(),
                        "Print the run log (with 'Write summary' also into <Base name>.log).");
    }
    prm.leave_subsection();
  }

  void OutputParameters::parse_history_interval(const std::string &text, unsigned int &steps, double &seconds)
  {
    const auto fail_with = [&](const std::string &why) {
      throw SceneError("parameter 'Output/History interval' = '" + text + "': " + why +
                       "; allowed: 'N steps' (a whole number N >= 1: a row after every N-th step), "
                       "'T s' (a number T > 0: a row after the first step past each multiple of T "
                       "seconds of simulated time), 'off' or 0 (no history file)");
    };
    std::istringstream in(text);
    std::string        number, unit, rest;
    in >> number >> unit >> rest;
    steps   = 0;
    seconds = 0;
    if (number == "off" && unit.empty())
      return;
    if (number.empty() || !rest.empty())
      fail_with("expected a number and a unit");
    std::size_t end = 0;
    double      x   = 0;
    try
      {
        x = std::stod(number, &end);
      }
    catch (const std::exception &)
      {
        end = 0;
      }
    if (end != number.size() || !std::isfinite(x) || x < 0)
      fail_with("'" + number + "' is not a number >= 0");
    if (x == 0 && unit.empty())
      return;
    if (unit.empty())
      fail_with("a number needs its unit, 'steps' or 's'");
    if (unit == "steps" || unit == "step")
      {
        if (x < 1 || x > 4e9 || x != std::floor(x))
          fail_with("a step count must be a whole number 1..4000000000");
        steps = static_cast<unsigned int>(x);
      }
    else if (unit == "s")
      {
        if (!(x > 0))
          fail_with("a time interval must be positive");
        seconds = x;
      }
    else
      fail_with("unknown unit '" + unit + "'");
  }

  void OutputParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    output_directory     = prm.get("Directory");
    base_name            = prm.get("Base name");
    output_interval      = prm.get_double("Interval");
    write_vtu            = prm.get_bool("Write VTU");
    write_profiles       = prm.get_bool("Write profiles");
    write_checkpoint     = prm.get_bool("Write checkpoint");
    write_summary        = prm.get_bool("Write summary");
    vtu_files_per_output = static_cast<unsigned int>(
      whole_number(prm.get("VTU files per output"), "Output/VTU files per output", 0, 1000000,
                   "0 = one file per MPI rank, K = at most K files per output time"));
    keep_checkpoints =
      static_cast<unsigned int>(whole_number(prm.get("Keep checkpoints"), "Output/Keep checkpoints", 1, 1000,
                                             "1 = only the latest checkpoint, N = the N most recent"));
    parse_history_interval(prm.get("History interval"), history_steps, history_seconds);
    {
      const std::string p = prm.get("Profile direction");
      profile_direction   = p == "auto" ? -1 : (p == "x" ? 0 : (p == "y" ? 1 : 2));
    }
    {
      const std::string c = prm.get("Cross-section direction");
      section_direction   = c == "none" ? -1 : (c == "x" ? 0 : (c == "y" ? 1 : 2));
    }
    progress_interval = prm.get_double("Progress interval");
    verbose           = prm.get_bool("Verbose");
    prm.leave_subsection();
  }

  void OutputParameters::check(const Scene &s)
  {
    const unsigned int dim = s.dimension;
    if (s.output_directory.empty())
      fail(s, "Output/Directory", "must not be empty");
    if (s.output_directory.size() > 1024)
      fail(s, "Output/Directory",
           "a path of " + std::to_string(s.output_directory.size()) + " characters; allowed up to 1024");
    for (const auto &part : std::filesystem::path(s.output_directory))
      if (part.string().size() > 255)
        fail(s, "Output/Directory",
             "a folder name of " + std::to_string(part.string().size()) +
               " characters; file systems allow up to 255");
    {
      // a file name, not a path: no '/', no leading '.', at most 100 characters of
      // letters, digits, '_', '-', '.'
      const std::string &b  = s.base_name;
      bool               ok = !b.empty() && b.size() <= 100 && b[0] != '.';
      for (const char ch : b)
        ok = ok && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.');
      if (!ok)
        fail(s, "Output/Base name",
             "'" + b +
               "' must be 1..100 characters of letters, digits, '_', "
               "'-' or '.', not starting with '.' (a file name, not a path: "
               "use 'Output/Directory' for folders)");
      // the output folder, or the nearest folder above it that exists, must be writable
      std::error_code       ec;
      std::filesystem::path dir = std::filesystem::absolute(s.output_directory, ec);
      while (!dir.empty() && !std::filesystem::exists(dir, ec) && dir.has_parent_path() &&
             dir.parent_path() != dir)
        dir = dir.parent_path();
      if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
        fail(s, "Output/Directory", "'" + dir.string() + "' exists and is not a folder");
      if (std::filesystem::exists(dir, ec) && ::access(dir.c_str(), W_OK) != 0)
        fail(s, "Output/Directory", "'" + dir.string() + "' is not writable");
      // access() trusts permissions: a folder (e.g. under /proc) may still refuse new entries
      if (std::filesystem::is_directory(dir, ec))
        {
          std::string probe = (dir / ".granhydro_probe_XXXXXX").string();
          if (::mkdtemp(&probe[0]) == nullptr)
            fail(s, "Output/Directory",
                 "cannot create folders in '" + dir.string() + "': " + std::strerror(errno));
          ::rmdir(probe.c_str());
        }
    }
    if (s.section_direction >= 0 && dim != 3)
      fail(s, "Output/Cross-section direction", "cross sections need a 3D scene");
    if (s.profile_direction >= static_cast<int>(dim))
      fail(s, "Output/Profile direction",
           "names a direction the " + std::to_string(dim) + "D scene does not resolve");
  }
} // namespace granhydro::scene
