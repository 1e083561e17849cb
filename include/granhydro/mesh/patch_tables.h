#pragma once
/**
 * @file patch_tables.h
 * The plain data a CartesianPatch (mesh/cartesian_patch.h) holds: the geometry of its
 * lattice and the flat tables of its slots. The parts of the patch (source/mesh: the
 * triangulation builder, the table builders) fill them; the patch reads them in its
 * inline accessors, so the operators' hot loops index the vectors directly. Slot
 * numbering and the meaning of each table: cartesian_patch.h.
 */
#include <granhydro/boundary/boundary_ghost.h>

#include <array>
#include <utility>
#include <vector>

namespace granhydro::mesh
{
  /// the lattice of a patch's box or mesh file, as its mesh was built
  struct LatticeGeometry
  {
    /// level-0 lattice points per direction (1 beyond dim)
    std::array<unsigned int, 3> cells{{1, 1, 1}};
    /// edge of a level-0 cell [m], and the lower corner of the lattice [m]
    std::array<double, 3> cell_size{{1, 1, 1}}, lower{{0, 0, 0}};
    std::array<bool, 3>   periodic{{true, true, true}};
    /// deal.II's refinement level of the level-0 cells (global refinements of the coarse mesh)
    unsigned int base_level = 0;
  };

  /// a face normal to some direction d between slots l (low side) and r; frac_l/frac_r:
  /// the share of l's/r's whole face this face is (1, or 1/2^(dim-1) on the coarse side
  /// of a hanging face; 1, 1/2 and 1/4 are floats exactly, so a float holds them in 4 bytes)
  struct PatchFace
  {
    unsigned int l, r;
    float        frac_l, frac_r;
    /// hanging face: index of the coarse face's Gauss point in this fine sub-face
    /// (the coarse side's value there is used at all of the sub-face's points); -1 else
    int coarse_point = -1;
  };

  /// a face of an owned cell: index into the faces of its direction, and whether the cell
  /// is the face's low side (the face is on the cell's upper side)
  struct PatchCellFace
  {
    unsigned int face;
    bool         upper;
  };

  /// a virtual cell: weighted sum of real slots (restriction or prolongation)
  struct VirtualSlot
  {
    unsigned int                                 slot;
    std::vector<std::pair<unsigned int, double>> sources;
  };

  /// the flat tables of a patch's slots (source/mesh/stencil_tables.cc builds them)
  struct SlotTables
  {
    /// G = r + 1 for a stencil half width r: neighbours at offsets -G .. G
    unsigned int ghost_width = 3;
    unsigned int n_owned = 0, n_mpi_ghosts = 0;
    /// extended lattice coordinates of each slot at its level, and the level
    std::vector<std::array<int, 3>> positions;
    std::vector<unsigned char>      levels;
    /// per slot: 1 if its reconstruction box is complete at its own level
    std::vector<unsigned char> uniform;
    /// slot s's neighbour at offset o along d: entry (s dim + d) (2 G + 1) + o + G, or -1
    std::vector<int> neighbors;
    /// gradient neighbour of s along j on side (0 lower, 1 upper): entry (s dim + j) 2 +
    /// side, or -1; and its offset from s's centre [m]
    std::vector<int>                     gradient_neighbors;
    std::vector<double>                  gradient_offsets;
    std::vector<boundary::BoundaryGhost> boundary_ghosts;
    /// boundary id of face 2 d + upper of each real-cell slot (2 dim per slot), -1 interior
    std::vector<signed char> face_boundary_ids;
    std::vector<VirtualSlot> virtual_cells;
    /// per direction: the faces, and each owned cell's faces (cell_faces[d] from
    /// cell_face_start[d][s] to cell_face_start[d][s + 1])
    std::vector<PatchFace>     faces[3];
    std::vector<unsigned int>  cell_face_start[3];
    std::vector<PatchCellFace> cell_faces[3];
  };
} // namespace granhydro::mesh
