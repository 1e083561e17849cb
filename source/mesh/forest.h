#pragma once
/**
 * @file forest.h
 * The adaptive octree of a box scene, kept in p4est directly (an internal part of
 * CartesianPatch: source/mesh, not installed).
 *
 * deal.II's parallel::distributed::Triangulation stores a p4est forest and,
 * beside it, a full deal.II mesh (vertices, lines, faces, cells on every
 * level) that it rebuilds after each refinement. The solver never looks at
 * that mesh: its tables come from the leaves' lattice positions. Rebuilding
 * it cost about 0.13 s per adaptation on 32^3 cells (as much as 1.5 time
 * steps of the adaptive blast), so the adaptive path keeps its own copy of
 * the forest and refines, coarsens, balances and partitions it with p4est
 * alone. The deal.II mesh is brought up to date only when something asks for
 * it (VTU output): Triangulation::load(forest) copies the forest over.
 *
 * The operations are those deal.II performs (refine and coarsen one level,
 * 2:1 balance across faces, edges and corners, partition keeping families
 * together), so the leaves, their order and (unweighted) the partition are the
 * ones the deal.II path gives; the values are moved with the finite element's own
 * interpolation matrices (see CartesianPatch::adapt()).
 */
#include <deal.II/distributed/p4est_wrappers.h>
#include <deal.II/distributed/tria.h>

#include <array>
#include <functional>
#include <vector>

namespace granhydro::mesh
{
  /// p4est's forest type of dimension dim (none in 1D)
  template <int dim>
  struct P4estForest
  {
    using type = typename dealii::internal::p4est::types<dim>::forest;
  };
  template <>
  struct P4estForest<1>
  {
    using type = void;
  };

  /// what p4est's callbacks read through the forest's user pointer
  struct ForestUserData
  {
    unsigned int n_values;    ///< doubles of payload per leaf (the refine/coarsen flag follows them)
    int          leaf_weight; ///< partition weight of each local leaf
  };

  template <int dim>
  class Forest
  {
  public:
    using forest_t = typename P4estForest<dim>::type;

    /// a local leaf: level above the mesh's base level, lattice index at that level
    struct Leaf
    {
      unsigned int       level;
      std::array<int, 3> ijk;
    };

    /// where a leaf after adapt() takes its values from (indices into the leaves before)
    struct Source
    {
      enum Kind
      {
        same,         ///< the leaf was there before: leaf `first`
        from_parent,  ///< child `child` (z-order) of the former leaf `first`
        from_children ///< parent of the former leaves first .. first + 2^dim - 1 (z-order)
      } kind;
      unsigned int first, child;
    };

    /// a copy of the forest of `tria` (which must outlive this object: the connectivity is
    /// shared); base_level: tria's level of the scene's Domain/Cells, lower and h: the box's
    /// lower corner and the edges of those cells; n_values: doubles carried per leaf
    Forest(const dealii::parallel::distributed::Triangulation<dim> &tria, unsigned int base_level,
           const std::array<double, 3> &lower, const std::array<double, 3> &h, unsigned int n_values);
    ~Forest();
    Forest(const Forest &)            = delete;
    Forest &operator=(const Forest &) = delete;

    /// the local leaves in the forest's order (trees in order, z-order within a tree)
    std::vector<Leaf> leaves() const;
    /// index of this rank's first leaf in the global order, and the global count
    unsigned long long first_global() const;
    unsigned long long n_global() const;
    const forest_t    *get() const { return forest; }

    /**
     * One adaptation: flags per local leaf (+1 refine, -1 coarsen, 0 keep); refine, coarsen
     * whole families whose members are all flagged, balance 2:1 (faces, edges, corners),
     * call fill(source, values) for each new local leaf (n_values doubles to write),
     * partition (families kept on one rank) and return the values of the leaves this rank
     * owns afterwards (n_values each, in order). refined/coarsened: local counts of new
     * families and of the leaves merged into parents. leaf_weight: 0 on every rank = equal
     * numbers of leaves per rank (p4est's partition, deal.II's); otherwise (> 0 on every
     * rank) each of this rank's leaves weighs leaf_weight and the ranks get equal sums of
     * weights, so a rank with heavier leaves hands some to its neighbours in the order.
     *
     * balanced (optional, called on every rank): after refining and coarsening, and
     * given each former local leaf's change of level (+1 refined, -1 merged into its
     * parent, 0 kept), true if the leaves are 2:1 balanced already (the same answer on
     * every rank). p4est's balance is then skipped: it would change nothing, and it
     * costs as much on 2 ranks as on 1. The answer may err only toward false.
     */
    std::vector<double> adapt(const std::vector<signed char>                      &flags,
                              const std::function<void(const Source &, double *)> &fill,
                              unsigned long long &refined, unsigned long long &coarsened, int leaf_weight = 0,
                              const std::function<bool(const std::vector<signed char> &)> &balanced = {});
    /// adaptations in which p4est's balance ran, and in which it was skipped (balanced)
    unsigned int balances_run() const { return n_balance_run; }
    unsigned int balances_skipped() const { return n_balance_skipped; }

  private:
    forest_t      *forest = nullptr;
    unsigned int   base_level;
    ForestUserData user{0, 1};
    unsigned int   n_balance_run = 0, n_balance_skipped = 0;
    /// lattice index of each tree's lower corner in units of base-level cells
    std::vector<std::array<int, 3>> tree_origin;
  };
} // namespace granhydro::mesh
