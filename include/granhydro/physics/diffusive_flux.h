#pragma once
/**
 * @file diffusive_flux.h
 * The viscous / heat-conduction flux F_i^v of granular hydrodynamics
 * (doc/physics.md 1 and 4; paper (2.2)-(2.5), (5.1)-(5.9), Appendix A (A1)-(A10)):
 *
 *   F_i^v = ( 0, tau_{k i}/m (k < dim), tau_{ij} u_j + kappa d_i T + mu d_i n )
 *   tau_ij = eta (d_i u_j + d_j u_i) + (gamma - 2 eta/3) delta_ij div u    (paper 2.2)
 *   q      = -kappa grad T - mu grad n                                      (paper 2.3)
 *
 * in three equivalent forms:
 *  - viscous_flux_primitive(): written directly from primitive gradients
 *    (doc/physics.md 4.1, the reference);
 *  - viscous_flux(): from conservative gradients dU via the chain rule of 4.1;
 *  - diffusion_matrix() / flux_from_matrices(): F_i = sum_j D_ij d_j U
 *    (paper 5.1 with the index order of doc/physics.md P7), D_ij as re-derived in
 *    doc/physics.md 4.2, which reproduces the paper's (A1)-(A10) (doc/physics.md P9).
 *    flux_from_matrices(..., true) is the paper's diagonal-only flux
 *    (5.6)-(5.9); cross_terms() is exactly what it drops (doc/physics.md 4.3, P8).
 *
 * State U = (n, n u_1..n u_dim, nE), E = m|u|^2/2 + 3T/2 per particle, T in
 * energy units (doc/physics.md 0). A dim-dimensional run is the 3D theory with the
 * unresolved directions homogeneous: unresolved velocity components and all
 * derivatives along unresolved directions are zero, so every sum below runs
 * over the resolved components 0..dim-1 only (doc/physics.md 0).
 *
 * Gradient conventions: dU[j] = d U / d x_j; grad_u[j][l] = d u_l / d x_j;
 * grad_T[j] = d T / d x_j; grad_n[j] = d n / d x_j. Matrices:
 * D[row][col] = d F_i[row] / d(d_j U[col]).
 *
 * Coefficients: any type with members eta, gamma, kappa, mu (T-based kappa,
 * mu multiplying grad n, doc/physics.md 0 and P4/P5 - mu may be negative, it is
 * not clipped). DiffusiveCoefficients below is the plain struct; the
 * Garzo-Dufty result granhydro::physics::TransportCoefficients
 * (garzo_dufty.h) can be passed directly. (The plain struct is not called
 * TransportCoefficients because garzo_dufty.h already declares that name in
 * this namespace.)
 *
 * Implicit Jacobian: F_i is linear in dU at frozen U, and D_ij is exactly
 * d F_i / d(d_j U); the U-dependence enters only through u = (nu)/n,
 * E = (nE)/n, 1/n and the coefficients. Everything is inline, allocation
 * free, and never divides by eta (valid for eta = 0), so the functions can be
 * differentiated or evaluated cheaply per quadrature point.
 *
 * Preconditions (not checked): n > 0, i, j < dim.
 * Header only, standard library only (plus State from ideal_gas.h).
 */
#include <granhydro/physics/ideal_gas.h>

#include <array>

namespace granhydro::physics
{
  /// Transport coefficients entering F^v (paper 2.2, 2.3; doc/physics.md 0, 3.4).
  struct DiffusiveCoefficients
  {
    double eta;   ///< shear viscosity
    double gamma; ///< bulk viscosity
    double kappa; ///< thermal conductivity multiplying grad T (T in energy units)
    double mu;    ///< heat-flux coefficient multiplying grad n (any sign, P5)
  };

  /// D_ij: (dim + 2) x (dim + 2), D[row][col] (paper 5.1, A1-A10).
  template <int dim>
  using DiffusionMatrix = std::array<std::array<double, dim + 2>, dim + 2>;

  /// Conservative gradient, dU[j] = d U / d x_j.
  template <int dim, typename Number = double>
  using StateGradient = std::array<std::array<Number, dim + 2>, dim>;

