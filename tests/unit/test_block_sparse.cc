// unit.block_sparse: the block-sparse Newton matrix and its block ILU(0)
// (include/granhydro/diffusion/block_sparse.h), against dense references built here
// independently from the same Jacobian blocks:
//  - M = I - dt (N (x) J): BlockSparseMatrix::vmult equals the dense product to 1e-14
//    relative (same terms, summed in another order: round-off only), for one stage
//    (block 5 x 5) and two coupled stages (10 x 10, the Gauss-Legendre layout);
//  - on a block-tridiagonal matrix (a 1D chain of cells) ILU(0) has no fill outside the
//    pattern, so it is the exact block LU factorisation: applying it to M x recovers x
//    to the precision of the factors, which are stored in single precision (unit
//    round-off 6e-8 times a condition number ~10: bound 1e-6; 3e-8 measured; with
//    double factors it was 3e-16, and a wrong factorisation misses by O(1));
//  - on a 2D five-point stencil (where ILU(0) drops fill) GMRES preconditioned with the
//    block ILU reaches a true residual <= 1e-12 |b| in fewer iterations than the same
//    GMRES with the identity as preconditioner.
#include <granhydro/diffusion/block_sparse.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include "common/test_common.h"

#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>

using namespace granhydro;
using namespace granhydro::diffusion;
using granhydro::testing::Checker;
using namespace dealii;

namespace
{
  constexpr unsigned int NC = 5;
  using Blocks              = std::vector<std::vector<std::pair<unsigned int, std::array<double, NC * NC>>>>;
  using Vec                 = LinearAlgebra::distributed::Vector<double>;

  /// Jacobian blocks of a grid nx x ny of cells with face neighbours; diagonal blocks
  /// dominant (like df/dU of a diffusion operator: -sum of the off-diagonal couplings)
  Blocks grid_jacobian(const unsigned int nx, const unsigned int ny, std::mt19937 &rng)
  {
    std::uniform_real_distribution<double> u(-1., 1.);
    Blocks                                 J(nx * ny);
    for (unsigned int j = 0; j < ny; ++j)
      for (unsigned int i = 0; i < nx; ++i)
        {
          const unsigned int s = j * nx + i;
          std::vector<unsigned int> nb;
          if (i > 0)
            nb.push_back(s - 1);
          if (i + 1 < nx)
            nb.push_back(s + 1);
          if (j > 0)
            nb.push_back(s - nx);
          if (j + 1 < ny)
            nb.push_back(s + nx);
          std::array<double, NC * NC> D{};
          for (const unsigned int t : nb)
            {
              std::array<double, NC * NC> B;
              for (auto &b : B)
                b = 0.2 * u(rng);
              for (unsigned int a = 0; a < NC; ++a)
                B[a * NC + a] += 1.;
              J[s].emplace_back(t, B);
              for (unsigned int k = 0; k < NC * NC; ++k)
                D[k] -= B[k];
            }
          for (auto &d : D)
            d += 0.1 * u(rng);
          J[s].emplace_back(s, D);
        }
    return J;
  }

  /// dense M = I - dt (N (x) J) in the interleaved numbering (cell, variable, stage)
  std::vector<std::vector<double>> dense(const Blocks &J, const std::vector<std::vector<double>> &N,
                                         const double dt)
  {
    const unsigned int S = N.size(), n = J.size() * NC * S;
    std::vector<std::vector<double>> M(n, std::vector<double>(n, 0.));
    for (unsigned int r = 0; r < n; ++r)
      M[r][r] = 1.;
    for (unsigned int s = 0; s < J.size(); ++s)
      for (const auto &[t, B] : J[s])
        for (unsigned int a = 0; a < NC; ++a)
          for (unsigned int i = 0; i < S; ++i)
            for (unsigned int b = 0; b < NC; ++b)
              for (unsigned int k = 0; k < S; ++k)
                M[(s * NC + a) * S + i][(t * NC + b) * S + k] -= dt * N[i][k] * B[a * NC + b];
    return M;
  }

  Vec make_vector(const unsigned int cells, const unsigned int stages)
  {
    Utilities::MPI::Partitioner cell_dofs(complete_index_set(cells * NC), MPI_COMM_SELF);
    Vec                         v;
    v.reinit(block_partitioner(cell_dofs, stages));
    return v;
  }

