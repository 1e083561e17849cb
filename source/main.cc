/**
 * granhydro: granular hydrodynamics in 1, 2 and 3 dimensions.
 *   granhydro [scene.prm]        run a scene (the embedded default without a file)
 *   granhydro --print-parameters write a documented default scene to stdout
 *   granhydro --check scene.prm  validate a scene without running it
 * Exit codes: 0 success, 2 bad input (scene or command line), 3 run failure.
 */
#include <granhydro/driver/simulation.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/mpi.h>

#include <iostream>

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
