#pragma once
/**
 * @file numerical_flux.h
 * Numerical fluxes across a face with normal e_d, from the reconstructed
 * states U_L (inside the cell on the low side) and U_R.
 *
 *  - MUSTA: multi-stage FORCE, paper eqs. (4.7)-(4.9), Titarev & Toro (2004),
 *    with the dissipation term carrying dx/dt (doc/physics.md P12). Each stage
 *    uses the local ratio dt/dx = C_loc / S_max(U_L, U_R) (Titarev-Toro's
 *    local Courant number, default 0.9). The iteration stops when the FORCE
 *    flux changes between stages by less than the tolerance (paper: 1 %) in
 *    mass, momentum (Euclidean norm) and energy, each relative to its own
 *    scale max(|F|, S_max (|U_L| + |U_R|)/2) - free of the unit system - or
 *    at the stage cap. If a predictor state leaves the admissible set
 *    (near vacuum) the face falls back to the Rusanov flux of the original
 *    states; such fallbacks are counted.
 *  - Rusanov (local Lax-Friedrichs) and HLL (Davis wave-speed estimates).
 *
 * Everything depends only on (U_L, U_R, d): two ranks computing the same
 * face get bit-identical results.
 */
#include <granhydro/convection/settings.h>
#include <granhydro/physics/ideal_gas.h>
#include <granhydro/physics/lanes.h>

#include <algorithm>
#include <cmath>

namespace granhydro::convection
{
  struct FluxStatistics
  {
    unsigned long long points = 0, stages = 0, fallbacks = 0;
    /// MUSTA points that stopped early because a stage state left the admissible set
    /// (they keep their last FORCE flux)
    unsigned long long early_stops = 0;
  };

  template <int dim, class Description>
  class NumericalFlux
  {
  public:
    using State                      = physics::State<dim>;
    static constexpr unsigned int NC = dim + 2;

    NumericalFlux(const Description &desc, const ConvectionSettings &settings)
      : desc(desc)
      , type(settings.flux)
      , max_stages(settings.musta_max_stages)
      , min_stages(settings.musta_min_stages)
      , tol(settings.musta_tolerance)
      , cloc(settings.musta_local_cfl)
    {}

    /// repair_energy: the step's splitting allowance of the temperature repair (scaled, per
    /// grain; physics::GranularGas::admissible()), for MUSTA's test of its predictor states
    void operator()(const State &UL, const State &UR, const unsigned int d, State &F, FluxStatistics &stats,
                    const double repair_energy) const
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
            musta(UL, UR, d, F, stats, repair_energy);
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

    void musta(const State &UL0, const State &UR0, const unsigned int d, State &F, FluxStatistics &stats,
               const double repair_energy) const
    {
      musta_lanes<double>(&UL0, &UR0, d, &F, stats, repair_energy);
    }

    /**
     * The fluxes F[q] of n points q of one face (operator() for each), the points as
     * lanes of the vector type V where the description takes vectors of states
     * (MUSTA): every lane does the same operations as musta() on its point, so the
     * result and the statistics are bit for bit those of operator() point by point.
     */
    template <class V>
    __attribute__((always_inline)) inline void points(const State *UL, const State *UR, const unsigned int n,
                                                      const unsigned int d, State *F, FluxStatistics &stats,
                                                      const double repair_energy) const
    {
      unsigned int q = 0;
      if constexpr (Description::vector_lanes)
        if (type == FluxType::musta)
          {
            constexpr unsigned int L = physics::lanes::width<V>;
            for (; q + L <= n; q += L)
              {
                stats.points += L;
                musta_lanes<V>(UL + q, UR + q, d, F + q, stats, repair_energy);
              }
            typedef double V2 __attribute__((vector_size(16)));
            if constexpr (L > 2)
              for (; q + 2 <= n; q += 2)
                {
                  stats.points += 2;
                  musta_lanes<V2>(UL + q, UR + q, d, F + q, stats, repair_energy);
                }
          }
      for (; q < n; ++q)
        operator()(UL[q], UR[q], d, F[q], stats, repair_energy);
    }

