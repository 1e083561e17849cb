#pragma once
/**
 * @file output.h
 * The 'Output' subsection of a scene: where and what a run writes.
 */
#include <deal.II/base/parameter_handler.h>

#include <string>

namespace granhydro
{
  struct Scene;

  struct OutputParameters
  {
    std::string  output_directory = "output";
    std::string  base_name        = "solution";
    /// a file of this run in the output directory: <Directory>/<Base name><suffix>
    /// (".pvd", ".checkpoint", "_profiles.csv", "_cross_section.csv", "_summary.csv"), so
    /// that two runs with different base names can share one directory
    std::string output_file(const std::string &suffix) const
    {
      return output_directory + "/" + base_name + suffix;
    }
    double       output_interval  = 0;
    bool         write_vtu        = true;
    bool         write_profiles   = true;
    bool         write_checkpoint = true;
    bool         write_summary    = true;
    int          profile_direction = -1; // -1: last dimension
    int          section_direction = -1; // 3D: average along this direction into a 2D map, -1: off
    /// VTU files per output time: 0 = one per rank; K > 0 = one per rank up to K ranks,
    /// beyond that K files, each holding the pieces of every K-th rank (MPI-IO)
    unsigned int vtu_files_per_output = 16;
    double       progress_interval = 5;  // wall seconds
    bool         verbose           = true;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void parse_parameters(dealii::ParameterHandler &prm);
    /// a usable, writable directory, a plain base name, directions the scene resolves
    static void check(const Scene &s);
  };
} // namespace granhydro
