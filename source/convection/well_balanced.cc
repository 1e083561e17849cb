// ConvectionOperator: the well-balanced gravity of the convective step (Käppeli & Mishra,
// "Well-balanced schemes for the Euler equations with gravitation", J. Comput. Phys. 259
// (2014) 199-219, section 3, with the granular equation of state of physics/hydrostatic.h):
// the local equilibrium of each cell, the reconstruction of the deviation from it, the
// first-order face states and the body force's sources (convection_operator.h)
#include <granhydro/boundary/ghost_state.h>
#include <granhydro/convection/convection_operator.h>
#include <granhydro/physics/hydrostatic.h>
#include <granhydro/physics/models.h>

#include <cmath>
#include <type_traits>

namespace granhydro::convection
{
  using namespace dealii;

  namespace
  {
    /// the local isothermal equilibrium of a slot along d: its chemical potential mu at the
    /// temperature Te = max(T, 0) (the pile's T may sit just below 0 inside a step), T
    /// itself for the energies, h the cell size along d (scaled)
    struct LocalEquilibrium
    {
      bool   ok = false;
      double n, T, Te, mu, h, slope;
    };

    template <int dim, class Description>
    LocalEquilibrium local_equilibrium(const Description &desc, const double *W, const double g,
                                       const double h)
    {
      LocalEquilibrium e;
      if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
        {
          physics::State<dim> S;
          std::copy(W, W + dim + 2, S.begin());
          e.n = S[0];
          if (!(e.n > 0) || !desc.convectively_admissible(S))
            return e;
          double W, pf, dpf; // the contact potential's n w, p_f, dp_f/dn at n
          desc.contact.evaluate(e.n, W, pf, dpf);
          e.T  = desc.temperature(S, W);
          e.Te = std::max(e.T, 0.);
          e.h  = h;
          // a hydrostatic profile needs a pressure that carries the weight of a cell without
          // changing n by more than a fraction of itself: dp/dn > 2 |g| h (else the point
          // source: cold dust, cavitation)
          physics::hydrostatic::chemical_potential_and_slope(desc, e.n, e.Te, W, pf, dpf, e.mu, e.slope);
          e.ok = e.slope > 2 * std::abs(g) * h && std::isfinite(e.mu);
        }
      return e;
    }

    /// the equilibrium density at the offset x (scaled length along d) from the centre. The
    /// Newton iteration starts from y_pred, a prediction of ln n there, or from the density
    /// found there (a neighbour) when that lies closer to the prediction than the change
    /// itself (a pile near its equilibrium: then the neighbour is the answer)
    template <int dim, class Description>
    double equilibrium_density(const Description &desc, const LocalEquilibrium &e, const double g,
                               const double x, const double y_pred, const double found = 0)
    {
      if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
        {
          const double y0   = std::log(e.n);
          const bool   near = found > 0 && std::abs(std::log(found) - y_pred) < std::abs(y_pred - y0);
          return physics::hydrostatic::equilibrium_density(
            desc, e.mu + g * x, e.Te,
            near ? found : std::exp(std::min(y_pred, std::log(0.99 / desc.phi_per_n))));
        }
      else
        return found;
    }

