#include <granhydro/boundary/ghost_state.h>
#include <granhydro/mesh/cartesian_patch.h>

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/fe/fe_dgq.h>

#include "forest.h"
#include "ghost_layer.h"
#include "lattice.h"
#include "stencil_tables.h"
#include "triangulation_builder.h"
#include "virtual_cells.h"

#include <algorithm>
#include <memory>

namespace granhydro::mesh
{
  using namespace dealii;

  template <int dim>
  CartesianPatch<dim>::CartesianPatch(const MPI_Comm comm)
    : communicator_(comm)
  {}

  template <int dim>
  CartesianPatch<dim>::~CartesianPatch()
  {
    forest_.reset(); // shares deal.II's connectivity
    dof_handler_.reset();
    triangulation_.reset();
  }

  template <int dim>
  double CartesianPatch<dim>::cell_volume(const unsigned int s) const
  {
    double v = 1;
    for (unsigned int d = 0; d < dim; ++d)
      v *= cell_size(s, d);
    return v;
  }

  template <int dim>
  Point<dim> CartesianPatch<dim>::center(const unsigned int s) const
  {
    Point<dim> p;
    for (unsigned int d = 0; d < dim; ++d)
      p[d] = geometry_.lower[d] + (tables_.positions[s][d] + 0.5) * cell_size(s, d);
    return p;
  }


  template <int dim>
  int CartesianPatch<dim>::wall_id(const unsigned int l, const unsigned int r, const unsigned int d) const
  {
    if (is_cell(l) == is_cell(r))
      return -1;
    const int id = is_cell(l) ? face_boundary_id(l, 2 * d + 1) : face_boundary_id(r, 2 * d);
    return id >= 0 && boundary::is_wall(walls_.settings[id].type) ? id : -1;
  }

  template <int dim>
  void CartesianPatch<dim>::build(const MeshSettings &settings, const unsigned int ghost_width)
  {
    tables_.ghost_width  = ghost_width;
    walls_.settings      = settings.walls;
    walls_.velocity_unit = settings.velocity_unit;
    subset_              = !settings.mesh_file.empty();
    max_level_           = subset_ ? 0 : settings.max_level;
    forest_.reset();
    dof_handler_.reset();
    triangulation_  = make_triangulation<dim>(communicator_);
    finite_element_ = std::make_unique<FESystem<dim>>(FE_DGQ<dim>(0), n_components);
    geometry_ =
      subset_ ? make_file_mesh(*triangulation_, settings) : make_box_mesh(*triangulation_, settings);
    if (max_level_ > 0)
      make_forest();
    dealii_mesh_current_ = true;
    rebuild();
  }

  template <int dim>
  void CartesianPatch<dim>::make_forest()
  {
    forest_.reset();
    if constexpr (dim > 1)
      forest_ = std::make_unique<Forest<dim>>(
        dynamic_cast<const parallel::distributed::Triangulation<dim> &>(*triangulation_),
        geometry_.base_level, geometry_.lower, geometry_.cell_size, n_components);
    dealii_mesh_current_ = true;
  }

