#pragma once
/**
 * @file triangulation_builder.h
 * The triangulation of a CartesianPatch (an internal part of the patch: source/mesh,
 * not installed): parallel::distributed (p4est) in 2 and 3 dimensions, parallel::shared in 1. The box and mesh-file meshes themselves are built
 * by the patch's private make_box_mesh() and make_file_mesh()
 * (source/mesh/triangulation_builder.cc).
 */
#include <deal.II/distributed/tria_base.h>

#include <memory>

namespace granhydro
{
  template <int dim>
  std::unique_ptr<dealii::parallel::TriangulationBase<dim>> make_triangulation(const MPI_Comm comm);
} // namespace granhydro
