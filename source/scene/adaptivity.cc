#include <granhydro/scene/adaptivity.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void AdaptivityParameters::declare_parameters(ParameterHandler &prm)
  {
    const AdaptivityParameters defaults;
    prm.enter_subsection("Adaptivity");
    {
      prm.declare_entry("Maximum level", default_text(defaults.max_level),
                        Patterns::Integer(0, mesh::max_levels - 1),
                        "Adaptive octree refinement (p4est): cells may be refined this many "
                        "levels above Domain/Cells; 0 = uniform mesh. Box domains in 2D and 3D.");
      prm.declare_entry("Indicator", to_string(defaults.adapt_indicator),
                        selection_of<mesh::RefinementIndicator>(),
                        "Refinement indicator, from the number density n and the pressure p: "
                        "'jumps' = the largest normalised jump across the cell's faces, "
                        "|a_L - a_R| / min(a_L, a_R); 'second differences' = Loehner's "
                        "indicator |a_R - 2 a + a_L| / (|a_R - a| + |a - a_L| + 0.05 (|a_R| + "
                        "2 |a| + |a_L|)) per direction, in [0, 1]: high at shocks, contacts and "
                        "kinks, low in smooth regions (a rarefaction fan stays coarse); "
                        "'packing fraction' (granular model) = the largest jump of the packing "
                        "fraction across the cell's faces, absolute: fine at falling fronts and "
                        "pile surfaces, coarse in a uniform gas, inside a pile and in a "
                        "near-vacuum.");
      prm.declare_entry("Refine threshold", default_text(defaults.refine_threshold),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Refine a cell where the indicator exceeds this.");
      prm.declare_entry("Coarsen threshold", default_text(defaults.coarsen_threshold),
                        Patterns::Double(0, Patterns::Double::max_double_value),
                        "Coarsen a family of cells where the indicator of all of them stays below "
                        "this (must be below the refine threshold).");
      prm.declare_entry("Interval", default_text(defaults.adapt_interval), Patterns::Integer(1),
                        "Time steps between adaptations.");
      prm.declare_entry("Buffer", default_text(defaults.adapt_buffer), Patterns::Integer(0, 8),
                        "Layers of cells around a cell flagged for refinement that are refined too, "
                        "so that a shock stays in the fine region until the next adaptation.");
      prm.declare_entry("Load balance", to_string(defaults.load_balance), selection_of<LoadBalance>(),
                        "How the cells are split among the MPI ranks at each adaptation (the "
                        "results do not depend on it): 'cells' = equal numbers of cells per rank "
                        "(p4est's partition along the octree order); 'measured cost' = each "
                        "rank's cells weighted by the time it spent per cell in the convective "
                        "step since the last adaptation (waits for other ranks excluded; "
                        "1/2 to 2 times the mean), so a rank on a slower or busier core, or "
                        "with more coarse/fine interfaces, hands cells to its neighbours in the "
                        "order; 'auto' = measured cost without the implicit step, cells with it "
                        "(GMRES + block ILU of the implicit step depend on the partition to "
                        "~1e-12, and a partition that depends on timings would make two runs "
                        "of the same scene differ at that level).");
    }
    prm.leave_subsection();
  }

  void AdaptivityParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Adaptivity");
    max_level         = prm.get_integer("Maximum level");
    adapt_indicator   = get_enum<mesh::RefinementIndicator>(prm, "Adaptivity", "Indicator");
    refine_threshold  = prm.get_double("Refine threshold");
    coarsen_threshold = prm.get_double("Coarsen threshold");
    adapt_interval    = prm.get_integer("Interval");
    adapt_buffer      = prm.get_integer("Buffer");
    load_balance      = get_enum<LoadBalance>(prm, "Adaptivity", "Load balance");
    prm.leave_subsection();
  }

  void AdaptivityParameters::check(const Scene &s)
  {
    const unsigned int dim  = s.dimension;
    const bool         mesh = !s.mesh_file.empty();
    if (s.max_level > 0)
      {
        if (mesh)
          fail(s, "Adaptivity/Maximum level",
               "adaptive meshes need a box domain (no 'Domain/Mesh "
               "file'); set it to 0 for a mesh file");
        if (dim == 1)
          fail(s, "Adaptivity/Maximum level",
               "adaptive meshes need 'Dimension' 2 or 3; set it to 0 "
               "in 1D");
        if (!(s.coarsen_threshold < s.refine_threshold))
          fail(s, "Adaptivity/Coarsen threshold",
               "must be below 'Adaptivity/Refine threshold' (" + std::to_string(s.refine_threshold) + ")");
        if (s.adapt_indicator == mesh::RefinementIndicator::packing_fraction &&
            s.model != physics::Model::granular)
          fail(s, "Adaptivity/Indicator",
               "'packing fraction' needs 'Material/Model = granular'; use jumps or second differences");
        double total = 1;
        for (unsigned int d = 0; d < dim; ++d)
          total *= double(s.cells[d]) * double(1u << s.max_level);
        if (total > 2e8)
          fail(s, "Adaptivity/Maximum level",
               "the finest lattice (Domain/Cells times 2^level per "
               "direction) would have more than 2e8 points");
      }
  }
} // namespace granhydro::scene
