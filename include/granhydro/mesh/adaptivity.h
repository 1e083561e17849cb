#pragma once
/**
 * @file adaptivity.h
 * Where an adaptive mesh refines and coarsens: the refinement indicator (the largest
 * normalised jump of two fields across a cell's faces, or Loehner's second differences),
 * the buffer of refined cells around each marked one, and the coarsening test. The fields
 * are given per slot (owned and ghost); the patch adapts itself to the flags
 * (CartesianPatch::adapt()).
 */
#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/mesh/settings.h>

#include <vector>

namespace granhydro::mesh
{
  /**
   * The flags CartesianPatch::adapt() takes, per owned slot (+1 refine, -1 coarsen, 0
   * keep), from two fields a and b given on every slot (owned and ghost; the run uses the
   * number density and the pressure): a cell is refined where its indicator exceeds the
   * refine threshold or a refined cell lies within `buffer` face neighbours, and coarsened
   * where the indicator stays below the coarsen threshold (never when `initial`: the
   * initial refinement only refines). Collective (the buffer exchanges ghost marks).
   */
  template <int dim>
  std::vector<signed char> refinement_flags(const CartesianPatch<dim> &patch, const std::vector<double> &a,
                                            const std::vector<double>         &b,
                                            const RefinementIndicatorSettings &settings, const bool initial);
} // namespace granhydro::mesh
