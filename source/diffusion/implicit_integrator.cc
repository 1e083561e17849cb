#include <granhydro/diffusion/implicit_integrator.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_solver.h>

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
  bool ImplicitIntegrator<dim>::admissible_owned(const std::vector<double> &Uv)
  {
    constexpr unsigned int NC = dim + 2;
    bool                   ok = true;
    for (unsigned int s = 0; s < patch.n_owned() && ok; ++s)
      {
        physics::State<dim> S;
        std::copy(&Uv[std::size_t(s) * NC], &Uv[std::size_t(s + 1) * NC], S.begin());
        ok = desc.admissible(S);
        if (!ok)
          {
            std::ostringstream os;
            os << "diffusion step result inadmissible at x = " << patch.center(s)
               << " m: packing fraction " << S[0] * M_PI / 6 << ", T = " << desc.temperature(S)
               << " (scaled units)";
            last_failure = os.str();
          }
      }
    return Utilities::MPI::min(ok ? 1 : 0, patch.communicator()) == 1;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::step(Vector &U, const double t, const double dt)
  {
    ++stats.steps;
    const double s3 = std::sqrt(3.) / 6.;
    const Table               A_gl{{0.25, 0.25 - s3}, {0.25 + s3, 0.25}};
    const std::vector<double> b_gl{0.5, 0.5};
    const Table               A_mp{{0.5}};
    const std::vector<double> b_mp{1.};
    const double              g = 1 - 1 / std::sqrt(2.); // SDIRK2: L-stable, stiffly accurate
    const Table               A_sd{{g, 0.}, {1 - g, g}};
    const std::vector<double> b_sd{1 - g, g};
    {
      // the explicit diffusive limit at the start of the step (diagnostic; one
      // coefficient evaluation per cell, a few % of a Newton iteration)
      patch.gather(U, W);
      const double limit = 0.9 / op.explicit_rate(W.data());
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
          return irk_step(U, t, dt, A_mp, b_mp);
        case ImplicitMethod::gauss_legendre:
          return irk_step(U, t, dt, A_gl, b_gl);
        case ImplicitMethod::sdirk2:
          return irk_step(U, t, dt, A_sd, b_sd);
        default:
          if (irk_step(U, t, dt, A_gl, b_gl))
            return true;
          ++stats.switches_to_midpoint;
          return irk_step(U, t, dt, A_mp, b_mp);
      }
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::irk_step(Vector &U, const double t, const double dt, const Table &A,
                                         const std::vector<double> &b)
  {
    if (irk_attempt(U, t, dt, A, b, settings.full_jacobian))
      return true;
    if (settings.full_jacobian)
      return false;
    // the lagged cross terms can stall the iteration where they are stiff (near
    // vacuum, P14): redo the step with the fully coupled Jacobian
    ++stats.full_jacobian_retries;
    return irk_attempt(U, t, dt, A, b, true);
  }

  template <int dim>
  void ImplicitIntegrator<dim>::setup_newton(const double dt, const Table &N, const bool coupled)
  {
    Timer      timer;
    const auto stages = N.size();
    M                 = &M_[stages][coupled];
    if (!have_pattern[stages][coupled])
      {
        TrilinosWrappers::SparsityPattern sp;
        op.make_sparsity(sp, stages, coupled);
        M->reinit(sp);
        have_pattern[stages][coupled] = true;
      }
    op.assemble_newton_matrix(W.data(), N, dt, *M, coupled);
    ++stats.jacobians;
    stats.jacobian_seconds += timer.wall_time();
    timer.restart();
    if (settings.amg)
      {
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic = false;
        amg.initialize(*M, data);
      }
    else
      ilu.initialize(*M);
    stats.preconditioner_seconds += timer.wall_time();
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::irk_attempt(Vector &U, const double t, const double dt, const Table &A,
                                            const std::vector<double> &b, const bool full)
  {
    constexpr unsigned int NC     = dim + 2;
    const unsigned int     stages = A.size();
    last_failure.clear();
    const std::size_t n    = std::size_t(patch.n_owned()) * NC;
    const MPI_Comm    comm = patch.communicator();
    U0.assign(U.begin(), U.begin() + n);
    if (Y.size() != U.size())
      Y.reinit(patch.partitioner());
    double scale = 0;
    for (std::size_t i = 0; i < n; ++i)
      scale = std::max(scale, std::abs(U0[i]));
    scale = Utilities::MPI::max(scale, comm);
    std::vector<double> c(stages, 0.);
    for (unsigned int k = 0; k < stages; ++k)
      for (unsigned int j = 0; j < stages; ++j)
        c[k] += A[k][j];
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
    op.residual(W.data(), f.data());
    const bool  coupled = full && !op.diagonal_only();
    const Table N       = dirk ? Table{{A[0][0]}} : A;
    // Newton matrix of an earlier step: kept while it makes the iteration contract fast
    // (the previous step converged in <= 7 iterations per stage; a fresh Jacobian and
    // preconditioner cost about as much as 7 Newton iterations), for at most 8 steps and
    // while dt stays within 10 % of the dt it was built for. I - dt N (x) J is then off by
    // the change of J and dt, which only slows the contraction of the modified Newton
    // iteration; if that fails, the step is redone with a fresh matrix (counted).
    const bool reuse = settings.reuse_matrix && matrix_valid && matrix_coupled == coupled &&
                       matrix_N == N && std::abs(dt / matrix_dt - 1) <= 0.1 && matrix_age < 8;
    if (reuse)
      {
        ++matrix_age;
        ++stats.matrix_reuses;
        M = &M_[N.size()][coupled];
      }
    else
      {
        setup_newton(dt, N, coupled);
        matrix_valid   = true;
        matrix_coupled = coupled;
        matrix_N       = N;
        matrix_dt      = dt;
        matrix_age     = 0;
      }
    unsigned int iterations = 0, max_iterations = 0; // per stage (DIRK) or per step
    auto         failed     = [&]() {
      matrix_valid = false;
      if (!reuse)
        {
          if (!gmres_failed) // GMRES failures are counted as such
            ++stats.newton_failures;
          return false;
        }
      ++stats.stale_matrix_retries; // the kept matrix did not do: a fresh one
      return irk_attempt(U, t, dt, A, b, full);
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
    if (!admissible_owned(U1))
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
  bool ImplicitIntegrator<dim>::newton(const std::vector<double> &base, const std::vector<double> &tk,
                                       const double dt, const Table &N, const double scale,
                                       std::vector<double> &K, std::vector<double> &power,
                                       unsigned int &iterations)
  {
    constexpr unsigned int NC     = dim + 2;
    const unsigned int     stages = N.size();
    const std::size_t      n      = std::size_t(patch.n_owned()) * NC;
    const MPI_Comm         comm   = patch.communicator();
    const IndexSet         owned  = M->locally_owned_range_indices();
    TrilinosWrappers::MPI::Vector rhs(owned, comm), delta(owned, comm);

    // f = f(Y_k) at the stage value Y_k = base + dt sum_j N_kj K_j, time tk[k]
    auto stage_slope = [&](const unsigned int k) {
      double *y = Y.begin();
      for (std::size_t i = 0; i < n; ++i)
        {
          double s = 0;
          for (unsigned int j = 0; j < stages; ++j)
            s += N[k][j] * K[i * stages + j];
          y[i] = base[i] + dt * s;
        }
      patch.gather(Y, W);
      op.set_time(tk[k]);
      op.residual(W.data(), f.data());
    };
    const auto &part = *patch.partitioner();
    double      prev = 0, r_prev = 0, eta = 1e-2;
    gmres_failed     = false;
    for (unsigned int it = 0; it < settings.newton_max_iterations; ++it)
      {
        // residual R_k = K_k - f(Y_k)
        for (unsigned int k = 0; k < stages; ++k)
          {
            stage_slope(k);
            for (std::size_t i = 0; i < n; ++i)
              rhs[(part.local_to_global(i)) * stages + k] = -(K[i * stages + k] - f[i]);
          }
        rhs.compress(VectorOperation::insert);
        const double r = rhs.l2_norm();
        if (settings.inexact_newton && it > 0)
          {
            // Eisenstat-Walker choice 2 with its safeguard; r / r_prev is the contraction
            const double eta_rule = 0.9 * (r / r_prev) * (r / r_prev), eta_safe = 0.9 * eta * eta;
            eta = std::min(0.1, eta_safe > 0.1 ? std::max(eta_rule, eta_safe) : eta_rule);
          }
        r_prev = r;
        const double  tol = settings.inexact_newton ? std::max(eta, settings.linear_tolerance) :
                                                       settings.linear_tolerance;
        SolverControl control(1000, std::max(tol * r, 1e-300));
        delta = 0;
        Timer timer;
        try
          {
            TrilinosWrappers::SolverGMRES gmres(control);
            if (settings.amg)
              gmres.solve(*M, delta, rhs, amg);
            else
              gmres.solve(*M, delta, rhs, ilu);
          }
        catch (const std::exception &)
          {
            stats.linear_seconds += timer.wall_time();
            ++stats.linear_failures;
            gmres_failed = true;
            stats.linear_iterations += control.last_step();
            last_failure = "GMRES did not reach its tolerance in " + std::to_string(control.last_step()) +
                           " iterations";
            return false;
          }
        stats.linear_seconds += timer.wall_time();
        stats.linear_iterations += control.last_step();
        ++stats.newton_iterations;
        double      dmax = 0;
        std::size_t imax = 0;
        for (std::size_t i = 0; i < n; ++i)
          for (unsigned int k = 0; k < stages; ++k)
            {
              const double d = delta[part.local_to_global(i) * stages + k];
              K[i * stages + k] += d;
              if (std::abs(d) > dmax)
                {
                  dmax = std::abs(d);
                  imax = i;
                }
            }
        const double dmax_local = dmax;
        dmax = Utilities::MPI::max(dmax, comm) * dt;
        if (!std::isfinite(dmax))
          break;
        if (dmax <= settings.newton_tolerance * scale)
          {
            // final slopes K_k = f(Y_k) at the converged stage values
            std::vector<double> Kf(n * stages);
            for (unsigned int k = 0; k < stages; ++k)
              {
                stage_slope(k);
                power[k] = op.friction_power();
                for (std::size_t i = 0; i < n; ++i)
                  Kf[i * stages + k] = f[i];
              }
            K.swap(Kf);
            iterations = it + 1;
            return true;
          }
        if (it > 2 && dmax > 0.9 * prev) // no contraction: give up early
          {
            std::ostringstream os;
            os << "modified Newton stalled after " << it + 1 << " iterations (update "
               << dmax / scale << " of max|U|, tolerance " << settings.newton_tolerance << ")";
            if (dmax_local * dt == dmax && n > 0) // this rank holds the largest update: where
              {
                const unsigned int c = imax / NC;
                os << ", largest in component " << imax % NC << " of the cell at x = "
                   << patch.center(c) << " m (packing fraction " << base[c * NC] * M_PI / 6
                   << ")";
              }
            last_failure = os.str();
            break;
          }
        prev = dmax;
      }
    if (last_failure.empty())
      last_failure = "modified Newton did not converge in " +
                     std::to_string(settings.newton_max_iterations) + " iterations";
    return false;
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
        op.residual(W.data(), f.data());
        if (op.friction())
          stats.friction_dissipation += h * Utilities::MPI::sum(op.friction_power(), patch.communicator());
        double *u = U.begin();
        for (std::size_t i = 0; i < n; ++i)
          u[i] += h * f[i];
        ++stats.explicit_substeps;
      }
    std::vector<double> Uv(U.begin(), U.begin() + n);
    return admissible_owned(Uv);
  }

  template <int dim>
  IntegratorStatistics ImplicitIntegrator<dim>::global_statistics() const
  {
    IntegratorStatistics g = stats; // identical on all ranks (collective decisions)
    return g;
  }

  template class ImplicitIntegrator<1>;
  template class ImplicitIntegrator<2>;
  template class ImplicitIntegrator<3>;
} // namespace granhydro::diffusion
