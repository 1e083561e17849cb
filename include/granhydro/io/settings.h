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
  struct OutputSettings
  {
    std::string directory = "output";
    std::string base_name = "solution";
    /// directory/base_name + suffix
    std::string file(const std::string &suffix) const { return directory + "/" + base_name + suffix; }
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