    /// the energy density of the equilibrium state at rest with density n, temperature T
    /// (GranularGas::from_primitive with u = 0)
    template <int dim, class Description>
    double rest_energy(const Description &desc, const double n, const double T)
    {
      if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
        {
          const double u[dim] = {};
          return desc.from_primitive(n, u, T)[dim + 1];
        }
      else
        return n * T;
    }
  } // namespace

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::setup_well_balanced()
  {
    constexpr bool granular = std::is_same_v<Description, physics::GranularGas<dim>>;
    ghost_record.assign(patch.n_slots(), -1);
    const auto &ghosts = patch.boundary_ghosts();
    for (std::size_t i = 0; i < ghosts.size(); ++i)
      ghost_record[ghosts[i].slot] = int(i);
    const int r = stencil_half_width(rtype);
    wb_any      = false;
    for (unsigned int d = 0; d < dim; ++d)
      {
        // a periodic direction holds no hydrostatic profile (the potential g . x is not
        // periodic): there the body force is the point source of this step
        wb_dir[d] = granular && gravity[d] != 0 && !patch.periodic(d);
        wb_any    = wb_any || (granular && gravity[d] != 0);
        wb_row[d].clear();
        wb_mirror[d].clear();
        wb_wall_ghost[d].clear();
        wb_source[d].clear();
        if (!wb_dir[d])
          continue;
        wb_source[d].assign(patch.n_owned(), 0.);
        // behind a wall normal to d: a boundary ghost one of whose walls is normal to d
        auto behind = [&](const int t) {
          if (t < 0 || ghost_record[t] < 0)
            return false;
          const auto &g = ghosts[ghost_record[t]];
          for (unsigned int k = 0; k < g.n_walls; ++k)
            if (g.wall_dir[k] == d)
              return true;
          return false;
        };
        wb_row[d].assign(patch.n_slots(), -1);
        for (const unsigned int s : listA[d])
          {
            if (behind(int(s)))
              {
                wb_row[d][s] = -2; // a ghost's own faces normal to d are not used (mirror_wall_points)
                continue;
              }
            std::array<signed char, 5> row;
            row.fill(-1);
            bool any = false;
            for (const int side : {-1, 1})
              {
                // the first position behind the wall on this side; the wall lies half a cell
                // before it, and position o mirrors to 2 o_w - side - o
                int o_w = 0;
                for (int o = side; std::abs(o) <= r && o_w == 0; o += side)
                  if (behind(patch.neighbor(s, d, o)))
                    o_w = o;
                if (o_w == 0)
                  continue;
                for (int o = o_w; std::abs(o) <= r; o += side)
                  {
                    const int m = 2 * o_w - side - o;
                    AssertThrow(std::abs(m) <= r, ExcMessage("internal error: mirror outside the stencil"));
                    row[o + r] = static_cast<signed char>(m + r);
                    any        = true;
                  }
              }
            if (any)
              {
                wb_row[d][s] = int(wb_mirror[d].size());
                wb_mirror[d].push_back(row);
              }
          }
        const auto &faces = patch.faces(d);
        wb_wall_ghost[d].assign(faces.size(), -1);
        for (std::size_t k = 0; k < faces.size(); ++k)
          if (wall[d][k])
            {
              const unsigned int gs = patch.is_cell(faces[k].l) ? faces[k].r : faces[k].l;
              wb_wall_ghost[d][k]   = ghost_record[gs];
            }
      }
  }

