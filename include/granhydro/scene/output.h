#pragma once
/**
 * @file output.h
 * The 'Output' subsection of a scene: where and what a run writes.
 */
#include <granhydro/io/settings.h>

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace granhydro::scene
{
  struct Scene;

  struct OutputParameters
  {
    std::string output_directory = "output";
    std::string base_name        = "solution";
    /// a file of this run in the output directory: <Directory>/<Base name><suffix> (io::run_file())
    std::string output_file(const std::string &suffix) const
    {
      return io::run_file(output_directory, base_name, suffix);
    }
    double output_interval   = 0;
    bool   write_vtu         = true;
    bool   write_profiles    = true;
    bool   write_checkpoint  = true;
    bool   write_summary     = true;
    int    profile_direction = -1; // -1: last dimension
    int    section_direction = -1; // 3D: average along this direction into a 2D map, -1: off
    /// VTU files per output time: 0 = one per rank; K > 0 = one per rank up to K ranks,
    /// beyond that K files, each holding the pieces of every K-th rank (MPI-IO)
    unsigned int vtu_files_per_output = 16;
    /// Output/History interval: a row of <base>_history.csv after every step whose number
    /// is a multiple of history_steps, or after the first step at or past each multiple of
    /// history_seconds [s] (simulated time); both 0: no history file
    unsigned int history_steps   = 10;
    double       history_seconds = 0;
    /// Output/Keep checkpoints: 1 = only <base>.checkpoint (and its .bak); N > 1 = also the
    /// N most recent as <base>_checkpoint_<step>.checkpoint
    unsigned int keep_checkpoints  = 1;
    double       progress_interval = 5; // wall seconds
    bool         verbose           = true;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// Output/History interval: 'N steps', 'T s', 'off' or 0 into steps and seconds
    /// (both 0: off); SceneError naming the parameter and what is allowed
    static void parse_history_interval(const std::string &text, unsigned int &steps, double &seconds);
    /// a usable, writable directory, a plain base name, directions the scene resolves
    static void check(const Scene &s);
  };
} // namespace granhydro::scene
