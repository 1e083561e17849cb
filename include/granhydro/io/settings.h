#pragma once
/**
 * @file settings.h
 * What the output needs to know: where to write, what to write, the unit system, and
 * the container motion (velocities are written in the lab frame). scene/ fills it
 * (Scene::output_settings()); io never sees the scene.
 */
#include <granhydro/base/units.h>
#include <granhydro/boundary/moving_frame.h>

#include <string>

namespace granhydro::io
{
  /// a file of a run: <directory>/<base name><suffix> (".pvd", ".checkpoint",
  /// "_profiles.csv", "_summary.csv", ...), so that two runs with different base names can
  /// share one directory. The one place the name is formed (the output, the run's files,
  /// the scene's checks)
  inline std::string run_file(const std::string &directory, const std::string &base_name,
                              const std::string &suffix)
  {
    return directory + "/" + base_name + suffix;
  }

  struct OutputSettings
  {
    std::string directory = "output";
    std::string base_name = "solution";
    /// directory/base_name + suffix
    std::string file(const std::string &suffix) const { return run_file(directory, base_name, suffix); }
    bool        write_vtu = true, write_profiles = true, write_checkpoint = true;
    /// VTU files per output time: 0 = one per rank, else at most this many (ranks are
    /// grouped round robin: rank r writes into file r mod K)
    unsigned int vtu_files         = 16;
    int          profile_direction = -1; ///< -1: the last dimension
    int          section_direction = -1; ///< 3D: average along it into a 2D map; -1: off
    Units        units;
    /// the vibrated container's motion s(t) = A sin(w t) e_s [m], [rad/s] (lab-frame
    /// velocities add its velocity)
    boundary::MovingFrame container_motion;
  };
} // namespace granhydro::io
