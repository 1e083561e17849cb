#pragma once
/**
 * @file numerical_flux.h
 * Numerical fluxes across a face with normal e_d, from the reconstructed
 * states U_L (inside the cell on the low side) and U_R.
 *
 *  - MUSTA: multi-stage FORCE, paper eqs. (4.7)-(4.9), Titarev & Toro (2004),
 *    with the dissipation term carrying dx/dt (physics.md P12). Each stage
 *    uses the local ratio dt/dx = C_loc / S_max(U_L, U_R) (Titarev-Toro's
 *    local Courant number, default 0.9). The iteration stops when the relative
 *    change of the FORCE flux between stages is below the tolerance (paper:
 *    1 %) or at the stage cap. If a predictor state leaves the admissible set
 *    (near vacuum) the face falls back to the Rusanov flux of the original
 *    states; such fallbacks are counted.
 *  - Rusanov (local Lax-Friedrichs) and HLL (Davis wave-speed estimates).
 *
 * Everything depends only on (U_L, U_R, d): two ranks computing the same
 * face get bit-identical results.
 */
#include <granhydro/physics/ideal_gas.h>
#include <granhydro/scene/scene.h>

#include <algorithm>
#include <cmath>

namespace granhydro::convection
{
  struct FluxStatistics
  {
    unsigned long long points = 0, stages = 0, fallbacks = 0;
  };

  template <int dim, class Description>
  class NumericalFlux
  {
  public:
    using State = physics::State<dim>;
    static constexpr unsigned int NC = dim + 2;

    NumericalFlux(const Description &desc, const Scene &scene)
      : desc(desc)
      , type(scene.flux)
      , max_stages(scene.musta_max_stages)
      , tol(scene.musta_tolerance)
      , cloc(scene.musta_local_cfl)
    {}

    void operator()(const State &UL, const State &UR, const unsigned int d, State &F,
                    FluxStatistics &stats) const
    {
      ++stats.points;
      switch (type)
        {
          case FluxType::rusanov:
            rusanov(UL, UR, d, F);
            return;
          case FluxType::hll:
            hll(UL, UR, d, F);
            return;
          default:
            musta(UL, UR, d, F, stats);
        }
    }

    void rusanov(const State &UL, const State &UR, const unsigned int d, State &F) const
    {
      State FL, FR;
      desc.flux(UL, d, FL);
      desc.flux(UR, d, FR);
      const double a = std::max(desc.max_wave_speed(UL, d), desc.max_wave_speed(UR, d));
      for (unsigned int c = 0; c < NC; ++c)
        F[c] = 0.5 * (FL[c] + FR[c]) - 0.5 * a * (UR[c] - UL[c]);
    }

    void hll(const State &UL, const State &UR, const unsigned int d, State &F) const
    {
      State        FL, FR;
      const double pL = desc.flux(UL, d, FL), pR = desc.flux(UR, d, FR);
      const double cL = desc.sound_speed(UL[0], std::max(pL, 0.)),
                   cR = desc.sound_speed(UR[0], std::max(pR, 0.));
      const double uL = UL[1 + d] / UL[0], uR = UR[1 + d] / UR[0];
      const double SL = std::min(uL - cL, uR - cR), SR = std::max(uL + cL, uR + cR);
      if (SL >= 0)
        F = FL;
      else if (SR <= 0)
        F = FR;
      else
        for (unsigned int c = 0; c < NC; ++c)
          F[c] = (SR * FL[c] - SL * FR[c] + SL * SR * (UR[c] - UL[c])) / (SR - SL);
    }

    void musta(const State &UL0, const State &UR0, const unsigned int d, State &F,
               FluxStatistics &stats) const
    {
      State UL = UL0, UR = UR0, FL, FR, Uh, Fh, Fprev;
      // the pressure of each state once per stage, for its flux and its wave speed
      double pL = desc.pressure(UL), pR = desc.pressure(UR);
      for (unsigned int l = 0; l < max_stages; ++l)
        {
          ++stats.stages;
          desc.flux(UL, pL, d, FL);
          desc.flux(UR, pR, d, FR);
          const double smax = std::max(desc.max_wave_speed(UL, d, pL), desc.max_wave_speed(UR, d, pR));
          const double r    = cloc / smax; // local dt/dx
          for (unsigned int c = 0; c < NC; ++c)
            Uh[c] = 0.5 * (UL[c] + UR[c]) - 0.5 * r * (FR[c] - FL[c]); // eq. 4.7a
          if (!desc.admissible(Uh))
            {
              ++stats.fallbacks;
              rusanov(UL0, UR0, d, F);
              return;
            }
          desc.flux(Uh, d, Fh);
          double diff = 0, norm = 0;
          for (unsigned int c = 0; c < NC; ++c)
            {
              F[c] = 0.25 * (FL[c] + 2 * Fh[c] + FR[c] - (UR[c] - UL[c]) / r); // eq. 4.7b, P12
              diff += (F[c] - Fprev[c]) * (F[c] - Fprev[c]);
              norm += F[c] * F[c];
            }
          if (l > 0 && diff <= tol * tol * norm) // 1 % rule
            return;
          if (l + 1 == max_stages)
            return;
          for (unsigned int c = 0; c < NC; ++c)
            {
              UL[c] -= r * (F[c] - FL[c]); // eq. 4.8
              UR[c] -= r * (FR[c] - F[c]); // eq. 4.9
            }
          if (!desc.admissible(UL) || !desc.admissible(UR))
            return; // keep the last FORCE flux, computed from admissible states
          pL = desc.pressure(UL);
          pR = desc.pressure(UR);
          Fprev = F;
        }
    }

  private:
    const Description &desc;
    FluxType           type;
    unsigned int       max_stages;
    double             tol, cloc;
  };
} // namespace granhydro::convection