    /**
     * MUSTA for the L lanes of V at once (points UL0[i], UR0[i] -> Fout[i], i < L; V =
     * double: one point). Each stage uses each state's pressure once, for its flux and
     * its wave speed. A lane stops when its flux has converged, at the stage cap, or
     * when its states leave the admissible set (it keeps its last FORCE flux); a lane
     * whose predictor state is inadmissible takes the Rusanov flux of its original
     * states. The other lanes go on; every lane does the operations of one point alone.
     */
    template <class V>
    __attribute__((always_inline)) inline void
    musta_lanes(const State *UL0, const State *UR0, const unsigned int d, State *Fout, FluxStatistics &stats,
                const double repair_energy) const
    {
      namespace lanes          = physics::lanes;
      constexpr unsigned int L = lanes::width<V>;
      std::array<V, NC>      UL, UR, F;
      for (unsigned int c = 0; c < NC; ++c)
        for (unsigned int i = 0; i < L; ++i)
          {
            lanes::ref(UL[c], i) = UL0[i][c];
            lanes::ref(UR[c], i) = UR0[i][c];
          }
      const auto fallback = musta_vector<V>(UL, UR, d, F, stats, repair_energy);
      for (unsigned int i = 0; i < L; ++i)
        if (lanes::set(fallback, i))
          rusanov(UL0[i], UR0[i], d, Fout[i]);
        else
          for (unsigned int c = 0; c < NC; ++c)
            Fout[i][c] = lanes::get(F[c], i);
    }