  template <int dim>
  void CartesianPatch<dim>::sync_dealii() const
  {
    if (!forest_)
      return;
    if constexpr (dim > 1)
      if (!dealii_mesh_current_)
        {
          // deal.II copies the forest and refines/coarsens its mesh until they match
          dynamic_cast<parallel::distributed::Triangulation<dim> &>(*triangulation_).load(forest_->get());
          dealii_mesh_current_ = true;
          dealii_dofs_current_ = false;
        }
    if (dealii_dofs_current_)
      return;
    if (!dof_handler_)
      dof_handler_ = std::make_unique<DoFHandler<dim>>(*triangulation_);
    dof_handler_->distribute_dofs(*finite_element_);
    DoFRenumbering::hierarchical(*dof_handler_);
    // deal.II's owned cells in DoF order must be the slots (same partition and order)
    Lattice<dim>                 lattice = make_lattice();
    const std::vector<OwnedCell> owned =
      lattice.owned_cells(*dof_handler_, geometry_.lower, geometry_.cell_size, geometry_.base_level);
    bool same = owned.size() == tables_.n_owned &&
                dof_handler_->locally_owned_dofs() == partitioner_->locally_owned_range();
    for (unsigned int s = 0; same && s < tables_.n_owned; ++s)
      same = owned[s].level == tables_.levels[s] && owned[s].ijk == tables_.positions[s];
    AssertThrow(same, ExcMessage("deal.II's mesh does not match the adaptive forest (internal error)"));
    active_index_.resize(tables_.n_owned);
    for (unsigned int s = 0; s < tables_.n_owned; ++s)
      active_index_[s] = owned[s].active;
    dealii_dofs_current_ = true;
  }

  template <int dim>
  Lattice<dim> CartesianPatch<dim>::make_lattice() const
  {
    return Lattice<dim>(geometry_.cells, geometry_.periodic, max_level_, tables_.ghost_width, walls_,
                        subset_);
  }

  template <int dim>
  void CartesianPatch<dim>::rebuild()
  {
    AssertThrow(max_level_ <= 7, ExcMessage("at most 7 refinement levels"));
    for (unsigned int c = 0; c < n_components; ++c)
      AssertThrow(finite_element_->system_to_component_index(c).first == c, ExcInternalError());
    Lattice<dim>           lattice = make_lattice();
    std::vector<OwnedCell> owned;
    IndexSet               owned_dofs;
    if (forest_)
      {
        // adaptive: the cells are numbered along the octree's z-order (p4est's order, which
        // depends on the leaves only, not on the history of refinement and coarsening): a
        // restart that rebuilds the mesh gets the same numbering, hence the same block-ILU
        // preconditioner and bitwise the same run. deal.II's DoFs are numbered alike
        // (DoFRenumbering::hierarchical) when output asks for them.
        n_global_                       = forest_->n_global();
        const unsigned long long first  = forest_->first_global();
        const auto               leaves = forest_->leaves();
        owned_dofs                      = IndexSet(n_global_ * n_components);
        owned_dofs.add_range(first * n_components, (first + leaves.size()) * n_components);
        owned.reserve(leaves.size());
        for (std::size_t i = 0; i < leaves.size(); ++i)
          {
            const auto                     &l = leaves[i];
            typename Lattice<dim>::Position corner{{0, 0, 0}};
            for (unsigned int d = 0; d < dim; ++d)
              corner[d] = (long long)(l.ijk[d]) << (max_level_ - l.level);
            owned.push_back({types::global_dof_index((first + i) * n_components),
                             lattice.fine_key(corner) * 8 + l.level, 0, l.level, l.ijk, 0});
          }
        dealii_dofs_current_ = false;
      }
    else
      {
        if (!dof_handler_)
          dof_handler_ = std::make_unique<DoFHandler<dim>>(*triangulation_);
        dof_handler_->distribute_dofs(*finite_element_);
        owned_dofs = dof_handler_->locally_owned_dofs();
        AssertThrow(owned_dofs.is_contiguous(), ExcMessage("owned DoFs must be contiguous"));
        n_global_ = triangulation_->n_global_active_cells();
        owned =
          lattice.owned_cells(*dof_handler_, geometry_.lower, geometry_.cell_size, geometry_.base_level);
      }
    tables_.n_owned = owned.size();
    lattice.distribute(owned, n_global_, communicator_);

    // the positions needed besides the owned cells, then the slots and tables
    const auto                        face_keys = face_neighbour_keys(owned, lattice);
    VirtualCells<dim>                 virtuals(lattice);
    std::unique_ptr<DilatedMask<dim>> mask;
    std::vector<long long>            needed;
    std::vector<char>                 full_box; // per owned cell (the stencil closure)
    if (subset_)
      {
        mask   = std::make_unique<DilatedMask<dim>>(owned, tables_.ghost_width);
        needed = mask->keys(lattice);
      }
    else
      needed = stencil_closure(owned, face_keys, lattice, virtuals, int(tables_.ghost_width) - 1, full_box);
    add_wall_sources(needed, lattice);
    SlotIndex index;
    partitioner_ = assign_slots(owned, needed, lattice, virtuals, owned_dofs, communicator_, tables_,
                                active_index_, index);
    make_face_ids(lattice, tables_);
    const SlotGrid<dim> grid(lattice, tables_.positions, tables_.levels);
    make_neighbor_table(lattice, virtuals, index, grid, mask.get(), full_box, geometry_, tables_);
    std::vector<unsigned int> face_slots(face_keys.keys.size());
    for (std::size_t i = 0; i < face_slots.size(); ++i)
      face_slots[i] = index.slot_of.at(face_keys.keys[i]);
    // gradient rows are read for the owned cells and their face neighbours only
    std::vector<char> rows(tables_.positions.size(), 0);
    std::fill(rows.begin(), rows.begin() + tables_.n_owned, 1);
    for (const unsigned int s : face_slots)
      rows[s] = 1;
    std::vector<char> incomplete; // per slot: a gradient neighbour lies beyond the fetched blocks
    make_gradient_table(lattice, index, grid, mask.get(), rows, geometry_, tables_, incomplete);
    make_faces<dim>(face_keys.start, face_slots, tables_);
    // the rows made are the ones read (owned and face cells): each must be complete
    AssertThrow(std::find(incomplete.begin(), incomplete.end(), 1) == incomplete.end(),
                ExcMessage("internal error: a face cell's gradient neighbour lies beyond the part "
                           "of the mesh this rank fetched (Lattice::reach() too small)"));
  }

