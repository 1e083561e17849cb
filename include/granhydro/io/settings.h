#pragma once
/**
 * @file settings.h
 * What the output needs to know: where to write, what to write, the unit system, and
 * the container motion (velocities are written in the lab frame). scene/ fills it
 * (Scene::output_settings()); io never sees the scene.
 */
#include <granhydro/base/units.h>

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
    unsigned int vtu_files = 16;
    int         profile_direction = -1; ///< -1: the last dimension
    int         section_direction = -1; ///< 3D: average along it into a 2D map; -1: off
    Units       units;
    /// container motion s(t) = A sin(2 pi f t) e_direction (lab-frame velocities)
    double       vibration_amplitude = 0, vibration_frequency = 0; // [m], [Hz]
    unsigned int vibration_direction = 1;
  };
} // namespace granhydro::io
