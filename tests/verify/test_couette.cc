// Plane Couette flow between no-slip adiabatic walls (doc/physics.md 6(c)): walls at y = 0 and y = H move with -+ gdot H/2 along x, no gravity.
// The uniform state with a linear velocity profile is an exact solution whose
// temperature follows ds/dt = A - B s^2 (s = sqrt(T), A = eta^ gdot^2/(3n),
// B = zeta^/2) towards the simple-shear steady state T_s, where viscous heating
// (supplied by the walls' shear stress, doc/physics.md 5.1 / P10) balances cooling.
// Checks the transient at 0.05 s and the steady state to 1 % (phi = 0.3, eps = 0.9,
// gdot = 10/s: T_s = 1.683131e-10 J, T(0.05 s) = 1.896610e-9 J from T0 = 1e-8 J),
// and that with slip walls (no wall shear stress) the gas just cools (Haff).
#include "common/test_common.h"

#include <iomanip>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  // the scene is couette.prm beside this file; the numbers of the exact solution
  // are read back from it (constants_from()), not written here again
  double       sigma, rho_s, phi, eps, gdot, T0, H;
  unsigned int N;

  void constants_from(const scene::Scene &s)
  {
    sigma = s.grain_diameter;
    rho_s = s.material_density;
    eps   = s.restitution;
    phi   = constant_expression(s.initial_packing_fraction);
    T0    = constant_expression(s.initial_temperature);
    H     = s.upper[1] - s.lower[1];
    N     = s.cells[1];
    gdot  = (s.wall_velocity[3][0] - s.wall_velocity[2][0]) / H; // walls at -+ gdot H/2
  }

  /// the scene of a case: couette.prm (no-slip walls) with the end time and the
  /// walls set
  scene::Scene make_scene(const double t_end, const std::string &walls)
  {
    std::vector<std::string> o{"Time/End time=" + number(t_end)};
    if (walls != "no-slip wall")
      o.insert(o.end(), {"Domain/Boundary y-=" + walls, "Domain/Boundary y+=" + walls,
                         "Domain/Wall velocity y-=0, 0, 0", "Domain/Wall velocity y+=0, 0, 0"});
    return test_scene("couette.prm", o);
  }

  /// exact homogeneous temperature under shear (doc/physics.md 6(c))
  double T_exact(const double t, const double shear)
  {
    const physics::GarzoDufty1999 gd(eps);
    const double m = rho_s * M_PI * sigma * sigma * sigma / 6, n = 6 * phi / (M_PI * sigma * sigma * sigma);
    const double eta_hat  = gd.eta(n, 1., m, sigma);   // eta = eta_hat sqrt(T)
    const double zeta_hat = gd.zeta0(n, 1., m, sigma); // zeta0 = zeta_hat sqrt(T)
    const double A = eta_hat * shear * shear / (3 * n), B = zeta_hat / 2, s0 = std::sqrt(T0);
    if (A == 0)
      return T0 / std::pow(1 + B * s0 * t, 2); // Haff: ds/dt = -B s^2
    const double sinf = std::sqrt(A / B), k = std::sqrt(A * B);
    const double s = s0 < sinf ? sinf * std::tanh(k * t + std::atanh(s0 / sinf)) :
                                 sinf / std::tanh(k * t + std::atanh(sinf / s0));
    return s * s;
  }

  /// max relative deviation of the cell temperatures from T_exact(t_end)
  double run(const double t_end, const std::string &walls, double &T_mean)
  {
    driver::Simulation<2, physics::GranularGas<2>> sim(make_scene(t_end, walls), MPI_COMM_SELF, std::cout);
    sim.setup();
    const auto sum = sim.run();
    AssertThrow(sum.diffusion.newton_failures == 0, dealii::ExcMessage("Newton failed"));
    const double m     = rho_s * M_PI * sigma * sigma * sigma / 6;
    const double exact = T_exact(t_end, walls == "no-slip wall" ? gdot : 0.);
    double       worst = 0;
    T_mean             = 0;
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto   S = sim.state_si(c);
        const double n = S[0], ux = S[1] / n, uy = S[2] / n;
        // cell averages of a linear profile carry m gdot^2 h^2/24 of sub-cell kinetic
        // energy per grain that is not temperature: T = (2/3)(E - m u^2/2 - m gdot^2 h^2/24)
        const double h     = H / N;
        const double shear = walls == "no-slip wall" ? gdot : 0.;
        const double T =
          (2. / 3.) * (S[3] / n - 0.5 * m * (ux * ux + uy * uy) - m * shear * shear * h * h / 24);
        worst = std::max(worst, std::abs(T - exact) / exact);
        T_mean += T / sim.patch().n_owned();
      }
    return worst;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  constants_from(test_scene("couette.prm"));
  // the exact formula reproduces doc/physics.md's numbers
  chk.check(
    std::abs(T_exact(0.05, gdot) / 1.896610e-9 - 1) < 1e-6 &&
      std::abs(T_exact(100., gdot) / 1.683131e-10 - 1) < 1e-6,
    "exact shear transient reproduces doc/physics.md 6(c): T(0.05 s) = 1.896610e-9 J, T_s = 1.683131e-10 J");
  for (const double t : {0.05, 0.2, 1.5})
    {
      double             Tm;
      const double       e = run(t, "no-slip wall", Tm);
      std::ostringstream os;
      os << "Couette, no-slip walls moving -+" << gdot * H / 2 << " m/s, t = " << t
         << " s: T = " << std::scientific << std::setprecision(6) << Tm << " J vs exact " << T_exact(t, gdot)
         << ", max cell deviation " << std::setprecision(2) << e << " (<= 1 %)";
      chk.check(e <= 0.01, os.str());
    }
  {
    double             Tm;
    const double       e = run(0.2, "slip wall", Tm);
    std::ostringstream os;
    os << "slip walls (no wall shear stress): the shear decays and the gas cools, T(0.2 s) = "
       << std::scientific << std::setprecision(4) << Tm << " J, below the sheared " << T_exact(0.2, gdot)
       << " J";
    chk.check(Tm < 0.9 * T_exact(0.2, gdot), os.str());
    (void)e;
  }
  return chk.failed != 0;
}
