// The stability suite. Each hard case is a scene in parameters/hard/ (the
// -ci file at CI size; the file without -ci is the larger version; doc/user-guide.md).
// Every case must
//  - reach its end time (or, for the collapse without a closure, stop with the
//    over-packing diagnostic and the last admissible state as its final state),
//  - leave an admissible state everywhere: n > 0, T > 0 (with the dense closure: T
//    above the repair allowance, GranularGas::admissible), phi < phi_c, no NaN,
//  - conserve mass to 1e-12 relative where the scene is closed (periodic or walls;
//    the fluxes are conservative and the implicit step ends in flux form, so the
//    drift is round-off: 1e-15..1e-14 measured),
//  - take steps set by the convective CFL limit alone: every accepted step is the
//    CFL step (cut only to land on output times) or a counted retry after a
//    rejected attempt, so the smallest step is at least min_CFL / 2^retries, and the
//    implicit step exceeds the explicit diffusive limit where that limit is binding,
//  - and show the case's own feature (see each case).
//   test_stability <scene.prm> dense_collapse|overpacking|shock_into_bed|vacuum_expansion|harsh_vibration|cooling_3d|chute_from_rest
//                              |frictional_layer_{flow,rest}[_nofriction]
#include "common/test_common.h"

using namespace dealii;
using namespace granhydro;
using namespace granhydro::testing;

namespace
{
  template <int dim>
  struct Case
  {
    using Sim = driver::Simulation<dim, physics::GranularGas<dim>>;

    /// scaled conservative state of owned cell c
    static physics::State<dim> cell(const Sim &sim, const unsigned int c)
    {
      physics::State<dim> S;
      for (unsigned int k = 0; k < dim + 2; ++k)
        S[k] = sim.state().local_element(std::size_t(c) * (dim + 2) + k);
      return S;
    }

    /// max phi, and mean and standard deviation of phi over all cells
    static std::array<double, 3> packing(const Sim &sim)
    {
      double v[3] = {0, 0, 0}, mx = 0;
      for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
        {
          const double phi = cell(sim, c)[0] * M_PI / 6;
          mx               = std::max(mx, phi);
          v[0] += phi;
          v[1] += phi * phi;
          v[2] += 1;
        }
      Utilities::MPI::sum(ArrayView<const double>(v, 3), MPI_COMM_WORLD, ArrayView<double>(v, 3));
      const double mean = v[0] / v[2];
      return {
        {Utilities::MPI::max(mx, MPI_COMM_WORLD), mean, std::sqrt(std::max(0., v[1] / v[2] - mean * mean))}};
    }

    /// strict admissibility of every owned cell (n > 0, T > 0, phi < phi_c, finite)
    static bool strictly_admissible(const Sim &sim)
    {
      bool ok = true;
      for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
        {
          const auto S = cell(sim, c);
          for (const double x : S)
            ok = ok && std::isfinite(x);
          ok = ok && sim.description().strictly_admissible(S);
        }
      return Utilities::MPI::min(ok ? 1 : 0, MPI_COMM_WORLD) == 1;
    }

