#include <granhydro/convection/convection_operator.h>
#include <granhydro/physics/granular_gas.h>
#include <granhydro/physics/models.h>

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>

#include "face_kernels.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <type_traits>

namespace granhydro::convection
{
  using namespace dealii;

  template <int dim, class Description>
  ConvectionOperator<dim, Description>::ConvectionOperator(const mesh::CartesianPatch<dim> &patch,
                                                           const Description               &desc,
                                                           const ConvectionSettings        &settings)
    : patch(patch)
    , desc(desc)
    , numflux(desc, settings)
    , rtype(settings.reconstruction)
    // first order: every transverse point carries the cell average, so the face
    // average is exact and the transverse stages are skipped
    , transverse(dim > 1 && settings.reconstruction != ReconstructionType::first_order)
    , P(settings.face_quadrature == FaceQuadrature::gauss ? 2 : 1)
    , no_slip_pressure_flux(settings.no_slip_pressure_flux)
    , no_wall_tension(settings.no_wall_tension)
  {
    length_unit = settings.length_unit;
    for (unsigned int d = 0; d < dim; ++d)
      gravity[d] = settings.gravity[d];
  }

  template <int dim, class Description>
  unsigned int ConvectionOperator<dim, Description>::stencil_half_width(const ReconstructionType t)
  {
    return t == ReconstructionType::weno5 ? 2 : (t == ReconstructionType::first_order ? 0 : 1);
  }

