#include <granhydro/diffusion/implicit_integrator.h>

#include <deal.II/base/mpi.h>
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
    const std::vector<std::vector<double>> A_gl{{0.25, 0.25 - s3}, {0.25 + s3, 0.25}};
    const std::vector<double>              b_gl{0.5, 0.5};
    const std::vector<std::vector<double>> A_mp{{0.5}};
    const std::vector<double>              b_mp{1.};
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
        default:
          if (irk_step(U, t, dt, A_gl, b_gl))
            return true;
          ++stats.switches_to_midpoint;
          return irk_step(U, t, dt, A_mp, b_mp);
      }
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::irk_step(Vector &U, const double t, const double dt,
                                         const std::vector<std::vector<double>> &A,
                                         const std::vector<double>              &b)
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
  bool ImplicitIntegrator<dim>::irk_attempt(Vector &U, const double t, const double dt,
                                            const std::vector<std::vector<double>> &A,
                                            const std::vector<double> &b, const bool full)
  {
    constexpr unsigned int NC     = dim + 2;
    const unsigned int     stages = A.size();
    last_failure.clear();
    const std::size_t      n      = std::size_t(patch.n_owned()) * NC;
    const MPI_Comm         comm   = patch.communicator();
    U0.assign(U.begin(), U.begin() + n);
    if (Y.size() != U.size())
      Y.reinit(patch.partitioner());

    // Jacobian at U0, Newton matrix, preconditioner (frozen for the whole step)
    patch.gather(U, W);
    f.resize(n);
    op.set_time(t);
    op.residual(W.data(), f.data());
    const bool coupled = full && !op.diagonal_only();
    auto      &M       = M_[stages][coupled];
    if (!have_pattern[stages][coupled])
      {
        TrilinosWrappers::SparsityPattern sp;
        op.make_sparsity(sp, stages, coupled);
        M.reinit(sp);
        have_pattern[stages][coupled] = true;
      }
    op.assemble_newton_matrix(W.data(), A, dt, M, coupled);
    ++stats.jacobians;
    TrilinosWrappers::PreconditionILU ilu;
    TrilinosWrappers::PreconditionAMG amg;
    if (settings.amg)
      {
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic = false;
        amg.initialize(M, data);
      }
    else
      ilu.initialize(M);

    const IndexSet owned = M.locally_owned_range_indices();
    TrilinosWrappers::MPI::Vector rhs(owned, comm), delta(owned, comm);
    std::vector<double> K(n * stages);
    for (std::size_t i = 0; i < n; ++i) // start from f(U0) in every stage
      for (unsigned int k = 0; k < stages; ++k)
        K[i * stages + k] = f[i];
    double scale = 0;
    for (std::size_t i = 0; i < n; ++i)
      scale = std::max(scale, std::abs(U0[i]));
    scale = Utilities::MPI::max(scale, comm);

    // f = f(Y_k) at the stage value Y_k = U0 + dt sum_j a_kj K_j, time t + c_k dt
    auto stage_slope = [&](const unsigned int k) {
      double *y  = Y.begin();
      double  ck = 0;
      for (unsigned int j = 0; j < stages; ++j)
        ck += A[k][j];
      for (std::size_t i = 0; i < n; ++i)
        {
          double s = 0;
          for (unsigned int j = 0; j < stages; ++j)
            s += A[k][j] * K[i * stages + j];
          y[i] = U0[i] + dt * s;
        }
      patch.gather(Y, W);
      op.set_time(t + ck * dt);
      op.residual(W.data(), f.data());
    };
    const auto &part = *patch.partitioner();
    double      prev = 0;
    for (unsigned int it = 0; it < settings.newton_max_iterations; ++it)
      {
        // residual R_k = K_k - f(U0 + dt sum_j a_kj K_j)
        for (unsigned int k = 0; k < stages; ++k)
          {
            stage_slope(k);
            for (std::size_t i = 0; i < n; ++i)
              rhs[(part.local_to_global(i)) * stages + k] = -(K[i * stages + k] - f[i]);
          }
        rhs.compress(VectorOperation::insert);
        SolverControl control(1000, std::max(settings.linear_tolerance * rhs.l2_norm(), 1e-300));
        delta = 0;
        try
          {
            TrilinosWrappers::SolverGMRES gmres(control);
            if (settings.amg)
              gmres.solve(M, delta, rhs, amg);
            else
              gmres.solve(M, delta, rhs, ilu);
          }
        catch (const std::exception &)
          {
            ++stats.linear_failures;
            stats.linear_iterations += control.last_step();
            return false;
          }
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
            // final slopes K_k = f(Y_k) at the converged stage values: f is in flux form,
            // so U1 = U0 + dt sum b_k f(Y_k) conserves mass (and energy and momentum where
            // no source acts) to round-off, not only to the Newton tolerance
            std::vector<double> Kf(n * stages);
            double              friction = 0; // frictional dissipation of the step, this rank
            for (unsigned int k = 0; k < stages; ++k)
              {
                stage_slope(k);
                friction += dt * b[k] * op.friction_power();
                for (std::size_t i = 0; i < n; ++i)
                  Kf[i * stages + k] = f[i];
              }
            K.swap(Kf);
            // U1 = U0 + dt sum b_i K_i
            std::vector<double> U1(n);
            for (std::size_t i = 0; i < n; ++i)
              {
                double s = 0;
                for (unsigned int k = 0; k < stages; ++k)
                  s += b[k] * K[i * stages + k];
                U1[i] = U0[i] + dt * s;
              }
            if (!admissible_owned(U1))
              break;
            std::copy(U1.begin(), U1.end(), U.begin());
            if (op.friction())
              stats.friction_dissipation += Utilities::MPI::sum(friction, comm);
            return true;
          }
        if (it > 2 && dmax > 0.9 * prev) // no contraction: give up early
          {
            std::ostringstream os;
            os << "modified Newton stalled after " << it + 1 << " iterations (update "
               << dmax / scale << " of max|U|, tolerance " << settings.newton_tolerance << ")";
            if (dmax_local * dt == dmax && n > 0) // this rank holds the largest update: where
              {
                const unsigned int c = imax / (dim + 2);
                os << ", largest in component " << imax % (dim + 2) << " of the cell at x = "
                   << patch.center(c) << " m (packing fraction " << U0[c * (dim + 2)] * M_PI / 6
                   << ")";
              }
            last_failure = os.str();
            break;
          }
        prev = dmax;
      }
    ++stats.newton_failures;
    if (last_failure.empty())
      last_failure = "modified Newton did not converge in " +
                     std::to_string(settings.newton_max_iterations) + " iterations";
    std::copy(U0.begin(), U0.end(), U.begin());
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
