// Measured order of accuracy in L1 on
// smooth periodic problems, on the finest pair of a refinement ladder, with a
// time step small enough that SSP-RK3 (third order) does not limit it:
//  - 1D density wave, WENO5: >= 4.5 (dt ~ h^(5/3), so dt^3 ~ h^5)
//  - 2D and 3D isentropic vortex (nonlinear flux), WENO5: >= 3.5 with 2x2 Gauss
//    points per face (2-point Gauss caps the order at 4; dt ~ h^(4/3)), and about 2
//    with the single face-midpoint point (the flux of the face average is a second
//    order approximation of the face-averaged flux).
// The 3D vortex has its axis along (1,1,1)/sqrt(3), so all three directions and
// both transverse reconstruction stages carry the solution.
//   test_order [1d|2d|3d|all] [--study]   (--study: longer ladders, no assertions; with
//   --study, GRANHYDRO_ORDER_LADDER=16,24,32 replaces the ladder of each dimension run and
//   GRANHYDRO_ORDER_END_TIME the vortex's end time 1)
#include <deal.II/base/quadrature_lib.h>

#include "common/test_common.h"

#include <chrono>
#include <iomanip>
#include <sstream>

using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  constexpr double gamma_a    = 5. / 3.;
  constexpr double L          = 10.;   // vortex box edge
  constexpr double beta       = 5.;    // vortex strength (Shu's standard vortex)
  bool             study_mode = false; // the GRANHYDRO_ORDER_* variables are read only then

  /// density wave: rho = 1 + 0.2 sin(2 pi (x - t)), u = 1, p = 1 (exact: advected)
  physics::State<1> density_wave(const double x, const double t)
  {
    const double u = 1;
    return conservative<1>(1 + 0.2 * std::sin(2 * M_PI * (x - t)), &u, 1., gamma_a);
  }

  /// isentropic vortex (Shu 1998) with axis a through the box centre, advected by v;
  /// the periodic field is the sum over the nearest image lines (nearest images are
  /// at least 8.16 apart; their overlap is below 1e-13, so the sum is an exact
  /// solution to round-off)
  template <int dim>
  physics::State<dim> vortex(const dealii::Point<dim> &x, const double t)
  {
    const double a[3] = {dim == 3 ? 1 / std::sqrt(3.) : 0, dim == 3 ? 1 / std::sqrt(3.) : 0,
                         dim == 3 ? 1 / std::sqrt(3.) : 1};
    const double v[3]  = {1, dim == 3 ? -1. : 1., 0}; // perpendicular to a in 3D
    double       du[3] = {0, 0, 0}, dT = 0;
    // distinct image lines: shifts by L(i, j, 0); in 3D a shift along (1,1,1) maps the
    // axis onto itself, so (i, j, 0) with |i|,|j| <= 3 covers every line within
    // sqrt(70) of the box (contributions beyond are below 1e-15)
    const int K = dim == 3 ? 3 : 1;
    for (int i = -K; i <= K; ++i)
      for (int j = -K; j <= K; ++j)
        for (int k = 0; k <= 0; ++k)
          {
            double    y[3]     = {0, 0, 0};
            const int shift[3] = {i, j, k};
            for (int d = 0; d < 3; ++d)
              y[d] = (d < dim ? x[d] : 0.) - L / 2 - v[d] * t + L * shift[d];
            const double ya = y[0] * a[0] + y[1] * a[1] + y[2] * a[2];
            for (int d = 0; d < 3; ++d)
              y[d] -= ya * a[d];
            const double r2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
            if (r2 > 70)
              continue;
            const double f = beta / (2 * M_PI) * std::exp(0.5 * (1 - r2));
            du[0] += f * (a[1] * y[2] - a[2] * y[1]);
            du[1] += f * (a[2] * y[0] - a[0] * y[2]);
            du[2] += f * (a[0] * y[1] - a[1] * y[0]);
            dT += -(gamma_a - 1) * beta * beta / (8 * gamma_a * M_PI * M_PI) * std::exp(1 - r2);
          }
    const double T   = 1 + dT;
    const double rho = std::pow(T, 1 / (gamma_a - 1));
    double       u[3];
    for (int d = 0; d < 3; ++d)
      u[d] = v[d] + du[d];
    return conservative<dim>(rho, u, rho * T, gamma_a);
  }

  struct Result
  {
    double              error, wall;
    std::vector<double> rho; // owned cell densities (same order for runs on the same mesh)
  };

  template <int dim>
  Result run(const unsigned int N, const std::string &quadrature, const MPI_Comm comm)
  {
    SceneSpec s;
    s.dim            = dim;
    s.quadrature     = quadrature;
    const double len = dim == 1 ? 1. : L;
    const double h   = len / N;
    for (unsigned int d = 0; d < 3; ++d)
      {
        s.cells[d]            = d < dim ? N : 1;
        s.upper[d]            = len;
        s.boundary[2 * d]     = "periodic";
        s.boundary[2 * d + 1] = "periodic";
      }
    const unsigned int nq = dim == 3 ? 3 : 4; // exact enough: Gauss error ~h^(2nq) << scheme error
    double             t_end;
    if (dim == 1)
      {
        t_end = 0.5;
        // CFL 0.17 at h = 1/20, then dt ~ h^(5/3)
        s.fixed_dt = 0.17 * h * std::pow(h / 0.05, 2. / 3.);
      }
    else
      {
        t_end = 1.0;
        if (const char *e = study_mode ? std::getenv("GRANHYDRO_ORDER_END_TIME") : nullptr)
          t_end = std::atof(e);
        // CFL-limited at h = 0.5, then dt ~ h^(4/3)
        s.fixed_dt = (dim == 2 ? 0.08 : 0.05) * h * std::pow(h / 0.5, 1. / 3.);
      }
    if (const char *f = std::getenv("GRANHYDRO_DT_FACTOR")) // studies: check dt does not limit
      s.fixed_dt *= std::atof(f);
    s.end_time = t_end;
    s.cfl      = 0.45;
    driver::Simulation<dim> sim(make_scene(s), comm, std::cout);
    sim.setup();
    const auto exact = [&](const dealii::Point<dim> &x, const double t) {
      if constexpr (dim == 1)
        return density_wave(x[0], t);
      else
        return vortex<dim>(x, t);
    };
    sim.set_initial_state([&](const dealii::Point<dim> &x) { return exact(x, 0.); }, nq);
    const auto t0 = std::chrono::steady_clock::now();
    sim.run();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // L1 error of the density against the exact cell averages
    const dealii::QGauss<1> q1(nq);
    double                  err = 0;
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      {
        const auto &ijk = sim.patch().lattice(c);
        double      avg = 0;
        for (unsigned int i = 0; i < nq; ++i)
          for (unsigned int j = 0; j < (dim > 1 ? nq : 1); ++j)
            for (unsigned int k = 0; k < (dim > 2 ? nq : 1); ++k)
              {
                const unsigned int id[3] = {i, j, k};
                dealii::Point<dim> x;
                double             w = 1;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    x[d] = (ijk[d] + q1.point(id[d])[0]) * h;
                    w *= q1.weight(id[d]);
                  }
                avg += w * exact(x, t_end)[0];
              }
        err += std::abs(sim.state_si(c)[0] - avg) * std::pow(h, dim);
      }
    err = dealii::Utilities::MPI::sum(err, comm) / std::pow(len, dim);
    std::vector<double> rho;
    for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
      rho.push_back(sim.state_si(c)[0] * std::pow(h / len, dim)); // weighted for the L1 norm
    return {err, wall, rho};
  }

  struct Orders
  {
    double gauss, midpoint, quadrature;
  };

  /// Gauss and midpoint runs on each mesh of the ladder; orders on the finest pair of
  /// (a) the Gauss error, (b) the midpoint error, (c) the midpoint quadrature error
  /// itself, measured as L1(rho_midpoint - rho_gauss): everything but the face
  /// quadrature is shared by the two runs, so the difference isolates it (the
  /// total midpoint error reaches its asymptotic order 2 only once the WENO5
  /// error, large on coarse meshes, has fallen below it: h/R < 0.07 in the 2D study)
  template <int dim>
  Orders ladder(std::vector<unsigned int> Ns, const MPI_Comm comm, const bool root)
  {
    if (const char *l = study_mode ? std::getenv("GRANHYDRO_ORDER_LADDER") : nullptr)
      {
        Ns.clear();
        std::stringstream ss(l);
        for (std::string n; std::getline(ss, n, ',');)
          Ns.push_back(std::stoul(n));
      }
    std::vector<double> eg, em, eq;
    for (const unsigned int N : Ns)
      {
        const Result g = run<dim>(N, "gauss", comm);
        const Result m = (dim == 1) ? g : run<dim>(N, "midpoint", comm);
        double       q = 0;
        for (std::size_t i = 0; i < g.rho.size(); ++i)
          q += std::abs(g.rho[i] - m.rho[i]);
        q = dealii::Utilities::MPI::sum(q, comm);
        eg.push_back(g.error);
        em.push_back(m.error);
        eq.push_back(q);
        const std::size_t n     = eg.size();
        auto              order = [&](const std::vector<double> &e) {
          return n > 1 ? std::log(e[n - 2] / e[n - 1]) / std::log(double(N) / Ns[n - 2]) : 0.;
        };
        if (root)
          {
            std::cout << "  " << dim << "D N = " << std::setw(4) << N << std::scientific
                      << std::setprecision(3) << "  L1 gauss " << g.error << " (order " << std::fixed
                      << std::setprecision(2) << order(eg) << ", " << g.wall << " s)";
            if (dim > 1)
              std::cout << std::scientific << std::setprecision(3) << "  L1 midpoint " << m.error
                        << " (order " << std::fixed << std::setprecision(2) << order(em) << ", " << m.wall
                        << " s)  L1(mid - gauss) " << std::scientific << std::setprecision(3) << q
                        << " (order " << std::fixed << std::setprecision(2) << order(eq) << ")";
            std::cout << std::defaultfloat << std::endl;
          }
      }
    const std::size_t n  = eg.size();
    const double      lr = std::log(double(Ns[n - 1]) / Ns[n - 2]);
    return {std::log(eg[n - 2] / eg[n - 1]) / lr, std::log(em[n - 2] / em[n - 1]) / lr,
            std::log(eq[n - 2] / eq[n - 1]) / lr};
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  Checker                                  chk;
  chk.root          = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  std::string which = "all";
  bool        study = false;
  for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "--study")
        study = study_mode = true;
      else
        which = a;
    }
  if (which == "1d" || which == "all")
    {
      const auto o =
        ladder<1>(study ? std::vector<unsigned>{20, 40, 80, 160, 320} : std::vector<unsigned>{40, 80, 160},
                  comm, chk.root);
      chk.check(study || o.gauss >= 4.5,
                "1D density wave, WENO5: order " + std::to_string(o.gauss) + " >= 4.5");
    }
  auto vortex_checks = [&](const std::string &name, const Orders &o) {
    chk.check(study || o.gauss >= 3.5,
              name + " vortex, WENO5 + Gauss points: order " + std::to_string(o.gauss) + " >= 3.5");
    chk.check(study || (o.quadrature > 1.6 && o.quadrature < 2.5),
              name + " vortex, midpoint quadrature error L1(mid - gauss): order " +
                std::to_string(o.quadrature) + " in (1.6, 2.5), about 2");
    chk.check(study || o.midpoint < o.gauss - 0.5,
              name + " vortex, WENO5 + midpoint: total order " + std::to_string(o.midpoint) +
                " clearly below the Gauss order (pre-asymptotic on these meshes, tends to 2)");
  };
  if (which == "2d" || which == "all")
    vortex_checks("2D",
                  ladder<2>(study ? std::vector<unsigned>{20, 40, 80, 160} : std::vector<unsigned>{40, 80},
                            comm, chk.root));
  // 3D: 32 -> 40 is the first pair in the asymptotic range (measured on 2 ranks: Gauss
  // order 16->24 2.37, 24->32 3.34, 32->40 3.83; midpoint total 2.44, L1(mid - gauss) 2.10
  // at 32->40). 32 -> 48 took twice the time for the same three checks.
  if (which == "3d" || which == "all")
    vortex_checks("3D",
                  ladder<3>(study ? std::vector<unsigned>{16, 24, 32, 40, 48} : std::vector<unsigned>{32, 40},
                            comm, chk.root));
  return chk.failed != 0;
}
