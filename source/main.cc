/**
 * granhydro: granular hydrodynamics in 1, 2 and 3 dimensions.
 *   granhydro [scene.prm]        run a scene (the embedded default without a file)
 *   granhydro --print-parameters write a documented default scene to stdout
 *   granhydro --check scene.prm  validate a scene without running it
 * Exit codes: 0 success, 2 bad input (scene or command line), 3 run failure.
 */
#include <granhydro/driver/simulation.h>
#include <granhydro/mesh/mesh_file.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/mpi.h>

#include <unistd.h>

#include <cmath>
#include <iostream>
#include <sstream>

namespace
{
  /// Refuses, before any allocation, a scene whose state and operators cannot fit in the
  /// memory of the ranks it runs on (each rank assumed to have this machine's memory).
  /// Per cell, measured on this code (peak resident set over cells, large meshes):
  /// convection alone ~2.3 KiB, with the diffusion step ~6.3 KiB (block ILU, one stage),
  /// ~13 KiB with Gauss-Legendre's two coupled stages; adaptive meshes add the replicated
  /// lattice map, 9 bytes per finest lattice point on every rank.
  void check_memory(const granhydro::Scene &s, const unsigned int ranks)
  {
    double cells = 1, finest = 1;
    if (!s.mesh_file.empty())
      {
        cells = granhydro::check_mesh_file(s.mesh_file, s.dimension).n_cells;
        for (unsigned int r = 0; r < s.mesh_refinements; ++r)
          cells *= 1u << s.dimension;
      }
    else
      for (unsigned int d = 0; d < s.dimension; ++d)
        {
          cells *= s.cells[d];
          finest *= double(s.cells[d]) * double(1u << s.max_level);
        }
    const double per_cell = !s.diffusion_active()                ? 2.3 * 1024 :
                            s.integrator == "gauss-legendre" ? 13.1 * 1024 :
                                                                  6.3 * 1024;
    const double need     = cells * per_cell + (s.max_level > 0 ? 9 * finest * ranks : 0);
    const double have     = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) * ranks;
    if (need > have)
      {
        std::ostringstream os;
        os.precision(3);
        os << "in " << s.source << ": parameter '"
           << (!s.mesh_file.empty() ? "Domain/Mesh refinements" :
               s.max_level > 0      ? "Adaptivity/Maximum level" :
                                      "Domain/Cells")
           << "': the run would need about " << need / 1073741824. << " GiB (" << cells
           << " cells at ~" << per_cell / 1024 << " KiB each), more than the "
           << have / 1073741824. << " GiB of " << ranks
           << " rank(s) with this machine's memory; use fewer cells or more ranks";
        throw granhydro::SceneError(os.str());
      }
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm comm  = MPI_COMM_WORLD;
  const bool     root  = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  std::string    file;
  bool           check_only = false;
  for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h")
        {
          if (root)
            std::cout << "usage: granhydro [scene.prm]\n"
                         "       granhydro --print-parameters   (documented default scene)\n"
                         "       granhydro --check scene.prm   (validate the scene, run nothing)\n"
                         "Without a scene file the embedded default scene runs.\n";
          return 0;
        }
      if (a == "--print-parameters")
        {
          if (root)
            {
              dealii::ParameterHandler prm;
              granhydro::declare_scene_parameters(prm);
              prm.parse_input_from_string(granhydro::default_scene_text());
              prm.print_parameters(std::cout, dealii::ParameterHandler::PRM);
            }
          return 0;
        }
      if (a == "--check")
        {
          check_only = true;
          continue;
        }
      if (!a.empty() && a[0] == '-')
        {
          if (root)
            std::cerr << "granhydro: error: unknown option '" << a
                      << "' (allowed: --help, --print-parameters, --check, a scene file)\n";
          return 2;
        }
      if (!file.empty())
        {
          if (root)
            std::cerr << "granhydro: error: more than one scene file given ('" << file << "', '"
                      << a << "')\n";
          return 2;
        }
      file = a;
    }
  try
    {
      const granhydro::Scene scene = granhydro::read_scene(file);
      check_memory(scene, dealii::Utilities::MPI::n_mpi_processes(comm));
      if (check_only)
        {
          if (root)
            std::cout << "granhydro: scene " << scene.source << " is valid\n";
          return 0;
        }
      return granhydro::run_scene(scene, comm, std::cout);
    }
  catch (const granhydro::SceneError &e)
    {
      if (root)
        std::cerr << "granhydro: error: " << e.what() << std::endl;
      return 2;
    }
  catch (const granhydro::io::OutputError &e)
    {
      if (root)
        std::cerr << "granhydro: run stopped: " << e.what() << std::endl;
      return 3;
    }
  catch (const granhydro::RunError &e)
    {
      if (root)
        std::cerr << "granhydro: run stopped: " << e.what() << std::endl;
      return 3;
    }
  catch (const std::exception &e)
    {
      std::cerr << "granhydro: internal error: " << e.what() << std::endl;
      MPI_Abort(comm, 1);
      return 1;
    }
}
