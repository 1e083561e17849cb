#include <granhydro/boundary/ghost_state.h>
#include <granhydro/diffusion/diffusion_operator.h>
#include <granhydro/physics/diffusive_flux.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>

namespace granhydro::diffusion
{
  using namespace dealii;
  using physics::State;

  namespace
  {
    // GCC vector of 4 doubles (element-wise IEEE arithmetic, no contraction on the default
    // target): 4 faces or 4 cells side by side, each lane bit for bit the scalar result
    typedef double v4d __attribute__((vector_size(32), aligned(8)));

    template <int dim>
    inline State<dim> state(const double *W, const unsigned int s)
    {
      State<dim> U;
      std::copy(W + std::size_t(s) * (dim + 2), W + std::size_t(s + 1) * (dim + 2), U.begin());
      return U;
    }

    /// the thermal state U* = U - (0, .., 0, n w(n)) of face_flux_lanes, lane by lane
    /// (the contact energy has branches and pow); U* = U without a dense closure
    template <int dim, class V, class SV>
    inline void thermal_state(const physics::GranularGas<dim> &desc, const SV &U, SV &Us)
    {
      namespace lanes = physics::lanes;
      Us              = U;
      if (desc.contact.active)
        {
          V nw;
          for (unsigned int i = 0; i < lanes::width<V>; ++i)
            lanes::ref(nw, i) = desc.contact.energy_density(lanes::get(U[0], i));
          Us[dim + 1] -= nw;
        }
    }
  } // namespace

  template <int dim>
  DiffusionOperator<dim>::DiffusionOperator(const mesh::CartesianPatch<dim> &patch,
                                            const physics::GranularGas<dim> &desc,
                                            const DiffusionSettings &settings, const double length_unit)
    : patch(patch)
    , desc(desc)
    , settings(settings)
    , length_unit(length_unit)
  {
    set_time(0);
  }

  template <int dim>
  void DiffusionOperator<dim>::setup()
  {
    const unsigned int n_owned = patch.n_owned();
    // scaled geometry: 1/dx of each owned cell, 1/(centre distance) of each face
    // per refinement level
    auto size = [&](const unsigned int d, const unsigned int k) { return patch.level_cell_size(k, d); };
    for (unsigned int d = 0; d < dim; ++d)
      for (unsigned int a = 0; a < mesh::max_levels; ++a)
        {
          inv_h[d][a] = length_unit / size(d, a);
          for (unsigned int b = 0; b < mesh::max_levels; ++b)
            inv_dist[d][a][b] = length_unit / (0.5 * (size(d, a) + size(d, b)));
        }
    // scaled cell volumes (the product of the edges, as 1 / prod inv_h)
    for (unsigned int k = 0; k < mesh::max_levels; ++k)
      {
        cell_volume[k] = 1.;
        for (unsigned int d = 0; d < dim; ++d)
          cell_volume[k] /= inv_h[d][k];
      }
    friction_active = desc.contact.active && desc.contact.friction.active() && settings.viscous;
    src.resize(patch.n_slots());
    flip.assign(patch.n_slots(), 0u);
    for (unsigned int s = 0; s < patch.n_slots(); ++s)
      src[s] = s;
    for (const auto &g : patch.boundary_ghosts())
      {
        src[g.slot]  = g.source;
        flip[g.slot] = boundary::ghost_velocity_signs<dim>(g); // the wall's rule
      }
    // each face counted once over the ranks: by the owner of its low cell, or of its
    // only cell at a wall (FaceFluxCounts)
    for (unsigned int d = 0; d < dim; ++d)
      {
        const auto &faces = patch.faces(d);
        counted_[d].assign(faces.size(), 0);
        for (std::size_t k = 0; k < faces.size(); ++k)
          {
            const unsigned int key = patch.is_cell(faces[k].l) ? faces[k].l : faces[k].r;
            counted_[d][k]         = key < n_owned ? 1 + patch.wall_face(faces[k].l, faces[k].r, d) : 0;
          }
      }
    // dissipative walls: a face between a cell and a boundary ghost whose cell face has a
    // wall id with eps_w < 1 (boundary/dissipative_wall.h)
    wall_kinds.assign(1, WallFace()); // 0: not a wall
    for (unsigned int d = 0; d < dim; ++d)
      {
        const auto &faces = patch.faces(d);
        wall_of[d].assign(faces.size(), 0);
        for (std::size_t k = 0; k < faces.size(); ++k)
          if (const int id = patch.wall_id(faces[k].l, faces[k].r, d); id >= 0)
            {
              // one entry per boundary id and side
              const bool        low  = patch.is_cell(faces[k].l);
              const std::size_t kind = 1 + 2 * std::size_t(id) + (low ? 1 : 0);
              if (wall_kinds.size() <= kind)
                wall_kinds.resize(kind + 1, WallFace());
              wall_kinds[kind] = boundary::dissipative_wall_face(patch.wall_settings(id), low);
              AssertThrow(kind <= 65535, ExcMessage("too many boundary ids"));
              wall_of[d][k] = std::uint16_t(kind);
            }
      }
  }

