#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/mesh/mesh_file.h>

#include "triangulation_builder.h"

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

namespace granhydro
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
  void CartesianPatch<dim>::make_box_mesh(const MeshSettings &settings)
  {
    // coarse box refined globally L times (p4est)
    for (unsigned int d = 0; d < 3; ++d)
      {
        N_[d]        = d < dim ? settings.cells[d] : 1;
        lo_[d]       = d < dim ? settings.lower[d] : 0;
        h_[d]        = d < dim ? (settings.upper[d] - settings.lower[d]) / N_[d] : 1;
        periodic_[d] = d < dim ? settings.boundary[2 * d] == BoundaryType::periodic : true;
      }
    unsigned int L = 0;
    if (dim > 1)
      while (L < 8)
        {
          bool ok = true;
          for (unsigned int d = 0; d < dim; ++d)
            ok = ok && (N_[d] % (1u << (L + 1)) == 0);
          if (!ok)
            break;
          ++L;
        }
    std::vector<unsigned int> rep(dim);
    Point<dim>                p1, p2;
    for (unsigned int d = 0; d < dim; ++d)
      {
        rep[d] = N_[d] >> L;
        p1[d]  = settings.lower[d];
        p2[d]  = settings.upper[d];
      }
    GridGenerator::subdivided_hyper_rectangle(*tria, rep, p1, p2, /*colorize=*/true);
    if constexpr (dim > 1)
      {
        auto &ptria = dynamic_cast<parallel::distributed::Triangulation<dim> &>(*tria);
        std::vector<GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<dim>::cell_iterator>> pairs;
        for (unsigned int d = 0; d < dim; ++d)
          if (periodic_[d])
            GridTools::collect_periodic_faces(ptria, 2 * d, 2 * d + 1, d, pairs);
        if (!pairs.empty())
          ptria.add_periodicity(pairs);
      }
    tria->refine_global(L);
    base_tria_level_ = L;
  }

  template <int dim>
  void CartesianPatch<dim>::make_file_mesh(const MeshSettings &settings)
  {
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
            N_[d]  = d < dim ? info.lattice[d] << settings.mesh_refinements : 1;
            lo_[d] = d < dim ? info.lower[d] : 0;
            // the same expression as for the box: a box read from a file gets bitwise
            // the same cell size and centres as the generated one
            h_[d]        = d < dim ? (info.upper[d] - info.lower[d]) / N_[d] : 1;
            periodic_[d] = d >= dim;
          }
        tria->copy_triangulation(coarse);
        tria->refine_global(settings.mesh_refinements);
        base_tria_level_ = settings.mesh_refinements;
      }
  }

#define GRANHYDRO_INSTANTIATE(d)                                                                   \
  template std::unique_ptr<parallel::TriangulationBase<d>> make_triangulation(const MPI_Comm);     \
  template void CartesianPatch<d>::make_box_mesh(const MeshSettings &);                            \
  template void CartesianPatch<d>::make_file_mesh(const MeshSettings &);
  GRANHYDRO_INSTANTIATE(1)
  GRANHYDRO_INSTANTIATE(2)
  GRANHYDRO_INSTANTIATE(3)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro
