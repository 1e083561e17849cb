#pragma once
/**
 * @file ghost_layer.h
 * Which positions a rank needs besides its owned cells (an internal part of
 * CartesianPatch): the keys (lattice.h) of the leaves owned elsewhere, the wall ghosts
 * and, through them, the leaves their states come from.
 *
 * Box and adaptive meshes take the stencil closure: the owned cells' face neighbours,
 * the gradient stencils of those face cells, the reconstruction boxes (Chebyshev radius
 * r = G - 1) of the owned cells and of the wall ghosts among the face neighbours, and
 * the leaves the virtual cells are made of. A face neighbour owned by another rank gets
 * no box: the convective operator receives its reconstruction stages from its owner
 * (mesh/slot_exchange.h). Mesh-file lattices take
 * every position within Chebyshev distance G of an owned cell (the dilated mask); their
 * neighbour tables cover the mask only.
 */
#include "lattice.h"
#include "virtual_cells.h"

#include <vector>

namespace granhydro::mesh
{
  /// the face neighbour keys of every owned cell i along d on side s (entry
  /// e = (i dim + d) 2 + s holds keys[start[e]] .. keys[start[e + 1] - 1]): the
  /// same-level leaf or wall ghost, one coarser leaf, or the 2^(dim-1) finer leaves of a
  /// hanging face (first transverse direction fastest). One flat array: the lists are
  /// short and rebuilt at every adaptation
  struct FaceKeys
  {
    std::vector<unsigned int> start;
    std::vector<long long>    keys;
  };
  template <int dim>
  FaceKeys face_neighbour_keys(const std::vector<OwnedCell> &owned, Lattice<dim> &lattice);

  /// the keys of the stencil closure (each once, the owned cells' first, in owned order),
  /// creating the virtual cells;
  /// uniform[i]: owned cell i's box of radius r holds leaves and wall ghosts of its level only
  template <int dim>
  std::vector<long long> stencil_closure(const std::vector<OwnedCell> &owned, const FaceKeys &face_keys,
                                         Lattice<dim> &lattice, VirtualCells<dim> &virtuals, const int r,
                                         std::vector<char> &uniform);

  /// the positions within Chebyshev distance G of the owned cells (level 0), in the
  /// rank's box: the owned bounding box widened by G
  template <int dim>
  class DilatedMask
  {
  public:
    using Position = typename Lattice<dim>::Position;
    DilatedMask(const std::vector<OwnedCell> &owned, const unsigned int G);
    bool contains(const Position &p) const;
    /// the keys of the mask's positions
    std::vector<long long> keys(Lattice<dim> &lattice) const;

  private:
    std::array<int, 3> box_lower{{0, 0, 0}}, box_size{{1, 1, 1}}; ///< the box the mask covers
    std::vector<char>  mask;
  };

  /// sort needed, drop repetitions, and add the leaves the wall ghosts mirror
  template <int dim>
  void add_wall_sources(std::vector<long long> &needed, const Lattice<dim> &lattice);
} // namespace granhydro::mesh