  template <int dim>
  template <class V>
  physics::TransportCoefficientsT<V> DiffusionOperator<dim>::coefficients(const V n, const V T) const
  {
    using physics::lanes::constant;
    // max(T, 0) as std::max(T, 0.): T < 0 ? 0 : T (a NaN stays)
    auto c = desc.model.transport(n, T < V{} ? V{} : T, 1., 1.);
    if (settings.max_free_path > 0)
      {
        // Knudsen cap: l = 1/(sqrt(2) pi n) > L scales the fluxes' coefficients by L/l
        // (min(1, x) as std::min(1., x): x < 1 ? x : 1)
        const V x = constant<V>(std::sqrt(2.) * M_PI) * n * settings.max_free_path;
        const V f = x < constant<V>(1.) ? x : constant<V>(1.);
        c.eta *= f;
        c.gamma *= f;
        c.kappa *= f;
        c.mu *= f;
      }
    if (!settings.viscous)
      c.eta = c.gamma = V{};
    if (!settings.heat)
      c.kappa = c.mu = V{};
    return c;
  }

  template <int dim>
  template <class V>
  void DiffusionOperator<dim>::face_flux_lanes(const double *W, const unsigned int d, const V ihn,
                                               const unsigned int *l, const unsigned int *r,
                                               const std::array<V, dim + 2> &UL,
                                               const std::array<V, dim + 2> &UR, std::array<V, dim + 2> &F,
                                               std::array<V, dim + 2> *friction, V *bounded, V *capped,
                                               V *cold) const
  {
    namespace lanes = physics::lanes;
    using lanes::constant;
    constexpr unsigned int L = lanes::width<V>;
    using SV                 = std::array<V, NC>;
    if (bounded)
      *bounded = V{};
    if (capped)
      *capped = V{};
    // The gradients come from differences of the *thermal* states U* = U - (0, .., 0, n w(n)):
    // the contact energy n w of a dense closure is not thermal, and w changes by orders of
    // magnitude across a cell near phi_c, so it is removed exactly from each cell's state
    // before the chain rule of doc/physics.md 4.1 (at the face state) turns the differences into
    // gradients of u and of the granular T - never of T + 2w/3 (doc/physics.md 4.5).
    // physics::primitive_gradients(..., dw_dn) is the pointwise form of the same
    // correction. Without a closure U* = U and nothing changes. The contact energy has
    // branches and pow: it is evaluated lane by lane.
    SV                             Uf, SL, SR;
    physics::StateGradient<dim, V> dU;
    thermal_state<dim, V>(desc, UL, SL);
    thermal_state<dim, V>(desc, UR, SR);
    for (unsigned int c = 0; c < NC; ++c)
      {
        Uf[c]    = 0.5 * (SL[c] + SR[c]);
        dU[d][c] = (SR[c] - SL[c]) * ihn;
      }
    for (unsigned int j = 0; j < dim; ++j)
      if (j != d)
        {
          dU[j].fill(V{});
          if (settings.diagonal_only)
            continue;
          // the average of the two cells' differences along j over their gradient
          // neighbours (central on a uniform mesh; one-sided next to a finer region)
          for (const unsigned int *side : {l, r})
            {
              SV             up, um;
              V              w{};
              lanes::Mask<V> use{};
              for (unsigned int i = 0; i < L; ++i)
                {
                  const unsigned int s = side[i];
                  const int    p = patch.gradient_neighbor(s, j, 1), m = patch.gradient_neighbor(s, j, 0);
                  const double span = (p >= 0 ? patch.gradient_offset(s, j, 1) : 0.) -
                                      (m >= 0 ? patch.gradient_offset(s, j, 0) : 0.);
                  const double *wp = W + std::size_t(p >= 0 ? p : s) * NC,
                               *wm = W + std::size_t(m >= 0 ? m : s) * NC;
                  for (unsigned int c = 0; c < NC; ++c)
                    {
                      lanes::ref(up[c], i) = wp[c];
                      lanes::ref(um[c], i) = wm[c];
                    }
                  if (span > 0)
                    {
                      lanes::ref(w, i) = 0.5 * length_unit / span;
                      if constexpr (L == 1)
                        use = true;
                      else
                        use[i] = -1;
                    }
                }
              if (!lanes::any(use))
                continue;
              thermal_state<dim, V>(desc, SV(up), up);
              thermal_state<dim, V>(desc, SV(um), um);
              for (unsigned int c = 0; c < NC; ++c)
                {
                  const V sum = dU[j][c] + w * (up[c] - um[c]);
                  dU[j][c]    = use ? sum : dU[j][c]; // lanes without a span add nothing
                }
            }
        }
    // the face state's granular temperature (its contact energy is already removed: nw = 0)
    const V nf = Uf[0], Tf = desc.temperature(Uf, V{});
    if (cold)
      *cold = Tf < V{} ? constant<V>(1.) : V{};
    const physics::PrimitiveGradients<dim, V> g = physics::primitive_gradients<dim, V>(Uf, dU, 1.);
    F = physics::viscous_flux_primitive<dim>(Uf, g, coefficients(nf, Tf), 1., d);
    V  tf{}; // the frictional normal stress tau_f,dd (for the no-tension bound)
    SV Ff{};
    V  pc{}; // the contact pressure p_f at the face state, lane by lane (pow, branches)
    if (desc.contact.active && (friction_active || settings.no_tension))
      for (unsigned int i = 0; i < L; ++i)
        lanes::ref(pc, i) = desc.contact.pressure(lanes::get(nf, i));
    if (friction_active)
      {
        // frictional (contact) shear stress of the dense closure: its momentum flux is
        // part of F, its work tau_f.u is not - that energy leaves the grains as heat
        // (doc/physics.md 4.5); residual() adds u . div(tau_f) to the energy instead, so that
        // T obeys the kinetic equation only. friction = (work flux, momentum flux).
        // mu_f from the face's strain rate and T (physics/frictional_stress.h; the grain
        // diameter is the length unit, so Theta / d^2 = T), lane by lane (pow, branches)
        struct
        {
          V eta, gamma, kappa, mu;
        } cf{V{}, V{}, V{}, V{}};
        V div, SS;
        physics::strain_rate_invariants<dim, V>(g.grad_u, div, SS);
        for (unsigned int i = 0; i < L; ++i)
          {
            bool c                = false;
            lanes::ref(cf.eta, i) = desc.contact.friction.viscosity(lanes::get(pc, i), lanes::get(div, i),
                                                                    lanes::get(SS, i), lanes::get(Tf, i), &c);
            if (capped)
              lanes::ref(*capped, i) = c ? 1. : 0.;
          }
        Ff = physics::viscous_flux_primitive<dim>(Uf, g, cf, 1., d);
        for (unsigned int k = 0; k < dim; ++k)
          F[1 + k] += Ff[1 + k];
        tf = Ff[1 + d];
      }
    if (settings.no_tension)
      {
        // Cohesionless grains (doc/physics.md 4.7): the total normal stress on the face,
        // p - tau_dd, stays compressive. A tensile viscous normal stress tau_dd (kinetic plus
        // frictional) above the face's pressure p = n T Z + p_f is scaled down to p, and its
        // work tau_dd u_d with it, so the face flux stays conservative (energy to round-off).
        const V    Tp = Tf < V{} ? V{} : Tf;
        const V    p  = nf * Tp * desc.model.Z(nf * constant<V>(physics::GranularGas<dim>::phi_per_n)) + pc;
        const V    t  = F[1 + d];
        const auto tensile = t > p;
        if (lanes::any(tensile))
          {
            const V one = constant<V>(1.);
            const V sc  = tensile ? p / t : one; // t > p >= 0 on tensile lanes
            const V ud  = Uf[1 + d] / Uf[0];
            F[1 + d]    = sc * t;
            F[dim + 1] -= (one - sc) * (t - tf) * ud; // the kinetic stress's work
            Ff[1 + d] = sc * tf;
            Ff[dim + 1] -= (one - sc) * tf * ud; // the frictional work flux
          }
        if (bounded)
          *bounded = tensile ? constant<V>(1.) : V{};
      }
    if (friction)
      {
        (*friction)[0] = Ff[dim + 1];
        for (unsigned int k = 0; k < dim; ++k)
          (*friction)[1 + k] = Ff[1 + k];
        (*friction)[dim + 1] = V{};
      }
  }

