#pragma once
/**
 * @file lattice.h
 * The lattice of a CartesianPatch: one description for box, adaptive and mesh-file
 * meshes (an internal part of the patch).
 *
 * The fine lattice has N_d << m points along d (m: maximum level; 0 for mesh files).
 * No rank holds the whole lattice: a rank knows the leaves (first DoF, boundary ids of
 * a mesh file's faces) of the level-0 blocks within reach of its own leaves, fetched
 * from a directory that is distributed over the ranks by level-0 block (distribute()).
 * A point of a fetched block is covered by one leaf, or solid (a mesh file); looking at
 * a point of a block that was not fetched is an internal error and throws. A position of level k
 * (lattice coordinates at level k) is named by a key: a leaf of level k by its fine
 * corner key * 8 + k (>= 0); a wall ghost (a position outside the lattice, or a solid
 * point) by -1 - (extended key * 8 + k), its coordinates shifted by E = 2 G + 2 (the
 * farthest position looked at lies 2 G outside). Wall ghosts are registered as they
 * are met, with the mirror of the wall mirror rule (boundary/wall_mirror.h).
 */
#include <granhydro/boundary/boundary_ghost.h>
#include <granhydro/boundary/wall_mirror.h>

#include <deal.II/dofs/dof_handler.h>

#include "flat_key_map.h"

#include <array>
#include <limits>
#include <map>
#include <vector>

namespace granhydro::mesh
{
  /// the key of no slot (a position that is neither a leaf of its level nor a wall ghost)
  constexpr long long no_slot_key = std::numeric_limits<long long>::min();

  /// a locally owned cell
  struct OwnedCell
  {
    dealii::types::global_dof_index first;         ///< its first DoF
    long long                       key;           ///< fine corner key * 8 + level
    unsigned int                    active, level; ///< active cell index, level above Domain/Cells
    std::array<int, 3>              ijk;           ///< lattice coordinates at its level
    int faces = 0; ///< a mesh file's boundary ids: 3 bits per lattice face 2 d + upper, id + 1 (0: none)
  };

  template <int dim>
  class Lattice
  {
  public:
    using BoundaryGhost = boundary::BoundaryGhost;
    using Position      = std::array<long long, 3>;
    /// a wall ghost: its reflections, the leaf whose state it takes, its position
    struct WallGhost
    {
      BoundaryGhost      bg;
      long long          source_key;
      std::array<int, 3> pos;
      unsigned int       level;
    };

    /// N: level-0 points per direction; subset: a mesh file's lattice (solid points,
    /// boundary ids from the mesh) rather than a box (colorized boundary ids)
    Lattice(const std::array<unsigned int, 3> &N, const std::array<bool, 3> &periodic,
            const unsigned int max_level, const unsigned int ghost_width, const boundary::WallTable &walls,
            const bool subset);

    /**
     * The owned cells of dofh in DoF order (the cells of level k lie base_level + k
     * levels below deal.II's coarse cells), with a mesh file's boundary ids (faces).
     */
    std::vector<OwnedCell> owned_cells(const dealii::DoFHandler<dim> &dofh, const std::array<double, 3> &lo,
                                       const std::array<double, 3> &h, const unsigned int base_level) const;
    /**
     * Learn the leaves near the owned ones. The level-0 blocks are dealt to the ranks in
     * contiguous ranges of their key (the directory); every rank sends its leaves to
     * their blocks' directory ranks, then asks them for the blocks within reach(): a
     * leaf of level k reaches reach() cells of its level in every direction (Chebyshev),
     * that is ceil(reach() / 2^k) blocks. Two all-to-all exchanges (three messages);
     * memory per rank: the local leaves, their halo and the rank's share of the
     * directory, nothing of the size of the whole lattice. Checks that the leaves tile
     * every block of a box (a mesh file: at most one leaf per block) and that there are
     * n_global of them.
     */
    void distribute(const std::vector<OwnedCell> &owned, const unsigned long long n_global,
                    const MPI_Comm comm);
    /// how far (cells of its level) the tables of a leaf look: stencil closure, the
    /// gradients and prolongations of virtual cells, wall mirrors (2 G + 4); a mesh file
    /// adds the search for the nearest fluid cell, ceil(sqrt(dim) G) (G + 2 ceil(sqrt(dim) G) + 2)
    unsigned int reach() const;

    unsigned int max_level() const { return max_level_; }
    bool         subset() const { return subset_; }
    /// points along d at level k
    long long n(const unsigned int k, const unsigned int d) const
    {
      return d < dim ? (long long)(cells_[d]) << k : 1;
    }
    long long fine_key(const Position &c) const
    {
      return c[0] + fine_cells_[0] * (c[1] + fine_cells_[1] * c[2]);
    }
    /// the fine lattice coordinates of fine key fk (the inverse of fine_key())
    Position fine_position(const long long fk) const
    {
      return {{fk % fine_cells_[0], (fk / fine_cells_[0]) % fine_cells_[1],
               fk / (fine_cells_[0] * fine_cells_[1])}};
    }
    /// fine key of the lower corner of position p of level k
    long long corner_key(const unsigned int k, const Position &p) const;
    /// wrap the periodic directions of p; false if p lies outside a non-periodic side
    bool wrap(const unsigned int k, Position &p) const;
    /// a non-negative number naming position p of level k (lattice coordinates at level
    /// k, periodic directions wrapped) up to E = 2 G + 2 outside the lattice, distinct
    /// for distinct (k, p); -1 farther out. A wall ghost's key is -1 - position_key()
    long long position_key(const unsigned int k, const Position &p) const
    {
      long long ek = 0;
      for (int d = dim - 1; d >= 0; --d)
        {
          const long long e = p[d] + margin_, ne = n(k, d) + 2 * margin_;
          if (e < 0 || e >= ne)
            return -1;
          ek = ek * ne + e;
        }
      return ek * 8 + k;
    }
    /// the first DoF of a leaf key
    long long first_dof(const long long key) const { return leaf(key).first; }