  template <int dim, class Description>
  template <class Recon>
  void ConvectionOperator<dim, Description>::reconstruct_well_balanced(
    const Recon &rec, const ArrayView<const unsigned int> &range, const unsigned int d, const double *Wp,
    double *out) const
  {
    constexpr int      r       = Recon::r;
    constexpr int      w       = 2 * r + 1;
    const double       g       = gravity[d];
    const unsigned int n_owned = patch.n_owned();
    for (const unsigned int s : range)
      {
        int idx[w];
        for (int o = -r; o <= r; ++o)
          idx[o + r] = patch.neighbor(s, d, o);
        const double *Ws  = Wp + std::size_t(s) * NC;
        double       *lo  = out + std::size_t(s) * 2 * NC;
        double       *hi  = lo + NC;
        const int     row = wb_row[d][s];
        auto          e =
          row == -2 ? LocalEquilibrium{} : local_equilibrium<dim>(desc, Ws, g, 1. / inv_h[d][patch.level(s)]);
        // the equilibrium densities at the stencil's cells (nearest first) and at the two
        // faces; each Newton iteration starts from a prediction of ln n: the linearised
        // profile, then the quadratic through the values found at -h, 0, h
        double       n0[w], nf[2] = {0, 0};
        const double y0 = e.ok ? std::log(e.n) : 0., lin = e.ok ? g * e.h / e.slope : 0.;
        double       yv[w]   = {};
        bool         have[w] = {};
        yv[r] = y0, have[r] = true;
        auto quadratic = [&](const double t) { // ln n at t h from the centre, or the linearisation
          if (r == 0 || !have[r - 1] || !have[r + 1])
            return y0 + t * lin;
          return y0 + t * 0.5 * (yv[r + 1] - yv[r - 1]) + t * t * 0.5 * (yv[r + 1] - 2 * y0 + yv[r - 1]);
        };
        n0[r] = e.n;
        for (int k = 1; k <= r && e.ok; ++k)
          for (const int o : {k, -k})
            {
              if (row >= 0 && wb_mirror[d][row][o + r] >= 0)
                continue; // behind a wall: the mirror position's equilibrium
              n0[o + r] =
                equilibrium_density<dim>(desc, e, g, o * e.h, quadratic(o), Wp[std::size_t(idx[o + r]) * NC]);
              e.ok = std::isfinite(n0[o + r]);
              if (e.ok)
                yv[o + r] = std::log(n0[o + r]), have[o + r] = true;
            }
        for (unsigned int side = 0; side < 2 && e.ok; ++side)
          {
            const double t = side == 0 ? -0.5 : 0.5;
            nf[side]       = equilibrium_density<dim>(desc, e, g, t * e.h, quadratic(t));
            e.ok           = std::isfinite(nf[side]);
          }
        if (!e.ok)
          {
            // the point source n g and the plain reconstruction
            for (unsigned int c = 0; c < NC; ++c)
              {
                double v[w];
                for (int k = 0; k < w; ++k)
                  v[k] = Wp[std::size_t(idx[k]) * NC + c];
                rec.pair(v, 0, lo[c], hi[c]);
              }
            if (s < n_owned)
              {
                wb_source[d][s] = Ws[0] * g;
                ++stats.gravity_point_sources;
              }
            continue;
          }
        // deviations from the equilibrium at rest (n0, 0, E0(n0, T)); a position behind a
        // wall normal to d takes the equilibrium of its mirror position (hydrostatic mirror)
        double E0[w];
        for (int o = -r; o <= r; ++o)
          if (row < 0 || wb_mirror[d][row][o + r] < 0)
            E0[o + r] = rest_energy<dim>(desc, n0[o + r], e.T);
        for (int o = -r; o <= r; ++o)
          if (row >= 0 && wb_mirror[d][row][o + r] >= 0)
            {
              const int m = wb_mirror[d][row][o + r];
              n0[o + r]   = n0[m];
              E0[o + r]   = E0[m];
            }
        for (unsigned int c = 0; c < NC; ++c)
          {
            double v[w];
            for (int k = 0; k < w; ++k)
              {
                const double ref = c == 0 ? n0[k] : (c == NC - 1 ? E0[k] : 0.);
                v[k]             = Wp[std::size_t(idx[k]) * NC + c] - ref;
              }
            v[r] = c == 0 ? 0. : v[r]; // the cell itself lies on its equilibrium
            rec.pair(v, 0, lo[c], hi[c]);
          }
        // the equilibrium at the faces: its state at rest, and its pressures for the source
        if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
          {
            double pf[2];
            for (unsigned int side = 0; side < 2; ++side)
              {
                double Wf, dpf;
                desc.contact.evaluate(nf[side], Wf, pf[side], dpf);
                double *face = side == 0 ? lo : hi;
                face[0] += nf[side];
                face[NC - 1] += rest_energy<dim>(desc, nf[side], e.T);
              }
            if (s < n_owned)
              wb_source[d][s] = (physics::hydrostatic::pressure(desc, nf[1], e.T, pf[1]) -
                                 physics::hydrostatic::pressure(desc, nf[0], e.T, pf[0])) /
                                e.h;
          }
      }
  }

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::first_order_face_state(const double *Wp, const unsigned int s,
                                                                    const unsigned int   d,
                                                                    const unsigned int   side,
                                                                    physics::State<dim> &U) const
  {
    const double *Ws = Wp + std::size_t(s) * NC;
    std::copy(Ws, Ws + NC, U.begin());
    if (!wb_dir[d] || wb_row[d][s] == -2)
      return;
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      {
        LocalEquilibrium e = local_equilibrium<dim>(desc, Ws, gravity[d], 1. / inv_h[d][patch.level(s)]);
        if (!e.ok)
          return;
        const double t  = side == 0 ? -0.5 : 0.5;
        const double nf = equilibrium_density<dim>(desc, e, gravity[d], t * e.h,
                                                   std::log(e.n) + t * gravity[d] * e.h / e.slope);
        if (!std::isfinite(nf))
          return;
        double u[dim];
        for (unsigned int j = 0; j < dim; ++j)
          u[j] = Ws[1 + j] / e.n;
        U = desc.from_primitive(nf, u, e.T);
      }
  }

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::mirror_wall_face(const unsigned int d, const std::size_t k,
                                                              double *low, double *high,
                                                              const unsigned int npts) const
  {
    const auto &g         = patch.boundary_ghosts()[wb_wall_ghost[d][k]];
    const bool  ghost_low = !patch.is_cell(patch.faces(d)[k].l);
    for (unsigned int q = 0; q < npts; ++q)
      if (ghost_low)
        boundary::ghost_state<dim>(g, high + q * NC, low + q * NC);
      else
        boundary::ghost_state<dim>(g, low + q * NC, high + q * NC);
  }

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::mirror_wall_points(const unsigned int d, double *points,
                                                                const unsigned int npts) const
  {
    // the points on face k: the lower slot's upper side, the upper slot's lower side
    const auto &faces = patch.faces(d);
    for (std::size_t k = 0; k < faces.size(); ++k)
      if (wb_wall_ghost[d][k] >= 0)
        mirror_wall_face(d, k, points + (std::size_t(faces[k].l) * 2 + 1) * npts * NC,
                         points + std::size_t(faces[k].r) * 2 * npts * NC, npts);
  }

