// unit.lanes_physics: the physics formulas evaluated on GCC vectors of 4 doubles (the
// lanes of the vectorised diffusion residual, physics/lanes.h) give, lane by lane, the
// double result bit for bit. Covered: the Garzo-Dufty transport coefficients and the
// cooling rate with the Torquato pair correlation on all three of its branches
// (Carnahan-Starling, Torquato, linear beyond phi_max) and at the branch points, the
// temperature floor, both zeta_U modes; the chain rule to primitive gradients and the
// viscous flux in 3D. Lanes are mixed (each vector holds states from different
// branches), so a wrong per-lane selection fails. The reference is the scalar code the
// solver ran before it was vectorised (same formulas, instantiated for double).
#include <granhydro/physics/diffusive_flux.h>
#include <granhydro/physics/garzo_dufty.h>
#include <granhydro/physics/lanes.h>

#include "test_common.h"

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

using namespace granhydro;
using granhydro::testing::Checker;
namespace lanes = physics::lanes;
typedef double v4 __attribute__((vector_size(32)));

namespace
{
  bool same(const double a, const double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
  v4   pack(const double *x) { v4 r; for (int i = 0; i < 4; ++i) r[i] = x[i]; return r; }
} // namespace

int main()
{
  Checker                                 check;
  std::mt19937                            rng(11);
  std::uniform_real_distribution<double>  U01(0., 1.);
  const physics::PairCorrelationTorquato  pc(0.49, 0.64, 1e-3);
  const double phi_max = 0.64 - 1e-3;
  // packing fractions: random on each branch, the branch points, beyond phi_max
  std::vector<double> phis = {0.49, std::nextafter(0.49, 1.), phi_max, std::nextafter(phi_max, 1.), 0.7};
  for (int k = 0; k < 400; ++k)
    {
      const double u = U01(rng);
      phis.push_back(k % 3 == 0 ? 1e-4 + 0.49 * u : (k % 3 == 1 ? 0.49 + (phi_max - 0.49) * u : phi_max + 0.05 * u));
    }
  std::shuffle(phis.begin(), phis.end(), rng);
  while (phis.size() % 4)
    phis.push_back(0.3);
  const double sigma = 1., m = 1.;
  for (const auto &[eps, mode] : {std::pair{0.9, physics::ZetaUMode::off}, std::pair{0.7, physics::ZetaUMode::full}})
    {
      const physics::GarzoDufty1999 gd(eps, pc, 1e-6, mode);
      std::size_t differ = 0, n = 0;
      for (std::size_t k = 0; k < phis.size(); k += 4)
        {
          double nn[4], TT[4];
          for (int i = 0; i < 4; ++i)
            {
              nn[i] = physics::GarzoDufty1999::number_density(phis[k + i], sigma);
              TT[i] = std::pow(10., -8 + 8 * U01(rng)); // below and above the floor 1e-6
            }
          const auto cv = gd.transport(pack(nn), pack(TT), m, sigma);
          const v4   zv = gd.zeta0(pack(nn), pack(TT), m, sigma);
          v4         chv, dchv;
          pc.chi_and_derivative(pack(nn) * (M_PI / 6.), chv, dchv);
          for (int i = 0; i < 4; ++i)
            {
              const auto cs = gd.transport(nn[i], TT[i], m, sigma);
              double     ch, dch;
              pc.chi_and_derivative(nn[i] * (M_PI / 6.), ch, dch);
              for (const auto &[a, b] : {std::pair{cv.p[i], cs.p}, {cv.c[i], cs.c}, {cv.eta[i], cs.eta},
                                         {cv.gamma[i], cs.gamma}, {cv.kappa[i], cs.kappa}, {cv.mu[i], cs.mu},
                                         {cv.zeta0[i], cs.zeta0}, {cv.zeta_U[i], cs.zeta_U},
                                         {zv[i], gd.zeta0(nn[i], TT[i], m, sigma)}, {chv[i], ch}, {dchv[i], dch},
                                         {pc.chi(pack(nn) * (M_PI / 6.))[i], pc.chi(nn[i] * (M_PI / 6.))}})
                {
                  differ += !same(a, b);
                  ++n;
                }
            }
        }
      check.check(differ == 0, "GD99 transport, zeta0, chi on 4 lanes = double, bit for bit (eps " +
                                 std::to_string(eps) + ", " + std::to_string(n) + " values, " +
                                 std::to_string(differ) + " differ)");
    }

  // the viscous flux of a face from conservative gradients, 3D
  {
    constexpr int dim = 3, NC = dim + 2;
    const physics::GarzoDufty1999 gd(0.9, pc);
    std::size_t differ = 0, n = 0;
    for (int rep = 0; rep < 200; ++rep)
      {
        std::array<v4, NC>                    Uv;
        physics::StateGradient<dim, v4>       dUv;
        std::array<physics::State<dim>, 4>    Us;
        std::array<physics::StateGradient<dim>, 4> dUs;
        for (int i = 0; i < 4; ++i)
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
        const v4 nf = Uv[0], Tf = (2. / 3.) * (Uv[NC - 1] - physics::kinetic_energy<dim>(Uv)) / Uv[0];
        const auto gv = physics::primitive_gradients<dim, v4>(Uv, dUv, 1.);
        for (unsigned int d = 0; d < dim; ++d)
          {
            const auto Fv = physics::viscous_flux_primitive<dim>(Uv, gv, gd.transport(nf, Tf, 1., 1.), 1., d);
            for (int i = 0; i < 4; ++i)
              {
                const double T  = (2. / 3.) * (Us[i][NC - 1] - physics::kinetic_energy<dim>(Us[i])) / Us[i][0];
                const auto   g  = physics::primitive_gradients<dim>(Us[i], dUs[i], 1.);
                const auto   F  = physics::viscous_flux_primitive<dim>(Us[i], g, gd.transport(Us[i][0], T, 1., 1.), 1., d);
                for (int c = 0; c < NC; ++c, ++n)
                  differ += !same(Fv[c][i], F[c]);
              }
          }
      }
    check.check(differ == 0, "3D viscous face flux on 4 lanes = double, bit for bit (" + std::to_string(n) +
                               " values, " + std::to_string(differ) + " differ)");
  }
  // lanes::constant broadcasts; lanes::any_sqrt is the correctly rounded sqrt per lane
  {
    const v4 c = lanes::constant<v4>(0.1), s = lanes::any_sqrt(c * 3.);
    bool     ok = true;
    for (int i = 0; i < 4; ++i)
      ok = ok && same(c[i], 0.1) && same(s[i], std::sqrt(0.1 * 3.));
    check.check(ok, "lanes::constant and lanes::any_sqrt");
  }
  return check.failed ? 1 : 0;
}
