#pragma once
/**
 * @file adaptivity.h
 * The 'Adaptivity' subsection of a scene: adaptive octree refinement of box domains in
 * 2D and 3D.
 */
#include <granhydro/base/enum_names.h>
#include <granhydro/mesh/settings.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <string>

namespace granhydro::scene
{
  /// Adaptivity/Load balance
  enum class LoadBalance
  {
    automatic,
    cells,
    measured_cost
  };
  constexpr auto enum_names(LoadBalance)
  {
    return enum_table(EnumName{LoadBalance::automatic, "auto"}, EnumName{LoadBalance::cells, "cells"},
                      EnumName{LoadBalance::measured_cost, "measured cost"});
  }
  static_assert(check_enum_names(enum_names(LoadBalance{})));

  struct Scene;

  struct AdaptivityParameters
  {
    unsigned int              max_level         = 0; ///< refinement levels above Domain/Cells; 0 = uniform
    mesh::RefinementIndicator adapt_indicator   = mesh::RefinementIndicator::jumps;
    double                    refine_threshold  = 0.05; ///< refine where the indicator exceeds this
    double                    coarsen_threshold = 0.01; ///< coarsen where it stays below this
    unsigned int              adapt_interval    = 5;    ///< steps between adaptations
    unsigned int              adapt_buffer      = 2; ///< the refine flag spreads over this many cell layers
    LoadBalance               load_balance      = LoadBalance::automatic; ///< the MPI partition

    /// weigh each rank's cells by its measured cost at each adaptation ('Load balance'
    /// resolved: 'auto' = when no implicit step runs, whose GMRES + block ILU iterates
    /// depend on the partition)
    bool balance_by_measured_cost(bool implicit_step) const
    {
      return load_balance == LoadBalance::measured_cost ||
             (load_balance == LoadBalance::automatic && !implicit_step);
    }

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// a box domain in 2D/3D, ordered thresholds, a finest lattice of at most 2e8 points
    static void check(const Scene &s);
  };
} // namespace granhydro::scene
