/**
 * granhydro: granular hydrodynamics in 1, 2 and 3 dimensions.
 *   granhydro [-p "Section/Name=value" ...] [scene.prm]   run a scene (the embedded
 *                                default without a file), with parameters overridden
 *   granhydro --print-parameters [-p ...] [scene.prm]   write the scene (the default
 *                                without a file) expanded, every parameter documented
 *   granhydro --resume [-p ...] scene.prm   continue the scene from its own latest checkpoint
 *                                (<Directory>/<Base name>.checkpoint) if there is one, else
 *                                start it from its initial state
 *   granhydro --check scene.prm  validate a scene without running it
 *   granhydro --checkpoint-info FILE   verify a checkpoint and print what it holds
 *   granhydro --version
 * Exit codes: 0 success, 2 bad input (scene, checkpoint or command line), 3 run failure
 * (including a failed output or checkpoint write), 130 / 143 stopped by SIGINT / SIGTERM
 * after writing the final output, checkpoint and summary.
 */
#include <granhydro/base/version.h>
#include <granhydro/driver/run_records.h>
#include <granhydro/driver/simulation.h>
#include <granhydro/io/checkpoint.h>
#include <granhydro/mesh/mesh_file.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/config.h>
#include <deal.II/base/mpi.h>

#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

namespace
{
  /// bytes this node can give the run: MemAvailable of /proc/meminfo (what the kernel can
  /// hand out without swapping), else the physical memory
  double available_memory()
  {
    std::ifstream in("/proc/meminfo");
    for (std::string key; in >> key;)
      {
        double kib = 0;
        if (key == "MemAvailable:" && in >> kib && kib > 0)
          return kib * 1024.;
        in.ignore(1 << 10, '\n');
      }
    return double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  }

  /// Refuses, before any allocation, a scene whose state and operators cannot fit in the
  /// memory of the ranks it runs on. Per cell, measured on this code (peak resident set
  /// over cells, large meshes; the implicit step's block matrix and its ILU included):
  /// convection alone ~2.3 KiB, with the diffusion step ~6.3 KiB (block ILU, one stage),
  /// ~13 KiB with Gauss-Legendre's two coupled stages. Counted: the most cells the run can
  /// have (an adaptive mesh refined everywhere to 'Adaptivity/Maximum level', a mesh file
  /// after its refinements), each rank's share plus its halo (the ghost layers around a
  /// compact part of that share), and every rank on this node (MPI_COMM_TYPE_SHARED)
  /// against this node's available memory. (No rank holds a map of the whole fine lattice:
  /// each knows the leaves near its own, see source/mesh/lattice.h.)
  void check_memory(const granhydro::scene::Scene &s, const MPI_Comm comm)
  {
    double cells = 1;
    if (!s.mesh_file.empty())
      {
        cells = granhydro::mesh::check_mesh_file(s.mesh_file, s.dimension).n_cells;
        for (unsigned int r = 0; r < s.mesh_refinements; ++r)
          cells *= 1u << s.dimension;
      }
    else
      for (unsigned int d = 0; d < s.dimension; ++d)
        {
          cells *= s.cells[d];
        }
    const double coarse = cells;
    cells *= std::ldexp(1., int(s.dimension * s.max_level));
    const double ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    const double share = std::ceil(cells / ranks);
    // the halo: ghost width (WENO5 3, MUSCL/WENO3 2, first order 1) plus the gradient's layer
    const double layers = s.reconstruction == granhydro::convection::ReconstructionType::weno5       ? 4 :
                          s.reconstruction == granhydro::convection::ReconstructionType::first_order ? 2 :
                                                                                                       3;
    const double halo   = ranks > 1 ?
                            std::min(cells - share, 2. * s.dimension * layers *
                                                      std::pow(share, (s.dimension - 1.) / s.dimension)) :
                            0.;
    using granhydro::diffusion::ImplicitMethod;
    const double per_cell = !s.diffusion_active()                          ? 2.3 * 1024 :
                            s.integrator == ImplicitMethod::gauss_legendre ? 13.1 * 1024 :
                                                                             6.3 * 1024;
    const double per_rank = 64. * 1048576.; // the process itself (MPI, deal.II, p4est)
    MPI_Comm     node;
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    const double on_node = dealii::Utilities::MPI::n_mpi_processes(node);
    MPI_Comm_free(&node);
    const double need = on_node * ((share + halo) * per_cell + per_rank);
    const double have = available_memory();
    // one answer on every rank (the nodes' available memory differs)
    if (dealii::Utilities::MPI::max(need > have ? 1 : 0, comm) == 0)
      return;
    // the numbers of the node that lacks the most (rank 0's if all do)
    std::ostringstream os;
    os.precision(3);
    os << "in " << s.source << ": parameter '"
       << (!s.mesh_file.empty() ? "Domain/Mesh refinements" :
           s.max_level > 0      ? "Adaptivity/Maximum level" :
                                  "Domain/Cells")
       << "': the run would need about " << need / 1073741824. << " GiB on this node, more than "
       << "its " << have / 1073741824. << " GiB of available memory: up to " << cells << " cells";
    if (s.max_level > 0)
      os << " (" << coarse << " cells of 'Domain/Cells' refined " << s.max_level
         << " levels everywhere, which 'Adaptivity/Maximum level' allows)";
    os << " at ~" << per_cell / 1024 << " KiB each"
       << (s.diffusion_active() ? " (with the implicit step's matrix)" : "") << ", " << share << " per rank";
    if (halo > 0)
      os << " plus about " << std::round(halo) << " halo cells";
    os << ", " << on_node << " rank(s) on this node; use fewer cells"
       << (s.max_level > 0 ? " or a lower 'Adaptivity/Maximum level'" : "") << ", or more nodes";
    throw granhydro::SceneError(os.str());
  }

