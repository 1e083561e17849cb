// Effects: only the operators a scene calls for are built and run:
//  a. a granular scene with eps = 1, no gravity and no transport builds no diffusion
//     step (0 Newton/GMRES work, counted) and equals, bit for bit, a hand-written
//     SSP-RK3 loop over the bare convection operator with the same time steps;
//  b. each effect switched off removes exactly its term: the diffusion/source operator
//     f = div F_visc + div F_heat + S_cool + S_grav is evaluated with every subset of
//     effects on a smooth 2D state; f(all) equals the sum of the single-effect
//     operators to round-off, and the source-only operators equal hand-made references
//     (-(3/2) n T zeta0 from GarzoDufty1999 directly; n g and n u.g).
#include <granhydro/diffusion/diffusion_operator.h>

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
  using Sim = driver::Simulation<2, physics::GranularGas<2>>;
  // ---- a: no diffusion step when nothing calls for it ------------------------------
  {
    // effects.prm with eps = 1, no gravity, no transport
    const scene::Scene sc = test_scene(
      "effects.prm", {"Effects/Viscosity=false", "Effects/Heat conduction=false",
                      "Material/Restitution coefficient=1", "Effects/Gravity=0, 0", "Time/End time=1"});
    Sim sim(sc, MPI_COMM_SELF, std::cout);
    sim.setup();
    const auto sum = sim.run();
    chk.check(
      !sc.diffusion_active() && !sum.diffusion_active && sum.diffusion.steps == 0 &&
        sum.diffusion.newton_iterations == 0 && sum.diffusion.linear_iterations == 0,
      "eps = 1, no gravity, no transport: no diffusion step built or run (0 steps, 0 Newton, 0 GMRES)");
    // the same scene by hand: bare convection operator, SSP-RK3, same CFL steps
    Sim ref(sc, MPI_COMM_SELF, std::cout);
    ref.setup();
    auto        U  = ref.state();
    const auto &op = ref.convection();
    double      t  = 0;
    for (unsigned int k = 0; k < sum.steps; ++k)
      {
        const double dt = std::min(sc.cfl / op.max_rate(U), sc.end_time / sim.units().time() - t);
        op.ssp_rk3_step(U, dt, 0.); // no repair allowance: the dense closure is off
        t += dt;
      }
    double diff = 0;
    for (std::size_t i = 0; i < U.locally_owned_size(); ++i)
      diff = std::max(diff, std::abs(U.local_element(i) - sim.state().local_element(i)));
    chk.check(diff == 0, "... and equals the bare convective SSP-RK3 loop bit for bit (max diff " +
                           std::to_string(diff) + ", " + std::to_string(sum.steps) + " steps)");
  }
  // ---- b: each effect contributes exactly its term -----------------------------------
  {
    const scene::Scene sc = test_scene("effects.prm"); // every effect on
    Sim                sim(sc, MPI_COMM_SELF, std::cout);
    sim.setup();
    const auto         &patch = sim.patch();
    std::vector<double> W;
    patch.gather(sim.state(), W);
    // gravity along y as the scene sets it
    const double L = sim.units().length, g_scaled = sc.gravity[1] * L / std::pow(sim.units().velocity, 2);
    auto         residual = [&](bool visc, bool heat, bool cool, bool grav) {
      diffusion::DiffusionSettings s;
      s.viscous         = visc;
      s.heat            = heat;
      s.cooling         = cool;
      s.body.gravity[1] = grav ? g_scaled : 0.;
      diffusion::DiffusionOperator<2> op(patch, sim.description(), s, L);
      op.setup();
      std::vector<double> f(std::size_t(patch.n_owned()) * 4);
      op.residual(W.data(), f.data());
      return f;
    };
    const auto f_all   = residual(true, true, true, true);
    const auto f_visc  = residual(true, false, false, false);
    const auto f_heat  = residual(false, true, false, false);
    const auto f_cool  = residual(false, false, true, false);
    const auto f_grav  = residual(false, false, false, true);
    double     sum_err = 0, scale = 0, cool_err = 0, grav_err = 0, cool_scale = 0, grav_scale = 0;
    const physics::GranularGas<2> &desc = sim.description();
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        physics::State<2> U;
        std::copy(&W[s * 4], &W[s * 4 + 4], U.begin());
        const double n = U[0], T = desc.temperature(U);
        // hand-made references of the sources (doc/physics.md 1, 3.5; scaled units m = sigma = 1)
        const double cool    = -1.5 * n * T * desc.model.zeta0(n, T, 1., 1.);
        const double gref[4] = {0, 0, n * g_scaled, U[2] * g_scaled};
        for (unsigned int c = 0; c < 4; ++c)
          {
            const std::size_t i = s * 4 + c;
            sum_err = std::max(sum_err, std::abs(f_all[i] - (f_visc[i] + f_heat[i] + f_cool[i] + f_grav[i])));
            scale   = std::max(scale, std::abs(f_visc[i]) + std::abs(f_heat[i]) + std::abs(f_cool[i]) +
                                        std::abs(f_grav[i]));
            cool_err   = std::max(cool_err, std::abs(f_cool[i] - (c == 3 ? cool : 0.)));
            grav_err   = std::max(grav_err, std::abs(f_grav[i] - gref[c]));
            cool_scale = std::max(cool_scale, std::abs(cool));
            grav_scale = std::max(grav_scale, std::abs(gref[c]));
          }
      }
    // the terms are added in a fixed order; round-off of a few ulp of the largest term
    chk.check(sum_err <= 1e-13 * scale,
              "f(all effects) = f(viscosity) + f(heat) + f(cooling) + f(gravity): max deviation " +
                std::to_string(sum_err / scale) + " of the term scale");
    chk.check(cool_err <= 1e-14 * cool_scale, "cooling alone = -(3/2) n T zeta0 from GarzoDufty1999 (rel. " +
                                                std::to_string(cool_err / cool_scale) + ")");
    chk.check(grav_err <= 1e-14 * grav_scale,
              "gravity alone = (0, n g, n u.g) (rel. " + std::to_string(grav_err / grav_scale) + ")");
    double visc_scale = 0, heat_scale = 0;
    for (std::size_t i = 0; i < f_visc.size(); ++i)
      {
        visc_scale = std::max(visc_scale, std::abs(f_visc[i]));
        heat_scale = std::max(heat_scale, std::abs(f_heat[i]));
      }
    chk.check(visc_scale > 0 && heat_scale > 0 && cool_scale > 0 && grav_scale > 0,
              "every effect is active in this state (no vacuous comparison)");
    // the viscous operator has no mass row, the heat operator only an energy row
    double mass = 0, heat_mom = 0;
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        mass     = std::max({mass, std::abs(f_visc[s * 4]), std::abs(f_heat[s * 4])});
        heat_mom = std::max({heat_mom, std::abs(f_heat[s * 4 + 1]), std::abs(f_heat[s * 4 + 2])});
      }
    chk.check(
      mass == 0 && heat_mom == 0,
      "viscosity and heat conduction leave the mass row, heat conduction the momentum rows, untouched");
  }
  return chk.failed != 0;
}
