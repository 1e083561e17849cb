// unit.lanes_physics: the physics formulas evaluated on GCC vectors of 4 doubles (the
// lanes of the vectorised diffusion residual, physics/lanes.h) give, lane by lane, the
// double result bit for bit. Covered: the Garzo-Dufty transport coefficients and the
// cooling rate with the Torquato pair correlation on all three of its branches
// (Carnahan-Starling, Torquato, linear beyond phi_max) and at the branch points, the
// temperature floor, both zeta_U modes; the chain rule to primitive gradients and the
// viscous flux in 3D; the convective formulas of the granular gas (pressure, sound and
// wave speeds, flux, admissible set, with and without the dense closure, whose contact
// potential is evaluated lane by lane) and the MUSTA flux of 4 Gauss points at once
// against the same flux point by point, with its stage counts and Rusanov fallbacks.
// Lanes are mixed (each vector holds states from different
// branches), so a wrong per-lane selection fails. The reference is the scalar code the
// solver ran before it was vectorised (same formulas, instantiated for double).
#include <granhydro/convection/numerical_flux.h>
#include <granhydro/physics/diffusive_flux.h>
#include <granhydro/physics/garzo_dufty.h>
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/lanes.h>

#include "common/test_common.h"

#include <algorithm>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

using namespace granhydro;
using granhydro::testing::Checker;
namespace lanes = physics::lanes;
typedef double v4 __attribute__((vector_size(32)));

