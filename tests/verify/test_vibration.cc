// Vibrated container as a non-inertial frame (doc/physics.md 5.3):
//  1. uniform elastic gas in a periodic box (no walls to push it): in the container
//     frame it accelerates uniformly with g_eff(t) = A w^2 sin(w t), u(t) = A w (1 - cos w t),
//     with n and T unchanged; in the lab frame (output adds ds/dt = A w cos w t) it moves
//     at the constant A w. The implicit step evaluates the force at its stage times, so
//     Gauss-Legendre (set explicitly) integrates it to 4th order: asserted to 1e-8 relative.
//  2. a closed box (slip walls) of a dense, stiff gas (acoustic time 2 ms << period
//     83 ms): the gas stays at rest in the container frame apart from the quasi-static
//     hydrostatic response to g_eff(t): after a full period max |u| is below 2 % of the
//     box speed A w, and mass is conserved to round-off.
#include "common/test_common.h"

#include <iomanip>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  // the scene is vibration.prm beside this file (the periodic box); the
  // vibration's A and f of the exact solution are read back from it
  // (constants_from())
  double A, f, w;

  void constants_from(const scene::Scene &s)
  {
    A = s.vibration_amplitude;
    f = s.vibration_frequency;
    w = 2 * M_PI * f;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  const scene::Scene                       periodic = test_scene("vibration.prm");
  constants_from(periodic);
  {
    driver::Simulation<1, physics::GranularGas<1>> sim(periodic, MPI_COMM_SELF, std::cout);
    sim.setup();
    const auto   s0    = sim.state_si(0);
    const auto   sum   = sim.run();
    const double exact = A * w * (1 - std::cos(w * sum.time_si));
    double       du = 0, dn = 0, dT = 0;
    const double m = periodic.grain_mass();
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto   S  = sim.state_si(c);
        const double u  = S[1] / S[0];
        du              = std::max(du, std::abs(u - exact) / exact);
        dn              = std::max(dn, std::abs(S[0] - s0[0]) / s0[0]);
        const double T  = (2. / 3.) * (S[2] / S[0] - 0.5 * m * u * u);
        const double T0 = (2. / 3.) * s0[2] / s0[0];
        dT              = std::max(dT, std::abs(T - T0) / T0);
      }
    std::ostringstream os;
    os << "periodic box: container-frame velocity " << std::setprecision(10) << exact * (1 + du)
       << " m/s vs A w (1 - cos w t) = " << exact << " (rel. " << std::scientific << std::setprecision(2)
       << du << "), n and T unchanged to " << std::max(dn, dT) << "; lab-frame velocity A w = " << A * w;
    chk.check(du < 1e-8 && dn < 1e-13 && dT < 1e-10, os.str());
  }
  {
    // the closed box: slip walls, a dense stiff gas, one period
    const scene::Scene closed =
      test_scene("vibration.prm", {"Domain/Boundary x-=slip wall", "Domain/Boundary x+=slip wall",
                                   "Initial state/Packing fraction=0.5", "Initial state/Temperature=1e-6",
                                   "Time/End time=" + number(1 / f), "Numerics/Fixed time step=2e-5"});
    driver::Simulation<1, physics::GranularGas<1>> sim(closed, MPI_COMM_SELF, std::cout);
    sim.setup();
    const auto before = sim.totals();
    double     umax   = 0; // at the end of the period
    const auto sum    = sim.run();
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto S = sim.state_si(c);
        umax         = std::max(umax, std::abs(S[1] / S[0]));
      }
    const auto         after = sim.totals();
    std::ostringstream os;
    os << "closed box, dense gas, one period (" << sum.steps << " steps): max |u| in the container frame "
       << std::scientific << std::setprecision(2) << umax << " m/s = " << umax / (A * w)
       << " of the box speed A w, mass drift " << std::abs(after[0] - before[0]) / before[0];
    chk.check(umax < 0.02 * A * w && std::abs(after[0] - before[0]) < 1e-13 * before[0], os.str());
  }
  return chk.failed != 0;
}