  /// Velocity gradient, grad_u[j][l] = d u_l / d x_j.
  template <int dim, typename Number = double>
  using VelocityGradient = std::array<std::array<Number, dim>, dim>;

  /// Primitive gradients (grad u, grad T, grad n).
  template <int dim, typename Number = double>
  struct PrimitiveGradients
  {
    VelocityGradient<dim, Number> grad_u; ///< [j][l] = d u_l / d x_j
    std::array<Number, dim>       grad_T; ///< d T / d x_j
    std::array<Number, dim>       grad_n; ///< d n / d x_j
  };

  namespace internal
  {
    /// u_l = (n u_l)/n for the resolved components; returns |u|^2.
    template <int dim, typename Number = double>
    inline Number velocity(const std::array<Number, dim + 2> &U, std::array<Number, dim> &u)
    {
      const Number inv_n = 1. / U[0];
      Number       u2{};
      for (int l = 0; l < dim; ++l)
        {
          u[l] = U[1 + l] * inv_n;
          u2 += u[l] * u[l];
        }
      return u2;
    }

    /// d_j u_l = (d_j(n u_l) - u_l d_j n)/n, doc/physics.md 4.1.
    template <int dim, typename Number = double>
    inline Number velocity_derivative(const std::array<Number, dim + 2> &dUj, const std::array<Number, dim> &u,
                                      const Number inv_n, int l)
    {
      return (dUj[1 + l] - u[l] * dUj[0]) * inv_n;
    }
  } // namespace internal

  /**
   * Chain rule of doc/physics.md 4.1 (conservative -> primitive gradients):
   *   d u_l = (d(n u_l) - u_l d n)/n,
   *   d T   = (2/(3n)) [ d(nE) - m u_k d(n u_k) + (m|u|^2 - E) d n ] - (2/3) (dw/dn) d n.
   * The last term belongs to a dense closure whose contact potential energy per grain
   * w(n) is stored in the energy density (nE = n|u|^2/2 + 3/2 n T + n w, see
   * contact_pressure.h): then d(nE) also holds d(n w) = (w + n dw/dn) dn, which is not
   * thermal, and forgetting it conducts heat along grad(T + 2w/3) instead of grad T.
   * dw_dn = dw/dn = p_f/n^2 (ContactPressure::dw_dn), 0 without a closure.
   */
  template <int dim, typename Number = double>
  inline PrimitiveGradients<dim, Number> primitive_gradients(const std::array<Number, dim + 2> &U,
                                                             const StateGradient<dim, Number>  &dU,
                                                             const double                       m,
                                                             const double                       dw_dn = 0.)
  {
    std::array<Number, dim>         u;
    const Number                    u2    = internal::velocity<dim, Number>(U, u);
    const Number                    inv_n = 1. / U[0];
    const Number                    E     = U[dim + 1] * inv_n;
    const Number                    cn    = m * u2 - E;
    PrimitiveGradients<dim, Number> g;
    for (int j = 0; j < dim; ++j)
      {
        const std::array<Number, dim + 2> &d = dU[j];
        Number                             s = d[dim + 1] + cn * d[0];
        for (int l = 0; l < dim; ++l)
          {
            g.grad_u[j][l] = internal::velocity_derivative<dim, Number>(d, u, inv_n, l);
            s -= m * u[l] * d[1 + l];
          }
        g.grad_T[j] = (2. / 3.) * (inv_n * s - dw_dn * d[0]);
        g.grad_n[j] = d[0];
      }
    return g;
  }

  /**
   * F_i^v written directly from primitive-variable gradients (doc/physics.md 1 and
   * 4.1; paper 2.2, 2.3, 2.5): (0, tau_{ki}/m, tau_ij u_j + kappa d_i T + mu d_i n).
   * Only the velocity is taken from U.
   */
  template <int dim, typename Coefficients, typename Number = double>
  inline std::array<Number, dim + 2> viscous_flux_primitive(const std::array<Number, dim + 2> &U,
                                                            const VelocityGradient<dim, Number> &grad_u,
                                                            const std::array<Number, dim>       &grad_T,
                                                            const std::array<Number, dim>       &grad_n,
                                                            const Coefficients                  &c,
                                                            const double                         m,
                                                            const unsigned int                   i)
  {
    std::array<Number, dim> u;
    internal::velocity<dim, Number>(U, u);
    Number div{};
    for (int k = 0; k < dim; ++k)
      div += grad_u[k][k];
    const Number lambda = c.gamma - (2. / 3.) * c.eta; // coefficient of delta_ij div u
    std::array<Number, dim + 2> F;
    F[0]          = Number{};
    Number energy = c.kappa * grad_T[i] + c.mu * grad_n[i];
    for (int k = 0; k < dim; ++k)
      {
        // tau_ki = tau_ik = eta (d_k u_i + d_i u_k) + lambda delta_ki div u   (2.2)
        const Number tau = c.eta * (grad_u[k][i] + grad_u[i][k]) + (k == int(i) ? lambda * div : Number{});
        F[1 + k]         = tau / m;
        energy += tau * u[k];
      }
    F[dim + 1] = energy;
    return F;
  }

  /// Same, taking a PrimitiveGradients bundle.
  template <int dim, typename Coefficients, typename Number = double>
  inline std::array<Number, dim + 2> viscous_flux_primitive(const std::array<Number, dim + 2>     &U,
                                                            const PrimitiveGradients<dim, Number> &g,
                                                            const Coefficients                    &c,
                                                            const double                           m,
                                                            const unsigned int                     i)
  {
    return viscous_flux_primitive<dim, Coefficients, Number>(U, g.grad_u, g.grad_T, g.grad_n, c, m, i);
  }

  /**
   * F_i^v from conservative gradients dU (dU[j] = dU/dx_j), via the chain
   * rule of doc/physics.md 4.1 - the recommended implementation.
   */
  template <int dim, typename Coefficients>
  inline State<dim> viscous_flux(const State<dim>         &U,
                                 const StateGradient<dim> &dU,
                                 const Coefficients       &c,
                                 const double              m,
                                 const unsigned int        i,
                                 const double              dw_dn = 0.)
  {
    return viscous_flux_primitive<dim>(U, primitive_gradients<dim>(U, dU, m, dw_dn), c, m, i);
  }

  /**
   * Diffusion matrix D_ij with F_i^v = sum_j D_ij d_j U (paper 5.1; doc/physics.md
   * 4.2 and P7). With e(u_l) the row (-u_l in column n, 1 in column n u_l),
   * so that e(u_l).dU = n d u_l, and lambda = gamma - 2 eta/3:
   *
   *   D_ij[k] = (1/(m n)) [ eta delta_jk e(u_i) + eta delta_ij e(u_k) + lambda delta_ik e(u_j) ]
   *   D_ij[E] = (1/n) [ eta delta_ij sum_l u_l e(u_l) + eta u_j e(u_i) + lambda u_i e(u_j) ]
   *           + delta_ij [ (2 kappa/(3n)) (e_E - m sum_l u_l e_(n u_l) + (m|u|^2 - E) e_n) + mu e_n ]
   *
   * (mass row zero), resolved components only. Identical to the paper's
   * (A1)-(A10) with alpha, beta, lambda, h1..h3 of (A4) (doc/physics.md P9), but
   * written without dividing by eta. With a dense closure (dw_dn > 0, see
   * primitive_gradients()) the n column of the energy row also carries
   * -(2 kappa/3) dw/dn, so that conduction acts on grad T only.
   */
  template <int dim, typename Coefficients>
  inline DiffusionMatrix<dim> diffusion_matrix(const State<dim>   &U,
                                               const Coefficients &c,
                                               const double        m,
                                               const unsigned int  i,
                                               const unsigned int  j,
                                               const double        dw_dn = 0.)
  {
    constexpr int           eE = dim + 1;
    std::array<double, dim> u;
    const double            u2    = internal::velocity<dim>(U, u);
    const double            inv_n = 1. / U[0];
    const double            lambda = c.gamma - (2. / 3.) * c.eta;
    DiffusionMatrix<dim>    D{};
    // add f * e(u_l) to row r
    auto add_e = [&](const int r, const unsigned int l, const double f) {
      D[r][0] -= f * u[l];
      D[r][1 + l] += f;
    };
    const double a = c.eta * inv_n / m, b = lambda * inv_n / m;
    for (unsigned int k = 0; k < unsigned(dim); ++k)
      {
        if (j == k)
          add_e(1 + k, i, a);
        if (i == j)
          add_e(1 + k, k, a);
        if (i == k)
          add_e(1 + k, j, b);
      }
    add_e(eE, i, c.eta * inv_n * u[j]);
    add_e(eE, j, lambda * inv_n * u[i]);
    if (i == j)
      {
        const double th = (2. / 3.) * c.kappa * inv_n;
        const double E  = U[eE] * inv_n;
        for (unsigned int l = 0; l < unsigned(dim); ++l)
          {
            add_e(eE, l, c.eta * inv_n * u[l]);
            D[eE][1 + l] -= th * m * u[l];
          }
        D[eE][0] += th * (m * u2 - E - U[0] * dw_dn) + c.mu;
        D[eE][eE] += th;
      }
    return D;
  }

