#pragma once
/**
 * @file block_sparse.h
 * A lean block-sparse matrix for the Newton matrix of the implicit step, its block
 * ILU(0) preconditioner and the GMRES solve.
 *
 * The Newton matrix I - dt (N (x) J) couples the NC conserved variables of the s
 * stages of a cell with those of its stencil neighbours, so it is a matrix of dense
 * B x B blocks (B = NC s) with one block row per owned cell and one block column per
 * cell of its stencil. Stored that way it needs one column index per block instead of
 * one per entry (B^2 of them) and no sparsity pattern beside it: for the one-stage
 * system in 3D, 7 blocks of 5 x 5 per cell (1.4 KB), half of that for the ILU factors
 * (single precision). The products run over small dense blocks with unit stride.
 *
 * Numbering: block columns are cells in the local numbering of the mesh's partitioner
 * (owned cells first, then the MPI ghost cells); inside a block the unknown (c, k),
 * variable c of stage k, has index c s + k. A vector holds B values per cell in the
 * same numbering (the partitioner of block_partitioner()).
 *
 * In parallel the preconditioner is block Jacobi over the ranks with ILU(0) inside
 * each rank's owned block rows (the couplings to ghost cells are left out of the
 * factors, as in Ifpack's additive Schwarz without overlap).
 */
#include <deal.II/base/partitioner.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <algorithm>
#include <array>
#include <memory>
#include <utility>
#include <vector>

namespace granhydro::diffusion
{
  /// the partitioner of vectors with `stages` values per scalar unknown of `cell_dofs`
  /// (global index i s + k for unknown i and stage k), ghosts included
  std::shared_ptr<const dealii::Utilities::MPI::Partitioner>
  block_partitioner(const dealii::Utilities::MPI::Partitioner &cell_dofs, const unsigned int stages);

  class BlockSparseMatrix
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    /// M = I - dt (N (x) J) from the Jacobian blocks J[s] = {(t, NC x NC block df_s/dU_t)} of
    /// the owned cells s (t local cell numbers, repeated t summed); N is the s x s matrix
    /// of stage coefficients. The old values are released first.
    template <unsigned int NC>
    void assemble(const std::vector<std::vector<std::pair<unsigned int, std::array<double, NC * NC>>>> &J,
                  const std::vector<std::vector<double>> &N, const double dt);

    /// dst = M src. src's ghost values are imported here: into src itself if it has ghost
    /// storage, else (src owned-only, like GMRES's Krylov vectors) into a work vector on
    /// the partitioner `ghosted`
    void vmult(Vector &dst, const Vector &src) const;

    unsigned int n_block_rows() const { return row_ptr.empty() ? 0 : row_ptr.size() - 1; }
    void         clear();

    unsigned int              B = 0;
    std::vector<unsigned int> row_ptr, col, diag; ///< CSR of blocks; diag: position of (s, s)
    std::vector<double>       val;                ///< B*B per block, row-major
    /// the partitioner of block_partitioner() (owned cells, then the mesh's ghost cells)
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> ghosted;

  private:
    mutable Vector work; ///< src with ghosts, when src has none
  };

  /// block ILU(0) of the owned block rows of a BlockSparseMatrix
  class BlockILU
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;
    /// factorise; false if a diagonal block is singular (then unusable)
    bool initialize(const BlockSparseMatrix &M);
    /// dst = (LU)^{-1} src on the owned entries
    void vmult(Vector &dst, const Vector &src) const;
    void clear();

  private:
    const BlockSparseMatrix *M = nullptr;
    /// factors in M's block layout: strictly lower blocks hold L (unit diagonal implied),
    /// the diagonal blocks hold the inverse of U's diagonal, the upper blocks U. Stored in
    /// single precision: half the memory and bandwidth of the solves; the factorisation
    /// runs in double and GMRES iterates with the double-precision matrix, so this only
    /// perturbs the preconditioner (by 1e-7 relative, far below what ILU(0) drops)
    std::vector<float> lu;
  };

  template <unsigned int NC>
  void BlockSparseMatrix::assemble(
    const std::vector<std::vector<std::pair<unsigned int, std::array<double, NC * NC>>>> &J,
    const std::vector<std::vector<double>> &N, const double dt)
  {
    const unsigned int S = N.size(), n = J.size();
    B                    = NC * S;
    row_ptr.assign(n + 1, 0);
    for (unsigned int s = 0; s < n; ++s)
      {
        bool has_diagonal = false;
        for (const auto &e : J[s])
          has_diagonal |= e.first == s;
        row_ptr[s + 1] = row_ptr[s] + J[s].size() + (has_diagonal ? 0 : 1);
      }
    std::vector<unsigned int>().swap(col);
    std::vector<double>().swap(val);
    col.resize(row_ptr[n]);
    diag.resize(n);
    val.assign(std::size_t(row_ptr[n]) * B * B, 0.);
    std::vector<std::pair<unsigned int, unsigned int>> order; // (column, index in J[s])
    for (unsigned int s = 0; s < n; ++s)
      {
        order.clear();
        bool has_diagonal = false;
        for (unsigned int e = 0; e < J[s].size(); ++e)
          {
            order.emplace_back(J[s][e].first, e);
            has_diagonal |= J[s][e].first == s;
          }
        if (!has_diagonal)
          order.emplace_back(s, ~0u);
        std::sort(order.begin(), order.end());
        for (unsigned int p = 0; p < order.size(); ++p)
          {
            const unsigned int pos = row_ptr[s] + p, t = order[p].first;
            col[pos]               = t;
            double *blk            = &val[std::size_t(pos) * B * B];
            if (t == s)
              {
                diag[s] = pos;
                for (unsigned int r = 0; r < B; ++r)
                  blk[r * B + r] = 1.;
              }
            if (order[p].second == ~0u)
              continue;
            const auto &Jb = J[s][order[p].second].second;
            for (unsigned int a = 0; a < NC; ++a)
              for (unsigned int i = 0; i < S; ++i)
                for (unsigned int b = 0; b < NC; ++b)
                  for (unsigned int j = 0; j < S; ++j)
                    blk[(a * S + i) * B + b * S + j] -= dt * N[i][j] * Jb[a * NC + b];
          }
      }
  }
} // namespace granhydro::diffusion