    /**
     * musta_lanes() on states already in lanes (UL, UR: component c of lane i is
     * UL[c][i]; they are overwritten), the fluxes into F; returns the lanes whose
     * predictor state was inadmissible (counted as fallbacks), whose flux the caller
     * takes as the Rusanov flux of their original states.
     */
    template <class V>
    __attribute__((always_inline)) inline physics::lanes::Mask<V>
    musta_vector(std::array<V, NC> &UL, std::array<V, NC> &UR, const unsigned int d, std::array<V, NC> &F,
                 FluxStatistics &stats, const double repair_energy) const
    {
      namespace lanes = physics::lanes;
      using VS        = std::array<V, NC>;
      using M         = lanes::Mask<V>;
      VS FL, FR, Uh, Fh, Fprev;
      for (unsigned int c = 0; c < NC; ++c)
        F[c] = Fprev[c] = V();
      M active = V() == V(), fallback = V() != V(); // all lanes, none
      // what the formulas read of each state's density (the dense closure's potential, chi),
      // evaluated once per state and stage for its pressure, wave speed and admissibility
      auto tL = desc.density_terms(UL[0]), tR = desc.density_terms(UR[0]);
      V    pL = desc.pressure(UL, tL), pR = desc.pressure(UR, tR);
      // each state's physical flux and wave speed next to its pressure (and admissibility):
      // the formulas share its velocity, kinetic energy and temperature
      V aL = physical_flux(UL, tL, pL, d, FL), aR = physical_flux(UR, tR, pR, d, FR);
      for (unsigned int l = 0; l < max_stages; ++l)
        {
          stats.stages += lanes::count(active);
          const V smax = aL < aR ? aR : aL; // std::max(aL, aR)
          const V r    = cloc / smax;       // local dt/dx
          for (unsigned int c = 0; c < NC; ++c)
            Uh[c] = 0.5 * (UL[c] + UR[c]) - 0.5 * r * (FR[c] - FL[c]); // eq. 4.7a
          const auto th = desc.density_terms(Uh[0]);
          const M    ok = desc.admissible(Uh, th, repair_energy);
          fallback      = fallback || (active && !ok);
          active        = active && ok;
          if (!lanes::any(active))
            break;
          desc.flux(Uh, desc.pressure(Uh, th), d, Fh);
          // the 1 % rule for mass, momentum (as a vector) and energy separately, each
          // against its own scale: its flux, or the wave speed times its state (for a
          // flux near 0, e.g. mass at rest), so the decision is the same in any unit
          // system (and in any rotated frame). With MUSTA minimum stages = 1, after the
          // first stage (no previous flux yet) the change a further stage would make is
          // estimated by S_max |U_R - U_L| (a stage moves the states by about C_loc
          // |U_R - U_L| / 2, and the flux with them at wave speeds <= S_max): a face
          // whose jump is that small keeps the FORCE flux
          // (a stage before the minimum count stops no lane: its test is skipped)
          const bool judged    = l + 1 >= min_stages;
          V          change[3] = {V(), V(), V()}, flux2[3] = {V(), V(), V()}, state2[3] = {V(), V(), V()};
          for (unsigned int c = 0; c < NC; ++c)
            {
              const V Fc = 0.25 * (FL[c] + 2 * Fh[c] + FR[c] - (UR[c] - UL[c]) / r); // eq. 4.7b, P12
              if (judged)
                {
                  const unsigned int g  = c == 0 ? 0 : (c + 1 == NC ? 2 : 1);
                  const V            Uc = 0.5 * (lanes::abs(UL[c]) + lanes::abs(UR[c]));
                  const V            dF = l == 0 ? smax * (UR[c] - UL[c]) : Fc - Fprev[c];
                  change[g] += dF * dF;
                  flux2[g] += Fc * Fc;
                  state2[g] += Uc * Uc;
                }
              F[c] = active ? Fc : F[c];
            }
          if (judged)
            {
              M converged = V() == V();
              for (unsigned int g = 0; g < 3; ++g)
                {
                  const V scale2 = smax * smax * state2[g];
                  converged = converged && (change[g] <= tol * tol * (flux2[g] < scale2 ? scale2 : flux2[g]));
                }
              active = active && !converged;
            }
          if (l + 1 == max_stages || !lanes::any(active))
            break;
          for (unsigned int c = 0; c < NC; ++c)
            {
              UL[c] -= r * (F[c] - FL[c]); // eq. 4.8
              UR[c] -= r * (FR[c] - F[c]); // eq. 4.9
            }
          // keep the last FORCE flux, computed from admissible states (counted)
          const M was = active;
          tL          = desc.density_terms(UL[0]);
          tR          = desc.density_terms(UR[0]);
          active = active && desc.admissible(UL, tL, repair_energy) && desc.admissible(UR, tR, repair_energy);
          stats.early_stops += lanes::count(was && !active);
          if (!lanes::any(active))
            break;
          pL    = desc.pressure(UL, tL);
          pR    = desc.pressure(UR, tR);
          aL    = physical_flux(UL, tL, pL, d, FL);
          aR    = physical_flux(UR, tR, pR, d, FR);
          Fprev = F;
        }
      stats.fallbacks += lanes::count(fallback);
      return fallback;
    }

    /// MUSTA on vectors of states (musta_vector()): the face loops then load the points
    /// into lanes themselves
    bool vector_musta() const { return Description::vector_lanes && type == FluxType::musta; }

  private:
    /// the flux F of the state U (its density terms t, pressure p); returns its largest
    /// wave speed
    template <class V, class Terms>
    __attribute__((always_inline)) inline V physical_flux(const std::array<V, NC> &U, const Terms &t,
                                                          const V p, const unsigned int d,
                                                          std::array<V, NC> &F) const
    {
      desc.flux(U, p, d, F);
      return desc.max_wave_speed(U, d, p, t);
    }

    const Description &desc;
    FluxType           type;
    unsigned int       max_stages, min_stages;
    double             tol, cloc;
  };
} // namespace granhydro::convection