  template <int dim>
  void DiffusionOperator<dim>::face_flux(const double *W, const unsigned int d, const double ihn,
                                         const unsigned int l, const unsigned int r, const State<dim> &UL,
                                         const State<dim> &UR, const WallFace &wall, State<dim> &F,
                                         State<dim> *friction, bool *bounded, bool *capped, bool *cold) const
  {
    double b = 0, c = 0, t = 0;
    face_flux_lanes<double>(W, d, ihn, &l, &r, UL, UR, F, friction, &b, &c, &t);
    if (bounded)
      *bounded = b > 0;
    if (capped)
      *capped = c > 0;
    if (cold)
      *cold = t > 0;
    if (wall.sign != 0) // energy into the wall (doc/physics.md 5.2)
      boundary::add_wall_heat_flux(wall, desc, wall.sign > 0 ? UL : UR, F[dim + 1]);
  }

  template <int dim>
  template <class V>
  __attribute__((always_inline)) inline void DiffusionOperator<dim>::face_fluxes(const double      *W,
                                                                                 const unsigned int d) const
  {
    namespace lanes          = physics::lanes;
    constexpr unsigned int L = lanes::width<V>;
    using SV                 = std::array<V, NC>;
    const auto       &faces  = patch.faces(d);
    const std::size_t nf     = faces.size();
    std::size_t       k      = 0;
    for (; k + L <= nf; k += L)
      {
        unsigned int l[L], r[L];
        SV           UL, UR, F, G;
        V            ihn;
        for (unsigned int i = 0; i < L; ++i)
          {
            l[i]               = faces[k + i].l;
            r[i]               = faces[k + i].r;
            lanes::ref(ihn, i) = this->ihn(d, l[i], r[i]);
            for (unsigned int c = 0; c < NC; ++c)
              {
                lanes::ref(UL[c], i) = W[std::size_t(l[i]) * NC + c];
                lanes::ref(UR[c], i) = W[std::size_t(r[i]) * NC + c];
              }
          }
        V bounded, capped, cold;
        face_flux_lanes<V>(W, d, ihn, l, r, UL, UR, F, friction_active ? &G : nullptr, &bounded, &capped,
                           &cold);
        for (unsigned int i = 0; i < L; ++i)
          {
            if (counted_[d][k + i])
              count_face(d, k + i, lanes::get(bounded, i) > 0, lanes::get(capped, i) > 0,
                         lanes::get(cold, i) > 0);
            double *Fk = &Fp[d][(k + i) * NC];
            for (unsigned int c = 0; c < NC; ++c)
              Fk[c] = lanes::get(F[c], i);
            if (friction_active)
              for (unsigned int c = 0; c < NC; ++c)
                Ff[d][(k + i) * NC + c] = lanes::get(G[c], i);
            const WallFace &wall = this->wall(d, k + i);
            if (wall.sign != 0) // as in face_flux()
              boundary::add_wall_heat_flux(
                wall, desc, wall.sign > 0 ? state<dim>(W, l[i]) : state<dim>(W, r[i]), Fk[dim + 1]);
          }
      }
    for (; k < nf; ++k)
      {
        const unsigned int l = faces[k].l, r = faces[k].r;
        State<dim>         F, G;
        bool               bounded, capped, cold;
        face_flux(W, d, ihn(d, l, r), l, r, state<dim>(W, l), state<dim>(W, r), wall(d, k), F,
                  friction_active ? &G : nullptr, &bounded, &capped, &cold);
        if (counted_[d][k])
          count_face(d, k, bounded, capped, cold);
        std::copy(F.begin(), F.end(), &Fp[d][k * NC]);
        if (friction_active)
          std::copy(G.begin(), G.end(), &Ff[d][k * NC]);
      }
  }

