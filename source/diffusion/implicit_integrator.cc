#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace granhydro::diffusion
{
  using namespace dealii;

  template <int dim>
  ImplicitIntegrator<dim>::ImplicitIntegrator(const DiffusionOperator<dim>    &op,
                                              const physics::GranularGas<dim> &desc,
                                              const IntegratorSettings        &settings)
    : op(op)
    , patch(op.get_patch())
    , desc(desc)
    , settings(settings)
  {}

  template <int dim>
  bool ImplicitIntegrator<dim>::admissible_owned(const double *Uv)
  {
    constexpr unsigned int NC = dim + 2;
    bool                   ok = true;
    for (unsigned int s = 0; s < patch.n_owned() && ok; ++s)
      {
        physics::State<dim> S;
        std::copy(&Uv[std::size_t(s) * NC], &Uv[std::size_t(s + 1) * NC], S.begin());
        ok = desc.admissible(S, repair_energy_);
        if (!ok)
          {
            std::ostringstream os;
            os << "diffusion step result inadmissible at x = " << patch.center(s) << " m: packing fraction "
               << physics::packing_fraction(S[0]) << ", T = " << desc.temperature(S) << " (scaled units)";
            last_failure = os.str();
          }
      }
    return Utilities::MPI::min(ok ? 1 : 0, patch.communicator()) == 1;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::step(Vector &U, const double t, const double dt, const double repair_energy)
  {
    ++stats.steps;
    repair_energy_                 = repair_energy;
    static const ButcherTableau gl = butcher_tableau(ImplicitMethod::gauss_legendre),
                                mp = butcher_tableau(ImplicitMethod::implicit_midpoint),
                                sd = butcher_tableau(ImplicitMethod::sdirk2);
    {
      // the explicit diffusive limit at the start of the step (diagnostic; one
      // coefficient evaluation per cell, a few % of a Newton iteration)
      W = patch.scratch(mesh::Scratch::slot_array, std::size_t(patch.n_slots()) * (dim + 2));
      patch.gather(U, W);
      const double limit = 0.9 / op.explicit_rate(W);
      explicit_limit     = limit;
      if (limit < stats.min_explicit_dt)
        {
          stats.min_explicit_dt      = limit;
          stats.min_explicit_dt_time = t;
        }
      stats.max_dt_over_explicit = std::max(stats.max_dt_over_explicit, dt / limit);
    }
    switch (settings.method)
      {
        case ImplicitMethod::explicit_euler:
          return explicit_step(U, t, dt);
        case ImplicitMethod::implicit_midpoint:
          return irk_step(U, t, dt, mp);
        case ImplicitMethod::gauss_legendre:
          return irk_step(U, t, dt, gl);
        case ImplicitMethod::sdirk2:
          return implicit_step(U, t, dt, sd);
        case ImplicitMethod::rkl2:
          return rkl2_step(U, t, dt);
        case ImplicitMethod::cost_based:
          {
            // cost in evaluations of f, from global quantities only (dt and the explicit
            // limit): the same choice on any number of ranks and after a restart
            constexpr double NC            = dim + 2;
            const double     ratio         = dt / explicit_limit;
            const double     stages        = rkl2_stages(ratio);
            const bool       blocks        = settings.block_ilu && !settings.amg;
            const double     implicit_cost = sdirk2_cost(NC, blocks);
            if (rkl2_blocked > 0)
              --rkl2_blocked;
            else if (stages < implicit_cost)
              {
                if (rkl2_step(U, t, dt))
                  return true;
                ++stats.rkl2_fallbacks; // U is unchanged; the implicit step gathers it again
                rkl2_blocked = 10;
              }
            return implicit_step(U, t, dt, sd);
          }
        default:
          if (irk_step(U, t, dt, gl))
            return true;
          ++stats.switches_to_midpoint;
          return irk_step(U, t, dt, mp);
      }
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::irk_step(Vector &U, const double t, const double dt,
                                         const ButcherTableau &tableau)
  {
    if (irk_attempt(U, t, dt, tableau, settings.full_jacobian))
      return true;
    if (settings.full_jacobian)
      return false;
    // the lagged cross terms can stall the iteration where they are stiff (near
    // vacuum, P14): redo the step with the fully coupled Jacobian
    ++stats.full_jacobian_retries;
    return irk_attempt(U, t, dt, tableau, true);
  }

  template <int dim>
  typename ImplicitIntegrator<dim>::History ImplicitIntegrator<dim>::history() const
  {
    History h;
    h.rkl2_blocked = rkl2_blocked;
    h.matrix_valid = matrix_valid && settings.reuse_matrix;
    if (h.matrix_valid)
      {
        h.matrix_coupled = matrix_coupled;
        h.matrix_age     = matrix_age;
        h.matrix_t       = matrix_t;
        h.matrix_dt      = matrix_dt;
        h.matrix_N       = matrix_N;
        h.state          = matrix_state;
      }
    return h;
  }

  template <int dim>
  void ImplicitIntegrator<dim>::restore(const History &h)
  {
    rkl2_blocked = h.rkl2_blocked;
    matrix_valid = false;
    if (!h.matrix_valid || !settings.reuse_matrix)
      return;
    AssertThrow(h.state.size() == std::size_t(patch.n_owned()) * (dim + 2),
                ExcMessage("integrator history of another mesh"));
    // the same gathered state, time and coefficients as when it was built: the same matrix
    Vector V(patch.partitioner());
    std::copy(h.state.begin(), h.state.end(), V.begin());
    W = patch.scratch(mesh::Scratch::slot_array, std::size_t(patch.n_slots()) * (dim + 2));
    patch.gather(V, W);
    op.set_time(h.matrix_t);
    if (!setup_newton(h.matrix_dt, h.matrix_N, h.matrix_coupled))
      return; // as in the interrupted run's next step: a fresh matrix
    M              = &M_[h.matrix_N.size()][h.matrix_coupled];
    matrix_valid   = true;
    matrix_coupled = h.matrix_coupled;
    matrix_N       = h.matrix_N;
    matrix_dt      = h.matrix_dt;
    matrix_age     = h.matrix_age;
    matrix_t       = h.matrix_t;
    matrix_state   = h.state;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::irk_attempt(Vector &U, const double t, const double dt,
                                            const ButcherTableau &tableau, const bool full)
  {
    const Table           &A = tableau.A;
    const auto            &b = tableau.b, &c = tableau.c;
    constexpr unsigned int NC     = dim + 2;
    const unsigned int     stages = A.size();
    last_failure.clear();
    const std::size_t n    = std::size_t(patch.n_owned()) * NC;
    const MPI_Comm    comm = patch.communicator();
    U0.assign(U.begin(), U.begin() + n);
    if (Y.size() != U.size())
      Y.reinit(patch.partitioner());
    const std::vector<double> scale = newton_scale(U0, NC, comm);
    // diagonally implicit (lower triangular, one diagonal value): stage by stage
    bool dirk = stages > 1;
    for (unsigned int k = 0; k < stages; ++k)
      for (unsigned int j = k; j < stages; ++j)
        if ((j > k && A[k][j] != 0) || (j == k && A[k][k] != A[0][0]))
          dirk = false;

    // Jacobian at U0, Newton matrix, preconditioner (frozen for the whole step)
    patch.gather(U, W);
    f.resize(n);
    op.set_time(t);
    op.residual(W, f.data());
    const bool  coupled = full && !op.diagonal_only();
    const Table N       = dirk ? Table{{A[0][0]}} : A;
    // Newton matrix of an earlier step: kept while it makes the iteration contract fast
    // (the previous step converged in <= 7 iterations per stage; a fresh Jacobian and
    // preconditioner cost about as much as 7 Newton iterations), for at most 8 steps and
    // while dt stays within 10 % of the dt it was built for. I - dt N (x) J is then off by
    // the change of J and dt, which only slows the contraction of the modified Newton
    // iteration; if that fails, the step is redone with a fresh matrix (counted).
    const bool reuse = settings.reuse_matrix && matrix_valid && matrix_coupled == coupled && matrix_N == N &&
                       std::abs(dt / matrix_dt - 1) <= 0.1 && matrix_age < 8;
    if (reuse)
      {
        ++matrix_age;
        ++stats.matrix_reuses;
        M = &M_[N.size()][coupled];
      }
    else
      {
        if (!setup_newton(dt, N, coupled))
          {
            matrix_valid = false;
            ++stats.newton_failures;
            return false;
          }
        matrix_valid   = true;
        matrix_coupled = coupled;
        matrix_N       = N;
        matrix_dt      = dt;
        matrix_age     = 0;
        if (settings.reuse_matrix) // kept for history(): an interrupted run rebuilds it
          {
            matrix_t = t;
            matrix_state.assign(U.begin(), U.begin() + n);
          }
      }
    unsigned int iterations = 0, max_iterations = 0; // per stage (DIRK) or per step
    auto         failed = [&]() {
      matrix_valid = false;
      if (!reuse)
        {
          if (!gmres_failed) // GMRES failures are counted as such
            ++stats.newton_failures;
          return false;
        }
      ++stats.stale_matrix_retries; // the kept matrix did not do: a fresh one
      return irk_attempt(U, t, dt, tableau, full);
    };

    std::vector<double> K(n * stages), power(stages, 0.);
    if (!dirk)
      {
        for (std::size_t i = 0; i < n; ++i) // start from f(U0) in every stage
          for (unsigned int k = 0; k < stages; ++k)
            K[i * stages + k] = f[i];
        std::vector<double> tk(stages);
        for (unsigned int k = 0; k < stages; ++k)
          tk[k] = t + c[k] * dt;
        if (!newton(U0, tk, dt, A, scale, K, power, iterations))
          return failed();
        max_iterations = iterations;
      }
    else
      {
        std::vector<double> base(n), Kk(f), pk(1);
        for (unsigned int k = 0; k < stages; ++k)
          {
            // Y_k = U0 + dt sum_{j<k} a_kj K_j + dt g K_k; first guess: the previous slope
            for (std::size_t i = 0; i < n; ++i)
              {
                double s = 0;
                for (unsigned int j = 0; j < k; ++j)
                  s += A[k][j] * K[i * stages + j];
                base[i] = U0[i] + dt * s;
              }
            if (!newton(base, {t + c[k] * dt}, dt, N, scale, Kk, pk, iterations))
              return failed();
            max_iterations = std::max(max_iterations, iterations);
            for (std::size_t i = 0; i < n; ++i)
              K[i * stages + k] = Kk[i];
            power[k] = pk[0];
          }
      }
    // U1 = U0 + dt sum b_i K_i with K_i = f(Y_i): f is in flux form, so U1 conserves mass
    // (and energy and momentum where no source acts) to round-off, not only to the
    // Newton tolerance
    std::vector<double> U1(n);
    for (std::size_t i = 0; i < n; ++i)
      {
        double s = 0;
        for (unsigned int k = 0; k < stages; ++k)
          s += b[k] * K[i * stages + k];
        U1[i] = U0[i] + dt * s;
      }
    if (!admissible_owned(U1.data()))
      {
        matrix_valid = false;
        ++stats.newton_failures; // counted as before: the step failed after Newton
        return false;
      }
    if (max_iterations > 7)
      matrix_valid = false;
    std::copy(U1.begin(), U1.end(), U.begin());
    if (op.friction())
      {
        double friction = 0; // frictional dissipation of the step, this rank
        for (unsigned int k = 0; k < stages; ++k)
          friction += dt * b[k] * power[k];
        stats.friction_dissipation += Utilities::MPI::sum(friction, comm);
      }
    return true;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::implicit_step(Vector &U, const double t, const double dt,
                                              const ButcherTableau &tableau)
  {
    Timer      timer;
    const bool ok = irk_step(U, t, dt, tableau);
    ++stats.implicit_steps;
    stats.implicit_seconds += timer.wall_time();
    return ok;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::rkl2_step(Vector &U, const double t, const double dt)
  {
    Timer                  timer;
    constexpr unsigned int NC = dim + 2;
    const std::size_t      n  = std::size_t(patch.n_owned()) * NC;
    last_failure.clear();
    // stage count from the stability bound dt <= dt_E (s^2 + s - 2) / 4 (W and
    // explicit_limit hold U's gather and its explicit limit, from step())
    const double ratio = dt / explicit_limit;
    if (!(ratio <= 1e6))
      {
        last_failure = "RKL2: dt is " + std::to_string(ratio) + " x the explicit limit (cap 1e6)";
        return false;
      }
    const unsigned int s = rkl2_stages(ratio);
    if (Y.size() != U.size())
      Y.reinit(patch.partitioner());
    // three stage vectors: Y_j-1 in Y (its owned values; gathered for f(Y_j-1)), Y_j-2 in
    // Yjm2 (overwritten by Y_j value by value), Y_0 is U itself (U changes only when the
    // result is accepted)
    const double *u0 = U.begin();
    double       *y  = Y.begin();
    // f(Y_0), f(Y_j-1) and Y_j-2 in the patch's shared scratch
    double *const L0   = patch.scratch(mesh::Scratch::owned_0, n);
    double *const Ljm1 = patch.scratch(mesh::Scratch::owned_1, n);
    double *const Yjm2 = patch.scratch(mesh::Scratch::owned_2, n);
    std::copy(u0, u0 + n, Yjm2);
    op.set_time(t);
    op.residual(W, L0);
    // weights beta_j,k: Y_j = Y_0 + dt sum_k beta_j,k f(Y_k), for the frictional dissipation
    std::vector<double> power(s, 0.), beta_jm2(s, 0.), beta_jm1(s, 0.), beta_j(s, 0.);
    power[0]         = op.friction_power();
    const double mu1 = rkl2_stage(1, s).mu_tilde;
    for (std::size_t i = 0; i < n; ++i)
      y[i] = u0[i] + mu1 * dt * L0[i];
    beta_jm1[0]  = mu1;
    double c_jm2 = 0, c_jm1 = mu1; // stage times (fractions of dt)
    for (unsigned int j = 2; j <= s; ++j)
      {
        const auto   st = rkl2_stage(j, s);
        const double mu = st.mu, nu = st.nu, mut = st.mu_tilde, gt = st.gamma_tilde;
        patch.gather(Y, W);
        op.set_time(t + c_jm1 * dt);
        op.residual(W, Ljm1);
        power[j - 1] = op.friction_power();
        for (std::size_t i = 0; i < n; ++i)
          {
            const double yj =
              mu * y[i] + nu * Yjm2[i] + (1 - mu - nu) * u0[i] + mut * dt * Ljm1[i] + gt * dt * L0[i];
            Yjm2[i] = y[i];
            y[i]    = yj;
          }
        for (unsigned int k = 0; k < s; ++k)
          beta_j[k] = mu * beta_jm1[k] + nu * beta_jm2[k] + (k == j - 1 ? mut : 0.) + (k == 0 ? gt : 0.);
        const double c_j = mu * c_jm1 + nu * c_jm2 + mut + gt;
        c_jm2            = c_jm1;
        c_jm1            = c_j;
        beta_jm2.swap(beta_jm1);
        beta_jm1.swap(beta_j);
      }
    ++stats.rkl2_steps;
    stats.rkl2_stages += s;
    const bool ok = admissible_owned(y);
    if (ok)
      {
        std::copy(y, y + n, U.begin());
        if (op.friction())
          {
            double friction = 0;
            for (unsigned int k = 0; k < s; ++k)
              friction += dt * beta_jm1[k] * power[k];
            stats.friction_dissipation += Utilities::MPI::sum(friction, patch.communicator());
          }
      }
    else
      last_failure = "RKL2 (" + std::to_string(s) + " stages): " + last_failure;
    stats.rkl2_seconds += timer.wall_time();
    return ok;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::explicit_step(Vector &U, const double t, const double dt)
  {
    const std::size_t n = std::size_t(patch.n_owned()) * (dim + 2);
    // W holds U's gather and explicit_limit its diffusive limit (both from step())
    const double m_needed = std::ceil(dt / explicit_limit);
    if (!(m_needed <= 1e6)) // the baseline's time-step collapse: report it, do not hang
      {
        std::ostringstream os;
        os << "explicit baseline: the diffusive limit collapsed to " << explicit_limit
           << " (scaled time) at t = " << t << " (scaled); one step would need " << m_needed
           << " sub-steps (cap 1e6)";
        last_failure = os.str();
        return false;
      }
    const unsigned int m = std::max(1u, unsigned(m_needed));
    const double       h = dt / m;
    f.resize(n);
    for (unsigned int k = 0; k < m; ++k)
      {
        if (k > 0)
          patch.gather(U, W);
        op.set_time(t + k * h);
        op.residual(W, f.data());
        if (op.friction())
          stats.friction_dissipation += h * Utilities::MPI::sum(op.friction_power(), patch.communicator());
        double *u = U.begin();
        for (std::size_t i = 0; i < n; ++i)
          u[i] += h * f[i];
        ++stats.explicit_substeps;
      }
    return admissible_owned(U.begin());
  }

  template <int dim>
  IntegratorStatistics ImplicitIntegrator<dim>::global_statistics() const
  {
    IntegratorStatistics     g        = stats;            // identical on all ranks (collective decisions)
    const FaceFluxCounts    &c        = op.face_counts(); // each face counted by one rank
    const unsigned long long local[5] = {c.faces, c.tension_bounded, c.tension_bounded_walls,
                                         c.friction_capped, c.negative_temperature};
    unsigned long long       total[5];
    Utilities::MPI::sum(ArrayView<const unsigned long long>(local, 5), op.get_patch().communicator(),
                        ArrayView<unsigned long long>(total, 5));
    g.faces = {total[0], total[1], total[2], total[3], total[4]};
    return g;
  }

  template class ImplicitIntegrator<1>;
  template class ImplicitIntegrator<2>;
  template class ImplicitIntegrator<3>;
} // namespace granhydro::diffusion
