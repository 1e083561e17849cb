#pragma once
/**
 * @file face_kernels.h
 * The convective operator's hot loops (an internal part of ConvectionOperator, included
 * by convection_operator.cc only): one reconstruction stage over a list of slots, and the
 * numerical fluxes of a direction's faces, each written once on GCC vectors of doubles
 * and compiled for the default target (2 lanes) and for AVX2 without FMA (4 lanes), so
 * that every lane is the scalar IEEE result bit for bit.
 */
#include <granhydro/convection/numerical_flux.h>
#include <granhydro/convection/reconstruction.h>
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/physics/lanes.h>

#include <deal.II/base/array_view.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <type_traits>

namespace granhydro::convection
{
  namespace
  {
    using namespace dealii;

    /// a piece of a slot list
    using SlotRange = ArrayView<const unsigned int>;

    // GCC vectors of doubles (element-wise IEEE arithmetic, no contraction on the default
    // target): lanes are independent stencils, each bit for bit the scalar result
    typedef double v2d __attribute__((vector_size(16), aligned(8)));
    typedef double v4d __attribute__((vector_size(32), aligned(8)));

    template <class T>
    __attribute__((always_inline)) inline T load(const double *p)
    {
      T x;
      std::memcpy(&x, p, sizeof(T));
      return x;
    }
    template <class T>
    __attribute__((always_inline)) inline void store(double *p, const T x)
    {
      std::memcpy(p, &x, sizeof(T));
    }

    template <class Recon>
    constexpr bool has_lanes = std::is_same_v<Recon, Weno5>;

    /**
     * Point pairs of lanes [j0, j0 + L) of one slot (L = lanes of T): lane j of the
     * stencil's k-th cell is src[k][j]. Weno5 runs on vectors (all lanes in one call);
     * the other reconstructions lane by lane.
     */
    template <class T, class Recon>
    __attribute__((always_inline)) inline void pair_chunk(const Recon &rec, const double *const *src,
                                                          const unsigned int j, const unsigned int p,
                                                          double *lo, double *hi)
    {
      if constexpr (has_lanes<Recon>)
        {
          T l, h;
          rec.template pair_v<T>(load<T>(src[0] + j), load<T>(src[1] + j), load<T>(src[2] + j),
                                 load<T>(src[3] + j), load<T>(src[4] + j), p, l, h);
          store<T>(lo + j, l);
          store<T>(hi + j, h);
        }
      else
        {
          constexpr int w = 2 * Recon::r + 1;
          double        v[w];
          for (int k = 0; k < w; ++k)
            v[k] = src[k][j];
          rec.pair(v, p, lo[j], hi[j]);
        }
    }

    /**
     * One reconstruction stage along dir for the slots of list: the input has m = G * NC
     * values per slot (G groups of NC components), the output 2 m: lane g * NC + c gives
     * the lower point at out[2 g NC + c] and the upper one at out[(2 g + 1) NC + c].
     * V: the widest vector type to use.
     */
    template <class V, class Recon, int dim, unsigned int Mc = 0>
    __attribute__((always_inline)) inline void
    reconstruct_stage(const Recon &rec, const mesh::CartesianPatch<dim> &patch, const SlotRange &list,
                      const unsigned int dir, const double *in, const unsigned int m_in,
                      const unsigned int NC_in, const unsigned int p, double *outbase)
    {
      // Mc > 0: m = Mc and NC = dim + 2 known at compile time (the loops over the values
      // unrolled)
      const unsigned int m = Mc > 0 ? Mc : m_in, NC = Mc > 0 ? dim + 2 : NC_in;
      constexpr int      r = Recon::r;
      constexpr int      w = 2 * r + 1;
      constexpr unsigned L = has_lanes<Recon> ? sizeof(V) / sizeof(double) : 1;
      double             lo[4 * 5], hi[4 * 5];
      const double      *src[w];
      for (const unsigned int s : list)
        {
          for (int o = -r; o <= r; ++o)
            src[o + r] = in + std::size_t(patch.neighbor(s, dir, o)) * m;
          unsigned int j = 0;
          if constexpr (L > 1)
            for (; j + L <= m; j += L)
              pair_chunk<V>(rec, src, j, p, lo, hi);
          if constexpr (L > 2)
            for (; j + 2 <= m; j += 2)
              pair_chunk<v2d>(rec, src, j, p, lo, hi);
          for (; j < m; ++j)
            pair_chunk<double>(rec, src, j, p, lo, hi);
          double *out = outbase + std::size_t(s) * 2 * m;
          for (unsigned int g = 0; g * NC < m; ++g)
            for (unsigned int c = 0; c < NC; ++c)
              {
                out[2 * g * NC + c]       = lo[g * NC + c];
                out[(2 * g + 1) * NC + c] = hi[g * NC + c];
              }
        }
    }

