// DiffusionOperator: the Newton matrix of the implicit integrators - the sparsity of the
// Jacobian, the finite-difference Jacobian df/dU of the face fluxes and sources, and
// I - dt A (x) J (the residual f itself is in diffusion_operator.cc)
#include <granhydro/diffusion/diffusion_operator.h>

#include <algorithm>
#include <cmath>

namespace granhydro::diffusion
{
  using namespace dealii;
  using physics::State;

  template <int dim>
  void DiffusionOperator<dim>::make_sparsity(TrilinosWrappers::SparsityPattern &sp, const unsigned int stages,
                                             const bool edge_neighbours) const
  {
    const auto                   &part  = *patch.partitioner();
    const unsigned int            n_own = patch.n_owned();
    const types::global_dof_index N     = part.size();
    IndexSet                      owned(N * stages);
    const auto                    range = part.local_range();
    owned.add_range(range.first * stages, range.second * stages);
    owned.compress();
    sp.reinit(owned, patch.communicator());
    std::vector<types::global_dof_index> cols;
    for (unsigned int s = 0; s < n_own; ++s)
      {
        std::vector<unsigned int> cells{s};
        for (unsigned int d = 0; d < dim; ++d)
          {
            const auto [b, e] = patch.cell_faces(d, s);
            for (auto cf = b; cf != e; ++cf)
              {
                const unsigned int f = patch.across(d, *cf);
                cells.push_back(src[f]);
                for (const unsigned int c : {s, f}) // gradient neighbours (cross terms)
                  for (unsigned int j = 0; j < dim; ++j)
                    if (j != d && edge_neighbours)
                      for (const unsigned int side : {0u, 1u})
                        if (const int g = patch.gradient_neighbor(c, j, side); g >= 0)
                          cells.push_back(src[g]);
              }
          }
        cols.clear();
        for (const unsigned int t : cells)
          for (unsigned int c = 0; c < NC; ++c)
            for (unsigned int k = 0; k < stages; ++k)
              cols.push_back(part.local_to_global(std::size_t(t) * NC + c) * stages + k);
        std::sort(cols.begin(), cols.end());
        cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
        for (unsigned int c = 0; c < NC; ++c)
          for (unsigned int k = 0; k < stages; ++k)
            sp.add_entries(part.local_to_global(std::size_t(s) * NC + c) * stages + k, cols.begin(),
                           cols.end());
      }
    sp.compress();
  }

