#pragma once
/**
 * @file cartesian_patch.h
 * The mesh of a scene and the stencil tables of its uniform Cartesian patch.
 *
 * deal.II/p4est own the mesh, the partition and the DoF numbering (DG0
 * FESystem with dim+2 components: one value per cell and conserved
 * variable). deal.II gives one ghost layer; WENO5 with transverse Gauss-point
 * reconstruction needs every cell within Chebyshev distance r+1 (r = stencil
 * half width) of an owned cell. This class builds that wider ghost set from
 * the cells' lattice indices, a Utilities::MPI::Partitioner for the state
 * vector with those ghosts, and flat neighbour tables (no cell iterators in
 * hot loops). Walls are represented by boundary-ghost slots whose state is a
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
 * Limits (to be lifted by the AMR issue): uniform meshes only; the lattice to
 * DoF map and the boundary face ids are replicated on every rank (8 bytes per
 * lattice point plus one per boundary face).
 */
#include <granhydro/scene/scene.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <array>
#include <memory>
#include <vector>

namespace granhydro
{
  template <int dim>
  class CartesianPatch
  {
  public:
    static constexpr unsigned int n_components = dim + 2;

    /// a boundary-ghost slot: copy of slot source, momentum components with bit d of
    /// flip_mask set change sign (mirror at a slip wall normal to d)
    struct BoundaryGhost
    {
      unsigned int slot, source, flip_mask;
      /// true if any wall this ghost lies behind is a no-slip wall
      bool no_slip = false;
      /// the walls this ghost lies behind (1 at a face, 2 at an edge, 3 at a corner),
      /// applied in turn: slip wall flips the normal velocity, no-slip wall mirrors the
      /// velocity about the wall velocity u -> 2 u_w - u (scaled units); n and the
      /// internal energy are copied (physics.md 5.1). wall_dir is the geometric normal
      /// direction, wall_id the boundary id (index of the scene's Boundary entry)
      unsigned int n_walls = 0;
      std::array<unsigned int, 3>          wall_dir{{0, 0, 0}};
      std::array<unsigned int, 3>          wall_id{{0, 0, 0}};
      std::array<bool, 3>                  wall_no_slip{{false, false, false}};
      std::array<std::array<double, 3>, 3> wall_velocity{};
    };

    CartesianPatch(const MPI_Comm comm);
    ~CartesianPatch();

    /// build mesh, DoFs and tables; ghost_width = r + 1 for a stencil half width r
    void build(const Scene &scene, const unsigned int ghost_width);

    const dealii::parallel::TriangulationBase<dim> &triangulation() const { return *tria; }
    const dealii::DoFHandler<dim> &dof_handler() const { return *dofh; }
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner() const { return part; }
    MPI_Comm communicator() const { return comm; }

    unsigned int n_owned() const { return n_owned_; }
    unsigned int n_mpi_ghosts() const { return n_mpi_ghost_; }
    unsigned int n_slots() const { return lattice_.size(); }
    unsigned int ghost_width() const { return G; }
    unsigned long long n_global_cells() const { return n_global_; }

    /// neighbour slot of s at offset o (|o| <= ghost_width) along d, or -1
    int neighbor(const unsigned int s, const unsigned int d, const int o) const
    {
      return nb_[(std::size_t(s) * dim + d) * (2 * G + 1) + (o + int(G))];
    }

    /// true for the slots of real cells (owned or MPI ghost), false for boundary ghosts
    bool is_cell(const unsigned int s) const { return s < n_owned_ + n_mpi_ghost_; }

    /// boundary id of the face on side f = 2 d + upper of the real-cell slot s (lattice
    /// directions, not deal.II's face numbering), or -1 for an interior face
    int face_boundary_id(const unsigned int s, const unsigned int f) const
    {
      return slot_face_id_[std::size_t(s) * 2 * dim + f];
    }

    /// the boundary condition of boundary id i
    BoundaryType boundary_type(const unsigned int i) const { return btype_[i]; }

    /// true if the face between slots l (low side) and r along d is a wall (slip or
    /// no-slip): one real cell, one boundary ghost, and the cell's face has a wall id
    bool wall_face(const unsigned int l, const unsigned int r, const unsigned int d) const;

    /// extended lattice coordinates of a slot (may lie outside [0,N) for boundary ghosts)
    const std::array<int, 3> &lattice(const unsigned int s) const { return lattice_[s]; }
    const std::vector<BoundaryGhost> &boundary_ghosts() const { return bghosts_; }

    double cell_size(const unsigned int d) const { return h_[d]; }
    double cell_volume() const;
    /// lattice points per direction (the box, or the bounding box of a mesh file; a mesh
    /// file may leave some of them without a cell)
    unsigned int cells(const unsigned int d) const { return N_[d]; }
    double lower(const unsigned int d) const { return lo_[d]; }
    dealii::Point<dim> center(const unsigned int s) const;

    /// slot array from a state vector on partitioner(): update ghosts, copy owned and
    /// MPI-ghost values, fill boundary ghosts (mirror or copy)
    void gather(const dealii::LinearAlgebra::distributed::Vector<double> &U,
                std::vector<double>                                        &W) const;

    /// active_cell_index of each owned slot (for output only)
    const std::vector<unsigned int> &owned_active_cell_index() const { return active_index_; }

  private:
    MPI_Comm comm;
    std::unique_ptr<dealii::parallel::TriangulationBase<dim>> tria;
    std::unique_ptr<dealii::FESystem<dim>> fe;
    std::unique_ptr<dealii::DoFHandler<dim>> dofh;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> part;

    unsigned int G = 3;
    std::array<unsigned int, 3> N_{{1, 1, 1}};
    std::array<double, 3> h_{{1, 1, 1}}, lo_{{0, 0, 0}};
    std::array<bool, 3> periodic_{{true, true, true}};
    unsigned long long n_global_ = 0;
    unsigned int n_owned_ = 0, n_mpi_ghost_ = 0;
    std::vector<std::array<int, 3>> lattice_;
    std::vector<int> nb_;
    std::vector<BoundaryGhost> bghosts_;
    std::vector<signed char> slot_face_id_; ///< 2 dim per real-cell slot
    std::array<BoundaryType, 6> btype_{};
    std::vector<unsigned int> active_index_;
  };
} // namespace granhydro
