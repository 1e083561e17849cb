// ContactStep (diffusion/contact_step.h): the implicit contact pressure and gravity after
// each convective step, Newton's method on the density with GMRES and block ILU(0)
#include <granhydro/diffusion/contact_step.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace granhydro::diffusion
{
  using namespace dealii;

  namespace
  {
    /// one value per cell of a partitioner of NC values per cell (owned range and ghosts
    /// divided by NC; the ghost cells keep their order, so local index = patch slot)
    std::shared_ptr<const Utilities::MPI::Partitioner> per_cell(const Utilities::MPI::Partitioner &dofs,
                                                                const unsigned int NC, const bool ghosts)
    {
      const auto r = dofs.local_range();
      IndexSet   own(dofs.size() / NC), gh(dofs.size() / NC);
      own.add_range(r.first / NC, r.second / NC);
      if (ghosts)
        {
          std::vector<types::global_dof_index> g;
          for (const auto i : dofs.ghost_indices())
            if (i % NC == 0)
              g.push_back(i / NC);
          gh.add_indices(g.begin(), g.end());
        }
      own.compress();
      gh.compress();
      return std::make_shared<Utilities::MPI::Partitioner>(own, gh, dofs.get_mpi_communicator());
    }
  } // namespace

  template <int dim>
  ContactStep<dim>::ContactStep(const mesh::CartesianPatch<dim> &patch, const physics::GranularGas<dim> &desc,
                                const physics::GranularGas<dim> &explicit_desc,
                                const ContactStepSettings &settings, const double length_unit)
    : patch(patch)
    , desc(desc)
    , explicit_desc(explicit_desc)
    , settings(settings)
    , length_unit(length_unit)
  {}

  template <int dim>
  physics::GranularGas<dim> ContactStep<dim>::explicit_description(const physics::GranularGas<dim> &desc)
  {
    const auto               &chi = desc.model.pair_correlation();
    physics::GranularGas<dim> e(
      physics::GarzoDufty1999(desc.model.eps(), chi.phi_c() - 2 * chi.delta(), chi.phi_c(), chi.delta()));
    return e; // no dense closure
  }

  template <int dim>
  void ContactStep<dim>::implicit_pressure(const unsigned int s, const double n, double &p,
                                           double &dp_dn) const
  {
    const double phi = n * desc.phi_per_n, T = T_star[s];
    double       Z, dZ, Ze, dZe;
    desc.model.Z_and_derivative(phi, Z, dZ);
    explicit_desc.model.Z_and_derivative(phi, Ze, dZe);
    double nw, pf_phi, pf, dpf; // one evaluation of the potential: pf = pressure(), dpf = dpressure_dn()
    desc.contact.evaluate(n, nw, pf_phi, dpf, pf);
    p     = pf + n * T * (Z - Ze);
    dp_dn = dpf + T * ((Z - Ze) + phi * (dZ - dZe));
  }

  template <int dim>
  void ContactStep<dim>::setup()
  {
    cells = per_cell(*patch.partitioner(), NC, true);
    owned = per_cell(*patch.partitioner(), NC, false);
    AssertThrow(cells->n_ghost_indices() == patch.n_mpi_ghosts(),
                ExcMessage("contact step: the cell partitioner's ghosts are not the patch's MPI ghosts"));
    n_min = std::min(desc.contact.phi_min, desc.model.pair_correlation().phi_f()) / desc.phi_per_n;
    for (unsigned int k = 0; k < mesh::max_levels; ++k)
      for (unsigned int d = 0; d < dim; ++d)
        inv_h_level[k][d] = length_unit / patch.level_cell_size(k, d);
    matrix.clear();
    matrix.ghosted = cells;
    n_iter.reinit(cells);
    rhs.reinit(owned);
    delta.reinit(owned);
  }

  template <int dim>
  void ContactStep<dim>::shift_energy(Vector &U, const double sign) const
  {
    U.zero_out_ghost_values();
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      {
        double *u = &U.local_element(std::size_t(s) * NC);
        u[NC - 1] += sign * desc.contact.energy_density(u[0]);
      }
  }

  template <int dim>
  void ContactStep<dim>::contact_energies(const Vector &U, double *w) const
  {
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      w[s] = desc.contact.energy_density(U.local_element(std::size_t(s) * NC));
  }

  template <int dim>
  void ContactStep<dim>::begin_convective_step(Vector &U)
  {
    n_before.resize(patch.n_owned());
    for (unsigned int s = 0; s < patch.n_owned(); ++s)
      n_before[s] = U.local_element(std::size_t(s) * NC);
    shift_energy(U, -1.);
  }

  template <int dim>
  bool ContactStep<dim>::face_flux(const unsigned int d, const unsigned int l, const unsigned int r,
                                   const double h, const double *n, FaceFlux &F) const
  {
    if (!patch.is_cell(l) || !patch.is_cell(r)) // walls, outflow, solid: no mass through it
      return false;
    if (!(n_star[l] > n_min || n_star[r] > n_min)) // no grains in enduring contact here
      return false;
    const double inv_dist = 2. / (1. / inv_h(l, d) + 1. / inv_h(r, d));
    const double g        = settings.gravity[d];
    F.J     = -h * ((p_imp[r] - p_imp[l] + p_exp[r] - p_exp[l]) * inv_dist - 0.5 * (n[l] + n[r]) * g);
    F.dJ_dl = -h * (-dp_imp[l] * inv_dist - 0.5 * g);
    F.dJ_dr = -h * (dp_imp[r] * inv_dist - 0.5 * g);
    return true;
  }

  template <int dim>
  double ContactStep<dim>::read_state(Vector &U)
  {
    const unsigned int no = patch.n_owned(), nl = no + patch.n_mpi_ghosts();
    U.update_ghost_values();
    // the step's per-cell values in a work array the convective and diffusion steps share
    // (neither runs inside this step): no memory of their own
    n_star       = patch.scratch(mesh::Scratch::stage_c, 6 * std::size_t(nl));
    T_star       = n_star + nl;
    p_exp        = T_star + nl;
    p_imp        = p_exp + nl;
    dp_imp       = p_imp + nl;
    thermal      = dp_imp + nl;
    double n_max = 0;
    for (unsigned int s = 0; s < nl; ++s)
      {
        physics::State<dim> S;
        for (unsigned int c = 0; c < NC; ++c)
          S[c] = U.local_element(std::size_t(s) * NC + c);
        const double e = S[NC - 1] - physics::kinetic_energy<dim>(S) - desc.contact.energy_density(S[0]);
        n_star[s]      = S[0];
        T_star[s]      = std::max(e, 0.) / (1.5 * S[0]);
        if (s < no && e < 0) // counted: the run summary's contact_negative_thermal_cells
          ++counts_.negative_thermal_cells;
        p_exp[s] = S[0] * T_star[s] * explicit_desc.model.Z(S[0] * desc.phi_per_n);
        if (s < no)
          {
            thermal[s] = e;
            n_max      = std::max(n_max, S[0]);
          }
      }
    for (unsigned int s = 0; s < no; ++s)
      n_iter.local_element(s) = n_star[s];
    return Utilities::MPI::max(n_max, patch.communicator());
  }

  template <int dim>
  double
  ContactStep<dim>::residual_row(const unsigned int i, const double h, const double *n,
                                 std::vector<std::pair<unsigned int, std::array<double, 1>>> &row) const
  {
    double R = n[i] - n_star[i];
    row.clear();
    for (unsigned int d = 0; d < dim; ++d)
      {
        const auto [b, e] = patch.cell_faces(d, i);
        for (auto cf = b; cf != e; ++cf)
          {
            const auto &f = patch.faces(d)[cf->face];
            FaceFlux    F;
            if (!face_flux(d, f.l, f.r, h, n, F))
              continue;
            // the flux leaves i through its upper faces, enters through its lower ones
            const double w = h * inv_h(i, d) * (cf->upper ? f.frac_l : -f.frac_r);
            R += w * F.J;
            row.push_back({f.l, {{-w * F.dJ_dl}}}); // the matrix is I - J
            row.push_back({f.r, {{-w * F.dJ_dr}}});
          }
      }
    // one block per column (BlockSparseMatrix::assemble() keeps repeated columns apart)
    std::sort(row.begin(), row.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
    std::size_t k = 0;
    for (std::size_t j = 0; j < row.size(); ++j)
      if (k > 0 && row[k - 1].first == row[j].first)
        row[k - 1].second[0] += row[j].second[0];
      else
        row[k++] = row[j];
    row.resize(k);
    return R;
  }

  template <int dim>
  bool ContactStep<dim>::newton(const double h, const double n_max)
  {
    const unsigned int no = patch.n_owned(), nl = no + patch.n_mpi_ghosts();
    const MPI_Comm     comm = patch.communicator();
    J.resize(no);
    const std::vector<std::vector<double>> N         = {{1.}};
    bool                                   converged = false;
    unsigned int                           it        = 0;
    for (; it < settings.newton_max_iterations && !converged; ++it)
      {
        unsigned long long active = 0;
        n_iter.update_ghost_values();
        const double *n = n_iter.begin();
        for (unsigned int s = 0; s < nl; ++s)
          implicit_pressure(s, n[s], p_imp[s], dp_imp[s]);
        for (unsigned int i = 0; i < no; ++i)
          {
            rhs.local_element(i) = -residual_row(i, h, n, J[i]);
            active += !J[i].empty();
          }
        if (it == 0 && Utilities::MPI::sum(active, comm) == 0) // no dense grains: gravity only
          {
            converged = true;
            break;
          }
        matrix.assemble<1>(J, N, 1.);
        if (!ilu.initialize(matrix))
          {
            last_failure_ = "contact step: singular diagonal in the Newton matrix";
            break;
          }
        SolverControl control(200, settings.linear_tolerance * rhs.l2_norm(), false, false);
        delta = 0;
        try
          {
            SolverGMRES<Vector> gmres(control, SolverGMRES<Vector>::AdditionalData(32, true));
            gmres.solve(matrix, delta, rhs, ilu);
          }
        catch (const std::exception &)
          {
            last_failure_ = "contact step: GMRES did not converge";
            counts_.linear_iterations += control.last_step();
            break;
          }
        counts_.linear_iterations += control.last_step();
        double largest = 0;
        for (unsigned int i = 0; i < no; ++i)
          {
            n_iter.local_element(i) += delta.local_element(i);
            largest = std::max(largest, std::abs(delta.local_element(i)));
          }
        converged = Utilities::MPI::max(largest, comm) <= settings.newton_tolerance * n_max;
        if (!converged && it + 1 == settings.newton_max_iterations)
          last_failure_ = "contact step: Newton's method did not converge";
      }
    counts_.newton_iterations += it;
    counts_.max_newton_iterations = std::max(counts_.max_newton_iterations, it);
    if (!converged)
      return false;
    double n_low = 1;
    for (unsigned int i = 0; i < no; ++i)
      n_low = std::min(n_low, n_iter.local_element(i));
    if (Utilities::MPI::min(n_low, comm) <= 0)
      {
        last_failure_ = "contact step: a density became non-positive";
        return false;
      }
    return true;
  }

  template <int dim>
  void ContactStep<dim>::update(Vector &U, const double h)
  {
    const unsigned int no = patch.n_owned(), nl = no + patch.n_mpi_ghosts();
    n_iter.update_ghost_values();
    const double *n = n_iter.begin();
    for (unsigned int s = 0; s < nl; ++s)
      implicit_pressure(s, n[s], p_imp[s], dp_imp[s]);
    U.zero_out_ghost_values();
    for (unsigned int i = 0; i < no; ++i)
      {
        double *u = &U.local_element(std::size_t(i) * NC);
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double g = settings.gravity[d], hd = 1. / inv_h(i, d);
            double       force = 0; // minus the pressure's difference across the cell, times the share
            const auto [b, e]  = patch.cell_faces(d, i);
            for (auto cf = b; cf != e; ++cf)
              {
                const auto  &f    = patch.faces(d)[cf->face];
                const double frac = cf->upper ? f.frac_l : f.frac_r;
                const double sign = cf->upper ? -1. : 1.;
                double       p_face;
                if (patch.is_cell(f.l) && patch.is_cell(f.r))
                  p_face = 0.5 * (p_imp[f.l] + p_imp[f.r]);
                else // a wall: the cell's pressure extrapolated hydrostatically to it, >= 0 (counted)
                  {
                    const double p_wall = p_imp[i] - sign * 0.5 * hd * n[i] * g;
                    p_face              = p_imp[i] > 0 ? std::max(0., p_wall) : 0.;
                    counts_.wall_pressure_floors += p_imp[i] > 0 && p_wall < 0;
                  }
                force += sign * frac * p_face;
              }
            u[1 + d] += h * (force / hd + n[i] * g);
          }
        // thermal energy per grain kept up to the kinetic pressure's reversible compression:
        // by the convective step's density change from its part beyond the explicit equation of
        // state (the convective step did the work of the explicit part), and by this step's
        // density change from all of it
        double T0 = thermal[i] / (1.5 * n_star[i]);
        if (T0 > 0 && n_before.size() == no)
          {
            const double phi = n_star[i] * desc.phi_per_n;
            const double dZ  = desc.model.Z(phi) - explicit_desc.model.Z(phi);
            T0 *= std::exp((2. / 3.) * dZ * std::log(n_star[i] / n_before[i]));
          }
        const double th = T0 > 0 ? 1.5 * n[i] * desc.compressed_temperature(T0, n_star[i], n[i]) :
                                   thermal[i] * n[i] / n_star[i];
        u[0]            = n[i];
        physics::State<dim> S;
        std::copy(u, u + NC, S.begin());
        u[NC - 1] = physics::kinetic_energy<dim>(S) + desc.contact.energy_density(n[i]) + th;
      }
  }

  template <int dim>
  bool ContactStep<dim>::step(Vector &U, const double h)
  {
    ++counts_.steps;
    if (!newton(h, read_state(U)))
      {
        ++counts_.failures;
        return false;
      }
    update(U, h);
    return true;
  }

  template class ContactStep<1>;
  template class ContactStep<2>;
  template class ContactStep<3>;
} // namespace granhydro::diffusion
