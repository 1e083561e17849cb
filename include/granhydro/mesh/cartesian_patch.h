#pragma once
/**
 * @file cartesian_patch.h
 * The mesh of a scene and the stencil tables of its uniform Cartesian patch.
 *
 * deal.II/p4est own the mesh, the partition and the DoF numbering (DG0
 * FESystem with dim+2 components: one value per cell and conserved
 * variable); on adaptive boxes a p4est forest of its own (source/mesh/forest.h)
 * does, and deal.II's mesh follows it only for output. deal.II gives one ghost layer; WENO5 with transverse Gauss-point
 * reconstruction reaches the cells within Chebyshev distance r (r = stencil
 * half width) of an owned cell, and the face neighbours' gradient stencils
 * reach one further (the reconstruction stages of a face neighbour owned by
 * another rank come from that rank: source/mesh/ghost_layer.h, mesh/slot_exchange.h). This
 * class builds that wider ghost set from the cells' lattice indices, a
 * Utilities::MPI::Partitioner for the state vector with those ghosts, and
 * flat neighbour tables (no cell iterators in hot loops). Walls are represented by boundary-ghost slots whose state is a
 * mirror (slip wall) or a copy (outflow) of an interior cell.
 *
 * Slot numbering: [0, n_owned) owned cells in DoF order, then [n_owned,
 * n_owned + n_mpi_ghost) cells owned by other ranks in DoF order, then
 * boundary ghosts. Slot s's conserved variables are entries s*(dim+2)+c of
 * the local storage of a vector built on partitioner() (owned + ghosts), so
 * the vector's memory is the beginning of a slot-indexed array.
 *
 * Lattice subsets (mesh files, mesh/mesh_file.h): the lattice is the bounding
 * box of the mesh divided into cells of the fine cell size; lattice points
 * without a cell are solid. The ghost of a solid point (or of a point outside
 * the lattice) mirrors the nearest fluid cell f across f's faces towards it,
 * one reflection per direction with the wall type of that face's boundary id;
 * for a box this is exactly the composed reflection at faces, edges, corners.
 *
 * Adaptive boxes (scene 'Adaptivity/Maximum level' m > 0): the cells of the
 * p4est octree have levels 0..m above the scene's 'Domain/Cells'. Every slot
 * has a level k and lattice coordinates at its own level; neighbor(s, d, o)
 * is the neighbour at the same level: a leaf, a wall ghost, or a *virtual
 * cell* where the neighbourhood is refined (volume average of the leaves
 * inside: restriction) or coarser (the coarse leaf's value plus its
 * central-difference slopes at the virtual cell's centre: linear prolongation), so WENO runs on a uniform neighbourhood everywhere (the
 * approach of AMReX, Athena++, ForestClaw). uniform(s) is true when s's whole
 * (r)-box (Chebyshev radius r = ghost_width - 1) consists of leaves or wall
 * ghosts of its level (output field 'uniform_stencil').
 * Faces are explicit lists per direction (faces(d)); a face between a coarse
 * and a fine cell is a fine sub-face, and the coarse cell takes 1/2^(dim-1)
 * of its flux per sub-face (conservative to round-off). cell_faces(d, s)
 * lists an owned cell's faces in a fixed geometric order, so a cell's update
 * does not depend on the partition. gradient_neighbor(s, j, side) is the face
 * neighbour used for cell gradients: the same-level cell, else a coarser one
 * (never a finer one; then the gradient is one-sided); the rows exist for the
 * owned cells and the cells on their faces (-1 elsewhere), the only ones read.
 *
 * The class is a facade: its parts live beside its sources in source/mesh and are not
 * installed (triangulation_builder.h: the mesh and its LatticeGeometry; lattice.h: the
 * leaves a rank knows and the wall ghosts; ghost_layer.h and virtual_cells.h: the
 * positions a rank needs; stencil_tables.h: the table builders; forest.h: the adaptive
 * octree). What they build is plain data held here (mesh/patch_tables.h: SlotTables), so
 * the accessors the operators call in their hot loops (neighbor(), faces(),
 * cell_faces(), gradient_neighbor(), ...) are inline reads of those vectors.
 *
 * Limits: adaptive meshes need a box domain (no mesh file) and 2 or 3
 * dimensions. No rank holds the whole fine lattice: the leaves a rank's
 * tables reach come from a directory distributed by level-0 block (source/mesh/lattice.h).
 */