    /**
     * The flux of every face of patch.faces(d) (Gauss-weighted sum over its npts points,
     * wall faces not yet zeroed) into F (NC per face); fin: the points of each slot,
     * [slot][side][point][component]. V: the vector type for the points as lanes.
     */
    template <class V, int dim, class Description>
    __attribute__((always_inline)) inline void
    face_fluxes_impl(const NumericalFlux<dim, Description> &numflux, const mesh::CartesianPatch<dim> &patch,
                     const unsigned int d, const double *fin, const unsigned int npts, const double wq,
                     double *F, FluxStatistics &stats, const double repair_energy)
    {
      constexpr unsigned int NC    = dim + 2;
      const auto            &faces = patch.faces(d);
      physics::State<dim>    UL[4], UR[4], Fq[4];
      // the counts are of this rank's faces only (its low-side cell owned, or a boundary
      // face of an owned cell): a face between two ranks is computed by both, and the run
      // summary's flux_points and musta_stages must not depend on the partition
      FluxStatistics        shared;
      const unsigned int    n_owned = patch.n_owned();
      constexpr std::size_t ahead   = 4; // faces: the point values are read from memory (L3)
      for (std::size_t k = 0; k < faces.size(); ++k)
        {
          if (k + ahead < faces.size())
            {
              const char *pl =
                reinterpret_cast<const char *>(fin + (std::size_t(faces[k + ahead].l) * 2 + 1) * npts * NC);
              const char *pr =
                reinterpret_cast<const char *>(fin + std::size_t(faces[k + ahead].r) * 2 * npts * NC);
              const std::size_t bytes = npts * NC * sizeof(double);
              for (std::size_t b = 0; b < bytes; b += 64)
                {
                  __builtin_prefetch(pl + b);
                  __builtin_prefetch(pr + b);
                }
              __builtin_prefetch(pl + bytes - 1);
              __builtin_prefetch(pr + bytes - 1);
            }
          const unsigned int sl = faces[k].l, sr = faces[k].r;
          FluxStatistics    &counted = sl < n_owned || (sr < n_owned && !patch.is_cell(sl)) ? stats : shared;
          const double      *vl      = fin + (std::size_t(sl) * 2 + 1) * npts * NC;
          const double      *vr      = fin + (std::size_t(sr) * 2 + 0) * npts * NC;
          // a hanging (fine sub-) face: the coarse side's Gauss point in this sub-face
          const int  cp       = npts > 1 ? faces[k].coarse_point : -1;
          const bool l_fixed  = cp >= 0 && patch.level(sl) < patch.level(sr);
          const bool r_fixed  = cp >= 0 && patch.level(sr) < patch.level(sl);
          bool       in_lanes = false;
          if constexpr (physics::lanes::width<V> == 4)
            if (npts == 4 && numflux.vector_musta())
              {
                // the 4 points straight into lanes (no detour through states in memory):
                // the same operations per lane as points(), so bit for bit its fluxes
                std::array<V, NC> ul, ur, fv;
                unsigned int      ol[4], orr[4];
                for (unsigned int q = 0; q < 4; ++q)
                  {
                    ol[q]  = (l_fixed ? cp : q) * NC;
                    orr[q] = (r_fixed ? cp : q) * NC;
                  }
                for (unsigned int c = 0; c < NC; ++c)
                  {
                    ul[c] = V{vl[ol[0] + c], vl[ol[1] + c], vl[ol[2] + c], vl[ol[3] + c]};
                    ur[c] = V{vr[orr[0] + c], vr[orr[1] + c], vr[orr[2] + c], vr[orr[3] + c]};
                  }
                counted.points += 4;
                const auto fallback = numflux.template musta_vector<V>(ul, ur, d, fv, counted, repair_energy);
                for (unsigned int q = 0; q < 4; ++q)
                  if (fallback[q])
                    {
                      // the Rusanov flux of the lane's original states (re-read)
                      for (unsigned int c = 0; c < NC; ++c)
                        {
                          UL[q][c] = vl[ol[q] + c];
                          UR[q][c] = vr[orr[q] + c];
                        }
                      numflux.rusanov(UL[q], UR[q], d, Fq[q]);
                    }
                  else
                    for (unsigned int c = 0; c < NC; ++c)
                      Fq[q][c] = fv[c][q];
                in_lanes = true;
              }
          if (!in_lanes)
            {
              for (unsigned int q = 0; q < npts; ++q)
                {
                  const unsigned int ql = l_fixed ? cp : q, qr = r_fixed ? cp : q;
                  for (unsigned int c = 0; c < NC; ++c)
                    {
                      UL[q][c] = vl[ql * NC + c];
                      UR[q][c] = vr[qr * NC + c];
                    }
                }
              numflux.template points<V>(UL, UR, npts, d, Fq, counted, repair_energy);
            }
          double *Fsum = F + k * NC;
          for (unsigned int c = 0; c < NC; ++c)
            Fsum[c] = 0.;
          for (unsigned int q = 0; q < npts; ++q)
            for (unsigned int c = 0; c < NC; ++c)
              Fsum[c] += wq * Fq[q][c];
        }
    }