  double max_abs(const Vec &v)
  {
    return v.linfty_norm();
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Checker                          chk;
  std::mt19937                     rng(20261202);
  std::uniform_real_distribution<double> u(-1., 1.);
  const double dt = 0.3;
  const std::vector<std::vector<double>> one{{0.29289321881345254}}, gl{{0.25, 0.25 - std::sqrt(3.) / 6},
                                                                        {0.25 + std::sqrt(3.) / 6, 0.25}};

  for (const auto &[N, name] : {std::pair{one, std::string("one stage")}, std::pair{gl, std::string("two stages")}})
    {
      // ---- vmult against the dense product (2D grid 6 x 5)
      const Blocks      J = grid_jacobian(6, 5, rng);
      diffusion::BlockSparseMatrix M;
      M.assemble<NC>(J, N, dt);
      const auto D  = dense(J, N, dt);
      Vec        x  = make_vector(J.size(), N.size()), y = x;
      for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
        x.local_element(i) = u(rng);
      M.vmult(y, x);
      double err = 0, ref = 0;
      for (unsigned int r = 0; r < D.size(); ++r)
        {
          double s = 0;
          for (unsigned int c = 0; c < D.size(); ++c)
            s += D[r][c] * x.local_element(c);
          err = std::max(err, std::abs(s - y.local_element(r)));
          ref = std::max(ref, std::abs(s));
        }
      std::ostringstream os;
      os << std::scientific << std::setprecision(2) << name << ": block vmult vs dense, max error "
         << err / ref << " (relative) <= 1e-14";
      chk.check(err <= 1e-14 * ref, os.str());

      // ---- ILU(0) of a block-tridiagonal matrix is its exact LU
      const Blocks      Jc = grid_jacobian(40, 1, rng);
      diffusion::BlockSparseMatrix Mc;
      Mc.assemble<NC>(Jc, N, dt);
      BlockILU ilu;
      chk.check(ilu.initialize(Mc), name + ": block ILU(0) of the chain factorises");
      Vec xc = make_vector(Jc.size(), N.size()), b = xc, z = xc;
      for (unsigned int i = 0; i < xc.locally_owned_size(); ++i)
        xc.local_element(i) = u(rng);
      Mc.vmult(b, xc);
      ilu.vmult(z, b);
      z -= xc;
      os.str("");
      os << name << ": chain (block tridiagonal): ILU(0) solve error " << max_abs(z) / max_abs(xc)
         << " (relative) <= 1e-6 (exact LU, factors in single precision)";
      chk.check(max_abs(z) <= 1e-6 * max_abs(xc), os.str());

      // ---- 2D grid: preconditioned GMRES (the solver of the implicit step)
      const Blocks      J2 = grid_jacobian(12, 10, rng);
      diffusion::BlockSparseMatrix M2;
      M2.assemble<NC>(J2, N, 4 * dt); // stiffer
      BlockILU ilu2;
      chk.check(ilu2.initialize(M2), name + ": block ILU(0) of the grid factorises");
      Vec b2 = make_vector(J2.size(), N.size()), x2 = b2, x3 = b2, r2 = b2;
      for (unsigned int i = 0; i < b2.locally_owned_size(); ++i)
        b2.local_element(i) = u(rng);
      unsigned int its[2] = {0, 0};
      for (const bool precondition : {true, false})
        {
          SolverControl   control(1000, 1e-13 * b2.l2_norm());
          SolverGMRES<Vec> gmres(control, SolverGMRES<Vec>::AdditionalData(32, true));
          Vec &xs = precondition ? x2 : x3;
          if (precondition)
            gmres.solve(M2, xs, b2, ilu2);
          else
            gmres.solve(M2, xs, b2, PreconditionIdentity());
          its[precondition ? 0 : 1] = control.last_step();
        }
      M2.vmult(r2, x2);
      r2 -= b2;
      os.str("");
      os << name << ": 2D grid, GMRES + block ILU(0): true residual " << r2.l2_norm() / b2.l2_norm()
         << " <= 1e-12 in " << its[0] << " iterations (identity: " << its[1] << ")";
      chk.check(r2.l2_norm() <= 1e-12 * b2.l2_norm() && its[0] < its[1], os.str());
    }
  return chk.failed != 0;
}
