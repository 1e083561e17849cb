#include <granhydro/diffusion/block_sparse.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/index_set.h>

#include <cmath>

namespace granhydro::diffusion
{
  using namespace dealii;

  std::shared_ptr<const Utilities::MPI::Partitioner>
  block_partitioner(const Utilities::MPI::Partitioner &cell_dofs, const unsigned int stages)
  {
    const types::global_dof_index N = cell_dofs.size() * stages;
    const auto                    r = cell_dofs.local_range();
    IndexSet                      owned(N), ghost(N);
    owned.add_range(types::global_dof_index(r.first) * stages, types::global_dof_index(r.second) * stages);
    std::vector<types::global_dof_index> g;
    for (const auto i : cell_dofs.ghost_indices())
      for (unsigned int k = 0; k < stages; ++k)
        g.push_back(i * stages + k); // ascending: i ascending, k ascending
    ghost.add_indices(g.begin(), g.end());
    owned.compress();
    ghost.compress();
    return std::make_shared<Utilities::MPI::Partitioner>(owned, ghost, cell_dofs.get_mpi_communicator());
  }

  namespace
  {
    /// acc += sign A x for a dense B x B block A (row-major) and a vector x of B values,
    /// acc held by the caller (registers when BB, the block size, is known at compile time)
    template <unsigned int BB, int sign, class T>
    inline void block_acc(const T *__restrict A, const double *__restrict x, double *__restrict acc,
                          const unsigned int B_rt)
    {
      const unsigned int B = BB ? BB : B_rt;
      for (unsigned int r = 0; r < B; ++r)
        {
          double s = 0;
          for (unsigned int c = 0; c < B; ++c)
            s += A[r * B + c] * x[c];
          acc[r] += sign * s;
        }
    }

    /// Z = X Y for dense B x B blocks (row-major; Y in the factors' single precision)
    inline void block_product(const double *X, const float *Y, double *Z, const unsigned int B)
    {
      for (unsigned int r = 0; r < B; ++r)
        for (unsigned int c = 0; c < B; ++c)
          {
            double s = 0;
            for (unsigned int m = 0; m < B; ++m)
              s += X[r * B + m] * Y[m * B + c];
            Z[r * B + c] = s;
          }
    }

    /// calls f.template operator()<BB>() with BB = B for the usual block sizes (NC s with
    /// NC = 3, 4, 5 and s = 1, 2), BB = 0 (run-time size) otherwise
    template <class F>
    void dispatch(const unsigned int B, F &&f)
    {
      switch (B)
        {
          case 3: f(std::integral_constant<unsigned int, 3>()); break;
          case 4: f(std::integral_constant<unsigned int, 4>()); break;
          case 5: f(std::integral_constant<unsigned int, 5>()); break;
          case 6: f(std::integral_constant<unsigned int, 6>()); break;
          case 8: f(std::integral_constant<unsigned int, 8>()); break;
          case 10: f(std::integral_constant<unsigned int, 10>()); break;
          default: f(std::integral_constant<unsigned int, 0>());
        }
    }

    /// in-place inverse of a dense B x B block by Gauss-Jordan elimination with partial
    /// pivoting; false if singular (a zero or non-finite pivot)
    bool invert(double *A, const unsigned int B)
    {
      double inv[16 * 16] = {};
      for (unsigned int r = 0; r < B; ++r)
        inv[r * B + r] = 1.;
      for (unsigned int c = 0; c < B; ++c)
        {
          unsigned int p = c;
          for (unsigned int r = c + 1; r < B; ++r)
            if (std::abs(A[r * B + c]) > std::abs(A[p * B + c]))
              p = r;
          const double piv = A[p * B + c];
          if (!(std::abs(piv) > 0) || !std::isfinite(piv))
            return false;
          if (p != c)
            for (unsigned int k = 0; k < B; ++k)
              {
                std::swap(A[p * B + k], A[c * B + k]);
                std::swap(inv[p * B + k], inv[c * B + k]);
              }
          const double ip = 1. / piv;
          for (unsigned int k = 0; k < B; ++k)
            {
              A[c * B + k] *= ip;
              inv[c * B + k] *= ip;
            }
          for (unsigned int r = 0; r < B; ++r)
            if (r != c)
              {
                const double m = A[r * B + c];
                if (m != 0)
                  for (unsigned int k = 0; k < B; ++k)
                    {
                      A[r * B + k] -= m * A[c * B + k];
                      inv[r * B + k] -= m * inv[c * B + k];
                    }
              }
        }
      std::copy(inv, inv + B * B, A);
      return true;
    }
  } // namespace

  void BlockSparseMatrix::vmult(Vector &dst, const Vector &src) const
  {
    const bool own_ghosts = src.get_partitioner()->n_ghost_indices() > 0 || !ghosted ||
                            ghosted->n_ghost_indices() == 0;
    if (own_ghosts)
      src.update_ghost_values();
    else
      {
        AssertThrow(src.locally_owned_size() == ghosted->locally_owned_size(),
                    ExcMessage("block vector does not match the matrix"));
        if (work.get_partitioner() != ghosted)
          work.reinit(ghosted);
        std::copy(src.begin(), src.begin() + src.locally_owned_size(), work.begin());
        work.update_ghost_values();
      }
    const double      *x = own_ghosts ? src.begin() : work.begin(); // owned values, then the ghosts
    double            *y = dst.begin();
    const unsigned int n = n_block_rows();
    dispatch(B, [&](auto BBc) {
      constexpr unsigned int BB = decltype(BBc)::value;
      const unsigned int     b  = BB ? BB : B;
      for (unsigned int s = 0; s < n; ++s)
        {
          double acc[16] = {};
          for (unsigned int p = row_ptr[s]; p < row_ptr[s + 1]; ++p)
            block_acc<BB, 1>(&val[std::size_t(p) * b * b], x + std::size_t(col[p]) * b, acc, b);
          std::copy(acc, acc + b, y + std::size_t(s) * b);
        }
    });
    if (own_ghosts)
      src.zero_out_ghost_values();
  }

