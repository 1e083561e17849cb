#pragma once
/**
 * @file triangulation_builder.h
 * The triangulation of a CartesianPatch (an internal part of the patch: source/mesh,
 * not installed): parallel::distributed (p4est) in 2 and 3 dimensions, parallel::shared
 * in 1, and the box or mesh-file mesh in it with the geometry of its lattice
 * (source/mesh/triangulation_builder.cc).
 */
#include <granhydro/mesh/patch_tables.h>
#include <granhydro/mesh/settings.h>

#include <deal.II/distributed/tria_base.h>

#include <memory>

namespace granhydro::mesh
{
  template <int dim>
  std::unique_ptr<dealii::parallel::TriangulationBase<dim>> make_triangulation(const MPI_Comm comm);

  /// a box: the coarse box refined globally as often as the cell numbers allow (p4est's
  /// coarse cells; periodic faces matched), up to the scene's Domain/Cells; its lattice
  template <int dim>
  LatticeGeometry make_box_mesh(dealii::parallel::TriangulationBase<dim> &tria, const MeshSettings &settings);
  /// a mesh file's coarse mesh refined settings.mesh_refinements times; the lattice is its
  /// bounding box at the fine cell size (2 and 3 dimensions)
  template <int dim>
  LatticeGeometry make_file_mesh(dealii::parallel::TriangulationBase<dim> &tria,
                                 const MeshSettings                       &settings);
} // namespace granhydro::mesh
