#pragma once
/**
 * @file diagnostics.h
 * The words a run ends with when a step stays inadmissible: what failed and, when the
 * state sits at close packing, where and how dense it is (the usual cause: a settling
 * layer without a dense closure); and the totals and extremes of a state (the run's
 * history rows, the summary's final mass and energy, Simulation::totals()).
 */
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <mpi.h>

#include <array>
#include <optional>
#include <string>

namespace granhydro::io
{
  /// totals and extremes of a state over the mesh, in scaled units: sums over the owned
  /// cells of every rank of the cell value times its volume in units of length^dim
  /// (so n gives grains per length^(3 - dim) of the unresolved extent)
  template <int dim>
  struct StateTotals
  {
    double                  n = 0;       ///< sum n v (grains)
    std::array<double, dim> nu{};        ///< sum n u v (number momentum)
    double                  energy  = 0; ///< sum nE v (total energy, the conserved one)
    double                  kinetic = 0, thermal = 0, contact = 0; ///< its parts (physics/energy_parts.h)
    std::array<double, dim> nx{};                                  ///< sum n x v, x the cell centre [m]
    double                  max_packing_fraction = 0; ///< over the cells (meaningful for the granular gas)
    double                  min_temperature      = 0; ///< over the cells (scaled)
    double                  max_speed            = 0; ///< max |u| over the cells (scaled)
  };

  /// the totals and extremes of the state V (scaled, on the patch) with the description
  /// desc: one pass over the owned cells and two reductions (one sum, one max), the same
  /// values on every rank. length: the length unit [m] (cell volumes in its units)
  template <int dim, class Description>
  StateTotals<dim> state_totals(const mesh::CartesianPatch<dim>                          &patch,
                                const dealii::LinearAlgebra::distributed::Vector<double> &V,
                                const Description &desc, const double length, const MPI_Comm comm);

  /// empty unless the state V (scaled, on the patch) is near close packing (max phi >= 0.99
  /// phi_c): then where, how dense and how much mass sits in the near-close-packed cells
  template <int dim>
  std::string overpacking_report(const mesh::CartesianPatch<dim>                          &patch,
                                 const dealii::LinearAlgebra::distributed::Vector<double> &V,
                                 const double phi_c, const MPI_Comm comm);

  /// why a step failed after all its retries (times in s); newton_failures: those of the
  /// diffusion step, when there is one
  std::string inadmissible_step_message(const unsigned int step, const double t_si,
                                        const unsigned int max_retries, const double dt_si,
                                        const std::string                      &why,
                                        const std::optional<unsigned long long> newton_failures);

  /// the message of a run stopped at close packing: the report of overpacking_report(),
  /// the remedy, then the details of inadmissible_step_message()
  std::string overpacking_message(const double t_si, const std::string &report, const std::string &details);
} // namespace granhydro::io
