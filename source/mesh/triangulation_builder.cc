#include "triangulation_builder.h"

#include <granhydro/mesh/mesh_file.h>

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

namespace granhydro::mesh
{
  using namespace dealii;

  template <int dim>
  std::unique_ptr<parallel::TriangulationBase<dim>> make_triangulation(const MPI_Comm comm)
  {
    if constexpr (dim == 1)
      return std::make_unique<parallel::shared::Triangulation<1>>(comm);
    else
      return std::make_unique<parallel::distributed::Triangulation<dim>>(comm);
  }

  template <int dim>
  LatticeGeometry make_box_mesh(parallel::TriangulationBase<dim> &tria, const MeshSettings &settings)
  {
    LatticeGeometry geometry;
    // coarse box refined globally L times (p4est)
    for (unsigned int d = 0; d < 3; ++d)
      {
        geometry.cells[d]     = d < dim ? settings.cells[d] : 1;
        geometry.lower[d]     = d < dim ? settings.lower[d] : 0;
        geometry.cell_size[d] = d < dim ? (settings.upper[d] - settings.lower[d]) / geometry.cells[d] : 1;
        geometry.periodic[d] =
          d < dim ? settings.walls[2 * d].type == boundary::BoundaryType::periodic : true;
      }
    unsigned int L = 0;
    if (dim > 1)
      while (L < 8)
        {
          bool ok = true;
          for (unsigned int d = 0; d < dim; ++d)
            ok = ok && (geometry.cells[d] % (1u << (L + 1)) == 0);
          if (!ok)
            break;
          ++L;
        }
    std::vector<unsigned int> rep(dim);
    Point<dim>                p1, p2;
    for (unsigned int d = 0; d < dim; ++d)
      {
        rep[d] = geometry.cells[d] >> L;
        p1[d]  = settings.lower[d];
        p2[d]  = settings.upper[d];
      }
    GridGenerator::subdivided_hyper_rectangle(tria, rep, p1, p2, /*colorize=*/true);
    if constexpr (dim > 1)
      {
        auto &ptria = dynamic_cast<parallel::distributed::Triangulation<dim> &>(tria);
        std::vector<
          GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<dim>::cell_iterator>>
          pairs;
        for (unsigned int d = 0; d < dim; ++d)
          if (geometry.periodic[d])
            GridTools::collect_periodic_faces(ptria, 2 * d, 2 * d + 1, d, pairs);
        if (!pairs.empty())
          ptria.add_periodicity(pairs);
      }
    tria.refine_global(L);
    geometry.base_level = L;
    return geometry;
  }

  template <int dim>
  LatticeGeometry make_file_mesh(parallel::TriangulationBase<dim> &tria, const MeshSettings &settings)
  {
    LatticeGeometry geometry;
    // the lattice is the bounding box at the fine cell size
    if constexpr (dim == 1)
      {
        (void)settings;
        AssertThrow(false, ExcMessage("mesh files need 2 or 3 dimensions"));
      }
    else
      {
        Triangulation<dim> coarse;
        read_mesh_file(settings.mesh_file, coarse);
        const MeshFileInfo info = inspect_mesh(coarse);
        for (unsigned int d = 0; d < 3; ++d)
          {
            geometry.cells[d] = d < dim ? info.lattice[d] << settings.mesh_refinements : 1;
            geometry.lower[d] = d < dim ? info.lower[d] : 0;
            // the same expression as for the box: a box read from a file gets bitwise
            // the same cell size and centres as the generated one
            geometry.cell_size[d] = d < dim ? (info.upper[d] - info.lower[d]) / geometry.cells[d] : 1;
            geometry.periodic[d]  = d >= dim;
          }
        tria.copy_triangulation(coarse);
        tria.refine_global(settings.mesh_refinements);
        geometry.base_level = settings.mesh_refinements;
      }
    return geometry;
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                  \
  template std::unique_ptr<parallel::TriangulationBase<d>> make_triangulation(const MPI_Comm);    \
  template LatticeGeometry make_box_mesh(parallel::TriangulationBase<d> &, const MeshSettings &); \
  template LatticeGeometry make_file_mesh(parallel::TriangulationBase<d> &, const MeshSettings &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::mesh