#include <granhydro/boundary/boundary_ghost.h>
#include <granhydro/boundary/wall_settings.h>
#include <granhydro/mesh/patch_tables.h>
#include <granhydro/mesh/settings.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <array>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace granhydro::mesh
{
  // parts of the patch (source/mesh, not installed), held by pointer or made on demand
  template <int dim>
  class Lattice;
  template <int dim>
  class Forest;

  /// the work arrays the operators share (CartesianPatch::scratch()). A convective step and
  /// a diffusion step run one after the other and neither keeps values in them from one
  /// call to the next, so each buffer serves one array of each: the memory of a buffer is
  /// the larger of its two uses, not their sum
  enum class Scratch : unsigned int
  {
    slot_array, ///< the gathered slot array W (both)
    /// convection: reconstruction stages A, B, C; diffusion: face fluxes normal to 0, 1, 2;
    /// stage_c also the implicit contact step's per-cell values (between the two steps)
    stage_a,
    stage_b,
    stage_c,
    /// convection: face fluxes normal to 0, 1, 2; diffusion: their frictional parts
    flux_0,
    flux_1,
    flux_2,
    /// owned values (n_owned (dim + 2)): the SSP-RK3 step's U0, L(u) and candidate; the
    /// RKL2 step's f(Y0), f(Y_j-1) and Y_j-2
    owned_0,
    owned_1,
    owned_2,
    n_buffers
  };

  template <int dim>
  class CartesianPatch
  {
  public:
    static constexpr unsigned int n_components = dim + 2;

    /// a boundary-ghost slot (boundary/boundary_ghost.h)
    using BoundaryGhost = boundary::BoundaryGhost;

    CartesianPatch(const MPI_Comm comm);
    ~CartesianPatch();

    /// build mesh, DoFs and tables; ghost_width = r + 1 for a stencil half width r
    void build(const MeshSettings &settings, const unsigned int ghost_width);

    /// a face normal to direction d between slots l (low side) and r (mesh/patch_tables.h)
    using Face = PatchFace;
    /// a face of an owned cell: index into faces(d), and whether the cell is the face's
    /// low side (mesh/patch_tables.h)
    using CellFace = PatchCellFace;
    const std::vector<Face> &faces(const unsigned int d) const { return tables_.faces[d]; }
    /// faces of owned slot s normal to d: lower ones first, then upper ones, each in
    /// a fixed geometric order
    std::pair<const CellFace *, const CellFace *> cell_faces(const unsigned int d, const unsigned int s) const
    {
      const auto &start = tables_.cell_face_start[d];
      return {tables_.cell_faces[d].data() + start[s], tables_.cell_faces[d].data() + start[s + 1]};
    }
    /// the slot on the other side of an owned cell's face cf normal to d
    unsigned int across(const unsigned int d, const CellFace &cf) const
    {
      const Face &f = tables_.faces[d][cf.face];
      return cf.upper ? f.r : f.l;
    }
    /// the fluxes F (NC values per face of faces(d)) through owned slot s's faces normal to
    /// d, each times its share of the cell's face, summed per side in the fixed order of
    /// cell_faces(d, s) (partition independent); lower and upper start at 0
    template <unsigned int NC>
    void sum_face_fluxes(const unsigned int d, const unsigned int s, const double *F, double (&lower)[NC],
                         double (&upper)[NC]) const
    {
      const auto [b, e] = cell_faces(d, s);
      for (auto cf = b; cf != e; ++cf)
        {
          const Face   &f    = tables_.faces[d][cf->face];
          const double *Ff   = F + std::size_t(cf->face) * NC;
          double       *sum  = cf->upper ? upper : lower;
          const double  frac = cf->upper ? f.frac_l : f.frac_r;
          for (unsigned int c = 0; c < NC; ++c)
            sum[c] += frac * Ff[c];
        }
    }
    /// neighbour used for the gradient of slot s along j (side 0: lower, 1: upper):
    /// same level, else coarser, else -1; offset: its centre minus s's centre along j [m].
    /// Only for owned cells and the cells on their faces (other slots: -1)
    int gradient_neighbor(const unsigned int s, const unsigned int j, const unsigned int side) const
    {
      return tables_.gradient_neighbors[(std::size_t(s) * dim + j) * 2 + side];
    }
    double gradient_offset(const unsigned int s, const unsigned int j, const unsigned int side) const
    {
      return tables_.gradient_offsets[(std::size_t(s) * dim + j) * 2 + side];
    }
    /// true if the slot's reconstruction stencil box is complete at its own level
    bool uniform(const unsigned int s) const { return tables_.uniform[s] != 0; }
    /// refinement level of a slot above the scene's Domain/Cells (0 on uniform meshes)
    unsigned int level(const unsigned int s) const { return tables_.levels[s]; }
    unsigned int max_level() const { return max_level_; }
    /// edge of slot s along d [m], and its volume [m^dim]
    double cell_size(const unsigned int s, const unsigned int d) const
    {
      return level_cell_size(tables_.levels[s], d);
    }
    /// edge along d [m] of a cell of refinement level k (< max_levels)
    double level_cell_size(const unsigned int k, const unsigned int d) const
    {
      return geometry_.cell_size[d] / double(1u << k);
    }
    double cell_volume(const unsigned int s) const;
    /// first fine-lattice index along d covered by slot s and how many it covers
    /// (the fine lattice has cells(d) << max_level() points along d)
    int fine_begin(const unsigned int s, const unsigned int d) const
    {
      return tables_.positions[s][d] << (max_level_ - tables_.levels[s]);
    }
    unsigned int fine_span(const unsigned int s) const { return 1u << (max_level_ - tables_.levels[s]); }

    /**
     * Adapt the mesh: flags per owned slot (+1 refine, -1 coarsen, 0 keep; p4est adds
     * refinements for 2:1 balance and coarsens only whole families), transfer U
     * (a parent takes the mean of its children; children take the parent's average, or,
     * if `admissible` is given, the parent's value plus its minmod-limited slopes times
     * their offsets, when all 2^dim siblings' states pass `admissible`: conservative
     * either way), repartition and rebuild all tables. U is reinitialised on the new
     * partitioner(). Returns true if the mesh changed. leaf_weight: 0 (on every rank) =
     * equal numbers of cells per rank; > 0 (on every rank) = the weight of each of this
     * rank's cells in the partition (Forest::adapt()). The results do not depend on it.
     */
    bool adapt(const std::vector<signed char> &flags, dealii::LinearAlgebra::distributed::Vector<double> &U,
               const std::function<bool(const double *)> &admissible = {}, int leaf_weight = 0);
    /// cells refined and coarsened (global) by the last adapt(), after 2:1 balance
    unsigned long long last_refined() const { return last_refined_; }
    unsigned long long last_coarsened() const { return last_coarsened_; }

    /**
     * Refine the mesh so that it has the leaves in `cells` (fine-lattice corner key * 8 +
     * level, see leaf_key()), e.g. from a checkpoint; keys not matching a leaf are ignored.
     */
    void refine_to(const std::vector<long long> &cells);
    /// adaptations so far in which p4est's 2:1 balance ran, and in which it was skipped
    /// because the changes of level provably kept the balance (adaptive boxes; else 0, 0)
    std::pair<unsigned int, unsigned int> balance_counts() const;
    /// fine-lattice corner key * 8 + level of owned slot s: names a leaf independently of
    /// the partition and numbering
    long long leaf_key(const unsigned int s) const;

    /// deal.II's mesh and DoFs of the current leaves (on adaptive meshes brought up to date
    /// from the forest on demand: see sync_dealii())
    const dealii::parallel::TriangulationBase<dim> &triangulation() const
    {
      sync_dealii();
      return *triangulation_;
    }
    const dealii::DoFHandler<dim> &dof_handler() const
    {
      sync_dealii();
      return *dof_handler_;
    }
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner() const { return partitioner_; }
    MPI_Comm                                                   communicator() const { return communicator_; }

    unsigned int       n_owned() const { return tables_.n_owned; }
    unsigned int       n_mpi_ghosts() const { return tables_.n_mpi_ghosts; }
    unsigned int       n_slots() const { return tables_.positions.size(); }
    unsigned int       ghost_width() const { return tables_.ghost_width; }
    unsigned long long n_global_cells() const { return n_global_; }

    /// neighbour slot of s at offset o (|o| <= ghost_width) along d, or -1
    int neighbor(const unsigned int s, const unsigned int d, const int o) const
    {
      const unsigned int G = tables_.ghost_width;
      return tables_.neighbors[(std::size_t(s) * dim + d) * (2 * G + 1) + (o + int(G))];
    }

    /// true for the slots of real cells (owned or MPI ghost), false for boundary ghosts
    bool is_cell(const unsigned int s) const { return s < tables_.n_owned + tables_.n_mpi_ghosts; }

    /// boundary id of the face on side f = 2 d + upper of the real-cell slot s (lattice
    /// directions, not deal.II's face numbering), or -1 for an interior face
    int face_boundary_id(const unsigned int s, const unsigned int f) const
    {
      return tables_.face_boundary_ids[std::size_t(s) * 2 * dim + f];
    }

    /// the boundary condition of boundary id i
    boundary::BoundaryType boundary_type(const unsigned int i) const { return walls_.settings[i].type; }

    /// true if the face between slots l (low side) and r along d is a wall (slip or
    /// no-slip): one real cell, one boundary ghost, and the cell's face has a wall id
    bool wall_face(const unsigned int l, const unsigned int r, const unsigned int d) const
    {
      return wall_id(l, r, d) >= 0;
    }
    /// the boundary id of the wall face between slots l (low side) and r along d, -1 if
    /// it is not a wall face
    int wall_id(const unsigned int l, const unsigned int r, const unsigned int d) const;
    /// the settings of the boundary with id i (wall velocities in [m/s])
    const boundary::WallSettings &wall_settings(const unsigned int i) const { return walls_.settings[i]; }

    /// extended lattice coordinates of a slot (may lie outside [0,N) for boundary ghosts)
    const std::array<int, 3>         &lattice(const unsigned int s) const { return tables_.positions[s]; }
    const std::vector<BoundaryGhost> &boundary_ghosts() const { return tables_.boundary_ghosts; }

    /// edge of a level-0 cell along d [m] (the scene's Domain/Cells)
    double cell_size(const unsigned int d) const { return geometry_.cell_size[d]; }
    /// whether direction d is periodic
    bool periodic(const unsigned int d) const { return geometry_.periodic[d]; }
    /// lattice points per direction (the box, or the bounding box of a mesh file; a mesh
    /// file may leave some of them without a cell)
    unsigned int       cells(const unsigned int d) const { return geometry_.cells[d]; }
    double             lower(const unsigned int d) const { return geometry_.lower[d]; }
    dealii::Point<dim> center(const unsigned int s) const;

    /// slot array from a state vector on partitioner(): update ghosts, copy owned and
    /// MPI-ghost values, fill boundary ghosts (mirror or copy)
    void gather(const dealii::LinearAlgebra::distributed::Vector<double> &U, std::vector<double> &W) const;
    /// the same into W with room for n_slots() (dim + 2) values
    void gather(const dealii::LinearAlgebra::distributed::Vector<double> &U, double *W) const;

    /// shared work array b (Scratch) with room for at least n doubles: what its last user
    /// left in it, never zeroed (a user writes every value it reads). A larger n than
    /// before moves it, so a user asks for it at the start of each call and keeps no
    /// pointer beyond the call
    double *scratch(const Scratch b, const std::size_t n) const
    {
      auto &buffer = scratch_[static_cast<unsigned int>(b)];
      if (buffer.second < n)
        {
          buffer.first.reset(); // the old one goes first: never both at once
          buffer.first.reset(new double[n]);
          buffer.second = n;
        }
      return buffer.first.get();
    }

    /// active_cell_index of each owned slot (for output only)
    const std::vector<unsigned int> &owned_active_cell_index() const
    {
      sync_dealii();
      return active_index_;
    }

  private:
    /// DoFs, slots and all tables of the current mesh: ONE builder for box, adaptive and
    /// mesh-file lattices (the table builders: source/mesh/stencil_tables.h)
    void rebuild();
    /// the lattice of this patch's box or mesh file, nothing fetched yet (Lattice::distribute())
    Lattice<dim> make_lattice() const;
    /// adaptive boxes (2, 3 dimensions): the forest, a copy of deal.II's current one
    void make_forest();
    /// adaptive meshes: bring deal.II's triangulation to the forest's leaves and number its
    /// DoFs (the same partition and order as the slots: checked), if not done yet
    void sync_dealii() const;
    /// adapt(): true if the forest stays 2:1 balanced when each owned leaf changes its
    /// level by delta (+1, 0, -1) and the MPI ghosts as their owners say (collective)
    bool stays_balanced(const std::vector<signed char> &delta) const;

    MPI_Comm                                                   communicator_;
    std::unique_ptr<dealii::parallel::TriangulationBase<dim>>  triangulation_;
    std::unique_ptr<dealii::FESystem<dim>>                     finite_element_;
    mutable std::unique_ptr<dealii::DoFHandler<dim>>           dof_handler_;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner_;

    /// the lattice as the mesh was built (source/mesh/triangulation_builder.cc)
    LatticeGeometry geometry_;
    bool            subset_    = false; ///< a mesh file's lattice (solid points, boundary ids from the file)
    unsigned int    max_level_ = 0;
    /// the boundary kinds and wall velocities per boundary id (velocities in [m/s])
    boundary::WallTable walls_;
    unsigned long long  n_global_ = 0;
    /// the slots' tables, held here so that the inline accessors index them directly
    SlotTables                        tables_;
    mutable std::vector<unsigned int> active_index_;
    /// scratch(): the buffers and their sizes
    mutable std::array<std::pair<std::unique_ptr<double[]>, std::size_t>,
                       static_cast<unsigned int>(Scratch::n_buffers)>
      scratch_;
    /// adaptive boxes: the octree, adapted by p4est alone (source/mesh/forest.h); deal.II's
    /// mesh and DoFs follow it only when asked for
    std::unique_ptr<Forest<dim>> forest_;
    mutable bool                 dealii_mesh_current_ = true, dealii_dofs_current_ = true;
    unsigned long long           last_refined_ = 0, last_coarsened_ = 0;
  };
} // namespace granhydro::mesh
