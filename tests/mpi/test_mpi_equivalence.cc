// A run on N MPI ranks gives the same
// state as on 1 rank (here: bit for bit; the assertion allows 1e-12 relative).
// Run under mpirun -np N: the N-rank run uses MPI_COMM_WORLD, then rank 0
// repeats the scene alone on MPI_COMM_SELF and compares cell by cell (cells
// matched by their octree leaf key, since the numbering differs).
// Argument "3d" (run on 4 and 8 ranks): only the 3D cases, a blast (bit for bit) and a
// uniform 3D granular gas with the implicit step (1e-12).
// The cases are shock problems with walls and periodic directions, so the
// wide WENO5 ghost layers, mirror ghosts across rank boundaries and the
// a-posteriori fallback (flags exchanged between ranks) are all exercised.
#include <granhydro/mesh/slot_exchange.h>

#include "common/test_common.h"

#include <map>

using namespace granhydro;
using namespace granhydro::testing;

template <int dim, class Description = physics::IdealGas<dim>>
std::map<long long, physics::State<dim>> run(const scene::Scene &scene, const MPI_Comm comm,
                                             unsigned long long &fallbacks)
{
  driver::Simulation<dim, Description> sim(scene, comm, std::cout);
  sim.setup();
  if constexpr (std::is_same_v<Description, physics::IdealGas<dim>>)
    sim.set_initial_state(
      [&](const dealii::Point<dim> &x) {
        double r2 = 0;
        for (unsigned int d = 0; d < dim; ++d)
          r2 += (x[d] - 0.3 - 0.1 * d) * (x[d] - 0.3 - 0.1 * d);
        const double u[3] = {0.3, -0.2, 0.1};
        return conservative<dim>(r2 < 0.05 ? 1. : 0.125, u, r2 < 0.05 ? 50. : 0.1, 5. / 3.);
      },
      2);
  const auto sum = sim.run();
  fallbacks      = sum.convection.fallback_cells + sum.convection.limited_cells;
  return gather_state(sim, comm);
}

template <int dim, class Description = physics::IdealGas<dim>>
void compare(const std::string &name, const scene::Scene &s, Checker &chk, const double tol = 1e-12)
{
  const MPI_Comm     world = MPI_COMM_WORLD;
  const unsigned int me    = dealii::Utilities::MPI::this_mpi_process(world);
  unsigned long long fN = 0, f1 = 0;
  const auto         par = run<dim, Description>(s, world, fN);
  if (me == 0)
    {
      const auto ser          = run<dim, Description>(s, MPI_COMM_SELF, f1);
      const auto [same, diff] = compare_states<dim>(par, ser);
      std::ostringstream os;
      os << name << ": " << dealii::Utilities::MPI::n_mpi_processes(world) << " ranks vs 1 rank, "
         << ser.size() << " cells, limiter/fallback events " << f1 << " (1 rank) / " << fN
         << " (N ranks): max relative difference " << diff;
      chk.check(same && diff <= tol, os.str());
    }
}

/**
 * SlotExchange (the convective stages of halo cells come from their owners): rank p owns
 * cells [p n, (p + 1) n) with NC entries each and holds as ghosts every third cell of the
 * other ranks; ghost g asks for channel k iff (g + k) % 3 != 0. After exchanging channel
 * k with m doubles per slot, every ghost that asked holds exactly its owner's values
 * (global cell * 100 + k + entry / 1000: exact in binary64 comparisons since both sides
 * compute the same expression), and every other ghost still holds the sentinel -1.
 */