  template <int dim>
  inline void DiffusionOperator<dim>::count_face(const unsigned int d, const std::size_t k,
                                                 const bool bounded, const bool capped, const bool cold) const
  {
    ++counts_.faces;
    if (cold)
      ++counts_.negative_temperature;
    if (bounded)
      {
        ++counts_.tension_bounded;
        if (counted_[d][k] == 2)
          ++counts_.tension_bounded_walls;
      }
    if (capped)
      ++counts_.friction_capped;
  }

  template <int dim>
  template <class V>
  void DiffusionOperator<dim>::source_lanes(const std::array<V, dim + 2> &U, std::array<V, dim + 2> &S) const
  {
    namespace lanes = physics::lanes;
    S.fill(V{});
    if (settings.body.active() || settings.container_motion.active())
      physics::BodyForce::add_source<dim, V>(body_force(), U.data(), S.data());
    if (settings.cooling && desc.model.effective_restitution() < 1)
      {
        V nw{}; // contact energy density, lane by lane (branches and pow)
        if (desc.contact.active)
          for (unsigned int i = 0; i < lanes::width<V>; ++i)
            lanes::ref(nw, i) = desc.contact.energy_density(lanes::get(U[0], i));
        const V n = U[0], T0 = desc.temperature(U, nw), T = T0 < V{} ? V{} : T0; // max(T, 0)
        S[dim + 1] -= 1.5 * n * T * desc.model.zeta0(n, T, 1., 1.);              // doc/physics.md 3.5
      }
  }

