// Adaptive octree refinement (doc/user-guide.md, "Adaptive mesh refinement").
//   test_amr conservation : a 3D periodic blast (ideal gas, WENO5) refined and coarsened
//                           every 5 steps for 500 steps: mass and energy are conserved to
//                           1e-13 relative (hanging-face fluxes are fine sub-faces taken by
//                           the coarse cell with weight 1/4; transfer is conservative).
//                           Run under mpirun -n 2 too: the same on 2 ranks.
//   test_amr mpi          : under mpirun -n N: an adaptive 3D blast (ideal gas) and an
//                           adaptive 2D granular gas with all diffusion effects (with split
//                           and with well-balanced gravity) give the same
//                           state on N ranks as on 1 rank (cells matched by their leaf key):
//                           the adaptation decisions do not depend on the partition.
//   test_amr mpi-3d       : under mpirun -n N (4, 8): the adaptive 3D blast alone, bit for
//                           bit (convection only: the same floating-point operations in the
//                           same order on any partition); "mpi" and "mpi-3d" also run it with
//                           the partition weighted 3 : 1 (Adaptivity/Load balance): bitwise
//                           again, and rank 0 ends with the share the weights predict.
//   test_amr walls-3d     : the 3D blast between slip and no-slip walls (periodic in x): runs
//                           through its adaptations, conserves mass and energy to 2e-13;
//                           under mpirun also equals 1 rank bit for bit.
//   test_amr mpi-open-2d  : under mpirun -n 3: a 2D granular box with slip walls and outflow
//                           sides, 15 adaptations, equals 1 rank (the rows of far slots
//                           reach beyond the lattice blocks a rank fetched: left empty).
//   test_amr dealii-sync  : the adaptive forest is refined by p4est alone; deal.II's mesh and
//                           DoFs (what VTU output writes) follow it on demand. After 60 steps
//                           of the 3D blast (12 adaptations), every owned deal.II cell must
//                           sit at its slot's centre and level, own the slot's DoFs, and its
//                           DoF values be the slot's state, exactly (same cells, same
//                           numbering: the copy is not an interpolation). Also under mpirun.
//   test_amr slot-grid    : the table builders find slots by position (SlotGrid: a dense
//                           grid per level, or a hash map for a scattered level). Both
//                           variants must give, for every position of every level within
//                           the lattice keys' reach (periodic sides unwrapped), the slot a
//                           plain std::map of the wrapped positions holds, or -1.
//   test_amr balance      : random refine and coarsen flags on adaptive boxes (2D, 3D;
//                           periodic in x, walls elsewhere; 3 levels), 24 adaptations each:
//                           after each one the forest must be 2:1 balanced across faces,
//                           edges and corners (p4est's own check), whether p4est balanced
//                           it or the patch proved that the changes kept the balance and
//                           skipped p4est's balance; both must occur. Also under mpirun
//                           (ghost leaves' changes come from their owners).
//   test_amr sod DIM [refine coarsen buffer levels indicator interval max_error max_cells]
//                         : Sod's problem along the diagonal of the unit square/cube with AMR
//                           against the uniform mesh at the finest level: L1 density errors
//                           (reference: the exact Riemann solution, tests/exact_riemann.h),
//                           cells and wall times; GRANHYDRO_SOD_LEVELS=1 prints the error
//                           per level and per band along the diagonal (interior);
//                           GRANHYDRO_SOD_FINEST=N sets the finest lattice (default 256^2,
//                           32^3); GRANHYDRO_SOD_UNIFORM=... reuses a uniform run's numbers
//                           (printed by an earlier run) for parameter scans.
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/distributed/tria.h>

