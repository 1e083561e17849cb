#pragma once
/**
 * @file virtual_cells.h
 * Virtual cells of an adaptive CartesianPatch (an internal part of the patch).
 *
 * Every position of the reconstruction box of a face cell that is not a leaf of the
 * cell's level gets a virtual cell: the volume average of the finer leaves inside it
 * (restriction) or the linear prolongation of the coarser leaf that contains it (its
 * value plus central-difference slopes); outside a wall, the mirror of such a
 * position. WENO then runs on a uniform (partly virtual) neighbourhood everywhere.
 */
#include "lattice.h"

#include <array>
#include <utility>
#include <vector>

namespace granhydro::mesh
{
  template <int dim>
  class VirtualCells
  {
  public:
    using Position = typename Lattice<dim>::Position;
    struct Virtual
    {
      unsigned int                              level;
      Position                                  pos;
      std::vector<std::pair<long long, double>> sources; ///< (leaf key, weight), inside
      bool                                      ghost = false;
      typename Lattice<dim>::BoundaryGhost      bg;         ///< outside: reflections of the mirror
      unsigned int                              mirror = 0; ///< outside: index of the mirror
    };

    explicit VirtualCells(Lattice<dim> &lattice)
      : lattice(lattice)
    {}

    /// the virtual cell at position q of level k (created with its mirror if new)
    unsigned int add(const unsigned int k, const Position &q);
    /// index of the virtual cell at q of level k, or -1
    int find(const unsigned int k, const Position &q) const;
    /// the virtual cells in the order of creation
    const std::vector<Virtual> &cells() const { return virtuals; }
    void                        reserve(const std::size_t n)
    {
      index.reserve(n);
      virtuals.reserve(n);
    }

  private:
    /// restriction or prolongation weights of position q of level k inside the lattice,
    /// sorted by leaf key
    std::vector<std::pair<long long, double>> region_sources(const unsigned int k, const Position &q);
    /// the index key of q of level k (periodic directions wrapped; Lattice::position_key)
    long long key_of(const unsigned int k, const Position &q, bool &inside, Position &w) const;

    Lattice<dim>            &lattice;
    std::vector<Virtual>     virtuals;
    FlatKeyMap<unsigned int> index;
  };
} // namespace granhydro::mesh
