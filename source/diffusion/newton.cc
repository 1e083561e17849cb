// ImplicitIntegrator: the modified Newton iteration of the implicit stages - its
// convergence scale, the Newton matrix and preconditioner of a step, and the iteration
// with its GMRES solves (the methods and steps are in implicit_integrator.cc)
#include <granhydro/diffusion/implicit_integrator.h>
#include <granhydro/physics/packing_fraction.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_solver.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace granhydro::diffusion
{
  using namespace dealii;

  std::vector<double> newton_scale(const std::vector<double> &U, const unsigned int NC, const MPI_Comm comm)
  {
    const std::size_t   cells = U.size() / NC;
    std::vector<double> s(U.size()), floor(NC, 0.);
    for (std::size_t i = 0; i < cells; ++i)
      {
        const double *u = &U[i * NC];
        const double  n = std::abs(u[0]), E = std::abs(u[NC - 1]);
        s[i * NC] = n;
        for (unsigned int c = 1; c + 1 < NC; ++c)
          s[i * NC + c] = std::sqrt(2 * n * E); // >= |n u_c|: E >= n |u|^2 / 2
        s[i * NC + NC - 1] = E;
        for (unsigned int c = 0; c < NC; ++c)
          floor[c] = std::max(floor[c], s[i * NC + c]);
      }
    Utilities::MPI::max(floor, comm, floor);
    for (std::size_t i = 0; i < s.size(); ++i)
      s[i] = std::max(s[i], newton_scale_floor * floor[i % NC]);
    return s;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::setup_newton(const double dt, const Table &N, const bool coupled)
  {
    Timer      timer;
    const auto stages = N.size();
    if (settings.block_ilu && !settings.amg)
      {
        // release the old matrix and factors first: the peak memory is the Jacobian
        // blocks plus one matrix, then one matrix plus its factors
        bilu.clear();
        bmat.clear();
        {
          typename DiffusionOperator<dim>::JacobianBlocks J;
          op.jacobian(W, J, coupled);
          bmat.assemble<dim + 2>(J, N, dt);
        }
        if (!block_part[stages])
          {
            block_part[stages]       = block_partitioner(*patch.partitioner(), stages);
            block_part_owned[stages] = std::make_shared<Utilities::MPI::Partitioner>(
              block_part[stages]->locally_owned_range(), patch.communicator());
          }
        bmat.ghosted = block_part[stages];
        ++stats.jacobians;
        stats.jacobian_seconds += timer.wall_time();
        timer.restart();
        const bool ok = bilu.initialize(bmat);
        stats.preconditioner_seconds += timer.wall_time();
        if (!ok)
          last_failure = "block ILU(0): singular diagonal block in the Newton matrix";
        return ok;
      }
    M = &M_[stages][coupled];
    if (!have_pattern[stages][coupled])
      {
        TrilinosWrappers::SparsityPattern sp;
        op.make_sparsity(sp, stages, coupled);
        M->reinit(sp);
        have_pattern[stages][coupled] = true;
      }
    op.assemble_newton_matrix(W, N, dt, *M, coupled);
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
    return true;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::solve_correction(SolverControl                       &control,
                                                 const TrilinosWrappers::MPI::Vector &rhs,
                                                 TrilinosWrappers::MPI::Vector       &delta)
  {
    delta  = 0;
    bdelta = 0;
    Timer timer;
    try
      {
        if (settings.block_ilu && !settings.amg)
          {
            // right preconditioning: GMRES measures the true residual, like AztecOO;
            // 32 temporary vectors = restart after 30 iterations, as Trilinos' default
            using BV = LinearAlgebra::distributed::Vector<double>;
            SolverGMRES<BV> gmres(control, typename SolverGMRES<BV>::AdditionalData(32, true));
            gmres.solve(bmat, bdelta, brhs, bilu);
          }
        else
          {
            TrilinosWrappers::SolverGMRES gmres(control);
            if (settings.amg)
              gmres.solve(*M, delta, rhs, amg);
            else
              gmres.solve(*M, delta, rhs, ilu);
          }
      }
    catch (const std::exception &)
      {
        stats.linear_seconds += timer.wall_time();
        ++stats.linear_failures;
        gmres_failed = true;
        // a solver that fails before its first check leaves last_step() at
        // invalid_unsigned_int: count its full budget, never a wrapped 2^32 - 1
        const unsigned int k =
          control.last_step() == numbers::invalid_unsigned_int ? control.max_steps() : control.last_step();
        stats.linear_iterations += k;
        last_failure = "GMRES did not reach its tolerance in " + std::to_string(k) + " iterations";
        return false;
      }
    stats.linear_seconds += timer.wall_time();
    stats.linear_iterations += control.last_step();
    return true;
  }

  template <int dim>
  bool ImplicitIntegrator<dim>::newton(const std::vector<double> &base, const std::vector<double> &tk,
                                       const double dt, const Table &N, const std::vector<double> &scale,
                                       std::vector<double> &K, std::vector<double> &power,
                                       unsigned int &iterations)
  {
    constexpr unsigned int        NC     = dim + 2;
    const unsigned int            stages = N.size();
    const std::size_t             n      = std::size_t(patch.n_owned()) * NC;
    const MPI_Comm                comm   = patch.communicator();
    const bool                    blocks = settings.block_ilu && !settings.amg;
    TrilinosWrappers::MPI::Vector rhs, delta;
    if (blocks)
      {
        brhs.reinit(block_part_owned[stages]);
        bdelta.reinit(block_part_owned[stages]);
      }
    else
      {
        rhs.reinit(M->locally_owned_range_indices(), comm);
        delta.reinit(M->locally_owned_range_indices(), comm);
      }

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
      op.residual(W, f.data());
    };
    const auto &part = *patch.partitioner();
    double      prev = 0, r_prev = 0, eta = 1e-2;
    gmres_failed = false;
    for (unsigned int it = 0; it < settings.newton_max_iterations; ++it)
      {
        // residual R_k = K_k - f(Y_k)
        for (unsigned int k = 0; k < stages; ++k)
          {
            stage_slope(k);
            if (blocks) // local numbering: unknown i, stage k at i * stages + k
              for (std::size_t i = 0; i < n; ++i)
                brhs.local_element(i * stages + k) = -(K[i * stages + k] - f[i]);
            else
              for (std::size_t i = 0; i < n; ++i)
                rhs[(part.local_to_global(i)) * stages + k] = -(K[i * stages + k] - f[i]);
          }
        if (!blocks)
          rhs.compress(VectorOperation::insert);
        const double r = blocks ? brhs.l2_norm() : rhs.l2_norm();
        if (settings.inexact_newton && it > 0)
          {
            // Eisenstat-Walker choice 2 with its safeguard; r / r_prev is the contraction
            const double eta_rule = 0.9 * (r / r_prev) * (r / r_prev), eta_safe = 0.9 * eta * eta;
            eta = std::min(0.1, eta_safe > 0.1 ? std::max(eta_rule, eta_safe) : eta_rule);
          }
        r_prev = r;
        const double tol =
          settings.inexact_newton ? std::max(eta, settings.linear_tolerance) : settings.linear_tolerance;
        SolverControl control(1000, std::max(tol * r, 1e-300));
        if (!solve_correction(control, rhs, delta))
          return false;
        ++stats.newton_iterations;
        // the largest update relative to its cell's own scale
        double      dmax = 0;
        std::size_t imax = 0;
        for (std::size_t i = 0; i < n; ++i)
          for (unsigned int k = 0; k < stages; ++k)
            {
              const double d =
                blocks ? bdelta.local_element(i * stages + k) : delta[part.local_to_global(i) * stages + k];
              K[i * stages + k] += d;
              if (std::abs(d) > dmax * scale[i])
                {
                  dmax = std::abs(d) / scale[i];
                  imax = i;
                }
            }
        const double dmax_local = dmax;
        dmax                    = Utilities::MPI::max(dmax, comm) * dt;
        if (!std::isfinite(dmax))
          break;
        if (dmax <= settings.newton_tolerance)
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
            os << "modified Newton stalled after " << it + 1 << " iterations (update " << dmax
               << " of the cell's own scale, tolerance " << settings.newton_tolerance << ")";
            if (dmax_local * dt == dmax && n > 0) // this rank holds the largest update: where
              {
                const unsigned int c = imax / NC;
                os << ", largest in component " << imax % NC << " of the cell at x = " << patch.center(c)
                   << " m (packing fraction " << physics::packing_fraction(base[c * NC]) << ")";
              }
            last_failure = os.str();
            break;
          }
        prev = dmax;
      }
    if (last_failure.empty())
      last_failure = "modified Newton did not converge in " + std::to_string(settings.newton_max_iterations) +
                     " iterations";
    return false;
  }

  template class ImplicitIntegrator<1>;
  template class ImplicitIntegrator<2>;
  template class ImplicitIntegrator<3>;
} // namespace granhydro::diffusion