    static int run(const scene::Scene &scene, const std::string &kind, Checker &check)
    {
      Sim sim(scene, MPI_COMM_WORLD, std::cout);
      sim.setup();
      const auto         M0     = sim.totals();
      const auto         p0     = packing(sim);
      const double       floor0 = dim > 1 ? layer_phi(sim, scene, 0) : 0;
      driver::RunSummary sum;
      std::string        error;
      try
        {
          sum = sim.run();
        }
      catch (const RunError &e)
        {
          error = e.what();
        }
      const auto   p1    = packing(sim);
      const auto   M1    = sim.totals();
      const double drift = std::abs(M1[0] - M0[0]) / M0[0];
      if (check.root)
        std::cout << kind << ": max phi " << p0[0] << " -> " << p1[0] << ", std(phi)/mean " << p0[2] / p0[1]
                  << " -> " << p1[2] / p1[1] << ", mass drift " << drift << ", steps " << sum.steps
                  << ", rejected " << sum.rejected_steps << ", dt " << sum.min_dt_si << " .. "
                  << sum.max_dt_si << " s, min CFL dt " << sum.min_cfl_dt_si << " s, explicit limit "
                  << sum.diffusion.min_explicit_dt * sim.units().time() << " s, largest dt / explicit limit "
                  << sum.diffusion.max_dt_over_explicit << ", temperature repairs " << sum.temperature_repairs
                  << "\n";
      std::string what;
      check.check(sim.convection().admissible(sim.state(), &what), "admissible final state " + what);
      check.check(strictly_admissible(sim),
                  "T > 0 strictly (after the temperature repair), no NaN, phi < phi_c");
      check.check(p1[0] < sim.description().phi_c, "phi < phi_c everywhere");
      if (kind != "shock_into_bed") // the only open scene (inflow on the left)
        check.check(drift <= 1e-12, "mass conserved to 1e-12 relative");

      if (kind == "overpacking")
        {
          // without the closure the floor layer reaches phi_c in finite time (x' = -K sqrt x,
          // x = phi_c - phi): the run must stop with the diagnostic, not crash or lose mass
          check.check(error.find("over-packing at t = ") != std::string::npos &&
                        error.find("Dense closure") != std::string::npos,
                      "the over-packing diagnostic fires and names the remedy: " + error.substr(0, 80));
          check.check(p1[0] > 0.99 * sim.description().phi_c, "it fires at close packing (phi > 0.99 phi_c)");
          return check.failed;
        }
      check.check(error.empty(), "the run does not stop early " + error);
      check.check(std::abs(sum.time_si - scene.end_time) < 1e-12 * scene.end_time || sum.steady,
                  "the run reaches its end time (or a steady state)");
      // steps come from the convective CFL limit: at most max retries halvings below it
      check.check(sum.min_dt_si >= sum.min_cfl_dt_si * std::pow(0.5, scene.max_step_retries) * (1 - 1e-12),
                  "every step is the CFL step or a counted retry of it");

      if (kind == "dense_collapse")
        {
          // a bed at phi = 0.55 falls, compacts and comes to rest below phi_c under the
          // Johnson-Jackson contact pressure: the steady-state stop fires (kinetic energy and
          // centre of mass change < 1e-3 over 20 ms) with the densest layer above 0.56
          // (compaction: measured 0.623) and below phi_c; the implicit step is far above the
          // explicit limit
          check.check(sum.steady, "the pile comes to rest (steady state reached)");
          check.check(p1[0] > 0.56, "the pile compacts (max phi > 0.56)");
          // measured 5.8x at 40 cells (1 mm): the limit (~dx^2) is set by the frictional
          // viscosity of the pile once the Knudsen cap tames the dilute atmosphere; the contact
          // law of phi_min = 0.62 is stiffer than that of 0.5 (14.9x), which shortens the CFL
          // step 3x (the ratio grows as 1/dx at finer meshes)
          check.check(sum.diffusion.max_dt_over_explicit > 4, "steps > 4x the explicit diffusive limit");
          // temperature repairs (counted after each of the 3 parts of a step, per cell): rare.
          // Measured with the default step (cost-based: RKL2 here): 0 at 40 cells; 0 of 15.8
          // million in the 200-cell version with Gauss-Legendre. Gauss-Legendre gives 4.4e-3
          // here (its Newton tolerance is relative to the largest energy in the domain, so the
          // pile's cold top cell converges loosely); before the dense-closure fixes 0.045 and
          // 0.098 (the pile's T drained by heat conducted along grad(T + 2w/3)). The bound
          // 1e-3 is the one the larger version is held to (doc/performance.md, stability suite)
          const double updates = 3. * sum.steps * sim.patch().n_global_cells();
          check.check(sum.temperature_repairs <= 1e-3 * updates,
                      "temperature repairs <= 1e-3 of the cell updates (" +
                        std::to_string(sum.temperature_repairs / updates) + ")");
        }
      else if (kind == "shock_into_bed")
        {
          // a Mach > 10 stream (1.5 m/s against c ~ 0.12 m/s of the incoming gas) hits a bed
          // at phi = 0.6 on a wall: the bed is compressed towards phi_c but stays below it
          check.check(p0[0] >= 0.6 - 1e-12, "the bed starts at phi = 0.6");
          // the implicit step goes far beyond the explicit limit (the frictional viscosity's
          // bound t_f sin(theta_f) p_f in the pile sets it): measured 25x
          check.check(sum.diffusion.max_dt_over_explicit > 10, "steps > 10x the explicit diffusive limit");
        }
      else if (kind == "vacuum_expansion")
        {
          // the bed (x < 50 mm) expands into near-vacuum: after 50 ms the front is near
          // x = 78 mm and 5.8 % of the grains are in the right half (measured); the
          // vacuum side stays at phi >= 1e-8 (n > 0 everywhere is checked above)
          double v[2] = {0, 0};
          for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
            {
              const double n = cell(sim, c)[0];
              v[0] += n;
              if (sim.patch().center(c)[0] > 0.05)
                v[1] += n;
            }
          Utilities::MPI::sum(ArrayView<const double>(v, 2), MPI_COMM_WORLD, ArrayView<double>(v, 2));
          if (check.root)
            std::cout << "share of the grains in the right half " << v[1] / v[0] << "\n";
          check.check(v[1] / v[0] > 0.02 && v[1] / v[0] < 0.2,
                      "the bed expands into the vacuum (2 % .. 20 % of the grains in the right half)");
          check.check(sum.rejected_steps == 0, "no rejected step with the Knudsen cap");
        }
      else if (kind == "harsh_vibration")
        {
          // Gamma = A w^2 / g = 10: within a cycle the bed is thrown off the floor, leaving
          // a dilute gap (floor phi below 20 % of its start) at the end of the run (2 cycles,
          // phase of maximal upward container acceleration just passed)
          const double floor1 = layer_phi(sim, scene, 0);
          if (check.root)
            std::cout << "floor layer phi " << floor0 << " -> " << floor1 << "\n";
          check.check(floor1 < 0.2 * floor0, "a dilute gap opens under the thrown bed");
          check.check(p1[0] > 0.3, "the bed stays dense (phi > 0.3)");
        }
      else if (kind == "cooling_3d")
        {
          // the homogeneous cooling state of a gas with eps = 0.8 in a box of ~54 mean free
          // paths is unstable (clustering, Goldhirsch & Zanetti 1993): the density
          // fluctuations, seeded at 2 %, grow instead of decaying (measured growth: see note)
          check.check(p1[2] / p1[1] > 3 * p0[2] / p0[1],
                      "density fluctuations grow more than 3x (clustering)");
        }
      else if (kind == "chute_from_rest")
        {
          check.check(p1[0] > 0.3, "a dense layer flows");
        }
      else if (kind.rfind("frictional_layer", 0) == 0)
        {
          // a layer of frictional beads on a rough incline (parameters/frictional_chute.prm),
          // at 24 degrees (flow) and 20 degrees (below glass beads' arrest angle 20.9, rest),
          // with and without the frictional stress: 1 s without an inadmissible step (checked
          // above: end time reached, no stop, CFL steps only), and above the arrest angle the
          // layer flows (surface speed > 1 cm/s). Whether it stops below the arrest angle is
          // not asserted: it does not yet (0.25 m/s at 1 s, doc/validation.md "Frictional
          // chute"); the speed is printed.
          const double us = surface_speed(sim);
          if (check.root)
            std::cout << kind << ": surface speed " << us << " m/s at t = " << sum.time_si << " s\n";
          if (kind.find("_flow") != std::string::npos)
            check.check(us > 0.01, "above the arrest angle the layer flows (surface speed > 1 cm/s)");
        }
      else
        check.check(false, "unknown case " + kind);
      return check.failed;
    }