    using physics::lanes::use_avx2;

#if defined(__x86_64__) || defined(__i386__)
    /// flatten: every physics formula the flux calls is inlined into this AVX2 clone (a
    /// formula instantiated on vectors of 4 doubles outside it would be compiled for the
    /// default target, with another calling convention for such vectors)
    template <int dim, class Description>
    __attribute__((target("avx2"), flatten)) void
    face_fluxes_avx2(const NumericalFlux<dim, Description> &numflux, const mesh::CartesianPatch<dim> &patch,
                     const unsigned int d, const double *fin, const unsigned int npts, const double wq,
                     double *F, FluxStatistics &stats, const double repair_energy)
    {
      face_fluxes_impl<v4d>(numflux, patch, d, fin, npts, wq, F, stats, repair_energy);
    }
#endif

    template <int dim, class Description>
    void face_fluxes(const NumericalFlux<dim, Description> &numflux, const mesh::CartesianPatch<dim> &patch,
                     const unsigned int d, const double *fin, const unsigned int npts, const double wq,
                     double *F, FluxStatistics &stats, const double repair_energy)
    {
#if defined(__x86_64__) || defined(__i386__)
      if (Description::vector_lanes && use_avx2())
        face_fluxes_avx2(numflux, patch, d, fin, npts, wq, F, stats, repair_energy);
      else
#endif
        face_fluxes_impl<v2d>(numflux, patch, d, fin, npts, wq, F, stats, repair_energy);
    }

    /// reconstruct_stage() with the stage's width m (NC, 2 NC or 4 NC values per slot) a
    /// compile-time constant
    template <class V, class Recon, int dim>
    __attribute__((always_inline)) inline void
    reconstruct_stage_fixed(const Recon &rec, const mesh::CartesianPatch<dim> &patch, const SlotRange &list,
                            const unsigned int dir, const double *in, const unsigned int m,
                            const unsigned int NC, const unsigned int p, double *outbase)
    {
      constexpr unsigned int nc = dim + 2;
      if (NC == nc && m == nc)
        reconstruct_stage<V, Recon, dim, nc>(rec, patch, list, dir, in, m, NC, p, outbase);
      else if (NC == nc && m == 2 * nc)
        reconstruct_stage<V, Recon, dim, 2 * nc>(rec, patch, list, dir, in, m, NC, p, outbase);
      else if (NC == nc && m == 4 * nc)
        reconstruct_stage<V, Recon, dim, 4 * nc>(rec, patch, list, dir, in, m, NC, p, outbase);
      else
        reconstruct_stage<V>(rec, patch, list, dir, in, m, NC, p, outbase);
    }

#if defined(__x86_64__) || defined(__i386__)
    /// reconstruct_stage() compiled for AVX2 (4 lanes per vector; AVX2 without FMA, so
    /// every lane is the same IEEE operation sequence as on the default target)
    template <class Recon, int dim>
    __attribute__((target("avx2"))) void
    reconstruct_stage_avx2(const Recon &rec, const mesh::CartesianPatch<dim> &patch, const SlotRange &list,
                           const unsigned int dir, const double *in, const unsigned int m,
                           const unsigned int NC, const unsigned int p, double *outbase)
    {
      reconstruct_stage_fixed<v4d>(rec, patch, list, dir, in, m, NC, p, outbase);
    }
#endif

    template <class Recon, int dim>
    void reconstruct(const Recon &rec, const mesh::CartesianPatch<dim> &patch, const SlotRange &list,
                     const unsigned int dir, const double *in, const unsigned int m, const unsigned int NC,
                     const unsigned int p, double *outbase)
    {
#if defined(__x86_64__) || defined(__i386__)
      if (has_lanes<Recon> && use_avx2())
        reconstruct_stage_avx2(rec, patch, list, dir, in, m, NC, p, outbase);
      else
#endif
        reconstruct_stage_fixed<v2d>(rec, patch, list, dir, in, m, NC, p, outbase);
    }
  } // namespace
} // namespace granhydro::convection
