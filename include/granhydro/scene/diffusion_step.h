#pragma once
/**
 * @file diffusion_step.h
 * The 'Diffusion step' subsection of a scene: the integrator of the implicit
 * diffusion/source step V and its Newton-Krylov solver.
 */
#include <deal.II/base/parameter_handler.h>

#include <string>

namespace granhydro
{
  struct Scene;

  struct DiffusionStepParameters
  {
    std::string  integrator         = "cost-based";
    double       newton_tolerance   = 1e-10;
    unsigned int newton_max_iterations = 25;
    double       linear_tolerance   = 1e-12;
    bool         inexact_newton     = true; ///< Linear forcing = eisenstat-walker
    bool         reuse_matrix       = true; ///< Reuse Newton matrix
    std::string  preconditioner     = "block ilu";
    bool         full_jacobian      = false;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void parse_parameters(dealii::ParameterHandler &prm);
    /// a linear tolerance GMRES can reach
    static void check(const Scene &s);
  };
} // namespace granhydro