#include "common/exact_riemann.h"
#include "common/test_common.h"
#include "stencil_tables.h" // source/mesh: an internal header of the patch
#include <p4est_ghost.h>
#include <p8est_ghost.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <map>
#include <random>
#include <sstream>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{

  scene::Scene blast_3d(const unsigned int steps)
  {
    // a dense hot sphere off centre in a periodic box, moving diagonally: its shock
    // crosses the periodic boundaries, the refined shell follows it and the wake coarsens
    return test_scene("blast_3d.prm", {"Time/Maximum steps=" + std::to_string(steps)});
  }

  /// the blast between walls: slip walls across y, a no-slip floor and a slip lid in z,
  /// periodic in x, 8^3 cells: the refined shell meets the walls next to coarser cells, and
  /// the stencils of virtual cells reach wall ghosts across the periodic sides
  scene::Scene blast_3d_walls(const unsigned int steps)
  {
    return test_scene("blast_3d.prm", {"Time/Maximum steps=" + std::to_string(steps), "Domain/Cells=8, 8, 8",
                                       "Domain/Boundary y-=slip wall", "Domain/Boundary y+=slip wall",
                                       "Domain/Boundary z-=no-slip wall", "Domain/Boundary z+=slip wall"});
  }

  /// A Riemann problem along the diagonal: left/right density, normal velocity, pressure
  struct RiemannCase
  {
    double rho[2], u[2], p[2], gamma, t_end;
  };
  /// studies (mode "sod-study") may change the problem, the finest lattice and reuse a
  /// uniform reference through GRANHYDRO_SOD_* environment variables; the ctest (mode
  /// "sod") never reads them, so the environment cannot change what it asserts
  bool        study_mode = false;
  const char *study_env(const char *name)
  {
    return study_mode ? std::getenv(name) : nullptr;
  }

  /// Sod (gamma 5/3, t = 0.2), or Toro's 123 problem (two rarefactions leaving a
  /// near-vacuum, gamma 1.4, t = 0.15) if GRANHYDRO_SOD_PROBLEM=123 (studies only)
  RiemannCase riemann_case()
  {
    const char *pr = study_env("GRANHYDRO_SOD_PROBLEM");
    if (pr && std::string(pr) == "123")
      return {{1, 1}, {-2, 2}, {0.4, 0.4}, 1.4, 0.15};
    return {{1, 0.125}, {0, 0}, {1, 0.1}, 5. / 3., 0.2};
  }

  /// The Riemann problem along the diagonal of the unit square/cube: the initial
  /// discontinuity is the plane through the centre normal to (1,..,1)/sqrt(dim). The scene
  /// is sod_diagonal.prm (beside this source) with the case's values as overrides: the
  /// states come from riemann_case(), which the exact solution reads too
  scene::Scene sod_diagonal(const unsigned int dim, const unsigned int cells, const unsigned int level,
                            const double refine, const double coarsen, const unsigned int buffer,
                            const std::string &indicator, const unsigned int interval)
  {
    const std::string        xi   = dim == 2 ? "(x+y)" : "(x+y+z)";
    const std::string        left = "(" + xi + " < " + std::to_string(dim * 0.5) + ")";
    const std::string        n    = std::to_string(cells);
    std::vector<std::string> o    = {"Dimension=" + std::to_string(dim),
                                     std::string("Domain/Lower corner=") + (dim == 3 ? "0, 0, 0" : "0, 0"),
                                     std::string("Domain/Upper corner=") + (dim == 3 ? "1, 1, 1" : "1, 1"),
                                     "Domain/Cells=" + n + ", " + n + (dim == 3 ? ", " + n : std::string())};
    if (dim == 3)
      o.insert(o.end(), {"Domain/Boundary z-=outflow", "Domain/Boundary z+=outflow"});
    const RiemannCase rc = riemann_case();
    // unit grain mass: n = rho, T = p / rho; the velocity is u along the diagonal
    auto blend = [&](const double l, const double r) {
      return "(" + number(r) + " + " + number(l - r) + "*" + left + ")";
    };
    const std::string vel = blend(rc.u[0] / std::sqrt(double(dim)), rc.u[1] / std::sqrt(double(dim)));
    o.insert(o.end(),
             {"Material/Adiabatic index=" + number(rc.gamma),
              "Initial state/Packing fraction=" + number(M_PI / 6) + "*" + blend(rc.rho[0], rc.rho[1]),
              "Initial state/Temperature=" + blend(rc.p[0] / rc.rho[0], rc.p[1] / rc.rho[1]),
              "Initial state/Velocity=" + vel + "; " + vel + (dim == 3 ? "; " + vel : std::string()),
              "Adaptivity/Maximum level=" + std::to_string(level), "Adaptivity/Indicator=" + indicator,
              "Adaptivity/Refine threshold=" + number(refine),
              "Adaptivity/Coarsen threshold=" + number(coarsen),
              "Adaptivity/Buffer=" + std::to_string(buffer),
              "Adaptivity/Interval=" + std::to_string(interval), "Time/End time=" + number(rc.t_end)});
    return test_scene("sod_diagonal.prm", o);
  }

  /// L1 density error against the exact solution (cell averages of the exact solution by
  /// 3-point Gauss rules), the cells at the end and the wall time
  template <int dim>
  void sod_run(const scene::Scene &scene, double &error, double &error_all, unsigned long long &cells,
               unsigned long long &max_cells, double &cell_steps, double &wall)
  {
    driver::Simulation<dim> sim(scene, MPI_COMM_WORLD, std::cout);
    sim.setup();
    const auto               sum = sim.run();
    const RiemannCase        rc  = riemann_case();
    const ExactRiemannSolver exact({rc.rho[0], rc.u[0], rc.p[0]}, {rc.rho[1], rc.u[1], rc.p[1]}, rc.gamma);
    const double             xi0 = std::sqrt(double(dim)) / 2, gp[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)},
                 gw[3] = {5. / 18, 8. / 18, 5. / 18};
    double e = 0, e_all = 0, by_level[8] = {}, by_xi[40] = {};
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto   x   = sim.patch().center(c);
        const double h   = sim.patch().cell_size(c, 0);
        double       avg = 0;
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            for (unsigned int k = 0; k < (dim == 3 ? 3u : 1u); ++k)
              {
                double xi = x[0] + 0.5 * h * gp[a] + x[1] + 0.5 * h * gp[b];
                double w  = gw[a] * gw[b];
                if (dim == 3)
                  {
                    xi += x[dim - 1] + 0.5 * h * gp[k];
                    w *= gw[k];
                  }
                avg += w * exact.sample((xi / std::sqrt(double(dim)) - xi0) / rc.t_end).rho;
              }
        const double ec = std::abs(sim.state_si(c)[0] - avg) * sim.patch().cell_volume(c);
        // the interior [1/4, 3/4]^dim, outside the domain of influence of the outflow
        // boundaries at t = 0.2 (sound speed <= 1.3): there the 1D exact solution is the
        // 2D/3D one (near the boundaries the oblique waves meet the zero-gradient ghosts)
        bool interior = true;
        for (unsigned int d = 0; d < dim; ++d)
          interior = interior && x[d] > 0.25 && x[d] < 0.75;
        e += interior ? ec : 0.;
        e_all += ec;
        by_level[sim.patch().level(c) * 2 + (sim.patch().uniform(c) ? 0 : 1)] += ec;
        double xs = 0;
        for (unsigned int d = 0; d < dim; ++d)
          xs += x[d];
        const int bin = std::min(39, std::max(0, int(xs / double(dim) * 40)));
        by_xi[bin] += interior ? ec : 0.;
      }
    if (study_env("GRANHYDRO_SOD_LEVELS"))
      for (unsigned int l = 0; l < 8; ++l)
        std::cout << "    level " << l / 2 << (l % 2 ? " fallback" : " uniform") << ": " << by_level[l]
                  << "\n";
    if (study_env("GRANHYDRO_SOD_LEVELS"))
      for (unsigned int b = 0; b < 40; ++b)
        std::cout << "    interior, (x+y(+z))/dim in [" << b / 40. << ", " << (b + 1) / 40.
                  << "): " << by_xi[b] << "\n";
    error      = dealii::Utilities::MPI::sum(e, MPI_COMM_WORLD);
    error_all  = dealii::Utilities::MPI::sum(e_all, MPI_COMM_WORLD);
    cells      = sum.cells;
    max_cells  = sum.max_cells;
    cell_steps = sum.convection.cell_updates / 3.;
    wall       = sum.wall_seconds;
  }

  /// rank0_cost > 0: the partition weighs the cells by a cost per cell that is rank0_cost on
  /// rank 0 and 1 elsewhere (Adaptivity/Load balance = measured cost, the measurement
  /// replaced): the run must not notice, and rank 0 must end with the share of the cells
  /// that equal sums of weights give
  template <int dim, class Description>
  void compare_ranks(const std::string &name, scene::Scene s, Checker &chk, const double tol,
                     const double rank0_cost = 0)
  {
    const MPI_Comm     world = MPI_COMM_WORLD;
    const unsigned int me    = dealii::Utilities::MPI::this_mpi_process(world);
    const unsigned int P     = dealii::Utilities::MPI::n_mpi_processes(world);
    if (rank0_cost > 0)
      s.load_balance = scene::LoadBalance::measured_cost;
    driver::Simulation<dim, Description> par(s, world, std::cout);
    par.setup();
    if (rank0_cost > 0)
      par.set_cost_per_cell(me == 0 ? rank0_cost : 1.);
    const auto               sp = par.run();
    const auto               A  = gather_state(par, world);
    const unsigned long long n0 =
      dealii::Utilities::MPI::broadcast(world, (unsigned long long)(par.patch().n_owned()), 0);
    if (me != 0)
      return;
    if (rank0_cost > 0)
      {
        // the weights (Simulation::adapt_mesh): cost / mean cost, clamped to [1/2, 2]; each
        // adaptation moves the cut toward w0 n0 = n_j (j > 0, weight w), a contraction
        // (factor <= 1/3 here), so after >= 5 adaptations rank 0 holds n / (1 + (P - 1) w0 / w)
        // up to the families of 2^dim cells the cut keeps together and the cells refined
        // since the last adaptation: asserted within 10 % (2, 4, 8 ranks: 0.3 %, 2 %, 4 % seen)
        const double       mean = (rank0_cost + (P - 1)) / P;
        const double       w0 = std::clamp(rank0_cost / mean, 0.5, 2.), w = std::clamp(1. / mean, 0.5, 2.);
        const double       expected = 1. / (1 + (P - 1) * w0 / w);
        const double       share    = double(n0) / double(sp.cells);
        std::ostringstream os;
        os << name << ", partition weighted " << rank0_cost << " : 1 (rank 0 : others) on " << P
           << " ranks: rank 0 owns " << n0 << " of " << sp.cells << " cells = " << share << " (expected "
           << expected << " +- 10 %, " << sp.adaptations << " adaptations)";
        chk.check(std::abs(share / expected - 1) <= 0.1 && sp.adaptations >= 5, os.str());
      }
    driver::Simulation<dim, Description> ser(s, MPI_COMM_SELF, std::cout);
    ser.setup();
    const auto ss           = ser.run();
    const auto B            = gather_state(ser, MPI_COMM_SELF);
    const auto [same, diff] = compare_states<dim>(A, B);
    std::ostringstream os;
    os << name << ": " << dealii::Utilities::MPI::n_mpi_processes(world) << " ranks vs 1 rank, " << B.size()
       << " vs " << A.size() << " cells at the end, " << ss.adaptations << " / " << sp.adaptations
       << " adaptations, max cells " << ss.max_cells << ": max relative difference " << diff << " (tolerance "
       << tol << ")";
    chk.check(same && diff <= tol && ss.adaptations > 0, os.str());
  }
  /// random flags on an adaptive box: is the forest 2:1 balanced after every adaptation,
  /// and did both the skipped and the full balance occur? The flags depend on the leaf's
  /// key and the round only, so every partition sees the same adaptations.
  template <int dim>
  void balance_rounds(Checker &chk, const MPI_Comm comm)
  {
    const boundary::BoundaryType sides[6] = {
      boundary::BoundaryType::periodic,  boundary::BoundaryType::periodic,
      boundary::BoundaryType::slip_wall, boundary::BoundaryType::no_slip_wall,
      boundary::BoundaryType::slip_wall, boundary::BoundaryType::outflow};
    mesh::MeshSettings ms;
    ms.cells     = {{5, 4, 3}};
    ms.max_level = 3;
    for (unsigned int i = 0; i < 6; ++i)
      ms.walls[i].type = sides[i];
    mesh::CartesianPatch<dim> patch(comm);
    patch.build(ms, 3);
    constexpr unsigned int NC      = dim + 2;
    unsigned int           bad     = 0;
    const unsigned int     rounds  = 24;
    unsigned long long     changed = 0;
    for (unsigned int round = 0; round < rounds; ++round)
      {
        dealii::LinearAlgebra::distributed::Vector<double> U(patch.partitioner());
        std::vector<signed char>                           flags(patch.n_owned(), 0);
        for (unsigned int s = 0; s < patch.n_owned(); ++s)
          {
            // a hash of (leaf, round): refine 8 %, coarsen 40 % (families coarsen only
            // when all their members are flagged); early rounds mostly refine
            std::uint64_t h =
              std::uint64_t(patch.leaf_key(s)) * 0x9E3779B97F4A7C15ull + round * 0xBF58476D1CE4E5B9ull;
            h ^= h >> 31;
            h *= 0x94D049BB133111EBull;
            h ^= h >> 29;
            const unsigned int u = h % 100;
            flags[s]             = u < (round < 6 ? 20u : 8u) ? 1 : (u >= 60 ? -1 : 0);
            for (unsigned int c = 0; c < NC; ++c)
              U.local_element(std::size_t(s) * NC + c) = 1;
          }
        const auto before = patch.n_global_cells();
        patch.adapt(flags, U, {});
        changed += patch.n_global_cells() != before;
        patch.dof_handler(); // deal.II's copy of the forest (its p4est) follows the leaves
        const auto &tria =
          dynamic_cast<const dealii::parallel::distributed::Triangulation<dim> &>(patch.triangulation());
        int balanced;
        if constexpr (dim == 2)
          balanced = p4est_is_balanced(const_cast<p4est_t *>(tria.get_p4est()), P4EST_CONNECT_FULL);
        else
          balanced = p8est_is_balanced(const_cast<p8est_t *>(tria.get_p4est()), P8EST_CONNECT_FULL);
        bad += balanced ? 0 : 1;
      }
    const auto [ran, skipped] = patch.balance_counts();
    std::ostringstream os;
    os << dim << "D box, " << rounds << " adaptations with random flags (" << changed
       << " changed the cell count, " << patch.n_global_cells() << " cells at the end): p4est balanced in "
       << ran << ", skipped in " << skipped
       << " (proved balanced); unbalanced forests after an adaptation: " << bad
       << " (must be 0; both kinds of adaptation must occur)";
    chk.check(bad == 0 && ran > 0 && skipped > 0 && ran + skipped == rounds, os.str());
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  const MPI_Comm                           world = MPI_COMM_WORLD;
  chk.root                                       = dealii::Utilities::MPI::this_mpi_process(world) == 0;
  const std::string what                         = argc > 1 ? argv[1] : "";
  try
    {
      if (what == "conservation")
        {
          driver::Simulation<3> sim(blast_3d(500), world, std::cout);
          sim.setup();
          const auto         T0     = sim.totals();
          const auto         cells0 = sim.patch().n_global_cells();
          const auto         sum    = sim.run();
          const auto         T1     = sim.totals();
          const double       dm     = std::abs(T1[0] - T0[0]) / T0[0];
          const double       de     = std::abs(T1[4] - T0[4]) / T0[4];
          std::ostringstream os;
          os << "3D periodic blast, " << sum.steps << " steps, " << sum.adaptations << " adaptations ("
             << sum.refined_cells << " cells refined, " << sum.coarsened_cells << " coarsened), cells "
             << cells0 << " -> " << sum.cells << " (max " << sum.max_cells << "): mass drift " << dm
             << ", energy drift " << de << " (tolerance 1e-13)";
          // the mesh changes at >= half of the 100 adaptation points (else the test is void);
          // round-off only: each cell update and each coarsening (mean of 8 children)
          // rounds once; their random sum over ~1e3 cells and 1.5e3 stages stays ~1e-15
          chk.check(dm <= 1e-13 && de <= 1e-13 && sum.steps == 500 && sum.adaptations >= 50 &&
                      sum.refined_cells > 0 && sum.coarsened_cells > 0,
                    os.str());
        }
      else if (what == "mpi")
        {
          compare_ranks<3, physics::IdealGas<3>>("3D blast with AMR", blast_3d(60), chk, 1e-12);
          compare_ranks<3, physics::IdealGas<3>>("3D blast with AMR, skewed partition (bit for bit)",
                                                 blast_3d(60), chk, 0., 3.);
          // GMRES + block ILU iterates depend on the partition; Newton stops at 1e-13:
          // 1 and N ranks agree to ~1e-12, asserted with 1e-10 (the tolerance)
          compare_ranks<2, physics::GranularGas<2>>("2D granular gas with AMR, all effects",
                                                    test_scene("granular_2d.prm"), chk, 1e-10);
          // gravity in the convective step: the equilibrium reconstruction next to level
          // changes (virtual cells) and at walls, on both sides of rank boundaries
          compare_ranks<2, physics::GranularGas<2>>(
            "2D granular gas with AMR, all effects, well-balanced gravity",
            test_scene("granular_2d.prm", {"Numerics/Gravity scheme=well-balanced"}), chk, 1e-10);
        }
      else if (what == "walls-3d")
        {
          // closed walls: mass and energy stay to round-off (the wall flux of the mirrored
          // state carries neither); before the virtual cells outside a wall were keyed by
          // their position wrapped across the periodic sides, this scene stopped at an
          // adaptation ("stencil leaves the ghost patch")
          driver::Simulation<3> sim(blast_3d_walls(40), world, std::cout);
          sim.setup();
          const auto         T0  = sim.totals();
          const auto         sum = sim.run();
          const auto         T1  = sim.totals();
          const double       dm  = std::abs(T1[0] - T0[0]) / T0[0];
          const double       de  = std::abs(T1[4] - T0[4]) / T0[4];
          std::ostringstream os;
          os << "3D blast between walls, " << sum.steps << " steps, " << sum.adaptations << " adaptations, "
             << sum.cells << " cells at the end: mass drift " << dm << ", energy drift " << de
             << " (tolerance 2e-13: round-off of 40 x 3 stage updates of ~2e4 cells; 9e-14 seen)";
          chk.check(dm <= 2e-13 && de <= 2e-13 && sum.steps == 40 && sum.adaptations >= 7, os.str());
          if (dealii::Utilities::MPI::n_mpi_processes(world) > 1)
            compare_ranks<3, physics::IdealGas<3>>("3D blast between walls (bit for bit)", blast_3d_walls(40),
                                                   chk, 0.);
        }
      else if (what == "slot-grid")
        {
          // a 4 x 3 x 5 lattice, 2 levels, periodic in x and z, walls in y (slots up to
          // G = 3 outside, as wall ghosts and virtual cells outside a wall lie)
          const unsigned int     G = 3, m = 2;
          const mesh::Lattice<3> lattice({{4, 3, 5}}, {{true, false, true}}, m, G, boundary::WallTable{},
                                         false);
          using Position = mesh::Lattice<3>::Position;
          std::mt19937                            rng(7);
          std::vector<std::array<int, 3>>         pos;
          std::vector<unsigned char>              level;
          std::map<std::array<long long, 4>, int> reference; // (level, wrapped position) -> slot
          for (int i = 0; i < 4000; ++i)
            {
              const unsigned int k = rng() % (m + 1);
              Position           p{{0, 0, 0}};
              for (unsigned int d = 0; d < 3; ++d)
                {
                  const long long n = lattice.n(k, d), lo = d == 1 ? -long(G) : 0, hi = d == 1 ? n + G : n;
                  p[d] = lo + long(rng() % (hi - lo));
                }
              if (reference.emplace(std::array<long long, 4>{{k, p[0], p[1], p[2]}}, int(pos.size())).second)
                {
                  pos.push_back({{int(p[0]), int(p[1]), int(p[2])}});
                  level.push_back(k);
                }
            }
          const mesh::SlotGrid<3> dense(lattice, pos, level), sparse(lattice, pos, level, -1);
          unsigned long long      looked = 0, found = 0, wrong_dense = 0, wrong_sparse = 0;
          for (unsigned int k = 0; k <= m; ++k)
            {
              const long long R = 2 * G + 4; // past the lattice keys' reach (2 G + 2)
              for (long long z = -R; z < lattice.n(k, 2) + R; ++z)
                for (long long y = -R; y < lattice.n(k, 1) + R; ++y)
                  for (long long x = -R; x < lattice.n(k, 0) + R; ++x)
                    {
                      Position q{{x, y, z}};
                      lattice.wrap(k, q);
                      const auto it     = reference.find({{k, q[0], q[1], q[2]}});
                      const int  expect = it == reference.end() ? -1 : it->second;
                      wrong_dense += dense(k, {{x, y, z}}) != expect;
                      wrong_sparse += sparse(k, {{x, y, z}}) != expect;
                      found += expect >= 0;
                      ++looked;
                    }
            }
          std::ostringstream os;
          os << "SlotGrid: " << pos.size() << " slots on 3 levels, " << looked << " positions looked at ("
             << found << " with a slot): " << wrong_dense << " wrong answers (dense grids), " << wrong_sparse
             << " (hash maps); reference: std::map of the wrapped positions, exact";
          chk.check(pos.size() > 1000 && wrong_dense == 0 && wrong_sparse == 0 && found >= 2 * pos.size(),
                    os.str()); // periodic images found too
        }
      else if (what == "balance")
        {
          balance_rounds<2>(chk, world);
          balance_rounds<3>(chk, world);
        }
      else if (what == "dealii-sync")
        {
          driver::Simulation<3> sim(blast_3d(60), world, std::cout);
          sim.setup();
          const auto             sum   = sim.run();
          const auto            &patch = sim.patch();
          const auto            &dofh  = patch.dof_handler(); // brings deal.II's mesh up to date
          const auto            &U     = sim.state();
          constexpr unsigned int NC    = 5;
          std::vector<dealii::types::global_dof_index> dofs(NC);
          unsigned int                                 n = 0, bad = 0;
          double                                       dx = 0;
          for (const auto &cell : dofh.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                cell->get_dof_indices(dofs);
                const unsigned int s = patch.partitioner()->global_to_local(dofs[0]) / NC;
                dx                   = std::max(dx, (cell->center() - patch.center(s)).norm());
                bool ok              = s < patch.n_owned() &&
                          patch.owned_active_cell_index()[s] == cell->active_cell_index() &&
                          std::abs(cell->diameter() / std::sqrt(3.) - patch.cell_size(s, 0)) <=
                            1e-12 * patch.cell_size(s, 0);
                for (unsigned int c = 0; c < NC; ++c)
                  ok = ok && dofs[c] == dofs[0] + c && U[dofs[c]] == U.local_element(std::size_t(s) * NC + c);
                bad += ok ? 0 : 1;
                ++n;
              }
          n   = dealii::Utilities::MPI::sum(n, world);
          bad = dealii::Utilities::MPI::sum(bad, world);
          dx  = dealii::Utilities::MPI::max(dx, world);
          std::ostringstream os;
          os << "deal.II's mesh after " << sum.adaptations << " adaptations: " << n << " cells (forest "
             << patch.n_global_cells() << "), " << bad << " not matching their slot, centre offset " << dx
             << " (tolerance 1e-14: the same lattice arithmetic up to round-off)";
          chk.check(sum.adaptations >= 10 && n == patch.n_global_cells() && bad == 0 && dx <= 1e-14,
                    os.str());
        }
      else if (what == "mpi-open-2d")
        // GMRES + block ILU depend on the partition (see "mpi"): 1e-10
        compare_ranks<2, physics::GranularGas<2>>("2D granular box with walls and outflow, AMR",
                                                  test_scene("granular_2d_open.prm"), chk, 1e-10);
      else if (what == "mpi-3d")
        {
          compare_ranks<3, physics::IdealGas<3>>("3D blast with AMR (bit for bit)", blast_3d(60), chk, 0.);
          // a partition far from equal cell counts gives the same state, bit for bit
          compare_ranks<3, physics::IdealGas<3>>("3D blast with AMR, skewed partition (bit for bit)",
                                                 blast_3d(60), chk, 0., 3.);
        }
      else if ((what == "sod" || what == "sod-study") && argc >= 3)
        {
          study_mode = what == "sod-study";
          // --uniform-reference=FILE: the uniform run's figures from FILE (the ctest: a
          // golden file, tests/golden/); --write-uniform-reference=FILE: run it and write them
          std::vector<std::string> arg;
          std::string              reference, write_reference;
          for (int i = 0; i < argc; ++i)
            {
              const std::string a = argv[i];
              if (a.rfind("--uniform-reference=", 0) == 0)
                reference = a.substr(20);
              else if (a.rfind("--write-uniform-reference=", 0) == 0)
                write_reference = a.substr(26);
              else
                arg.push_back(a);
            }
          const auto         given = [&](const std::size_t i) { return arg.size() > i; };
          const unsigned int dim   = std::atoi(arg[2].c_str());
          const unsigned int level = given(6) ? std::atoi(arg[6].c_str()) : 2;
          // finest lattice: 256^2 / 32^3 unless GRANHYDRO_SOD_FINEST says otherwise
          const char        *fe      = study_env("GRANHYDRO_SOD_FINEST");
          const unsigned int finest  = fe ? std::atoi(fe) : (dim == 2 ? 256 : 32);
          const unsigned int base    = finest >> level;
          const double       refine  = given(3) ? std::atof(arg[3].c_str()) : 0.1;
          const double       coarsen = given(4) ? std::atof(arg[4].c_str()) : 0.02;
          const unsigned int buffer  = given(5) ? std::atoi(arg[5].c_str()) : 2;
          double             eu, ea, cu, ca, wu, wa, eu_all, ea_all;
          unsigned long long nu, na, mu, ma;
          const std::string  ind      = given(7) ? arg[7] : "jumps";
          const unsigned int interval = given(8) ? std::atoi(arg[8].c_str()) : 4;
          const scene::Scene uni =
            sod_diagonal(dim, base << level, 0, refine, coarsen, buffer, ind, interval);
          const scene::Scene amr = sod_diagonal(dim, base, level, refine, coarsen, buffer, ind, interval);
          // GRANHYDRO_SOD_UNIFORM="error,error_all,cells,cell_steps,wall" reuses a uniform run
          // printed before (for parameter scans on large meshes)
          const char *ue           = study_env("GRANHYDRO_SOD_UNIFORM");
          std::string uniform_text = ue ? ue : "";
          if (!reference.empty())
            {
              // the file's first line without '#': error,error_all,cells,cell_steps,wall
              std::ifstream in(reference);
              for (std::string line; std::getline(in, line);)
                if (!line.empty() && line[0] != '#')
                  {
                    uniform_text = line;
                    break;
                  }
              if (uniform_text.empty())
                {
                  std::cerr << "test_amr: cannot read the uniform reference " << reference << std::endl;
                  return 2;
                }
            }
          if (!uniform_text.empty())
            {
              std::istringstream is(uniform_text);
              char               sep;
              is >> eu >> sep >> eu_all >> sep >> nu >> sep >> cu >> sep >> wu;
              mu = nu;
            }
          else if (dim == 2)
            sod_run<2>(uni, eu, eu_all, nu, mu, cu, wu);
          else
            sod_run<3>(uni, eu, eu_all, nu, mu, cu, wu);
          if (chk.root && uniform_text.empty())
            std::cout << "uniform: GRANHYDRO_SOD_UNIFORM=" << std::setprecision(17) << eu << "," << eu_all
                      << "," << nu << "," << cu << "," << wu << std::setprecision(6) << std::endl;
          if (chk.root && !write_reference.empty())
            {
              std::ofstream out(write_reference);
              out << "# verify.amr_sod_diagonal_" << dim << "d: the uniform " << (base << level) << "^" << dim
                  << " run's L1 errors (interior, whole domain), cells, cell-steps and wall seconds\n"
                  << "# (tests/verify/test_amr.cc). Regenerate after a change of the uniform solution:\n"
                  << "#   build/tests/test_amr sod " << dim
                  << " --write-uniform-reference=" << write_reference << "\n"
                  << std::setprecision(17) << eu << "," << eu_all << "," << nu << "," << cu << "," << wu
                  << "\n";
              return out ? 0 : 2;
            }
          if (dim == 2)
            sod_run<2>(amr, ea, ea_all, na, ma, ca, wa);
          else
            sod_run<3>(amr, ea, ea_all, na, ma, ca, wa);
          std::ostringstream os;
          os << (riemann_case().gamma < 1.5 ? "123 problem" : "Sod") << " along the diagonal, " << dim
             << "D, WENO5 + Gauss + MUSTA, t = " << riemann_case().t_end << ": uniform " << (base << level)
             << "^" << dim << " (" << nu << " cells) L1 error in [1/4,3/4]^" << dim << " " << eu
             << " (whole domain " << eu_all << ") in " << wu << " s; AMR " << base << "^" << dim << " + "
             << level << " levels: L1 error " << ea << " (" << ea / eu << " x; whole domain " << ea_all
             << ", " << ea_all / eu_all << " x), cells at the end " << na << " (" << double(na) / nu
             << "), at most " << ma << " (" << double(ma) / nu << "), cell-steps " << ca / cu
             << " of the uniform run's, " << wa << " s (" << wa / wu << " x)";
          // The target: the uniform mesh's L1 error within 10 % with at most 30 % of
          // its cells (the largest count the adaptive mesh had at any time), asserted on
          // both errors: the interior one (where the 1D solution is exact) and the whole
          // domain's (dominated by the outflow corners). Measured with the defaults (256^2
          // finest = 64^2 + 2 levels, jumps 0.1/0.02, buffer 2, every 4 steps, limited
          // linear prolongation): 1.074 x / 1.073 x with 0.284 of the cells; the margin is
          // what a change in the mesh sequence moves (1.07 to 1.15 x over the thresholds
          // tried), so a regression in the AMR's accuracy or economy fails here.
          const double max_error = given(9) ? std::atof(arg[9].c_str()) : 1.1,
                       max_cells = given(10) ? std::atof(arg[10].c_str()) : 0.3;
          chk.check(ea <= max_error * eu && ea_all <= max_error * eu_all &&
                      double(ma) <= max_cells * double(nu),
                    os.str());
        }
      else
        {
          std::cerr << "usage: test_amr conservation|mpi|sod DIM [refine coarsen buffer levels indicator "
                       "interval]|sod-study DIM [...] (reads GRANHYDRO_SOD_*)"
                    << std::endl;
          return 2;
        }
    }
  catch (const std::exception &e)
    {
      chk.check(false, std::string("exception: ") + e.what());
    }
  return chk.failed != 0;
}