    /// the key of the leaf or wall ghost of level k at p, or no_slot_key (the
    /// neighbourhood is refined or coarser there). A position whose leaf (or, for a wall
    /// ghost, whose mirror's leaf) lies beyond the fetched blocks throws, unless `missing`
    /// is given: then *missing is set and no_slot_key returned
    long long same_level(const unsigned int k, Position p, bool *missing = nullptr);
    /// the leaf covering position p of level k (any level), or no_slot_key outside
    /// (`missing`: as for same_level())
    long long covering(const unsigned int k, Position p, bool *missing = nullptr) const;
    /// level and position of a key (a leaf or a registered wall ghost)
    void decode(const long long key, unsigned int &k, Position &p) const;
    /// gradient neighbour of key along j at offset o: same level, else a coarser leaf,
    /// else no_slot_key
    long long gradient_key(const long long key, const unsigned int j, const int o, bool *missing = nullptr);
    /// the mirror inside the lattice of a position p of level k without a cell, with the
    /// wall reflections that map its state to p's
    Position mirror(const unsigned int k, const Position &p, BoundaryGhost &bg) const;
    /// the registered wall ghost of a key
    const WallGhost &ghost(const long long key) const { return ghosts.at(key); }
    /// boundary id of lattice face lf = 2 d + upper of the cell at p of level k, -1 if interior
    int face_id(const unsigned int k, const Position &p, const unsigned int lf) const;

  private:
    struct Leaf
    {
      long long first; ///< first DoF
      int       faces; ///< see OwnedCell::faces
    };
    /// the fluid cell nearest to a position without a cell
    Position nearest_fluid(const unsigned int k, const Position &e) const;
    bool     fluid(const Position &e) const;
    /// the level of the leaf covering the position of level k whose fine corner key is
    /// fk (inside the lattice), -1: solid; throws if its block was not fetched
    /// (with `missing`: sets it instead of throwing, and returns -2)
    int level_from(const long long fk, const unsigned int k, bool *missing = nullptr) const;
    /// the window's entry of fine key fk (throws outside the fetched blocks; with
    /// `missing`: sets it and returns -2)
    int window_at(const long long fk, bool *missing = nullptr) const;
    /// the same for fine lattice coordinates c
    int       window_at_point(const Position &c, bool *missing = nullptr) const;
    long long window_index(const Position &c) const;
    /// the leaf of a key (throws if unknown)
    const Leaf &leaf(const long long key) const;
    /// the level-0 block of fine key fk
    long long block_of(const long long fk) const;

    // the steps of distribute() (lattice_distribute.cc)
    /// the rank that holds level-0 block b in the directory (blocks dealt in order)
    int directory_rank(const long long b, const int P) const;
    /// this rank's part of the directory: the records (block, key, first DoF, faces) of
    /// the leaves of its blocks, sorted by (block, key), checked to tile the lattice
    std::vector<long long> directory(const std::vector<OwnedCell> &owned, const unsigned long long n_global,
                                     const MPI_Comm comm) const;
    /// the blocks within reach of the owned leaves (into `blocks`), as requests to
    /// their directory ranks
    std::vector<std::vector<long long>> blocks_within_reach(const std::vector<OwnedCell> &owned,
                                                            const MPI_Comm                comm);
    /// the directory's answers to the requests: (key, first DoF, faces) of every leaf of
    /// the requested blocks (dir and requests are released)
    std::vector<long long> fetch_records(std::vector<long long>              &dir,
                                         std::vector<std::vector<long long>> &requests,
                                         const MPI_Comm                       comm) const;
    /// the fetched leaves and the refined positions above them (first DoF -1)
    void insert_leaves(const std::vector<long long> &got);
    /// the dense window of levels over the fetched blocks, when it is small
    void fill_window(const std::vector<long long> &got);

    std::array<unsigned int, 3> cells_; ///< N: level-0 points per direction
    std::array<bool, 3>         periodic;
    unsigned int                max_level_, ghost_width_; ///< m and G
    boundary::WallTable         walls;
    bool                        subset_;
    std::array<long long, 3>    fine_cells_{{1, 1, 1}}; ///< fine-lattice points per direction, N << m
    long long                   margin_;                ///< E = 2 G + 2: how far outside positions have keys
    FlatKeyMap<Leaf> leaves; ///< the leaves of the fetched blocks by key, and their ancestors (first -1)
    FlatKeyMap<char> blocks; ///< the fetched level-0 blocks
    /// the leaf level per fine point over the bounding box of the fetched blocks (-1:
    /// solid, -2: not fetched), if that box is at most 8 x the leaves; empty otherwise
    std::vector<signed char>       window_level;
    Position                       window_lo{{0, 0, 0}}, window_n{{1, 1, 1}};
    std::map<long long, WallGhost> ghosts;
  };
} // namespace granhydro::mesh