  /**
   * sum_j D_ij d_j U (paper 5.1), or with diagonal_only = true only
   * D_ii d_i U - the paper's (5.6)-(5.9), which drops cross_terms()
   * (doc/physics.md 4.3, P8). The code uses the full flux.
   */
  template <int dim, typename Coefficients>
  inline State<dim> flux_from_matrices(const State<dim>         &U,
                                       const StateGradient<dim> &dU,
                                       const Coefficients       &c,
                                       const double              m,
                                       const unsigned int        i,
                                       const bool                diagonal_only,
                                       const double              dw_dn = 0.)
  {
    State<dim> F{};
    for (unsigned int j = 0; j < unsigned(dim); ++j)
      {
        if (diagonal_only && j != i)
          continue;
        const DiffusionMatrix<dim> D = diffusion_matrix<dim>(U, c, m, i, j, dw_dn);
        for (int r = 0; r < dim + 2; ++r)
          for (int s = 0; s < dim + 2; ++s)
            F[r] += D[r][s] * dU[j][s];
      }
    return F;
  }

  /**
   * What the diagonal-only flux drops on an i-face, written as in doc/physics.md
   * 4.3 from tangential derivatives (j != i), e.g. on an x-face:
   *   x-momentum: (gamma - 2eta/3)(d_y u_y + d_z u_z)/m,
   *   y-momentum: eta d_y u_x / m,   z-momentum: eta d_z u_x / m,
   *   energy:     u_x (gamma - 2eta/3)(d_y u_y + d_z u_z) + eta (u_y d_y u_x + u_z d_z u_x);
   * no heat-flux term. Equals flux_from_matrices(full) - flux_from_matrices(diagonal).
   */
  template <int dim, typename Coefficients>
  inline State<dim> cross_terms(const State<dim>         &U,
                                const StateGradient<dim> &dU,
                                const Coefficients       &c,
                                const double              m,
                                const unsigned int        i)
  {
    std::array<double, dim> u;
    internal::velocity<dim>(U, u);
    const double inv_n  = 1. / U[0];
    const double lambda = c.gamma - (2. / 3.) * c.eta;
    double       tdiv   = 0.; // tangential divergence sum_{j != i} d_j u_j
    double       shear  = 0.; // sum_{k != i} u_k d_k u_i
    State<dim>   X{};
    for (unsigned int k = 0; k < unsigned(dim); ++k)
      {
        if (k == i)
          continue;
        tdiv += internal::velocity_derivative<dim>(dU[k], u, inv_n, k);
        const double dk_ui = internal::velocity_derivative<dim>(dU[k], u, inv_n, i);
        X[1 + k]           = c.eta * dk_ui / m;
        shear += u[k] * dk_ui;
      }
    X[1 + i]   = lambda * tdiv / m;
    X[dim + 1] = u[i] * lambda * tdiv + c.eta * shear;
    return X;
  }
} // namespace granhydro::physics