  /// a summary that still says "status,running" after the run stopped with exit 3 (a write
  /// failed before the final summary) gets `status`; rewritten in place: it only shrinks,
  /// so a full disk does not stop it
  void settle_running_summary(const std::string &file, const std::string &status)
  {
    std::FILE *f = std::fopen(file.c_str(), "r+");
    if (!f)
      return;
    std::string text;
    char        buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;)
      text.append(buf, n);
    // the line "status,running" (after the header line "key,value")
    const std::string running = "\nstatus,running\n";
    const auto        at      = text.find(running);
    if (at != std::string::npos && status.size() + 9 <= running.size())
      {
        text = text.substr(0, at) + "\nstatus," + status + "\n" + text.substr(at + running.size());
        std::rewind(f);
        if (std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0)
          if (::ftruncate(fileno(f), off_t(text.size())) != 0)
            std::rewind(f); // the old tail stays after the new text: still one status line
      }
    std::fclose(f);
  }

  void print_usage()
  {
    std::cout << "usage: granhydro [-p \"Section/Name=value\" ...] [scene.prm]\n"
                 "       granhydro --print-parameters [-p ...] [scene.prm]   (the scene expanded,\n"
                 "                 every parameter documented; without a file the default scene)\n"
                 "       granhydro --resume [-p ...] scene.prm   (continue the scene from its latest\n"
                 "                 checkpoint <Directory>/<Base name>.checkpoint if it exists, to the\n"
                 "                 scene's end time; else start it from its initial state)\n"
                 "       granhydro --check [-p ...] scene.prm   (validate the scene, run nothing)\n"
                 "       granhydro --checkpoint-info FILE   (verify a checkpoint, print its contents)\n"
                 "       granhydro --version\n"
                 "Without a scene file the embedded default scene runs. -p overrides a\n"
                 "parameter of the scene (nested sections joined by '/'), e.g.\n"
                 "  granhydro -p \"Time/End time=0.1\" -p \"Output/Directory=run2\" scene.prm\n"
                 "Exit codes: 0 done, 2 bad input, 3 run failure, 130/143 stopped by SIGINT/SIGTERM\n"
                 "(final output, checkpoint and summary written; go on with --resume).\n";
  }

  /// --resume: the scene's own latest checkpoint <Directory>/<Base name>.checkpoint, if
  /// it exists, added to the overrides as 'Initial state/Checkpoint' (the scene's end time
  /// stays); rank 0 looks, every rank gets its answer. Returns the line saying which
  std::string resume_from_own_checkpoint(const std::string &file, std::vector<std::string> &overrides,
                                         const MPI_Comm comm)
  {
    if (file.empty())
      throw granhydro::SceneError("--resume needs a scene file (its Output/Directory and Output/Base "
                                  "name give the checkpoint to continue from)");
    const granhydro::scene::Scene first = granhydro::scene::read_scene(file, overrides);
    const std::string             cp    = first.output_file(".checkpoint");
    std::error_code               ec;
    const bool                    root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
    if (dealii::Utilities::MPI::broadcast(comm, root && std::filesystem::is_regular_file(cp, ec), 0))
      {
        overrides.push_back("Initial state/Checkpoint=" + cp);
        return "granhydro: --resume: continuing from the checkpoint " + cp;
      }
    return "granhydro: --resume: no checkpoint " + cp + " yet: starting from the initial state" +
           (first.initial_checkpoint.empty() ? std::string() :
                                               " (the scene's checkpoint " + first.initial_checkpoint + ")");
  }

  /// --checkpoint-info: verify the checkpoint cp and print what it holds; the exit code
  int checkpoint_info(const std::string &cp, const bool root)
  {
    try
      {
        const granhydro::io::CheckpointReader d(cp);
        const auto                           &h = d.header();
        // every part is read and verified (the digest merges them in key order)
        const std::uint64_t digest = granhydro::io::state_digest(d);
        if (root)
          {
            std::printf("checkpoint %s: valid (format v%d, every checksum verified)\n", cp.c_str(),
                        d.version());
            std::printf("  dimension %d, model %s, %llu cells, step %llu, outputs %llu\n", h.dim, h.model,
                        (unsigned long long)h.n_cells, (unsigned long long)h.step,
                        (unsigned long long)h.outputs);
            std::printf("  time %.17g s\n", h.time * h.length / h.velocity);
            std::printf("  implicit-step history: %s\n",
                        h.history.matrix_valid ? "kept Newton matrix (interrupted run)" : "none");
            std::printf("  parts %zu (one per writing rank)\n", d.parts().size());
            const auto record   = granhydro::io::run_record(h);
            double     segments = 0;
            for (const auto &[key, value] : record)
              if (key == "segments")
                segments = value;
            if (record.empty())
              std::printf("  run record: none (the summary of a restart counts from this step)\n");
            else
              std::printf("  run record: %zu figures of %.0f segment(s)\n", record.size(), segments);
            std::printf("  state digest %016llx\n", (unsigned long long)digest);
          }
        return 0;
      }
    catch (const granhydro::io::CheckpointError &e)
      {
        if (root)
          std::cerr << "granhydro: error: checkpoint '" << cp << "' " << e.what() << "\n";
        return 2;
      }
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool                               root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  std::string                              file;
  bool                                     check_only = false, print_only = false, resume = false;
  std::vector<std::string>                 overrides;
  for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h")
        {
          if (root)
            print_usage();
          return 0;
        }
      if (a == "--version")
        {
          if (root)
            std::cout << "granhydro " << granhydro::version() << " (git " << granhydro::git_revision()
                      << "), deal.II " << DEAL_II_PACKAGE_VERSION << "\n";
          return 0;
        }
      if (a == "-p" || a == "--parameter")
        {
          if (i + 1 >= argc)
            {
              if (root)
                std::cerr << "granhydro: error: " << a
                          << " needs an argument \"Section/Name=value\" (e.g. -p \"Time/End time=0.1\")\n";
              return 2;
            }
          overrides.emplace_back(argv[++i]);
          continue;
        }
      if (a == "--checkpoint-info")
        {
          if (i + 1 >= argc)
            {
              if (root)
                std::cerr << "granhydro: error: --checkpoint-info needs a checkpoint file\n";
              return 2;
            }
          return checkpoint_info(argv[++i], root);
        }
      if (a == "--print-parameters")
        {
          print_only = true;
          continue;
        }
      if (a == "--check")
        {
          check_only = true;
          continue;
        }
      if (a == "--resume")
        {
          resume = true;
          continue;
        }
      if (!a.empty() && a[0] == '-')
        {
          if (root)
            std::cerr << "granhydro: error: unknown option '" << a
                      << "' (allowed: --help, --version, --print-parameters, --check, "
                         "--resume, --checkpoint-info, -p, a scene file)\n";
          return 2;
        }
      if (!file.empty())
        {
          if (root)
            std::cerr << "granhydro: error: more than one scene file given ('" << file << "', '" << a
                      << "')\n";
          return 2;
        }
      file = a;
    }
  // the run's records (<base>_parameters.prm, <base>.log), once the scene is read: the
  // messages of a run that stops go into its log too
  std::unique_ptr<granhydro::driver::RunRecords> records;
  std::string                                    summary_file; // once the run has started one
  const auto stopped = [&](const std::string &what, const std::string &status) {
    if (root)
      std::cerr << "granhydro: run stopped: " << what << std::endl;
    if (records)
      records->note("granhydro: run stopped: " + what);
    if (root && !summary_file.empty())
      settle_running_summary(summary_file, status);
    return 3;
  };
  try
    {
      if (print_only)
        {
          // every rank reads the scene (the same exit code everywhere); rank 0 prints it
          const std::string text = granhydro::scene::expanded_scene_text(file, overrides);
          if (root)
            std::cout << text;
          return 0;
        }
      const std::string resume_note       = resume ? resume_from_own_checkpoint(file, overrides, comm) : "";
      const granhydro::scene::Scene scene = granhydro::scene::read_scene(file, overrides);
      check_memory(scene, comm);
      if (check_only)
        {
          if (root)
            std::cout << "granhydro: scene " << scene.source << " is valid\n";
          return 0;
        }
      // a full disk or a file size limit makes a write fail with an error we report
      // (exit 3), not a SIGXFSZ that kills the process
      std::signal(SIGXFSZ, SIG_IGN);
      granhydro::driver::install_stop_signal_handlers();
      const granhydro::driver::RunSettings run = granhydro::driver::run_settings(scene, scene.dimension);
      records = std::make_unique<granhydro::driver::RunRecords>(run.files, run.report, comm, std::cout);
      if (scene.write_summary)
        summary_file = scene.output_file("_summary.csv");
      if (!resume_note.empty() && root)
        records->log() << resume_note << "\n";
      return granhydro::driver::run_scene(scene, comm, *records);
    }
  catch (const granhydro::SceneError &e)
    {
      if (root)
        std::cerr << "granhydro: error: " << e.what() << std::endl;
      if (records)
        records->note(std::string("granhydro: error: ") + e.what());
      return 2;
    }
  catch (const granhydro::io::OutputError &e)
    {
      return stopped(e.what(), "failed");
    }
  catch (const granhydro::RunError &e)
    {
      return stopped(e.what(), "failed");
    }
  catch (const granhydro::Error &e) // a checkpoint or mesh-file error no caller named
    {
      return stopped(e.what(), "failed");
    }
  catch (const std::exception &e)
    {
      std::cerr << "granhydro: internal error: " << e.what() << std::endl;
      if (records)
        records->note(std::string("granhydro: internal error: ") + e.what());
      MPI_Abort(comm, 1);
      return 1;
    }
}