  template <int dim>
  void DiffusionOperator<dim>::source(const State<dim> &U, State<dim> &S) const
  {
    source_lanes<double>(U, S);
  }

  template <int dim>
  template <class V>
  __attribute__((always_inline)) inline void
  DiffusionOperator<dim>::cell_residuals(const double *W, const unsigned int s0, double *f) const
  {
    namespace lanes          = physics::lanes;
    constexpr unsigned int L = lanes::width<V>;
    using SV                 = std::array<V, NC>;
    SV U, S;
    for (unsigned int i = 0; i < L; ++i)
      for (unsigned int c = 0; c < NC; ++c)
        lanes::ref(U[c], i) = W[std::size_t(s0 + i) * NC + c];
    source_lanes<V>(U, S);
    SV div_tf{};                           // div of (frictional work flux, frictional momentum flux)
    for (unsigned int d = 0; d < dim; ++d) // d_i F_i^v, fixed order: partition independent
      {
        SV fw, fe, gw, ge;
        V  ih;
        for (unsigned int i = 0; i < L; ++i)
          {
            double a[NC] = {}, b[NC] = {};
            patch.sum_face_fluxes(d, s0 + i, Fp[d], a, b);
            for (unsigned int c = 0; c < NC; ++c)
              {
                lanes::ref(fw[c], i) = a[c];
                lanes::ref(fe[c], i) = b[c];
              }
            if (friction_active)
              {
                double ag[NC] = {}, bg[NC] = {};
                patch.sum_face_fluxes(d, s0 + i, Ff[d], ag, bg);
                for (unsigned int c = 0; c < NC; ++c)
                  {
                    lanes::ref(gw[c], i) = ag[c];
                    lanes::ref(ge[c], i) = bg[c];
                  }
              }
            lanes::ref(ih, i) = this->ih(d, s0 + i);
          }
        for (unsigned int c = 0; c < NC; ++c)
          S[c] += ih * (fe[c] - fw[c]);
        if (friction_active)
          for (unsigned int c = 0; c < NC; ++c)
            div_tf[c] += ih * (ge[c] - gw[c]);
      }
    if (friction_active)
      {
        // the energy gets the kinetic-energy change of the frictional force, u . div tau_f,
        // and not the work flux div(tau_f . u): the difference, ~ mu_f Phi_f >= 0, is the
        // frictional dissipation, lost to heat (doc/physics.md 4.5)
        V uw{};
        for (unsigned int k = 0; k < dim; ++k)
          uw += U[1 + k] / U[0] * div_tf[1 + k];
        S[dim + 1] += uw;
        const V power = div_tf[0] - uw;
        for (unsigned int i = 0; i < L; ++i) // summed cell by cell: the same on any lane width
          friction_power_ += lanes::get(power, i) * cell_volume[patch.level(s0 + i)];
      }
    for (unsigned int i = 0; i < L; ++i)
      for (unsigned int c = 0; c < NC; ++c)
        f[std::size_t(s0 + i) * NC + c] = lanes::get(S[c], i);
  }

  template <int dim>
  template <class V>
  __attribute__((always_inline)) inline void DiffusionOperator<dim>::residual_lanes(const double *W,
                                                                                    double       *f) const
  {
    const unsigned int n_owned = patch.n_owned();
    for (unsigned int d = 0; d < dim; ++d)
      {
        const std::size_t nf = patch.faces(d).size();
        Fp[d]                = patch.scratch(
                         static_cast<mesh::Scratch>(static_cast<unsigned int>(mesh::Scratch::stage_a) + d), nf * NC);
        if (friction_active)
          Ff[d] = patch.scratch(
            static_cast<mesh::Scratch>(static_cast<unsigned int>(mesh::Scratch::flux_0) + d), nf * NC);
        face_fluxes<V>(W, d);
      }
    friction_power_ = 0;
    unsigned int s  = 0;
    for (; s + physics::lanes::width<V> <= n_owned; s += physics::lanes::width<V>)
      cell_residuals<V>(W, s, f);
    for (; s < n_owned; ++s)
      cell_residuals<double>(W, s, f);
  }

