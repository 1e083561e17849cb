#pragma once
/**
 * @file lattice.h
 * The lattice of a CartesianPatch: one description for box, adaptive and mesh-file
 * meshes (an internal part of the patch).
 *
 * The fine lattice has N_d << m points along d (m: maximum level; 0 for mesh files).
 * Every point knows the first DoF and the level of the leaf covering it (replicated
 * on every rank), or -1 for a solid point of a mesh file. A position of level k
 * (lattice coordinates at level k) is named by a key: a leaf of level k by its fine
 * corner key * 8 + k (>= 0); a wall ghost (a position outside the lattice, or a solid
 * point) by -1 - (extended key * 8 + k), its coordinates shifted by E = 2 G + 2 (the
 * farthest position looked at lies 2 G outside). Wall ghosts are registered as they
 * are met, with the mirror of the wall mirror rule (boundary/wall_mirror.h).
 */
#include <granhydro/boundary/wall_mirror.h>
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/dofs/dof_handler.h>

#include <array>
#include <limits>
#include <map>
#include <vector>

namespace granhydro
{
  /// the key of no slot (a position that is neither a leaf of its level nor a wall ghost)
  constexpr long long no_slot_key = std::numeric_limits<long long>::min();

  /// a locally owned cell
  struct OwnedCell
  {
    dealii::types::global_dof_index first; ///< its first DoF
    long long          key;                ///< fine corner key * 8 + level
    unsigned int       active, level;      ///< active cell index, level above Domain/Cells
    std::array<int, 3> ijk;                ///< lattice coordinates at its level
  };

  /// every rank's entries, concatenated in rank order, on every rank
  std::vector<long long> all_gather(const std::vector<long long> &mine, const MPI_Comm comm);

  template <int dim>
  class Lattice
  {
  public:
    using BoundaryGhost = typename CartesianPatch<dim>::BoundaryGhost;
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
            const unsigned int max_level, const unsigned int ghost_width, const WallTable &walls,
            const bool subset);

    /**
     * The owned cells of dofh in DoF order (the cells of level k lie base_level + k
     * levels below deal.II's coarse cells); boundary_faces (if given) receives
     * (fine key * 2 dim + lattice face) * 8 + boundary id of their boundary faces.
     */
    std::vector<OwnedCell> owned_cells(const dealii::DoFHandler<dim> &dofh,
                                       const std::array<double, 3> &lo, const std::array<double, 3> &h,
                                       const unsigned int base_level,
                                       std::vector<long long> *boundary_faces) const;
    /// fill the replicated map from every rank's (leaf key, first DoF) pairs
    void cover(const std::vector<long long> &all, const unsigned long long n_global);
    /// the boundary faces of a mesh file, from every rank (see owned_cells())
    void set_boundary_faces(std::vector<long long> all);

    unsigned int max_level() const { return m; }
    bool         subset() const { return subset_; }
    /// points along d at level k
    long long n(const unsigned int k, const unsigned int d) const
    {
      return d < dim ? (long long)(N[d]) << k : 1;
    }
    long long fine_key(const Position &c) const { return c[0] + Nf[0] * (c[1] + Nf[1] * c[2]); }
    /// fine key of the lower corner of position p of level k
    long long corner_key(const unsigned int k, const Position &p) const;
    /// wrap the periodic directions of p; false if p lies outside a non-periodic side
    bool wrap(const unsigned int k, Position &p) const;
    /// the first DoF of a leaf key
    long long first_dof(const long long key) const { return cover_first[key >> 3]; }

    /// the key of the leaf or wall ghost of level k at p, or no_slot_key (the
    /// neighbourhood is refined or coarser there)
    long long same_level(const unsigned int k, Position p);
    /// the leaf covering position p of level k (any level), or no_slot_key outside
    long long covering(const unsigned int k, Position p) const;
    /// level and position of a key (a leaf or a registered wall ghost)
    void decode(const long long key, unsigned int &k, Position &p) const;
    /// gradient neighbour of key along j at offset o: same level, else a coarser leaf,
    /// else no_slot_key
    long long gradient_key(const long long key, const unsigned int j, const int o);
    /// the mirror inside the lattice of a position p of level k without a cell, with the
    /// wall reflections that map its state to p's
    Position mirror(const unsigned int k, const Position &p, BoundaryGhost &bg) const;
    /// the registered wall ghost of a key
    const WallGhost &ghost(const long long key) const { return ghosts.at(key); }
    /// boundary id of lattice face lf = 2 d + upper of the cell at p of level k, -1 if interior
    int face_id(const unsigned int k, const Position &p, const unsigned int lf) const;

  private:
    /// the fluid cell nearest to a position without a cell
    Position nearest_fluid(const unsigned int k, const Position &e) const;
    bool     fluid(const Position &e) const;

    std::array<unsigned int, 3> N;
    std::array<bool, 3>         periodic;
    unsigned int                m, G;
    WallTable                   walls;
    bool                        subset_;
    std::array<long long, 3>    Nf{{1, 1, 1}};
    long long                   E;
    std::vector<long long>      cover_first;  ///< per fine point: first DoF of the leaf, -1: solid
    std::vector<signed char>    cover_level;  ///< per fine point: level of the leaf, -1: solid
    std::vector<long long>      bfaces;       ///< sorted boundary faces of a mesh file
    std::map<long long, WallGhost> ghosts;
  };
} // namespace granhydro
