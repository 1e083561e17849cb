#pragma once
/**
 * @file mesh_file.h
 * Coarse meshes read from files (deal.II GridIn: gmsh .msh, ucd .inp).
 *
 * The finite-volume operators work on a uniform Cartesian lattice, so a mesh
 * file is accepted only if its coarse cells are congruent axis-aligned boxes
 * whose vertices lie on one lattice (a "lattice subset"): the cells fill some
 * of the points of the lattice spanned by the mesh's bounding box, the other
 * points are solid. Boundary ids 0 .. 2 dim - 1 select the scene's
 * 'Boundary x-' .. 'Boundary z+' entries (deal.II's colorize convention, so a
 * box read from a file behaves like the generated box); the geometric
 * direction of a boundary face comes from the mesh, not from its id.
 */
#include <deal.II/grid/tria.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace granhydro::mesh
{
  /// what the scene validation and the patch need to know about a coarse mesh
  struct MeshFileInfo
  {
    std::array<double, 3>       lower{{0, 0, 0}}, upper{{1, 1, 1}};
    std::array<double, 3>       cell_size{{1, 1, 1}}; ///< of the coarse cells
    std::array<unsigned int, 3> lattice{{1, 1, 1}};   ///< coarse cells per direction of the bounding box
    unsigned long long          n_cells = 0;          ///< coarse cells in the file
    /// (boundary id, geometric normal direction) of every boundary face
    std::set<std::pair<unsigned int, unsigned int>> id_direction;
    /// centres of the coarse cells (every k-th cell beyond 262 144), where the scene
    /// checks the initial state
    std::vector<std::array<double, 3>> centres;
  };

  /// the largest mesh file read (every rank reads the whole file into memory, its lines
  /// and a serial triangulation of its cells): about 3 million coarse hexahedra in gmsh 2.2
  constexpr std::uintmax_t max_mesh_file_bytes = std::uintmax_t(256) << 20;

  /// read a gmsh (.msh) or ucd (.inp) file into an empty serial triangulation;
  /// throws MeshFileError with a message for a person
  template <int dim>
  void read_mesh_file(const std::string &filename, dealii::Triangulation<dim> &tria);

  /// check that the (coarse) cells are congruent axis-aligned boxes on one lattice, the
  /// mesh is conforming and the boundary ids lie in 0 .. 2 dim - 1; throws MeshFileError
  template <int dim>
  MeshFileInfo inspect_mesh(const dealii::Triangulation<dim> &tria);

  /// read_mesh_file + inspect_mesh for a run-time dimension (scene validation)
  MeshFileInfo check_mesh_file(const std::string &filename, const unsigned int dim);

  /// geometric normal direction (0, 1, 2) and side (0 lower, 1 upper) of face f of an
  /// axis-aligned box cell: from the face centre relative to the cell centre, because cells
  /// read from a file need not have deal.II's standard orientation
  template <class CellIterator>
  std::pair<unsigned int, unsigned int> face_direction(const CellIterator &cell, const unsigned int f)
  {
    const auto   dx = cell->face(f)->center() - cell->center();
    unsigned int d  = 0;
    for (unsigned int k = 1; k < CellIterator::AccessorType::dimension; ++k)
      if (std::abs(dx[k]) > std::abs(dx[d]))
        d = k;
    return {d, dx[d] > 0 ? 1u : 0u};
  }
} // namespace granhydro::mesh