  void BlockSparseMatrix::clear()
  {
    std::vector<unsigned int>().swap(row_ptr);
    std::vector<unsigned int>().swap(col);
    std::vector<unsigned int>().swap(diag);
    std::vector<double>().swap(val);
    work = Vector();
  }

  bool BlockILU::initialize(const BlockSparseMatrix &A)
  {
    M                  = &A;
    const unsigned int B = A.B, n = A.n_block_rows();
    AssertThrow(B <= 16, ExcMessage("block ILU: blocks larger than 16 x 16 are not supported"));
    const std::size_t BB = std::size_t(B) * B;
    lu.assign(A.val.size(), 0.f);
    std::vector<double> row, L(BB), LU(BB); // the block row being eliminated, in double
    // IKJ ILU(0) over the owned block rows; columns >= n (ghost cells) are left out. Row i
    // is eliminated in double with the finished rows k < i (stored in single precision)
    for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int p0 = A.row_ptr[i], p1 = A.row_ptr[i + 1];
        row.assign(A.val.begin() + p0 * BB, A.val.begin() + p1 * BB);
        for (unsigned int p = p0; p < p1 && A.col[p] < i; ++p)
          {
            const unsigned int k = A.col[p];
            // L_ik = A_ik U_kk^{-1} (the diagonal block of row k holds U_kk^{-1})
            double *Aik = &row[(p - p0) * BB];
            block_product(Aik, &lu[A.diag[k] * BB], L.data(), B);
            std::copy(L.begin(), L.end(), Aik);
            // A_ij -= L_ik U_kj for j > k present in row i (both rows sorted)
            unsigned int q = p + 1;
            for (unsigned int pk = A.diag[k] + 1; pk < A.row_ptr[k + 1]; ++pk)
              {
                const unsigned int j = A.col[pk];
                if (j >= n)
                  break;
                while (q < p1 && A.col[q] < j)
                  ++q;
                if (q == p1)
                  break;
                if (A.col[q] != j)
                  continue;
                double *Aij = &row[(q - p0) * BB];
                block_product(L.data(), &lu[pk * BB], LU.data(), B);
                for (std::size_t e = 0; e < BB; ++e)
                  Aij[e] -= LU[e];
              }
          }
        if (!invert(&row[(A.diag[i] - p0) * BB], B))
          return false;
        std::copy(row.begin(), row.end(), lu.begin() + p0 * BB);
      }
    return true;
  }

  void BlockILU::vmult(Vector &dst, const Vector &src) const
  {
    const BlockSparseMatrix &A = *M;
    const unsigned int       n = A.n_block_rows();
    const double            *r = src.begin();
    double                  *x = dst.begin();
    // the solves are sequential from row to row: prefetch the factors two rows ahead (twice
    // as fast on 250 000 cells in 3D), as the hardware stops its streams at page borders
    constexpr unsigned int ahead = 2;
    const char            *base  = reinterpret_cast<const char *>(lu.data());
    auto prefetch = [&](const std::size_t from, const std::size_t to) {
      for (const char *a = base + from * sizeof(float), *e = base + to * sizeof(float); a < e; a += 64)
        __builtin_prefetch(a);
    };
    dispatch(A.B, [&](auto BBc) {
      constexpr unsigned int BB = decltype(BBc)::value;
      const unsigned int     b  = BB ? BB : A.B;
      const std::size_t      bb = std::size_t(b) * b;
      // forward: y_i = r_i - sum_{k < i} L_ik y_k (y in x)
      for (unsigned int i = 0; i < n; ++i)
        {
          if (i + ahead < n)
            prefetch(A.row_ptr[i + ahead] * bb, (A.diag[i + ahead] + 1) * bb);
          double acc[16];
          std::copy(r + std::size_t(i) * b, r + std::size_t(i + 1) * b, acc);
          for (unsigned int p = A.row_ptr[i]; p < A.diag[i]; ++p)
            block_acc<BB, -1>(&lu[p * bb], x + std::size_t(A.col[p]) * b, acc, b);
          std::copy(acc, acc + b, x + std::size_t(i) * b);
        }
      // backward: x_i = U_ii^{-1} (y_i - sum_{j > i} U_ij x_j)
      for (unsigned int i = n; i-- > 0;)
        {
          if (i >= ahead)
            prefetch(A.diag[i - ahead] * bb, A.row_ptr[i - ahead + 1] * bb);
          double acc[16], t[16] = {};
          std::copy(x + std::size_t(i) * b, x + std::size_t(i + 1) * b, acc);
          for (unsigned int p = A.diag[i] + 1; p < A.row_ptr[i + 1] && A.col[p] < n; ++p)
            block_acc<BB, -1>(&lu[p * bb], x + std::size_t(A.col[p]) * b, acc, b);
          block_acc<BB, 1>(&lu[A.diag[i] * bb], acc, t, b);
          std::copy(t, t + b, x + std::size_t(i) * b);
        }
    });
  }

  void BlockILU::clear()
  {
    std::vector<float>().swap(lu);
    M = nullptr;
  }
} // namespace granhydro::diffusion
