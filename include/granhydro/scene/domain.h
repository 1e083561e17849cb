#pragma once
/**
 * @file domain.h
 * The 'Domain' subsection of a scene: the box or the mesh file, and what happens at
 * each of its sides (boundary kind, wall velocity, wall restitution).
 */
#include <granhydro/boundary/boundary_conditions.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <string>

namespace granhydro::mesh
{
  struct MeshFileInfo;
}

namespace granhydro::scene
{
  struct Scene;

  struct DomainParameters
  {
    /// coarse mesh file (gmsh .msh or ucd .inp; empty: the box Lower/Upper corner, Cells),
    /// a relative name resolved against the scene file's directory (mesh/mesh_file.h)
    std::string                 mesh_file;
    unsigned int                mesh_refinements = 0; ///< global refinements of the file's coarse mesh
    std::array<double, 3>       lower{{0, 0, 0}}, upper{{0.1, 0.1, 0.1}};
    std::array<unsigned int, 3> cells{{100, 100, 1}};
    /// boundary[2*d] lower side, boundary[2*d+1] upper side of direction d; with a mesh
    /// file, boundary[i] applies to the faces with boundary id i (whatever their direction)
    std::array<boundary::BoundaryType, 6> boundary{
      {boundary::BoundaryType::slip_wall, boundary::BoundaryType::slip_wall,
       boundary::BoundaryType::slip_wall, boundary::BoundaryType::slip_wall,
       boundary::BoundaryType::slip_wall, boundary::BoundaryType::slip_wall}};
    /// tangential velocity of each wall [m/s] (no-slip walls), 3 components
    std::array<std::array<double, 3>, 6> wall_velocity{};
    /// grain-wall restitution eps_w of each wall (1 = elastic/adiabatic, doc/physics.md 5.2)
    std::array<double, 6> wall_restitution{{1, 1, 1, 1, 1, 1}};

    static void declare_parameters(dealii::ParameterHandler &prm);
    /// the lists hold `dim` values or 3; a relative mesh file name is resolved against the
    /// directory of `source_name` (the scene file)
    void parse_parameters(dealii::ParameterHandler &prm, unsigned int dim, const std::string &source_name);

    // Checks, in the order validate() runs them (the first failure is the message).
    // Some limits depend on other subsections, hence the whole scene.

    /// a mesh file: readable, 2D/3D, no periodic sides, tangential wall velocities, cell
    /// count; what the file holds (empty without a mesh file)
    static mesh::MeshFileInfo check_mesh(const Scene &s);
    /// a box: corners, cell size, periodic pairs, cells enough for the reconstruction
    static void check_box(const Scene &s);
    /// the sides: wall velocities and restitutions only where walls can have them
    static void check_walls(const Scene &s);
    /// at most 5e7 cells in a box
    static void check_cell_count(const Scene &s);
  };
} // namespace granhydro::scene
