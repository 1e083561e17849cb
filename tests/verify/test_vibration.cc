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
  const double A = 0.004, f = 12, w = 2 * M_PI * f;

  std::string scene_text(const std::string &walls, double phi, double T, double t_end, double dt)
  {
    std::ostringstream os;
    os.precision(17);
    os
      << "set Dimension = 1\nsubsection Domain\n  set Lower corner = 0\n  set Upper corner = 0.02\n"
      << "  set Cells = 20\n  set Boundary x- = " << walls << "\n  set Boundary x+ = " << walls << "\nend\n"
      << "subsection Material\n  set Model = granular\n  set Restitution coefficient = 1\nend\n"
      << "subsection Effects\n  set Vibration amplitude = " << A << "\n  set Vibration frequency = " << f
      << "\n  set Vibration direction = x\nend\n"
      << "subsection Initial state\n  set Packing fraction = " << phi << "\n  set Velocity = 0\n"
      << "  set Temperature = " << T << "\nend\n"
      << "subsection Numerics\n  set Fixed time step = " << dt << "\nend\n"
      << "subsection Diffusion step\n  set Integrator = gauss-legendre\n  set Newton tolerance = 1e-13\nend\n"
      << "subsection Time\n  set End time = " << t_end << "\nend\n"
      << quiet_output;
    return os.str();
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  {
    const double                                   t_end = 0.03;
    driver::Simulation<1, physics::GranularGas<1>> sim(
      scene::parse_scene(scene_text("periodic", 0.3, 1e-7, t_end, 1e-4), "periodic"), MPI_COMM_SELF,
      std::cout);
    sim.setup();
    const auto   s0    = sim.state_si(0);
    const auto   sum   = sim.run();
    const double exact = A * w * (1 - std::cos(w * sum.time_si));
    double       du = 0, dn = 0, dT = 0;
    const double m = 2600 * M_PI * 1e-9 / 6;
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
    const double                                   period = 1 / f;
    driver::Simulation<1, physics::GranularGas<1>> sim(
      scene::parse_scene(scene_text("slip wall", 0.5, 1e-6, period, 2e-5), "closed"), MPI_COMM_SELF,
      std::cout);
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
