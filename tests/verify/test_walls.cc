// Boundary types with known answers:
//  1. a slip wall reflects a 1D shock exactly as the symmetric Riemann problem
//     (mirror data across the wall): the half-domain run with the wall equals the
//     left half of the full symmetric run bit for bit;
//  2. an elastic closed box (granular, eps = 1, viscosity and heat conduction, no
//     gravity) conserves mass and energy to round-off, with slip walls and with
//     no-slip walls at rest (no work, no heat through the walls);
//  3. a dissipative wall drains energy at the rate of doc/physics.md 5.2:
//     dE/dt = -(1 - eps_w) p sqrt(2 T/(pi m)) per unit wall area for a uniform gas at rest.
#include "common/test_common.h"

#include <iomanip>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  // ---- 1. slip wall = symmetric Riemann problem --------------------------------------
  {
    SceneSpec half;
    half.cells     = {{100, 1, 1}};
    half.upper     = {{0.5, 1, 1}};
    half.boundary  = {{"outflow", "slip wall", "", "", "", ""}};
    half.end_time  = 0.15;
    SceneSpec full = half;
    full.cells     = {{200, 1, 1}};
    full.upper     = {{1, 1, 1}};
    full.boundary  = {{"outflow", "outflow", "", "", "", ""}};
    auto state     = [](const dealii::Point<1> &x) {
      const double u = x[0] < 0.5 ? 1. : -1.; // gas running into the wall / its mirror image
      return conservative<1>(1., &u, 1., 5. / 3.);
    };
    driver::Simulation<1> a(make_scene(half), MPI_COMM_SELF, std::cout),
      b(make_scene(full), MPI_COMM_SELF, std::cout);
    a.setup();
    b.setup();
    a.set_initial_state(state, 1);
    b.set_initial_state(state, 1);
    a.run();
    b.run();
    std::map<int, physics::State<1>> fb;
    for (unsigned int c = 0; c < b.patch().n_owned(); ++c)
      fb[b.patch().lattice(c)[0]] = b.state_si(c);
    double diff = 0, rho_wall = 0;
    for (unsigned int c = 0; c < a.patch().n_owned(); ++c)
      {
        const auto S = a.state_si(c);
        const int  i = a.patch().lattice(c)[0];
        for (unsigned int k = 0; k < 3; ++k)
          diff = std::max(diff, std::abs(S[k] - fb[i][k]));
        if (i == 99)
          rho_wall = S[0];
      }
    std::ostringstream os;
    os << "slip wall reflects a shock exactly as the symmetric problem: max difference " << diff
       << " (density at the wall " << rho_wall << ")";
    // same arithmetic up to the order of a few additions: round-off of O(1) states
    chk.check(diff < 1e-13 && rho_wall > 1.5, os.str());
  }
  // ---- 2. elastic closed boxes conserve mass and energy ------------------------------
  for (const std::string walls : {"slip wall", "no-slip wall"})
    {
      // walls_box.prm as it is, or with no-slip walls
      std::vector<std::string> o;
      for (const char *b : {"x-", "x+", "y-", "y+"})
        o.push_back(std::string("Domain/Boundary ") + b + "=" + walls);
      const scene::Scene                             box = test_scene("walls_box.prm", o);
      driver::Simulation<2, physics::GranularGas<2>> sim(box, MPI_COMM_SELF, std::cout);
      sim.setup();
      const auto   before = sim.totals();
      const auto   sum    = sim.run();
      const auto   after  = sim.totals();
      const double dm     = std::abs(after[0] - before[0]) / before[0],
                   de     = std::abs(after[3] - before[3]) / before[3];
      std::ostringstream os;
      os << "elastic closed box with " << walls << "s, " << sum.steps << " Strang steps with viscosity and "
         << "heat conduction: mass drift " << dm << ", energy drift " << de;
      // flux form in both steps and the final stage slopes f(Y) of the implicit step: round-off
      chk.check(sum.steps == 40 && dm < 1e-13 && de < 1e-13, os.str());
    }
  // ---- 3. dissipative walls drain energy at the rate of doc/physics.md 5.2 ----------------
  {
    // walls_box.prm with dissipative walls, a uniform gas and one step: the
    // values of the rate formula are these C++ constants, passed as overrides;
    // sigma, the grain mass and the box side are read back from the scene
    const double             phi = 0.2, T = 1e-8, eps_w = 0.8, dt = 1e-6;
    std::vector<std::string> o{"Initial state/Packing fraction=" + number(phi),
                               "Initial state/Temperature=" + number(T),
                               "Numerics/Fixed time step=" + number(dt), "Time/Maximum steps=1"};
    for (const char *b : {"x-", "x+", "y-", "y+"})
      o.push_back(std::string("Domain/Wall restitution ") + b + "=" + number(eps_w));
    const scene::Scene box   = test_scene("walls_box.prm", o);
    const double       sigma = box.grain_diameter, m = box.grain_mass(), L = box.upper[0] - box.lower[0];
    driver::Simulation<2, physics::GranularGas<2>> sim(box, MPI_COMM_SELF, std::cout);
    sim.setup();
    const auto before = sim.totals();
    sim.run();
    const auto                    after = sim.totals();
    const double                  n     = 6 * phi / (M_PI * sigma * sigma * sigma);
    const physics::GarzoDufty1999 gd(1.0);
    const double                  p  = gd.pressure(n, T, m, sigma);
    const double                  qw = (1 - eps_w) * p * std::sqrt(2 * T / (M_PI * m)); // W/m^2
    // totals() are scaled: energy density * area / sigma^2 -> SI energy per unit depth
    const double       E_unit = sim.units().pressure() * sigma * sigma;
    const double       rate   = (after[3] - before[3]) * E_unit / dt; // W per m of depth
    const double       exact  = -qw * 4 * L;                          // four walls of 0.02 m
    std::ostringstream os;
    os << "dissipative walls (eps_w = 0.8): energy loss rate " << std::scientific << std::setprecision(6)
       << rate << " W/m vs (1 - eps_w) p sqrt(2T/(pi m)) x perimeter = " << exact;
    // first step of a uniform gas: the rate is exact up to O(dt) changes of p and T near the walls
    chk.check(std::abs(rate / exact - 1) < 1e-3, os.str());
  }
  // ---- 4. no-slip walls: the paper's pressure flux carries no tangential momentum -----
  // A gas sliding along two no-slip walls at rest (ideal gas: convection only, x periodic).
  // With the mirror flux the convective flux through the walls has a tangential part (a
  // numerical wall friction); with 'No-slip wall flux = pressure' (paper eq. 6.1a) it has
  // none, so the x-momentum stays at its initial value to round-off.
  {
    SceneSpec spec;
    spec.dim      = 2;
    spec.cells    = {{8, 16, 1}};
    spec.boundary = {{"periodic", "periodic", "no-slip wall", "no-slip wall", "periodic", "periodic"}};
    spec.end_time = 0.2;
    double drift[2];
    for (const bool pressure : {false, true})
      {
        std::vector<std::string> o{"Initial state/Velocity=1; 0"};
        if (pressure)
          o.push_back("Numerics/No-slip wall flux=pressure");
        const scene::Scene                          sliding = make_scene(spec, o);
        driver::Simulation<2, physics::IdealGas<2>> sim(sliding, MPI_COMM_SELF, std::cout);
        sim.setup();
        const auto before = sim.totals();
        sim.run();
        const auto after = sim.totals();
        drift[pressure]  = std::abs(after[1] - before[1]) / std::abs(before[1]);
      }
    std::ostringstream os;
    os << "gas sliding along no-slip walls: x-momentum change " << drift[0] << " (mirror flux), " << drift[1]
       << " (pressure flux, paper 6.1a)";
    // pressure flux: only round-off of the flux sums (1e-13); mirror: an O(1) friction
    chk.check(drift[1] < 1e-13 && drift[0] > 1e-3, os.str());
  }
  return chk.failed != 0;
}