    /// the largest down-slope (x) velocity [m/s] among the cells with phi > 0.3
    static double surface_speed(const Sim &sim)
    {
      double us = 0;
      for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
        if (const auto S = cell(sim, c); S[0] * M_PI / 6 > 0.3)
          us = std::max(us, S[1] / S[0] * sim.units().velocity);
      return Utilities::MPI::max(us, MPI_COMM_WORLD);
    }

    /// packing fraction of layer l along the profile direction (y in 2D/3D)
    static double layer_phi(const Sim &sim, const scene::Scene &scene, const int l)
    {
      double v[2] = {0, 0};
      if constexpr (dim > 1)
        for (unsigned int c = 0; c < sim.patch().n_owned(); ++c)
          if (sim.patch().lattice(c)[1] == l)
            {
              v[0] += cell(sim, c)[0] * M_PI / 6;
              v[1] += 1;
            }
      (void)scene;
      Utilities::MPI::sum(ArrayView<const double>(v, 2), MPI_COMM_WORLD, ArrayView<double>(v, 2));
      return v[0] / v[1];
    }
  };
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                          check;
  check.root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  if (argc != 3)
    {
      std::cerr << "usage: test_stability <scene.prm> <case>\n";
      return 2;
    }
  // frictional_layer_{flow,rest}[_nofriction]: parameters/frictional_chute.prm at 24 or 20
  // degrees, with or without the dense closure's frictional stress
  const std::string        kind      = argv[2];
  std::vector<std::string> overrides = no_output;
  if (kind.rfind("frictional_layer", 0) == 0)
    {
      overrides.push_back(std::string("Effects/Gravity=") +
                          (kind.find("_rest") != std::string::npos ? "3.3552, -9.2184" : "3.9901, -8.9619"));
      if (kind.find("_nofriction") != std::string::npos)
        overrides.push_back("Dense closure/Viscosity time=0");
    }
  const scene::Scene scene = scene::read_scene(argv[1], overrides);
  AssertThrow(scene.model == physics::Model::granular, ExcMessage("the hard cases are granular scenes"));
  switch (scene.dimension)
    {
      case 1:
        return Case<1>::run(scene, argv[2], check) ? 1 : 0;
      case 2:
        return Case<2>::run(scene, argv[2], check) ? 1 : 0;
      default:
        return Case<3>::run(scene, argv[2], check) ? 1 : 0;
    }
}