namespace
{
  bool same(const double a, const double b)
  {
    return std::memcmp(&a, &b, sizeof a) == 0;
  }
  typedef double v2 __attribute__((vector_size(16)));
  template <class V>
  __attribute__((always_inline)) inline V pack(const double *x)
  {
    V r;
    for (unsigned int i = 0; i < lanes::width<V>; ++i)
      r[i] = x[i];
    return r;
  }
  // the convective formulas of the granular gas (3D) and the MUSTA flux on the lanes of V
  template <class V>
  void granular_lanes(Checker &check, std::mt19937 &rng, const physics::PairCorrelationTorquato &pc)
  {
    constexpr unsigned int                 W = lanes::width<V>;
    std::uniform_real_distribution<double> U01(0., 1.);
    constexpr int                          dim = 3, NC = dim + 2;
    using State = physics::State<dim>;
    using VS    = std::array<V, NC>;
    const physics::GarzoDufty1999 gd(0.9, pc);
    for (const bool closure : {false, true})
      {
        physics::GranularGas<dim> gas(gd);
        if (closure) // Johnson-Jackson contact pressure (scaled F), phi_min 0.62: pow branch above it
          gas.contact = physics::ContactPressure(1e-3, 0.62, 0.64, 2, 5, 1e-3, physics::FrictionalStress{});
        // the tests inside a step, with a splitting allowance of the temperature repair
        const double repair_energy = closure ? 1e-7 : 0.;
        const auto   admissible    = [&](const auto &U) { return gas.admissible(U, repair_energy); };
        // states: dilute to dense (above phi_min, up to phi_c and beyond it), hot and cold,
        // with thermal energy slightly negative (repairable with the closure) or NaN
        auto make = [&](const int k) {
          const int kind = k % 8;
          const double phi  = kind == 0 ? 1e-4 + 0.3 * U01(rng) :
                              kind == 1 ? 0.3 + 0.32 * U01(rng) :
                              kind == 2 ? 0.62 + 0.0199 * U01(rng) :
                              kind == 3 ? 0.64 + 0.01 * U01(rng) : // beyond phi_c: inadmissible
                                          1e-3 + 0.638 * U01(rng);
          const double n = phi / (M_PI / 6.);
          State        S;
          S[0]      = kind == 4 ? -n : n; // n < 0: inadmissible
          double ke = 0;
          for (int d = 0; d < dim; ++d)
            {
              S[1 + d] = n * (U01(rng) - 0.5);
              ke += 0.5 * S[1 + d] * S[1 + d] / n;
            }
          const double T = kind == 5 ? -1e-9 * U01(rng) : std::pow(10., -9 + 9 * U01(rng));
          S[NC - 1]      = ke + 1.5 * n * T + gas.contact.energy_density(n);
          if (kind == 6)
            S[NC - 1] = std::nan("");
          return S;
        };
        std::size_t differ = 0, n = 0, mask_differ = 0, n_admissible = 0;
        for (int rep = 0; rep < 400; ++rep)
          {
            State Us[W];
            VS    Uv;
            for (unsigned int i = 0; i < W; ++i)
              {
                Us[i] = make(int(8 * U01(rng)));
                for (int c = 0; c < NC; ++c)
                  Uv[c][i] = Us[i][c];
              }
            const V    pv = gas.pressure(Uv);
            const auto av = admissible(Uv);
            const V    cv = gas.sound_speed(Uv[0], pv);
            for (unsigned int d = 0; d < dim; ++d)
              {
                const V wv = gas.max_wave_speed(Uv, d, pv);
                VS      Fv;
                const V pf = gas.flux(Uv, d, Fv);
                for (unsigned int i = 0; i < W; ++i)
                  {
                    const double p = gas.pressure(Us[i]);
                    State        F;
                    gas.flux(Us[i], d, F);
                    for (const auto &[a, b] : {std::pair{pv[i], p},
                                               {cv[i], gas.sound_speed(Us[i][0], p)},
                                               {wv[i], gas.max_wave_speed(Us[i], d, p)},
                                               {pf[i], p}})
                      differ += !same(a, b), ++n;
                    for (int c = 0; c < NC; ++c)
                      differ += !same(Fv[c][i], F[c]), ++n;
                  }
              }
            for (unsigned int i = 0; i < W; ++i)
              {
                mask_differ += (av[i] != 0) != admissible(Us[i]);
                n_admissible += admissible(Us[i]);
              }
          }
        const std::string what = closure ? " (dense closure)" : " (no closure)";
        // NaN-free values compare bitwise; NaN lanes (inadmissible states) as NaN on both sides
        check.check(differ == 0 && mask_differ == 0 && n_admissible > 100 * W && n_admissible < 300 * W,
                    "granular pressure, sound and wave speeds, flux and admissible set on " +
                      std::to_string(W) + " lanes = double" + what + ": " + std::to_string(n) + " values, " +
                      std::to_string(differ) + " differ; admissible masks differ at " +
                      std::to_string(mask_differ) + " of " + std::to_string(400 * W) + " (" +
                      std::to_string(n_admissible) + " admissible)");

        // MUSTA: 4 Gauss points as lanes = point by point (fluxes, stage counts, fallbacks)
        for (const unsigned int min_stages : {2u, 1u})
          {
            convection::ConvectionSettings settings;
            settings.musta_min_stages = min_stages;
            const convection::NumericalFlux<dim, physics::GranularGas<dim>> flux(gas, settings);
            convection::FluxStatistics                                      s1, s4;
            std::size_t                                                     fdiffer = 0, points = 0;
            for (int rep = 0; rep < 300; ++rep)
              {
                State L[W], R[W], F1[W], F4[W];
                for (unsigned int i = 0; i < W; ++i)
                  {
                    // admissible neighbours with small or large jumps (one in 16 is a
                    // pile next to near-vacuum: predictor states may leave the set)
                    do
                      L[i] = make(rep % 16 == 0 ? 2 : int(8 * U01(rng)));
                    while (!admissible(L[i]));
                    do
                      R[i] = rep % 3 == 0 ? make(int(8 * U01(rng))) : L[i];
                    while (!admissible(R[i]));
                    if (rep % 3 != 0)
                      for (int c = 0; c < NC; ++c)
                        R[i][c] *= 1 + 1e-3 * (U01(rng) - 0.5);
                    if (!admissible(R[i]))
                      R[i] = L[i];
                  }
                const unsigned int d = rep % dim;
                for (unsigned int i = 0; i < W; ++i)
                  flux(L[i], R[i], d, F1[i], s1, repair_energy);
                flux.template points<V>(L, R, W, d, F4, s4, repair_energy);
                for (unsigned int i = 0; i < W; ++i)
                  for (int c = 0; c < NC; ++c, ++points)
                    fdiffer += !same(F1[i][c], F4[i][c]);
              }
            check.check(fdiffer == 0 && s1.points == s4.points && s1.stages == s4.stages &&
                          s1.fallbacks == s4.fallbacks && s1.stages > s1.points,
                        "granular MUSTA on " + std::to_string(W) + " lanes" + what + ", minimum stages " +
                          std::to_string(min_stages) + ": points as lanes = point by point (" +
                          std::to_string(points) + " values, " + std::to_string(fdiffer) +
                          " differ; stages " + std::to_string(s1.stages) + " / " + std::to_string(s4.stages) +
                          ", fallbacks " + std::to_string(s1.fallbacks) + " / " +
                          std::to_string(s4.fallbacks) + ")");
          }
      }
  }
} // namespace

