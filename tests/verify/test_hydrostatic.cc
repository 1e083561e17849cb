// Isothermal hydrostatic column (doc/physics.md 6(d)): elastic
// grains (eps = 1: no cooling, mu = 0), gravity -g e_x, slip walls at bottom and top,
// started from the exact equilibrium profile G(phi(y)) = G(phi0) - (m g / T) y with
// G = ln phi + Z + 2 (1 + eps) X (cell averages by Gauss quadrature). After 1000
// steps of the full scheme (Strang splitting, WENO5 + MUSTA convection, implicit
// Gauss-Legendre diffusion/gravity step) the density profile must stay within 1e-3
// relative and the spurious velocities below 1e-3 sqrt(g sigma), shrinking under
// refinement; one column is dense (phi0 = 0.5), one over-dense (bottom phi0 = 0.62,
// above 0.6, where chi is on Torquato's branch towards close packing).
#include <deal.II/base/quadrature_lib.h>

#include "common/test_common.h"

#include <iomanip>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  // the scene is hydrostatic.prm beside this file; sigma, rho_s and g of the
  // exact profile are read back from it (constants_from()), each column's height,
  // cell count and temperature are C++ values passed as overrides (make_scene())
  double sigma, rho_s, g, m;

  void constants_from(const scene::Scene &s)
  {
    sigma = s.grain_diameter;
    rho_s = s.material_density;
    g     = -s.gravity[0];
    m     = rho_s * M_PI * sigma * sigma * sigma / 6;
  }

  struct Column
  {
    double phi0, T, height;
  };

  scene::Scene make_scene(const Column &c, const unsigned int N, const bool well_balanced)
  {
    return test_scene(
      "hydrostatic.prm",
      {"Domain/Upper corner=" + number(c.height), "Domain/Cells=" + std::to_string(N),
       "Initial state/Temperature=" + number(c.T),
       std::string("Numerics/Gravity scheme=") + (well_balanced ? "well-balanced" : "split")});
  }

  double G(const physics::GarzoDufty1999 &gd, const double phi)
  {
    return std::log(phi) + gd.Z(phi) + 2 * (1 + gd.eps()) * gd.pair_correlation().integral(phi);
  }

  /// phi(y) of the exact isothermal profile, by bisection (G increases with phi)
  double phi_exact(const physics::GarzoDufty1999 &gd, const Column &c, const double y)
  {
    const double target = G(gd, c.phi0) - m * g / c.T * y;
    double       lo = 1e-12, hi = c.phi0;
    for (int i = 0; i < 200; ++i)
      {
        const double mid                = 0.5 * (lo + hi);
        (G(gd, mid) < target ? lo : hi) = mid;
      }
    return 0.5 * (lo + hi);
  }

  /// returns (max relative density deviation, max |u| / sqrt(g sigma))
  std::pair<double, double> run(const Column &c, const unsigned int N, const bool well_balanced = false)
  {
    const physics::GarzoDufty1999                  gd(1.0);
    driver::Simulation<1, physics::GranularGas<1>> sim(make_scene(c, N, well_balanced), MPI_COMM_SELF,
                                                       std::cout);
    sim.setup();
    sim.set_initial_state(
      [&](const dealii::Point<1> &x) {
        const double phi = phi_exact(gd, c, x[0]);
        const double n   = 6 * phi / (M_PI * sigma * sigma * sigma);
        return physics::State<1>{{n, 0., 1.5 * n * c.T}};
      },
      well_balanced ? 1 : 4);
    std::vector<double> n0(sim.patch().n_owned());
    for (unsigned int i = 0; i < n0.size(); ++i)
      n0[i] = sim.state_si(i)[0];
    const auto sum = sim.run();
    AssertThrow(sum.steps == 1000, dealii::ExcMessage("the column did not run 1000 steps"));
    double dn = 0, du = 0;
    for (unsigned int i = 0; i < n0.size(); ++i)
      {
        const auto S = sim.state_si(i);
        dn           = std::max(dn, std::abs(S[0] - n0[i]) / n0[i]);
        du           = std::max(du, std::abs(S[1] / S[0]) / std::sqrt(g * sigma));
      }
    return {dn, du};
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  constants_from(test_scene("hydrostatic.prm"));
  for (const Column &c : {Column{0.5, 1e-6, 0.05}, Column{0.62, 1e-7, 0.02}})
    {
      std::vector<double> us;
      for (const unsigned int N : {50u, 100u})
        {
          const auto [dn, du] = run(c, N);
          us.push_back(du);
          std::ostringstream os;
          os << "column phi0 = " << c.phi0 << ", T = " << c.T << " J, " << N
             << " cells, 1000 steps: max |dn|/n = " << std::scientific << std::setprecision(2) << dn
             << ", max |u|/sqrt(g sigma) = " << du;
          chk.check(dn <= 1e-3 && du <= 1e-3, os.str());
        }
      for (const unsigned int N : {50u, 100u})
        {
          // well-balanced gravity from the discrete equilibrium (the exact profile's point
          // values at the cell centres lie on one isothermal equilibrium): at rest to
          // round-off, the bound 1e-12 sqrt(g sigma) for 1000 steps
          const auto [dn, du] = run(c, N, true);
          std::ostringstream os;
          os << "well-balanced column phi0 = " << c.phi0 << ", " << N
             << " cells, 1000 steps: max |dn|/n = " << std::scientific << std::setprecision(2) << dn
             << ", max |u|/sqrt(g sigma) = " << du;
          chk.check(dn <= 1e-12 && du <= 1e-12, os.str());
        }
      const double order = std::log(us[0] / us[1]) / std::log(2.);
      chk.check(us[1] < us[0], "column phi0 = " + std::to_string(c.phi0) +
                                 ": spurious velocity shrinks under refinement (observed order " +
                                 std::to_string(order) + ")");
    }
  return chk.failed != 0;
}