  template <int dim>
  long long CartesianPatch<dim>::leaf_key(const unsigned int s) const
  {
    long long key = 0;
    for (int d = dim - 1; d >= 0; --d)
      key = key * ((long long)(geometry_.cells[d]) << max_level_) + fine_begin(s, d);
    return key * 8 + tables_.levels[s];
  }

  template <int dim>
  void CartesianPatch<dim>::gather(const LinearAlgebra::distributed::Vector<double> &U,
                                   std::vector<double>                              &W) const
  {
    W.resize(std::size_t(n_slots()) * n_components);
    gather(U, W.data());
  }

  template <int dim>
  void CartesianPatch<dim>::gather(const LinearAlgebra::distributed::Vector<double> &U, double *W) const
  {
    constexpr unsigned int NC = n_components;
    U.update_ghost_values();
    const std::size_t nloc = std::size_t(tables_.n_owned + tables_.n_mpi_ghosts) * NC;
    AssertThrow(U.locally_owned_size() + U.get_partitioner()->n_ghost_indices() == nloc,
                ExcMessage("state vector does not match the patch"));
    if (nloc > 0)
      std::copy(U.begin(), U.begin() + nloc, W); // ghosts follow the owned entries
    for (const auto &v : tables_.virtual_cells)  // restriction / prolongation next to level changes
      for (unsigned int c = 0; c < NC; ++c)
        {
          double sum = 0;
          for (const auto &[t, w] : v.sources)
            sum += w * W[std::size_t(t) * NC + c];
          W[std::size_t(v.slot) * NC + c] = sum;
        }
    for (const auto &g : tables_.boundary_ghosts)
      {
        const double *in  = &W[std::size_t(g.source) * NC];
        double       *out = &W[std::size_t(g.slot) * NC];
        boundary::ghost_state<dim>(g, in, out); // the wall's rule: mirror, copy or no-slip
      }
  }

  template class CartesianPatch<1>;
  template class CartesianPatch<2>;
  template class CartesianPatch<3>;
} // namespace granhydro::mesh