  template <int dim, class Description>
  void ConvectionOperator<dim, Description>::add_gravity_sources(double *rhs) const
  {
    // the stage's state: apply()'s slot array (owned slots first)
    if (!wb_any)
      return;
    for (unsigned int d = 0; d < dim; ++d)
      if (gravity[d] != 0)
        for (unsigned int s = 0; s < patch.n_owned(); ++s)
          {
            const double *Ws = wb_W + std::size_t(s) * NC;
            rhs[std::size_t(s) * NC + 1 + d] += wb_dir[d] ? wb_source[d][s] : Ws[0] * gravity[d];
            rhs[std::size_t(s) * NC + NC - 1] += gravity[d] * Ws[1 + d]; // g . m
          }
  }

#define GRANHYDRO_INSTANTIATE(d, D)                                                                          \
  template class ConvectionOperator<d, D>;                                                                   \
  template void ConvectionOperator<d, D>::reconstruct_well_balanced(                                         \
    const FirstOrder &, const ArrayView<const unsigned int> &, const unsigned int, const double *, double *) \
    const;                                                                                                   \
  template void ConvectionOperator<d, D>::reconstruct_well_balanced(                                         \
    const Muscl &, const ArrayView<const unsigned int> &, const unsigned int, const double *, double *)      \
    const;                                                                                                   \
  template void ConvectionOperator<d, D>::reconstruct_well_balanced(                                         \
    const Weno3 &, const ArrayView<const unsigned int> &, const unsigned int, const double *, double *)      \
    const;                                                                                                   \
  template void ConvectionOperator<d, D>::reconstruct_well_balanced(                                         \
    const Weno5 &, const ArrayView<const unsigned int> &, const unsigned int, const double *, double *)      \
    const;
  GRANHYDRO_FOR_EACH_MODEL(GRANHYDRO_INSTANTIATE)
#undef GRANHYDRO_INSTANTIATE
} // namespace granhydro::convection
