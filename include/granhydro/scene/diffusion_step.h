#pragma once
/**
 * @file diffusion_step.h
 * The 'Diffusion step' subsection of a scene: the integrator of the implicit
 * diffusion/source step V and its Newton-Krylov solver.
 */
#include <granhydro/base/enum_names.h>
#include <granhydro/diffusion/butcher_tables.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <string>

namespace granhydro::scene
{
  /// Diffusion step/Preconditioner: the Newton matrix and the preconditioner of GMRES
  enum class Preconditioner
  {
    block_ilu, ///< granhydro's block-sparse matrix with block ILU(0)
    ilu,       ///< Trilinos Epetra matrix with Ifpack ILU(0)
    amg        ///< Trilinos Epetra matrix with ML
  };
  constexpr auto enum_names(Preconditioner)
  {
    return enum_table(EnumName{Preconditioner::block_ilu, "block ilu"}, EnumName{Preconditioner::ilu, "ilu"},
                      EnumName{Preconditioner::amg, "amg"});
  }
  static_assert(check_enum_names(enum_names(Preconditioner{})));

  struct Scene;

  struct DiffusionStepParameters
  {
    diffusion::ImplicitMethod integrator            = diffusion::ImplicitMethod::cost_based;
    double                    newton_tolerance      = 1e-10;
    unsigned int              newton_max_iterations = 25;
    double                    linear_tolerance      = 1e-12;
    bool                      inexact_newton        = true; ///< Linear forcing = eisenstat-walker
    bool                      reuse_matrix          = true; ///< Reuse Newton matrix
    Preconditioner            preconditioner        = Preconditioner::block_ilu;
    bool                      full_jacobian         = false;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// a linear tolerance GMRES can reach
    static void check(const Scene &s);
  };
} // namespace granhydro::scene
