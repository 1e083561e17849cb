// Meshes from files ('Domain/Mesh file', mesh/mesh_file.h):
//   test_mesh_files box <tests/data>        a box read from a file (gmsh and ucd, colorized
//       ids 2d+upper) gives bit for bit the same state as the generated box: 2D and 3D
//       blasts (slip, no-slip, outflow) and a granular gas with gravity, no-slip walls, a
//       moving wall and dissipative walls (the diffusion step's wall heat flux). Under
//       mpirun -n N the N-rank file run is also compared with the 1-rank generated run.
//   test_mesh_files closed <silo-ci.prm>    the silo with its outlet closed (a wall)
//       conserves mass to 1e-12 relative and stays admissible: the concave corners of
//       the orifice, where the ghost is the nearest fluid cell rather than an exact mirror
//   test_mesh_files discharge <silo-ci.prm> the silo discharges: mass leaves through the
//       outlet, by a plausible amount below the free-fall bound, and the state stays admissible
#include "common/test_common.h"

#include <fstream>
#include <map>

using namespace dealii;
using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  template <int dim, class Description>
  using StateMap = std::map<std::array<int, 3>, physics::State<dim>>;

  /// run a scene for its steps on comm; the state gathered on rank 0, keyed by lattice index
  template <int dim, class Description>
  StateMap<dim, Description> run(const scene::Scene &scene, const MPI_Comm comm)
  {
    driver::Simulation<dim, Description> sim(scene, comm, std::cout);
    sim.setup();
    sim.run();
    std::vector<double> mine;
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto &l = sim.patch().lattice(c);
        mine.insert(mine.end(), {double(l[0]), double(l[1]), double(l[2])});
        const auto S = sim.state_si(c);
        mine.insert(mine.end(), S.begin(), S.end());
      }
    const auto                 all = Utilities::MPI::gather(comm, mine, 0);
    StateMap<dim, Description> out;
    for (const auto &v : all)
      for (std::size_t i = 0; i < v.size(); i += dim + 5)
        {
          physics::State<dim> S;
          std::copy(v.begin() + i + 3, v.begin() + i + dim + 5, S.begin());
          out[{{int(v[i]), int(v[i + 1]), int(v[i + 2])}}] = S;
        }
    return out;
  }

  /// largest relative difference (0 = bitwise equal); +inf if the cell sets differ
  template <int dim, class Description>
  double max_difference(const StateMap<dim, Description> &a, const StateMap<dim, Description> &b)
  {
    if (a.size() != b.size())
      return std::numeric_limits<double>::infinity();
    double diff = 0;
    for (const auto &[key, S] : a)
      {
        const auto it = b.find(key);
        if (it == b.end())
          return std::numeric_limits<double>::infinity();
        for (unsigned int c = 0; c < dim + 2; ++c) // relative, momenta against n
          diff = std::max(diff, std::abs(it->second[c] - S[c]) / (std::abs(S[c]) + std::abs(S[0]) * 1e-3));
      }
    return diff;
  }

  /// generated box (text) vs the same text with the mesh file: bitwise equal on the same
  /// ranks. N-rank file run vs 1-rank generated run: bitwise for convection only; the
  /// implicit step's Krylov solver sums in a partition-dependent order (mpi.equivalence:
  /// 4e-14), so the granular case allows cross_rank_tolerance
  template <int dim, class Description>
  /// the scene file `scene` with `overrides` on its generated box and on the same box read
  /// from the mesh file `mesh`
  void compare_box(const std::string &name, const std::string &scene,
                   const std::vector<std::string> &overrides, const std::string &mesh,
                   const unsigned int refinements, Checker &chk, const double cross_rank_tolerance = 0)
  {
    const MPI_Comm           world     = MPI_COMM_WORLD;
    const scene::Scene       generated = scene::read_scene(scene, overrides);
    std::vector<std::string> with_mesh = overrides;
    with_mesh.insert(with_mesh.end(),
                     {"Domain/Mesh file=" + mesh, "Domain/Mesh refinements=" + std::to_string(refinements)});
    const scene::Scene from_file = scene::read_scene(scene, with_mesh);
    const auto         a         = run<dim, Description>(generated, world);
    const auto         b         = run<dim, Description>(from_file, world);
    const unsigned int nranks    = Utilities::MPI::n_mpi_processes(world);
    if (Utilities::MPI::this_mpi_process(world) != 0)
      return;
    const double       d = max_difference<dim, Description>(a, b);
    std::ostringstream os;
    os << name << ": " << a.size() << " cells, " << nranks
       << " rank(s), file vs generated: max relative difference " << d;
    chk.check(d == 0, os.str());
    if (nranks > 1)
      {
        const auto         c  = run<dim, Description>(generated, MPI_COMM_SELF);
        const double       d1 = max_difference<dim, Description>(c, b);
        std::ostringstream os1;
        os1 << name << ": file on " << nranks << " ranks vs generated on 1 rank: max relative difference "
            << d1 << " (allowed " << cross_rank_tolerance << ")";
        chk.check(d1 <= cross_rank_tolerance, os1.str());
      }
  }

  /// the overrides of tests/data/ideal_gas_box.prm for a blast in a box with these boundaries
  std::vector<std::string> blast(const unsigned int dim, const std::array<std::string, 6> &boundary)
  {
    SceneSpec s;
    s.dim   = dim;
    s.cells = dim == 2 ? std::array<unsigned int, 3>{{32, 24, 1}} : std::array<unsigned int, 3>{{16, 12, 8}};
    s.upper = {{1, 0.75, 0.5}};
    s.boundary                 = boundary;
    s.end_time                 = 0.05;
    std::vector<std::string> o = scene_overrides(s);
    // a blast off-centre, moving, so that every wall sees a shock
    const std::string r2 = "((x-0.3)^2 + (y-0.4)^2" + std::string(dim == 3 ? " + (z-0.2)^2" : "") + ")";
    o.insert(o.end(), {"Initial state/Packing fraction=0.5 * (0.125 + 0.875 * (" + r2 + " < 0.05))",
                       "Initial state/Temperature=0.1 + 49.9 * (" + r2 + " < 0.05)",
                       std::string("Initial state/Velocity=") + (dim == 3 ? "0.3; -0.2; 0.1" : "0.3; -0.2"),
                       "Initial state/Quadrature points=2"});
    return o;
  }

  /// the ideal-gas box all blasts start from
  const std::string ideal_gas_box = std::string(GRANHYDRO_TEST_DATA_DIR) + "/ideal_gas_box.prm";

  /// 2D granular gas in a box, no-slip + moving + dissipative walls (the file beside this source)
  const std::string granular_box = std::string(GRANHYDRO_TEST_DIR) + "/granular_box_2d.prm";

  using Sim3 = driver::Simulation<3, physics::GranularGas<3>>;

  /// total mass [kg]
  double mass(const Sim3 &sim, const scene::Scene &scene)
  {
    return sim.totals()[0] * scene.grain_mass();
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                          chk;
  chk.root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  if (argc != 3)
    {
      std::cerr
        << "usage: test_mesh_files box <tests/data> | closed <silo-ci.prm> | discharge <silo-ci.prm>\n";
      return 2;
    }
  const std::string mode = argv[1], arg = argv[2];
  if (mode == "box")
    {
      compare_box<2, physics::IdealGas<2>>(
        "2D blast, slip walls, gmsh", ideal_gas_box,
        blast(2, {{"slip wall", "slip wall", "slip wall", "slip wall", "", ""}}), arg + "/box_2d.msh", 3,
        chk);
      compare_box<2, physics::IdealGas<2>>(
        "2D blast, slip/outflow/no-slip, ucd", ideal_gas_box,
        blast(2, {{"slip wall", "outflow", "no-slip wall", "slip wall", "", ""}}), arg + "/box_2d.inp", 3,
        chk);
      compare_box<3, physics::IdealGas<3>>(
        "3D blast, slip/outflow/no-slip, gmsh", ideal_gas_box,
        blast(3, {{"slip wall", "outflow", "no-slip wall", "slip wall", "slip wall", "no-slip wall"}}),
        arg + "/box_3d.msh", 2, chk);
      compare_box<2, physics::GranularGas<2>>(
        "2D granular gas, gravity, no-slip + moving + dissipative walls, gmsh", granular_box, {},
        arg + "/box_2d.msh", 3, chk, 1e-12);
    }
  else if (mode == "closed" || mode == "discharge")
    {
      std::vector<std::string> overrides = {"Output/Write VTU=false", "Output/Write profiles=false",
                                            "Output/Verbose=false"};
      if (mode == "closed") // outlet bottom closed by a no-slip wall; 40 steps
        overrides.insert(overrides.end(), {"Domain/Boundary y-=no-slip wall", "Time/Maximum steps=40"});
      const scene::Scene scene = scene::read_scene(arg, overrides);
      Sim3               sim(scene, MPI_COMM_WORLD, std::cout);
      sim.setup();
      const double M0      = mass(sim, scene);
      const auto   summary = sim.run();
      const double M1      = mass(sim, scene);
      std::string  what;
      chk.check(sim.convection().admissible(sim.state(), &what), "admissible final state " + what);
      if (chk.root)
        std::cout << "  " << summary.steps << " steps to t = " << summary.time_si << " s; mass " << M0
                  << " kg -> " << M1 << " kg (relative change " << (M1 - M0) / M0 << ")\n";
      if (mode == "closed")
        chk.check(std::abs(M1 - M0) <= 1e-12 * M0, "closed silo: mass conserved to 1e-12 relative");
      else
        {
          chk.check(std::abs(summary.time_si - scene.end_time) < 1e-12 * scene.end_time,
                    "the run reaches its end time");
          // Upper bound: the grains leave through the outlet bottom, 8 mm x 10 mm. Nothing
          // in the silo moves faster than free fall from the top of the bed (y = 40 mm) to
          // the outlet bottom (y = 0), v <= sqrt(2 g h) with h = 0.04 m (pressure gradients
          // in a bed under gravity only slow it), and nothing is denser than close packing
          // (phi_c = 0.64), so the outflow rate is at most rho_s phi_c A sqrt(2 g h)
          // for the whole run: a generous bound (most of the run the outlet holds a
          // dilute jet that has not reached free-fall speed).
          const double A = 0.008 * 0.010, g = 9.81, h = 0.04, t = scene.end_time;
          const double bound =
            scene.material_density * scene.phi_close_packing * A * std::sqrt(2 * g * h) * t;
          // Lower bound: the outlet starts with phi = 1e-3 over 8 x 8 x 10 mm; it empties
          // in free fall within sqrt(2 * 8 mm / g) = 40 ms, and the bed above the orifice
          // follows. Require at least the initial content of the outlet channel.
          const double outlet0 = scene.material_density * 1e-3 * 0.008 * 0.008 * 0.010;
          if (chk.root)
            std::cout << "  discharged " << M0 - M1 << " kg; free-fall bound " << bound
                      << " kg; initial outlet content " << outlet0 << " kg\n";
          chk.check(M1 < M0, "the total mass decreases");
          chk.check(M0 - M1 > outlet0, "more than the outlet channel's initial content left");
          // and the bed itself flows: at least 1 % of the free-fall bound (measured: 8.8 %)
          chk.check(M0 - M1 > 0.01 * bound, "more than 1 % of the free-fall bound left (the bed flows)");
          chk.check(M0 - M1 < bound, "less than the free-fall bound rho_s phi_c A sqrt(2 g h) t left");
        }
    }
  else
    {
      std::cerr << "unknown mode " << mode << "\n";
      return 2;
    }
  return chk.failed != 0;
}
