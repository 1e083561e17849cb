#pragma once
/**
 * @file initial_state.h
 * The 'Initial state' subsection of a scene: FunctionParser expressions in x, y, z [m]
 * with SI values, or a checkpoint to continue from.
 */
#include <deal.II/base/parameter_handler.h>

#include <array>
#include <string>
#include <vector>

namespace granhydro::scene
{
  struct Scene;

  struct InitialStateParameters
  {
    std::string  initial_packing_fraction = "0.01";
    std::string  initial_velocity         = "0; 0; 0";
    std::string  initial_temperature      = "1e-8";
    std::string  initial_constants        = "";
    unsigned int initial_quadrature       = 3;
    std::string  initial_checkpoint       = ""; // restart/initial state from this file

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// the expressions (syntax, one value each, finite) or the checkpoint (valid, of this
    /// scene, before its end time); without a checkpoint the whole initial state sampled at
    /// the cell centres of the box, or at `mesh_centres` (a mesh file's coarse cells)
    /// mesh_cells: the coarse cells of a mesh file (0 for a box), to match a checkpoint
    static void check(const Scene &s, const std::vector<std::array<double, 3>> &mesh_centres,
                      unsigned long long mesh_cells = 0);
  };
} // namespace granhydro::scene
