#pragma once
/**
 * @file diagnostics.h
 * The words a run ends with when a step stays inadmissible: what failed and, when the
 * state sits at close packing, where and how dense it is (the usual cause: a settling
 * layer without a dense closure).
 */
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <mpi.h>

#include <optional>
#include <string>

namespace granhydro::io
{
  /// empty unless the state V (scaled, on the patch) is near close packing (max phi >= 0.99
  /// phi_c): then where, how dense and how much mass sits in the near-close-packed cells
  template <int dim>
  std::string overpacking_report(const CartesianPatch<dim>                              &patch,
                                 const dealii::LinearAlgebra::distributed::Vector<double> &V,
                                 const double phi_c, const MPI_Comm comm);

  /// why a step failed after all its retries (times in s); newton_failures: those of the
  /// diffusion step, when there is one
  std::string inadmissible_step_message(const unsigned int step, const double t_si,
                                        const unsigned int max_retries, const double dt_si,
                                        const std::string                     &why,
                                        const std::optional<unsigned long long> newton_failures);

  /// the message of a run stopped at close packing: the report of overpacking_report(),
  /// the remedy, then the details of inadmissible_step_message()
  std::string overpacking_message(const double t_si, const std::string &report,
                                  const std::string &details);
} // namespace granhydro::io
