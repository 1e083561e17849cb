// Mass, momentum and energy are conserved
// to 1e-13 relative on a periodic box over 1000 steps, with a strong blast so
// that shocks, the positivity limiter and the a-posteriori first-order fallback
// are exercised. The scheme is conservative by construction (one flux per face,
// added to one cell and subtracted from the other), so only round-off remains:
// about 1e-16 per cell update, random in sign, i.e. ~1e-16 * sqrt(steps*stages/cells)
// of the total, far below 1e-13.
#include "common/test_common.h"

using namespace granhydro;
using namespace granhydro::testing;

template <int dim>
void check_conservation(const unsigned int N, Checker &chk)
{
  SceneSpec s;
  s.dim = dim;
  for (unsigned int d = 0; d < 3; ++d)
    {
      s.cells[d]            = d < dim ? N : 1;
      s.boundary[2 * d]     = "periodic";
      s.boundary[2 * d + 1] = "periodic";
    }
  s.end_time  = 1e6;
  s.max_steps = 1000;
  driver::Simulation<dim> sim(make_scene(s), MPI_COMM_WORLD, std::cout);
  sim.setup();
  // blast (pressure ratio 1000) off-centre on top of a moving density wave
  sim.set_initial_state(
    [&](const dealii::Point<dim> &x) {
      double r2 = 0;
      for (unsigned int d = 0; d < dim; ++d)
        r2 += (x[d] - 0.4) * (x[d] - 0.4);
      const double u[3] = {0.5, -0.3, 0.2};
      const double rho  = 1 + 0.3 * std::sin(2 * M_PI * x[0]);
      return conservative<dim>(rho, u, r2 < 0.04 ? 100. : 0.1, 5. / 3.);
    },
    2);
  const auto before  = sim.totals();
  const auto summary = sim.run();
  const auto after   = sim.totals();
  // momentum scale: total mass times the largest initial sound speed (p = 100, rho >= 0.7)
  const double mom_scale = before[0] * std::sqrt(5. / 3. * 100 / 0.7);
  double       err[dim + 2];
  for (unsigned int c = 0; c < dim + 2; ++c)
    err[c] = std::abs(after[c] - before[c]) / (c == 0 || c == dim + 1 ? std::abs(before[c]) : mom_scale);
  std::ostringstream os;
  os << dim << "D periodic blast, " << summary.steps << " steps (a-posteriori fallbacks "
     << summary.convection.fallback_cells << ", reconstruction resets " << summary.convection.limited_cells
     << "): relative drift mass " << err[0];
  for (unsigned int d = 0; d < dim; ++d)
    os << ", momentum_"
       << "xyz"[d] << ' ' << err[1 + d];
  os << ", energy " << err[dim + 1];
  bool ok = summary.steps == 1000;
  for (unsigned int c = 0; c < dim + 2; ++c)
    ok = ok && err[c] < 1e-13;
  chk.check(ok, os.str());
}

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                                  chk;
  chk.root = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  check_conservation<1>(100, chk);
  check_conservation<2>(32, chk);
  check_conservation<3>(16, chk);
  return chk.failed != 0;
}