  namespace
  {
    /// sort v and drop repetitions; its entries lie below n (slots): a mark per slot and
    /// one scan when v is not much shorter than n, else a sort
    void unique_sort(std::vector<unsigned int> &v, const unsigned int n)
    {
      if (v.size() < n / 16)
        {
          std::sort(v.begin(), v.end());
          v.erase(std::unique(v.begin(), v.end()), v.end());
          return;
        }
      std::vector<char> mark(n, 0);
      for (const unsigned int s : v)
        {
          AssertIndexRange(s, n);
          mark[s] = 1;
        }
      v.clear();
      for (unsigned int s = 0; s < n; ++s)
        if (mark[s])
          v.push_back(s);
    }

  } // namespace

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::setup()
  {
    const int r = stencil_half_width(rtype);
    AssertThrow(patch.ghost_width() >= unsigned(r) + 1, ExcMessage("ghost width too small"));
    const unsigned int n_owned = patch.n_owned();
    auto               nb      = [&](unsigned int s, unsigned int d, int o) {
      const int t = patch.neighbor(s, d, o);
      AssertThrow(t >= 0, ExcMessage("stencil leaves the ghost patch (internal error)"));
      return unsigned(t);
    };
    // the patch geometry is in SI; the operator works in scaled units (length sigma)
    for (unsigned int d = 0; d < dim; ++d)
      for (unsigned int k = 0; k < mesh::max_levels; ++k)
        inv_h[d][k] = length_unit / patch.level_cell_size(k, d);
    // one flag per cell (stage_update()): the state's partitioner with one index per cell
    {
      const auto &p = *patch.partitioner();
      IndexSet    owned(p.size() / NC), ghosts(p.size() / NC);
      owned.add_range(p.local_range().first / NC, p.local_range().second / NC);
      for (const auto g : p.ghost_indices())
        if (g % NC == 0)
          ghosts.add_index(g / NC);
      cell_partitioner =
        std::make_shared<const Utilities::MPI::Partitioner>(owned, ghosts, patch.communicator());
      AssertThrow(cell_partitioner->locally_owned_size() == n_owned &&
                    cell_partitioner->n_ghost_indices() == patch.n_mpi_ghosts(),
                  ExcMessage("internal error: the state's partitioner is not NC values per cell"));
      flags.reinit(cell_partitioner);
    }
    // on several ranks the halo's cells (MPI ghosts) take their stage values from their
    // owners, who compute every stage of every owned cell: the same formula on the same
    // inputs, so the result is bitwise that of one rank, and no rank redoes the
    // reconstructions of the cells next to its partition boundary
    halo_exchange                       = Utilities::MPI::n_mpi_processes(patch.communicator()) > 1;
    const unsigned int         ghost_lo = n_owned, ghost_hi = n_owned + patch.n_mpi_ghosts();
    std::vector<std::uint16_t> need(patch.n_mpi_ghosts(), 0); // channels per MPI ghost
    for (unsigned int d = 0; d < dim; ++d)
      {
        const auto &faces = patch.faces(d);
        wall[d].resize(faces.size());
        for (std::size_t k = 0; k < faces.size(); ++k)
          {
            const int id = patch.wall_id(faces[k].l, faces[k].r, d);
            wall[d][k]   = id < 0 ?
                             char(boundary::not_a_wall) :
                             boundary::convective_wall_kind(patch.wall_settings(id), no_slip_pressure_flux);
          }
        // face cells (their neighbourhoods are uniform, partly virtual on adaptive meshes)
        std::vector<unsigned int> fin;
        for (const auto &f : faces)
          for (const unsigned int s : {f.l, f.r})
            fin.push_back(s);
        unique_sort(fin, patch.n_slots());
        // stage j of direction d on several ranks: the MPI ghosts among its slots get
        // their values from their owners (channel(d, j)), so they leave the list and the
        // previous stage is not needed around them
        auto strip = [&](std::vector<unsigned int> &L, const unsigned int j) {
          if (!halo_exchange)
            return;
          AssertThrow(n_owned == 0 || (L.size() >= n_owned && L[n_owned - 1] == n_owned - 1),
                      ExcMessage("internal error: a stage list lacks owned cells (sorted and unique, "
                                 "it holds all of them iff its n_owned-th entry is n_owned - 1)"));
          for (const unsigned int s : L)
            if (s >= ghost_lo && s < ghost_hi)
              need[s - ghost_lo] |= std::uint16_t(1u << channel(d, j));
          L.erase(std::remove_if(L.begin(), L.end(),
                                 [&](const unsigned int s) { return s >= ghost_lo && s < ghost_hi; }),
                  L.end());
        };
        auto widen = [&](const std::vector<unsigned int> &in, unsigned int dir) {
          std::vector<unsigned int> out;
          for (const unsigned int s : in)
            for (int o = -r; o <= r; ++o)
              out.push_back(nb(s, dir, o));
          unique_sort(out, patch.n_slots());
          return out;
        };
        std::vector<unsigned int> *L[3] = {&listA[d], &listB[d], &listC[d]};
        for (auto *l : L)
          l->clear();
        const unsigned int ns = n_stages();
        *L[ns - 1]            = fin;
        strip(*L[ns - 1], ns - 1);
        for (int j = int(ns) - 2; j >= 0; --j)
          {
            // stage j + 1 reads stage j along its direction
            *L[j] = widen(*L[j + 1], stage_direction(d, j + 1));
            strip(*L[j], j);
          }
        for (const unsigned int s : listA[d]) // the normal stencil must exist
          for (int o = -r; o <= r; ++o)
            nb(s, d, o);
        // widen() collected 2 r + 1 entries per slot before removing the duplicates
        for (auto *l : L)
          l->shrink_to_fit();
      }
    if (halo_exchange)
      {
        halo.setup(*patch.partitioner(), NC, n_owned, need);
        // the slots a neighbour waits for come first in each list: their values are sent
        // before the rest of the stage is computed
        std::vector<char> sent(patch.n_slots());
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int j = 0; j < n_stages(); ++j)
            {
              std::fill(sent.begin(), sent.end(), 0);
              halo.mark_sent(channel(d, j), sent);
              auto &l     = j == 0 ? listA[d] : (j == 1 ? listB[d] : listC[d]);
              split[d][j] = std::stable_partition(l.begin(), l.end(),
                                                  [&](const unsigned int s) { return sent[s] != 0; }) -
                            l.begin();
            }
      }
    else
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int j = 0; j < 3; ++j)
          split[d][j] = (j == 0 ? listA[d] : (j == 1 ? listB[d] : listC[d])).size();
    setup_well_balanced();
  }

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::apply(const double *Wp, double *rhs,
                                                   const double repair_energy) const
  {
    const auto t0 = std::chrono::steady_clock::now();
    wb_W          = Wp; // the state of the body force's sources (add_gravity_sources())
    switch (rtype)
      {
        case ReconstructionType::first_order:
          apply_impl(rec1, Wp, rhs, repair_energy);
          break;
        case ReconstructionType::muscl:
          apply_impl(rec_muscl, Wp, rhs, repair_energy);
          break;
        case ReconstructionType::weno3:
          apply_impl(rec3, Wp, rhs, repair_energy);
          break;
        default:
          apply_impl(rec5, Wp, rhs, repair_energy);
      }
    busy_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  template <int dim, class Description>
  template <class Recon>
  void ConvectionOperator<dim, Description>::apply_impl(const Recon &rec, const double *Wp, double *rhs,
                                                        const double repair_energy) const
  {
    constexpr int      r       = Recon::r;
    constexpr int      w       = 2 * r + 1;
    const unsigned int n_owned = patch.n_owned();
    ++stats.rhs_evaluations;
    stats.cell_updates += n_owned;
    const unsigned int npts = transverse ? (dim == 3 ? P * P : P) : 1;
    const double       wq   = 1. / npts;

    // midpoint quadrature: a transverse stage takes the 2 face values of each slot (2 NC
    // doubles) to the cell centre along direction t
    auto centre_stage = [&](const auto &list, const unsigned int t, const double *in, double *out_all) {
      for (const unsigned int s : list)
        {
          int idx[w];
          for (int o = -r; o <= r; ++o)
            idx[o + r] = patch.neighbor(s, t, o);
          double *out = out_all + std::size_t(s) * 2 * NC;
          for (unsigned int side = 0; side < 2; ++side)
            for (unsigned int c = 0; c < NC; ++c)
              {
                double v[w];
                for (int k = 0; k < w; ++k)
                  v[k] = in[(std::size_t(idx[k]) * 2 + side) * NC + c];
                out[side * NC + c] = rec.center(v);
              }
        }
    };
    // positivity: if a point value of slot s is inadmissible, all its 2 npts point values
    // in this direction fall back to the cell average
    auto positivity_fallback = [&](const SlotRange &range, const unsigned int d, double *vals_all) {
      for (const unsigned int s : range)
        {
          double *vals = vals_all + std::size_t(s) * 2 * npts * NC;
          bool    ok   = true;
          for (unsigned int q = 0; q < 2 * npts && ok; ++q)
            {
              physics::State<dim> U;
              for (unsigned int c = 0; c < NC; ++c)
                U[c] = vals[q * NC + c];
              ok = desc.convectively_admissible(U);
            }
          if (!ok)
            {
              // the cell average; with gravity along d, the equilibrium's face states
              physics::State<dim> face[2];
              for (unsigned int side = 0; side < 2; ++side)
                first_order_face_state(Wp, s, d, side, face[side]);
              for (unsigned int q = 0; q < 2 * npts; ++q)
                std::copy(face[q / npts].begin(), face[q / npts].end(), vals + q * NC);
              if (s < n_owned)
                ++stats.limited_cells;
            }
        }
    };
    // stage A along d to the two faces of each cell (face averages); with transverse stages,
    // B along the first transverse direction to its P points (Gauss pair or centre), C
    // along the second; the last stage's values are checked for positivity
    const unsigned int ns       = n_stages();
    const unsigned int m_out[3] = {2 * NC, 2 * P * NC, 2 * P * P * NC};
    // the stage arrays serve one direction at a time; every value a stage reads is written
    // first (by this rank, or received): no zeroing
    const std::size_t ns_all = patch.n_slots();
    double *const     A      = patch.scratch(mesh::Scratch::stage_a, ns_all * 2 * NC);
    double *const     B      = patch.scratch(mesh::Scratch::stage_b, transverse ? ns_all * 2 * P * NC : 0);
    double *const     C =
      patch.scratch(mesh::Scratch::stage_c, transverse && dim == 3 ? ns_all * 2 * P * P * NC : 0);
    for (unsigned int d = 0; d < dim; ++d)
      Fp[d] = patch.scratch(static_cast<mesh::Scratch>(static_cast<unsigned int>(mesh::Scratch::flux_0) + d),
                            patch.faces(d).size() * NC);
    auto stage_array = [&](const unsigned int j) { return j == 0 ? A : (j == 1 ? B : C); };
    auto run_stage   = [&](const unsigned int d, const unsigned int j, const unsigned int part) {
      const auto        &L     = j == 0 ? listA[d] : (j == 1 ? listB[d] : listC[d]);
      const unsigned int t     = stage_direction(d, j);
      double *const      out   = stage_array(j);
      const SlotRange    range = part == 0 ? SlotRange(L.data(), split[d][j]) :
                                               SlotRange(L.data() + split[d][j], L.size() - split[d][j]);
      if (j == 0 && wb_dir[d])
        reconstruct_well_balanced(rec, range, d, Wp, out);
      else if (j == 0)
        reconstruct(rec, patch, range, d, Wp, NC, NC, 0, out);
      else if (P == 2)
        reconstruct(rec, patch, range, t, stage_array(j - 1), m_out[j - 1], NC, 1, out);
      else
        centre_stage(range, t, stage_array(j - 1), out);
      if (j + 1 == ns && Recon::r > 0)
        positivity_fallback(range, d, out);
    };
    // fluxes per face (a hanging face is a fine sub-face); each owned cell then sums its
    // faces in a fixed geometric order, so the result does not depend on the numbering
    // (1 rank and N ranks agree bit for bit)
    auto fluxes = [&](const unsigned int d) {
      const auto &faces = patch.faces(d);
      double     *Fpd   = Fp[d];
      if (wb_dir[d])
        mirror_wall_points(d, stage_array(ns - 1), npts);
      face_fluxes(numflux, patch, d, stage_array(ns - 1), npts, wq, Fpd, stats.flux, repair_energy);
      for (std::size_t k = 0; k < faces.size(); ++k)
        if (wall[d][k])
          wall_flux(wall[d][k], d, &Fpd[k * NC], owned_wall_face(d, k));
    };
    // on several ranks each stage runs first on the slots other ranks wait for, whose values
    // are then sent, then on the rest, and only then are the halo's values received (the
    // wait overlaps the rest of the stage)
    auto finish = [&](const unsigned int d, const unsigned int j) {
      // the wait for the other ranks is not this rank's cost (busy_seconds())
      const auto t0 = std::chrono::steady_clock::now();
      halo.finish(channel(d, j), stage_array(j), m_out[j]);
      const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      busy_seconds_ -= waited;
      halo_wait_seconds_ += waited;
    };
    // with several stages, the last stage's values of direction d are received (and its
    // fluxes computed) only after stage A of direction d + 1 has run: stage A writes
    // another array, and the other rank's lag is absorbed by a whole stage instead of
    // stopping this rank at once
    const bool defer_last = halo_exchange && ns > 1;
    for (unsigned int d = 0; d < dim; ++d)
      {
        for (unsigned int j = 0; j < ns; ++j)
          {
            run_stage(d, j, 0);
            if (halo_exchange)
              halo.start(channel(d, j), stage_array(j), m_out[j]);
            run_stage(d, j, 1);
            if (defer_last && j == 0 && d > 0)
              {
                finish(d - 1, ns - 1);
                fluxes(d - 1);
              }
            if (halo_exchange && !(defer_last && j == ns - 1))
              finish(d, j);
          }
        if (!defer_last)
          fluxes(d);
      }
    if (defer_last)
      {
        finish(dim - 1, ns - 1);
        fluxes(dim - 1);
      }
    assemble_rhs(rhs);
  }

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::assemble_rhs(double *rhs) const
  {
    const unsigned int n_owned = patch.n_owned();
    std::fill(rhs, rhs + std::size_t(n_owned) * NC, 0.);
    for (unsigned int d = 0; d < dim; ++d)
      {
        for (unsigned int s = 0; s < n_owned; ++s)
          {
            double fw[NC] = {}, fe[NC] = {};
            patch.sum_face_fluxes(d, s, Fp[d], fw, fe);
            const double ih = inv_h[d][patch.level(s)];
            for (unsigned int c = 0; c < NC; ++c)
              rhs[std::size_t(s) * NC + c] += ih * (fw[c] - fe[c]);
          }
      }
    add_gravity_sources(rhs);
  }

#define GRANHYDRO_INSTANTIATE(d, D) template class ConvectionOperator<d, D>;
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_INSTANTIATE)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::convection