void check_slot_exchange(Checker &chk)
{
  const MPI_Comm     comm = MPI_COMM_WORLD;
  const unsigned int P    = dealii::Utilities::MPI::n_mpi_processes(comm),
                     me   = dealii::Utilities::MPI::this_mpi_process(comm);
  const unsigned int n = 10, NC = 5, m = 7, channels = 4;
  dealii::IndexSet   owned(std::size_t(P) * n * NC), ghosts(std::size_t(P) * n * NC);
  owned.add_range(std::size_t(me) * n * NC, std::size_t(me + 1) * n * NC);
  std::vector<unsigned long long> ghost_cells; // global cell of each ghost, increasing
  for (unsigned int c = 0; c < P * n; ++c)
    if (c / n != me && c % 3 == 0)
      {
        ghost_cells.push_back(c);
        ghosts.add_range(std::size_t(c) * NC, std::size_t(c + 1) * NC);
      }
  const dealii::Utilities::MPI::Partitioner part(owned, ghosts, comm);
  std::vector<std::uint16_t>                need(ghost_cells.size(), 0);
  for (unsigned int g = 0; g < need.size(); ++g)
    for (unsigned int k = 0; k < channels; ++k)
      if ((g + k) % 3 != 0)
        need[g] |= std::uint16_t(1u << k);
  mesh::SlotExchange ex;
  ex.setup(part, NC, n, need);
  auto value = [](const unsigned long long cell, const unsigned int k, const unsigned int i) {
    return double(cell) * 100 + k + i / 1000.;
  };
  unsigned int wrong = 0, received = 0;
  for (unsigned int k = 0; k < channels; ++k)
    {
      std::vector<double> a((n + ghost_cells.size()) * m, -1.);
      for (unsigned int s = 0; s < n; ++s)
        for (unsigned int i = 0; i < m; ++i)
          a[s * m + i] = value(std::size_t(me) * n + s, k, i);
      ex.exchange(k, a.data(), m);
      for (unsigned int g = 0; g < ghost_cells.size(); ++g)
        for (unsigned int i = 0; i < m; ++i)
          {
            const bool   asked  = need[g] >> k & 1u;
            const double expect = asked ? value(ghost_cells[g], k, i) : -1.;
            wrong += a[(n + g) * m + i] != expect;
            received += asked;
          }
      for (unsigned int s = 0; s < n; ++s) // the owned values are left alone
        for (unsigned int i = 0; i < m; ++i)
          wrong += a[s * m + i] != value(std::size_t(me) * n + s, k, i);
    }
  wrong    = dealii::Utilities::MPI::sum(wrong, comm);
  received = dealii::Utilities::MPI::sum(received, comm);
  std::ostringstream os;
  os << "SlotExchange on " << P << " ranks: " << received << " ghost values received on " << channels
     << " channels, the others untouched; wrong entries " << wrong;
  chk.check(wrong == 0 && received > 0, os.str());
}

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  chk.root           = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  const bool only_3d = argc > 1 && std::string(argv[1]) == "3d";
  check_slot_exchange(chk);
  if (only_3d)
    {
      {
        // convection only: the same operations in the same order on every partition
        SceneSpec s;
        s.dim      = 3;
        s.cells    = {{24, 20, 16}};
        s.upper    = {{1, 20. / 24, 16. / 24}};
        s.boundary = {{"slip wall", "outflow", "periodic", "periodic", "slip wall", "slip wall"}};
        s.end_time = 0.05;
        compare<3>("3D blast, slip/outflow in x, periodic in y, slip walls in z (bit for bit)", make_scene(s),
                   chk, 0.);
      }
      // a dense granular gas under gravity on a uniform 3D mesh, with every effect of the
      // diffusion step, SDIRK2: the Newton matrices are block ILU(0) per rank, so GMRES
      // iterates differ with the partition; Newton stops at 1e-13 of max|U| and GMRES at
      // 1e-14 relative: 1e-12 relative is what the solver tolerances allow
      compare<3, physics::GranularGas<3>>("3D granular gas, uniform 16x16x20, all effects, sdirk2",
                                          test_scene("granular_gas_3d.prm"), chk, 1e-12);
      return chk.failed != 0;
    }
  {
    SceneSpec s;
    s.dim      = 1;
    s.cells    = {{200, 1, 1}};
    s.boundary = {{"slip wall", "outflow", "", "", "", ""}};
    s.end_time = 0.15;
    compare<1>("1D blast, slip wall | outflow", make_scene(s), chk);
  }
  {
    SceneSpec s;
    s.dim      = 2;
    s.cells    = {{64, 48, 1}};
    s.upper    = {{1, 0.75, 1}};
    s.boundary = {{"slip wall", "slip wall", "periodic", "periodic", "", ""}};
    s.end_time = 0.1;
    compare<2>("2D blast, slip walls in x, periodic in y, WENO5 + Gauss + MUSTA", make_scene(s), chk);
  }
  {
    SceneSpec s;
    s.dim      = 3;
    s.cells    = {{24, 20, 16}};
    s.upper    = {{1, 20. / 24, 16. / 24}};
    s.boundary = {{"slip wall", "outflow", "periodic", "periodic", "slip wall", "slip wall"}};
    s.end_time = 0.05;
    compare<3>("3D blast, slip/outflow in x, periodic in y, slip walls in z", make_scene(s), chk);
  }
  {
    // granular gas with every effect of the diffusion step (viscosity, heat conduction,
    // cooling, gravity) and Strang splitting: the implicit step solves linear systems
    // with GMRES + ILU, whose iterates depend on the partition (block ILU); Newton
    // stops at 1e-13 of max|U| and GMRES at 1e-14 relative, so 1 and N ranks agree
    // to ~1e-12 of the state, asserted with 1e-10.
    // the default (cost-based: RKL2 here), and the two implicit integrators, whose Newton
    // matrices (block-sparse, block ILU(0) per rank) and GMRES iterates differ with the
    // partition
    for (const std::string integrator : {"cost-based", "sdirk2", "gauss-legendre"})
      compare<2, physics::GranularGas<2>>(
        "2D granular gas, all effects, Strang splitting, " + integrator,
        test_scene("granular_gas_2d.prm", {"Diffusion step/Integrator=" + integrator}), chk, 1e-10);
    // gravity in the convective step (well-balanced): the equilibrium reconstruction, the
    // hydrostatic mirror at the walls and the sources on both sides of rank boundaries
    compare<2, physics::GranularGas<2>>(
      "2D granular gas, all effects, well-balanced gravity",
      test_scene("granular_gas_2d.prm", {"Numerics/Gravity scheme=well-balanced"}), chk, 1e-10);
    // the implicit contact step on a dense blob (phi up to 0.63, in enduring contact): its
    // Newton matrices are block ILU(0) per rank too, Newton stops at 1e-10 of max n after
    // an update whose own error is ~1e-6 of it (GMRES), so the ranks agree to ~1e-14
    compare<2, physics::GranularGas<2>>(
      "2D dense granular gas, all effects, implicit contact pressure",
      test_scene("granular_gas_2d.prm",
                 {"Dense closure/Model=johnson-jackson", "Numerics/Contact pressure=implicit",
                  "Initial state/Packing fraction=0.5 + 0.13*exp(-((x-0.012)^2+(y-0.01)^2)/0.004^2)"}),
      chk, 1e-10);
  }
  return chk.failed != 0;
}