template <class V>
void lane_checks(Checker &check)
{
  constexpr unsigned int                 W = lanes::width<V>;
  std::mt19937                           rng(11);
  std::uniform_real_distribution<double> U01(0., 1.);
  const physics::PairCorrelationTorquato pc(0.49, 0.64, 1e-3);
  const double                           phi_max = 0.64 - 1e-3;
  // packing fractions: random on each branch, the branch points, beyond phi_max
  std::vector<double> phis = {0.49, std::nextafter(0.49, 1.), phi_max, std::nextafter(phi_max, 1.), 0.7};
  for (int k = 0; k < 400; ++k)
    {
      const double u = U01(rng);
      phis.push_back(k % 3 == 0 ? 1e-4 + 0.49 * u :
                                  (k % 3 == 1 ? 0.49 + (phi_max - 0.49) * u : phi_max + 0.05 * u));
    }
  std::shuffle(phis.begin(), phis.end(), rng);
  while (phis.size() % 4)
    phis.push_back(0.3);
  const double sigma = 1., m = 1.;
  for (const auto &[eps, mode] :
       {std::pair{0.9, physics::ZetaUMode::off}, std::pair{0.7, physics::ZetaUMode::full}})
    {
      const physics::GarzoDufty1999 gd(eps, pc, 1e-6, mode);
      std::size_t                   differ = 0, n = 0;
      for (std::size_t k = 0; k < phis.size(); k += W)
        {
          double nn[W], TT[W];
          for (unsigned int i = 0; i < W; ++i)
            {
              nn[i] = physics::GarzoDufty1999::number_density(phis[k + i], sigma);
              TT[i] = std::pow(10., -8 + 8 * U01(rng)); // below and above the floor 1e-6
            }
          const auto cv = gd.transport(pack<V>(nn), pack<V>(TT), m, sigma);
          const V    zv = gd.zeta0(pack<V>(nn), pack<V>(TT), m, sigma);
          V          chv, dchv;
          pc.chi_and_derivative(pack<V>(nn) * (M_PI / 6.), chv, dchv);
          for (unsigned int i = 0; i < W; ++i)
            {
              const auto cs = gd.transport(nn[i], TT[i], m, sigma);
              double     ch, dch;
              pc.chi_and_derivative(nn[i] * (M_PI / 6.), ch, dch);
              for (const auto &[a, b] : {std::pair{cv.p[i], cs.p},
                                         {cv.c[i], cs.c},
                                         {cv.eta[i], cs.eta},
                                         {cv.gamma[i], cs.gamma},
                                         {cv.kappa[i], cs.kappa},
                                         {cv.mu[i], cs.mu},
                                         {cv.zeta0[i], cs.zeta0},
                                         {cv.zeta_U[i], cs.zeta_U},
                                         {zv[i], gd.zeta0(nn[i], TT[i], m, sigma)},
                                         {chv[i], ch},
                                         {dchv[i], dch},
                                         {pc.chi(pack<V>(nn) * (M_PI / 6.))[i], pc.chi(nn[i] * (M_PI / 6.))}})
                {
                  differ += !same(a, b);
                  ++n;
                }
            }
        }
      check.check(differ == 0, "GD99 transport, zeta0, chi on " + std::to_string(W) +
                                 " lanes = double, bit for bit (eps " + std::to_string(eps) + ", " +
                                 std::to_string(n) + " values, " + std::to_string(differ) + " differ)");
    }

  // the viscous flux of a face from conservative gradients, 3D
  {
    constexpr int                 dim = 3, NC = dim + 2;
    const physics::GarzoDufty1999 gd(0.9, pc);
    std::size_t                   differ = 0, n = 0;
    for (int rep = 0; rep < 200; ++rep)
      {
        std::array<V, NC>                          Uv;
        physics::StateGradient<dim, V>             dUv;
        std::array<physics::State<dim>, W>         Us;
        std::array<physics::StateGradient<dim>, W> dUs;
        for (unsigned int i = 0; i < W; ++i)
          {
            const double nn = 0.01 + U01(rng), T = 1e-3 + U01(rng);
            double       ke = 0;
            Us[i][0]        = nn;
            for (int d = 0; d < dim; ++d)
              {
                Us[i][1 + d] = nn * (U01(rng) - 0.5);
                ke += 0.5 * Us[i][1 + d] * Us[i][1 + d] / nn;
              }
            Us[i][NC - 1] = ke + 1.5 * nn * T;
            for (int j = 0; j < dim; ++j)
              for (int c = 0; c < NC; ++c)
                dUs[i][j][c] = U01(rng) - 0.5;
            for (int c = 0; c < NC; ++c)
              {
                Uv[c][i] = Us[i][c];
                for (int j = 0; j < dim; ++j)
                  dUv[j][c][i] = dUs[i][j][c];
              }
          }
        const V    nf = Uv[0], Tf = (2. / 3.) * (Uv[NC - 1] - physics::kinetic_energy<dim>(Uv)) / Uv[0];
        const auto gv = physics::primitive_gradients<dim, V>(Uv, dUv, 1.);
        for (unsigned int d = 0; d < dim; ++d)
          {
            const auto Fv = physics::viscous_flux_primitive<dim>(Uv, gv, gd.transport(nf, Tf, 1., 1.), 1., d);
            for (unsigned int i = 0; i < W; ++i)
              {
                const double T = (2. / 3.) * (Us[i][NC - 1] - physics::kinetic_energy<dim>(Us[i])) / Us[i][0];
                const auto   g = physics::primitive_gradients<dim>(Us[i], dUs[i], 1.);
                const auto   F =
                  physics::viscous_flux_primitive<dim>(Us[i], g, gd.transport(Us[i][0], T, 1., 1.), 1., d);
                for (int c = 0; c < NC; ++c, ++n)
                  differ += !same(Fv[c][i], F[c]);
              }
          }
      }
    check.check(differ == 0, "3D viscous face flux on " + std::to_string(W) +
                               " lanes = double, bit for bit (" + std::to_string(n) + " values, " +
                               std::to_string(differ) + " differ)");
  }
  granular_lanes<v2>(check, rng, pc); // 2 lanes (SSE2)
  granular_lanes<V>(check, rng, pc);  // 4 lanes, as the AVX2 kernel runs them
  // lanes::constant broadcasts; lanes::any_sqrt is the correctly rounded sqrt per lane
  {
    const V c = lanes::constant<V>(0.1), s = lanes::any_sqrt(c * 3.);
    bool    ok = true;
    for (unsigned int i = 0; i < W; ++i)
      ok = ok && same(c[i], 0.1) && same(s[i], std::sqrt(0.1 * 3.));
    check.check(ok, "lanes::constant and lanes::any_sqrt");
  }
}

#if defined(__x86_64__) || defined(__i386__)
// the 4-lane checks compiled for AVX2, as the library's kernels are (flatten: every
// formula inlined; 4-wide vectors emulated on the default target make GCC 12 fail with an
// internal compiler error on this file, and are not what the solver runs)
__attribute__((target("avx2"), flatten)) void lane_checks_avx2(Checker &check)
{
  lane_checks<v4>(check);
}
#endif

int main()
{
  Checker check;
  lane_checks<v2>(check); // 2 lanes (SSE2, the default target's vectors)
#if defined(__x86_64__) || defined(__i386__)
  if (lanes::use_avx2())
    lane_checks_avx2(check); // 4 lanes, as the AVX2 kernels run them
  else
    std::cout << "no AVX2 (or GRANHYDRO_NO_AVX2 set): the 4-lane checks are skipped\n";
#endif
  return check.failed ? 1 : 0;
}