  template <int dim>
  void DiffusionOperator<dim>::jacobian(const double *W, JacobianBlocks &J, const bool cross_terms) const
  {
    std::vector<double> Wc; // perturbable copy of the slot array (cross-term derivatives)
    if (cross_terms)
      Wc.assign(W, W + std::size_t(patch.n_slots()) * NC);
    const unsigned int n_own = patch.n_owned();
    // J blocks per owned cell: J[s] = sum over stencil cells t of block (NC x NC) df_s/dU_t;
    // each row reserved for its face neighbours (no doubling of the capacity)
    J.assign(n_own, {});
    for (unsigned int s = 0; s < n_own; ++s)
      {
        unsigned int faces = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const auto [b, e] = patch.cell_faces(d, s);
            faces += e - b;
          }
        J[s].reserve(cross_terms ? 4 * faces : faces);
      }
    auto add_block = [&](const unsigned int s, unsigned int t, const std::array<double, NC * NC> &B,
                         const double sign) {
      // t may be a boundary ghost: U_t = Flip U_src(t) -> columns of src with signs
      const unsigned int fm = flip[t];
      t                     = src[t];
      auto &row             = J[s];
      auto  it = std::find_if(row.begin(), row.end(), [&](const auto &e) { return e.first == t; });
      if (it == row.end())
        {
          row.emplace_back(t, std::array<double, NC * NC>{});
          it = row.end() - 1;
        }
      for (unsigned int a = 0; a < NC; ++a)
        for (unsigned int b = 0; b < NC; ++b)
          {
            const double sb = (b >= 1 && b <= dim && (fm >> (b - 1) & 1u)) ? -1. : 1.;
            it->second[a * NC + b] += sign * sb * B[a * NC + b];
          }
    };
    // face fluxes: derivative of the normal part w.r.t. U_L and U_R (tangential frozen)
    for (unsigned int d = 0; d < dim; ++d)
      for (std::size_t k = 0; k < patch.faces(d).size(); ++k)
        {
          const auto        &fc = patch.faces(d)[k];
          const unsigned int l = fc.l, r = fc.r;
          const auto        &wall = this->wall(d, k);
          const double       ihn  = this->ihn(d, l, r);
          // f[l] += frac_l F / h_l, f[r] -= frac_r F / h_r
          const double wl = l < n_own ? fc.frac_l * ih(d, l) : 0.;
          const double wr = r < n_own ? fc.frac_r * ih(d, r) : 0.;
          State<dim>   UL, UR, F0, F1, G0, G1;
          std::copy(W + std::size_t(l) * NC, W + std::size_t(l + 1) * NC, UL.begin());
          std::copy(W + std::size_t(r) * NC, W + std::size_t(r + 1) * NC, UR.begin());
          State<dim> *g0 = friction_active ? &G0 : nullptr, *g1 = friction_active ? &G1 : nullptr;
          face_flux(W, d, ihn, l, r, UL, UR, wall, F0, g0);
          // block of the face flux (and of the frictional momentum flux) w.r.t. one state
          using Block     = std::array<double, NC * NC>;
          auto difference = [&](const State<dim> &Fa, const State<dim> &Ga, const double e,
                                const unsigned int b, Block &B, Block &BG) {
            for (unsigned int a = 0; a < NC; ++a)
              {
                B[a * NC + b] = (Fa[a] - F0[a]) / e;
                if (friction_active)
                  BG[a * NC + b] = (Ga[a] - G0[a]) / e;
              }
          };
          // the energy row of cell c also gets u_c . d(frictional momentum flux) (residual():
          // u . div tau_f; the dependence of u_c itself is left out of the Jacobian)
          auto with_friction = [&](Block B, const Block &BG, const unsigned int c) {
            if (friction_active)
              for (unsigned int k = 0; k < dim; ++k)
                {
                  const double uk = W[std::size_t(c) * NC + 1 + k] / W[std::size_t(c) * NC];
                  for (unsigned int b = 0; b < NC; ++b)
                    B[(dim + 1) * NC + b] += uk * BG[(1 + k) * NC + b];
                }
            return B;
          };
          Block BL{}, BR{}, GL{}, GR{};
          for (unsigned int b = 0; b < NC; ++b)
            for (const int side : {0, 1})
              {
                State<dim>   L2 = UL, R2 = UR;
                State<dim>  &P = side == 0 ? L2 : R2;
                const double e = 1e-7 * std::max(std::abs(P[b]), std::max(1e-3 * std::abs(P[0]), 1e-10));
                P[b] += e;
                face_flux(W, d, ihn, l, r, L2, R2, wall, F1, g1);
                difference(F1, G1, e, b, side == 0 ? BL : BR, side == 0 ? GL : GR);
              }
          if (cross_terms && !settings.diagonal_only)
            for (unsigned int j = 0; j < dim; ++j)
              if (j != d)
                for (const unsigned int c : {l, r})
                  for (const unsigned int side : {0u, 1u})
                    {
                      const int tg = patch.gradient_neighbor(c, j, side);
                      if (tg < 0)
                        continue;
                      const unsigned int t = tg;
                      Block              B{}, BG{};
                      for (unsigned int b = 0; b < NC; ++b)
                        {
                          double      &P  = Wc[std::size_t(t) * NC + b];
                          const double P0 = P;
                          const double e =
                            1e-7 *
                            std::max(std::abs(P0), std::max(1e-3 * std::abs(Wc[std::size_t(t) * NC]), 1e-10));
                          P += e;
                          face_flux(Wc.data(), d, ihn, l, r, UL, UR, wall, F1, g1);
                          P = P0;
                          difference(F1, G1, e, b, B, BG);
                        }
                      if (l < n_own)
                        add_block(l, t, with_friction(B, BG, l), wl);
                      if (r < n_own)
                        add_block(r, t, with_friction(B, BG, r), -wr);
                    }
          if (l < n_own)
            {
              add_block(l, l, with_friction(BL, GL, l), wl);
              add_block(l, r, with_friction(BR, GR, l), wl);
            }
          if (r < n_own)
            {
              add_block(r, l, with_friction(BL, GL, r), -wr);
              add_block(r, r, with_friction(BR, GR, r), -wr);
            }
        }
    // sources
    for (unsigned int s = 0; s < n_own; ++s)
      {
        State<dim> U, S0, S1;
        std::copy(W + std::size_t(s) * NC, W + std::size_t(s + 1) * NC, U.begin());
        source(U, S0);
        std::array<double, NC * NC> B{};
        for (unsigned int b = 0; b < NC; ++b)
          {
            State<dim>   U2 = U;
            const double e  = 1e-7 * std::max(std::abs(U[b]), std::max(1e-3 * std::abs(U[0]), 1e-10));
            U2[b] += e;
            source(U2, S1);
            for (unsigned int a = 0; a < NC; ++a)
              B[a * NC + b] = (S1[a] - S0[a]) / e;
          }
        add_block(s, s, B, 1.);
      }
  }

  template <int dim>
  void DiffusionOperator<dim>::assemble_newton_matrix(const double                           *W,
                                                      const std::vector<std::vector<double>> &A,
                                                      const double dt, TrilinosWrappers::SparseMatrix &M,
                                                      const bool cross_terms) const
  {
    const auto        &part   = *patch.partitioner();
    const unsigned int n_own  = patch.n_owned();
    const unsigned int stages = A.size();
    JacobianBlocks     J;
    jacobian(W, J, cross_terms);
    // M = I - dt A (x) J, interleaved numbering dof * stages + stage
    M = 0;
    std::vector<types::global_dof_index> cols;
    std::vector<double>                  vals;
    for (unsigned int s = 0; s < n_own; ++s)
      for (unsigned int a = 0; a < NC; ++a)
        {
          const types::global_dof_index row = part.local_to_global(std::size_t(s) * NC + a);
          for (unsigned int i = 0; i < stages; ++i)
            {
              cols.clear();
              vals.clear();
              for (const auto &[t, B] : J[s])
                for (unsigned int b = 0; b < NC; ++b)
                  {
                    const types::global_dof_index col = part.local_to_global(std::size_t(t) * NC + b);
                    for (unsigned int j = 0; j < stages; ++j)
                      {
                        cols.push_back(col * stages + j);
                        vals.push_back(-dt * A[i][j] * B[a * NC + b] +
                                       (t == s && a == b && i == j ? 1. : 0.));
                      }
                  }
              M.add(row * stages + i, cols.size(), cols.data(), vals.data(), false, true);
            }
        }
    M.compress(VectorOperation::add);
  }

  template class DiffusionOperator<1>;
  template class DiffusionOperator<2>;
  template class DiffusionOperator<3>;
} // namespace granhydro::diffusion
