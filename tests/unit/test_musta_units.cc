// unit.musta_units: the MUSTA flux (paper eqs. 4.7-4.9) and its 1 % stopping rule do not
// depend on the unit system. A change of units multiplies density by a, velocity by b;
// then momentum and energy densities scale by a b and a b^2, the flux components by
// a b, a b^2, a b^3 and every wave speed by b. With a and b powers of two (and b^2 a
// power of four, so that the square root of the sound speed scales exactly) every
// operation of the flux scales exactly in floating point, so the reference is the flux
// in the original units, scaled: it must agree bit for bit and take the same number of
// stages at every face, over random Riemann problems and unit changes of 2^-40 .. 2^40.
// A stopping rule that sums squared components of different units (the flux norm)
// weighs the components differently in each unit system and fails this test. Both
// rules are checked: at least 2 stages (default) and the first-stage test on the jump
// (MUSTA minimum stages = 1).
#include <granhydro/convection/numerical_flux.h>
#include <granhydro/physics/ideal_gas.h>

#include "common/test_common.h"

#include <cmath>
#include <random>

using namespace granhydro;
using granhydro::testing::Checker;

int main()
{
  constexpr int dim = 3;
  using Flux        = convection::NumericalFlux<dim, physics::IdealGas<dim>>;
  using State       = physics::State<dim>;
  physics::IdealGas<dim> gas;

  std::mt19937                           rng(7);
  std::uniform_real_distribution<double> U01(0., 1.);
  auto state = [&](const double n, const std::array<double, dim> &u, const double p) {
    State S;
    S[0]      = n;
    double ke = 0;
    for (unsigned int d = 0; d < dim; ++d)
      {
        S[1 + d] = n * u[d];
        ke += 0.5 * n * u[d] * u[d];
      }
    S[dim + 1] = ke + p / (gas.gamma - 1);
    return S;
  };
  // Riemann problems: smooth (jumps of 1e-6 .. 1e-2), shocks and rarefactions, states
  // at rest (mass flux 0) and fast flows (energy flux large against the pressure)
  std::vector<std::pair<State, State>> pairs;
  for (int k = 0; k < 400; ++k)
    {
      const double            n = std::exp(4 * U01(rng) - 2), p = std::exp(6 * U01(rng) - 3);
      const double            jump  = k % 4 == 0 ? std::pow(10., -6 + 4 * U01(rng)) : U01(rng);
      const double            speed = k % 3 == 0 ? 0. : std::exp(4 * U01(rng) - 2);
      std::array<double, dim> uL, uR;
      for (unsigned int d = 0; d < dim; ++d)
        {
          uL[d] = speed * (2 * U01(rng) - 1);
          uR[d] = uL[d] + jump * speed * (2 * U01(rng) - 1);
        }
      pairs.emplace_back(state(n, uL, p),
                         state(n * (1 + jump * (2 * U01(rng) - 1)), uR, p * (1 + jump * (3 * U01(rng) - 1))));
    }
  Checker chk;
  // the default rule (at least 2 stages) and the first-stage test (MUSTA minimum stages = 1)
  for (const unsigned int min_stages : {2u, 1u})
    {
      convection::ConvectionSettings settings; // defaults: MUSTA, <= 4 stages, tolerance 0.01, local CFL 0.9
      settings.musta_min_stages = min_stages;
      const Flux         flux(gas, settings);
      const std::string  rule         = "minimum stages " + std::to_string(min_stages) + ": ";
      unsigned long long total_stages = 0, two_stage = 0, one_stage = 0;
      for (const auto &[ea, eb] :
           std::vector<std::pair<int, int>>{{0, 0}, {20, -10}, {-20, 10}, {40, 20}, {-40, -20}, {3, 7}})
        {
          const double       a = std::ldexp(1., ea), b = std::ldexp(1., eb);
          unsigned long long stage_mismatch = 0, flux_mismatch = 0, faces = 0;
          for (unsigned int d = 0; d < dim; ++d)
            for (const auto &[L, R] : pairs)
              {
                State        L2, R2, F, F2;
                const double scale[3]  = {a, a * b, a * b * b};
                const double fscale[3] = {a * b, a * b * b, a * b * b * b};
                auto         kind = [](const unsigned int c) { return c == 0 ? 0 : (c == dim + 1 ? 2 : 1); };
                for (unsigned int c = 0; c < dim + 2; ++c)
                  {
                    L2[c] = L[c] * scale[kind(c)];
                    R2[c] = R[c] * scale[kind(c)];
                  }
                convection::FluxStatistics s1, s2, s3;
                flux.musta(L, R, d, F, s1, 0.); // an ideal gas: no repair allowance
                flux.musta(L2, R2, d, F2, s2, 0.);
                // the vectorised path (4 Gauss points of a face as lanes) in the new units
                State          Ls[4] = {L2, L2, L2, L2}, Rs[4] = {R2, R2, R2, R2}, Fs[4];
                typedef double V4 __attribute__((vector_size(32)));
                flux.points<V4>(Ls, Rs, 4, d, Fs, s3, 0.);
                ++faces;
                total_stages += s1.stages;
                two_stage += s1.stages == 2;
                one_stage += s1.stages == 1;
                stage_mismatch += s1.stages != s2.stages || 4 * s1.stages != s3.stages;
                bool same = true;
                for (unsigned int c = 0; c < dim + 2; ++c)
                  {
                    same = same && F2[c] == F[c] * fscale[kind(c)];
                    for (unsigned int q = 0; q < 4; ++q)
                      same = same && Fs[q][c] == F2[c];
                  }
                flux_mismatch += !same;
              }
          chk.check(stage_mismatch == 0 && flux_mismatch == 0,
                    rule + "density x 2^" + std::to_string(ea) + ", velocity x 2^" + std::to_string(eb) +
                      ": " + std::to_string(faces) + " faces, stage counts differ at " +
                      std::to_string(stage_mismatch) + ", fluxes differ (bitwise, after scaling) at " +
                      std::to_string(flux_mismatch));
        }
      // the rule must still stop early where MUSTA converges: not every face at the cap;
      // the first-stage test stops only with minimum stages 1, and only on small jumps
      const std::size_t faces = 6 * dim * pairs.size();
      chk.check(two_stage > 0 && total_stages < 4ull * faces && (min_stages == 1) == (one_stage > 0) &&
                  one_stage < faces / 2,
                rule + "the stopping rule stops early: " + std::to_string(one_stage) + " / " +
                  std::to_string(two_stage) + " of " + std::to_string(faces) + " faces after 1 / 2 stages");
    }
  return chk.failed != 0;
}