  // flatten: every formula inlines into the loops (no vector crosses a call boundary)
  template <int dim>
  __attribute__((flatten)) void DiffusionOperator<dim>::residual_default(const double *W, double *f) const
  {
    residual_lanes<v4d>(W, f);
  }

#if defined(__x86_64__) || defined(__i386__)
  // the same operations compiled for AVX2 (4 doubles per instruction, 16 vector registers
  // of 4: fewer spills); no FMA, so every lane is still the scalar IEEE result
  template <int dim>
  __attribute__((target("avx2"), flatten)) void DiffusionOperator<dim>::residual_avx2(const double *W,
                                                                                      double       *f) const
  {
    residual_lanes<v4d>(W, f);
  }
#endif

  template <int dim>
  void DiffusionOperator<dim>::residual(const double *W, double *f) const
  {
#if defined(__x86_64__) || defined(__i386__)
    if (physics::lanes::use_avx2())
      return residual_avx2(W, f);
#endif
    residual_default(W, f);
  }

  template <int dim>
  double DiffusionOperator<dim>::explicit_rate(const double *W) const
  {
    // Half the largest |eigenvalue| of f's Jacobian, bounded by the sum of its parts'
    // (Gershgorin): diffusion 2 D / dx^2 per direction (the Laplacian's 4 D / dx^2, halved),
    // inelastic cooling 0.75 zeta0 (d/dT of -zeta0(T) T with zeta0 ~ sqrt(T): -1.5 zeta0,
    // e_eff with friction, doc/physics.md 3.10) and a dissipative wall q_w / (2 n T dx)
    // (d/dT of -q_w / (1.5 n dx) with q_w ~ T^1.5, doc/physics.md 5.2). The RKL2 stage
    // count and the explicit limit 0.9 / rate follow from it (doc/physics.md 4.4).
    const unsigned int  n_own = patch.n_owned();
    std::vector<double> wall_rate(n_own, 0.);
    for (unsigned int d = 0; d < dim; ++d)
      for (std::size_t k = 0; k < wall_of[d].size(); ++k)
        if (const WallFace &wall = this->wall(d, k); wall.sign != 0)
          {
            const unsigned int s = wall.sign > 0 ? patch.faces(d)[k].l : patch.faces(d)[k].r;
            if (s >= n_own)
              continue;
            const State<dim> U  = state<dim>(W, s);
            const double     nT = U[0] * std::max(desc.temperature(U), 0.);
            if (nT > 0)
              wall_rate[s] += 0.5 * desc.wall_heat_flux(U, wall.eps_w) / nT * ih(d, s);
          }
    const bool cooling = settings.cooling && desc.model.effective_restitution() < 1;
    double     m       = 0;
    for (unsigned int s = 0; s < n_own; ++s)
      {
        const State<dim> U = state<dim>(W, s);
        const double     n = U[0], T = desc.temperature(U);
        auto             c = coefficients(n, T);
        // the frictional viscosity is a shear viscosity as well: its bound t_f sin(theta_f) p_f,
        // not its value at U (Srivastava-Sundaresan's follows the strain rate, which changes
        // within the step: a stage count from the value at U let RKL2 steps go unstable at
        // the free surface of the quarter-resolution chute)
        if (friction_active)
          c.eta += desc.contact.viscosity(n);
        // momentum diffusivity (gamma/eta + 4/3) eta/(m n), thermal 2 kappa/(3 n) (doc/physics.md 4.4)
        const double D    = std::max((c.gamma + 4. / 3. * c.eta) / n, 2. * c.kappa / (3. * n));
        double       rate = wall_rate[s];
        for (unsigned int d = 0; d < dim; ++d)
          rate += 2 * D * ih(d, s) * ih(d, s);
        if (cooling)
          rate += 0.75 * desc.model.zeta0(n, std::max(T, 0.), 1., 1.);
        m = std::max(m, rate);
      }
    return Utilities::MPI::max(m, patch.communicator());
  }

  template class DiffusionOperator<1>;
  template class DiffusionOperator<2>;
  template class DiffusionOperator<3>;
} // namespace granhydro::diffusion
