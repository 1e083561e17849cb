#pragma once
/**
 * @file output.h
 * Output for people: VTU/PVTU per output time plus a PVD series for ParaView
 * (SI fields under plain names, their units as VTK metadata; at most 'Output/VTU files
 * per output' .vtu files per output time however many ranks), <base>_profiles.csv with
 * averages over the directions other than the profile direction and (3D)
 * <base>_cross_section.csv, whose columns have the VTU fields' names (the units:
 * doc/user-guide.md, "Profiles and cross-sections"). Velocities are written in
 * the lab frame: for a vibrated container the frame velocity ds/dt is added.
 */
#include <granhydro/base/errors.h>
#include <granhydro/io/settings.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/ideal_gas.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::io
{
  /// a result file could not be written (base/errors.h): the run stops with exit code 3
  using granhydro::OutputError;

  /// the n_groups argument of deal.II's write_vtu_with_pvtu_record for 'Output/VTU files
  /// per output' = files_per_output on n_ranks ranks: 0 (one file per rank, the plain
  /// write) while the ranks do not exceed the bound, else the bound: file k then holds
  /// the pieces of ranks k, k + K, k + 2K, ... (written collectively with MPI-IO)
  unsigned int vtu_groups(const unsigned int files_per_output, const unsigned int n_ranks);

  template <int dim, class Description>
  class Output
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;
    Output(const OutputSettings &settings, const mesh::CartesianPatch<dim> &patch, const Description &desc);

    /// write VTU/PVTU/PVD and/or a block of profiles.csv, as the scene asks
    void write(const Vector &U, const double time_si, const unsigned int step);

    /// number of output times written so far (numbering of the VTU files)
    unsigned int count() const { return counter; }

    /// continue a run restarted from a checkpoint taken after `outputs` output times at
    /// time_si: VTU numbering continues, the PVD keeps its records up to time_si, the CSV
    /// files are appended to
    void resume(const unsigned int outputs, const double time_si);

  private:
    /// velocity of the frame the equations are solved in (vibrated container) [m/s]
    std::array<double, 3> frame_velocity(const double time_si) const;
    void                  write_vtu(const Vector &U, const double time_si, const unsigned int step);
    void                  write_profiles(const Vector &U, const double time_si);
    void                  write_cross_section(const Vector &U, const double time_si);

    const OutputSettings                        settings;
    const mesh::CartesianPatch<dim>            &patch;
    const Description                          &desc;
    Units                                       units;
    unsigned int                                counter = 0;
    std::vector<std::pair<double, std::string>> pvd_records;
    bool                                        profiles_started = false, section_started = false;
  };
} // namespace granhydro::io
