#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/mesh/mesh_file.h>

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>
#include <set>
#include <stdexcept>

namespace granhydro
{
  using namespace dealii;

  template <int dim>
  CartesianPatch<dim>::CartesianPatch(const MPI_Comm comm)
    : comm(comm)
  {}

  template <int dim>
  CartesianPatch<dim>::~CartesianPatch()
  {
    dofh.reset();
    tria.reset();
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
      p[d] = lo_[d] + (lattice_[s][d] + 0.5) * cell_size(s, d);
    return p;
  }

  namespace
  {
    template <int dim>
    std::unique_ptr<parallel::TriangulationBase<dim>> make_triangulation(const MPI_Comm comm)
    {
      if constexpr (dim == 1)
        return std::make_unique<parallel::shared::Triangulation<1>>(comm);
      else
        return std::make_unique<parallel::distributed::Triangulation<dim>>(comm);
    }
    /// every rank's entries, concatenated in rank order, on every rank
    std::vector<long long> all_gather(const std::vector<long long> &mine, const MPI_Comm comm)
    {
      const int        nranks = Utilities::MPI::n_mpi_processes(comm);
      std::vector<int> counts(nranks), displs(nranks);
      int              mycount = mine.size();
      MPI_Allgather(&mycount, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
      long long total = 0;
      for (int r = 0; r < nranks; ++r)
        {
          displs[r] = total;
          total += counts[r];
        }
      std::vector<long long> all(total);
      MPI_Allgatherv(mine.data(), mycount, MPI_LONG_LONG, all.data(), counts.data(),
                     displs.data(), MPI_LONG_LONG, comm);
      return all;
    }
  } // namespace

  template <int dim>
  bool CartesianPatch<dim>::wall_face(const unsigned int l, const unsigned int r,
                                      const unsigned int d) const
  {
    if (is_cell(l) == is_cell(r))
      return false;
    const int id = is_cell(l) ? face_boundary_id(l, 2 * d + 1) : face_boundary_id(r, 2 * d);
    return id >= 0 && (btype_[id] == BoundaryType::slip_wall || btype_[id] == BoundaryType::no_slip_wall);
  }

  template <int dim>
  void CartesianPatch<dim>::build(const MeshSettings &settings, const unsigned int ghost_width)
  {
    G = ghost_width;
    btype_               = settings.boundary;
    wall_velocity_       = settings.wall_velocity;
    velocity_unit_       = settings.velocity_unit;
    max_level_           = settings.mesh_file.empty() ? settings.max_level : 0;
    dofh.reset();
    tria = make_triangulation<dim>(comm);
    fe   = std::make_unique<FESystem<dim>>(FE_DGQ<dim>(0), n_components);
    if (settings.mesh_file.empty())
      {
        make_box_mesh(settings);
        rebuild_box();
      }
    else
      build_lattice_subset(settings);
  }

  template <int dim>
  void CartesianPatch<dim>::make_box_mesh(const MeshSettings &settings)
  {

        // ---- mesh: coarse box refined globally L times (p4est) -----------------
        for (unsigned int d = 0; d < 3; ++d)
          {
            N_[d]        = d < dim ? settings.cells[d] : 1;
            lo_[d]       = d < dim ? settings.lower[d] : 0;
            h_[d]        = d < dim ? (settings.upper[d] - settings.lower[d]) / N_[d] : 1;
            periodic_[d] = d < dim ? settings.boundary[2 * d] == BoundaryType::periodic : true;
          }
        unsigned int L = 0;
        if (dim > 1)
          while (L < 8)
            {
              bool ok = true;
              for (unsigned int d = 0; d < dim; ++d)
                ok = ok && (N_[d] % (1u << (L + 1)) == 0);
              if (!ok)
                break;
              ++L;
            }
        std::vector<unsigned int> rep(dim);
        Point<dim> p1, p2;
        for (unsigned int d = 0; d < dim; ++d)
          {
            rep[d] = N_[d] >> L;
            p1[d]  = settings.lower[d];
            p2[d]  = settings.upper[d];
          }
        GridGenerator::subdivided_hyper_rectangle(*tria, rep, p1, p2, /*colorize=*/true);
        if constexpr (dim > 1)
          {
            auto &ptria = dynamic_cast<parallel::distributed::Triangulation<dim> &>(*tria);
            std::vector<GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<dim>::cell_iterator>> pairs;
            for (unsigned int d = 0; d < dim; ++d)
              if (periodic_[d])
                GridTools::collect_periodic_faces(ptria, 2 * d, 2 * d + 1, d, pairs);
            if (!pairs.empty())
              ptria.add_periodicity(pairs);
          }
        tria->refine_global(L);
        base_tria_level_ = L;
  }

  template <int dim>
  void CartesianPatch<dim>::build_lattice_subset(const MeshSettings &settings)
  {
      {
        // ---- mesh file: the lattice is the bounding box at the fine cell size ----
        if constexpr (dim == 1)
          {
            AssertThrow(false, ExcMessage("mesh files need 2 or 3 dimensions"));
          }
        else
          {
            Triangulation<dim> coarse;
            read_mesh_file(settings.mesh_file, coarse);
            const MeshFileInfo info = inspect_mesh(coarse);
            for (unsigned int d = 0; d < 3; ++d)
              {
                N_[d]  = d < dim ? info.lattice[d] << settings.mesh_refinements : 1;
                lo_[d] = d < dim ? info.lower[d] : 0;
                // the same expression as for the box: a box read from a file gets bitwise
                // the same cell size and centres as the generated one
                h_[d]        = d < dim ? (info.upper[d] - info.lower[d]) / N_[d] : 1;
                periodic_[d] = d >= dim;
              }
            tria->copy_triangulation(coarse);
            tria->refine_global(settings.mesh_refinements);
          }
      }
    const long long n_lattice = 1ll * N_[0] * N_[1] * N_[2];
    n_global_                 = tria->n_global_active_cells();

    dofh = std::make_unique<DoFHandler<dim>>(*tria);
    dofh->distribute_dofs(*fe);
    for (unsigned int c = 0; c < n_components; ++c)
      AssertThrow(fe->system_to_component_index(c).first == c, ExcInternalError());
    const IndexSet owned_dofs = dofh->locally_owned_dofs();
    AssertThrow(owned_dofs.is_contiguous(), ExcMessage("owned DoFs must be contiguous"));

    auto key_of = [&](const std::array<int, 3> &e) {
      return e[0] + 1ll * N_[0] * (e[1] + 1ll * N_[1] * e[2]);
    };

    // ---- owned cells and their boundary faces ----------------------------------
    struct Owned
    {
      types::global_dof_index first;
      long long               key;
      unsigned int            active;
      std::array<int, 3>      ijk;
    };
    std::vector<Owned> owned;
    std::vector<long long> my_faces; // (key * 2 dim + lattice face) * 8 + boundary id
    std::vector<types::global_dof_index> dofs(n_components);
    for (const auto &cell : dofh->active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int c = 1; c < n_components; ++c)
            AssertThrow(dofs[c] == dofs[0] + c, ExcMessage("DG0 DoFs of a cell must be consecutive"));
          const Point<dim> x = cell->center();
          std::array<int, 3> ijk{{0, 0, 0}};
          for (unsigned int d = 0; d < dim; ++d)
            ijk[d] = static_cast<int>(std::floor((x[d] - lo_[d]) / h_[d]));
          const long long key = key_of(ijk);
          owned.push_back({dofs[0], key, cell->active_cell_index(), ijk});
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && !cell->has_periodic_neighbor(f))
              {
                const auto [d, upper]        = face_direction(cell, f);
                const types::boundary_id id = cell->face(f)->boundary_id();
                AssertThrow(id < 2 * dim, ExcMessage("boundary id out of range"));
                my_faces.push_back((key * 2 * dim + 2 * d + upper) * 8 + id);
              }
        }
    std::sort(owned.begin(), owned.end(),
              [](const Owned &a, const Owned &b) { return a.first < b.first; });
    n_owned_ = owned.size();

    // ---- replicated lattice -> first DoF map and boundary face ids --------------
    std::vector<long long> first_dof_of(n_lattice, -1); // -1: solid lattice point
    {
      std::vector<long long> mine(2 * n_owned_);
      for (unsigned int i = 0; i < n_owned_; ++i)
        {
          mine[2 * i]     = owned[i].key;
          mine[2 * i + 1] = owned[i].first;
        }
      const auto all = all_gather(mine, comm);
      AssertThrow(all.size() == 2 * n_global_, ExcMessage("mesh is not the expected lattice"));
      for (std::size_t i = 0; i < all.size(); i += 2)
        {
          AssertThrow(all[i] >= 0 && all[i] < n_lattice && first_dof_of[all[i]] < 0,
                      ExcMessage("two cells on one lattice point"));
          first_dof_of[all[i]] = all[i + 1];
        }
    }
    std::vector<long long> bfaces = all_gather(my_faces, comm);
    std::sort(bfaces.begin(), bfaces.end());
    // boundary id of lattice face lf of the cell at key, -1 if interior (or no cell)
    auto face_id = [&](const long long key, const unsigned int lf) -> int {
      const long long code = (key * 2 * dim + lf) * 8;
      const auto      it   = std::lower_bound(bfaces.begin(), bfaces.end(), code);
      return (it != bfaces.end() && *it < code + 8) ? int(*it - code) : -1;
    };
    auto inside = [&](const std::array<int, 3> &e) {
      for (unsigned int d = 0; d < 3; ++d)
        if (e[d] < 0 || e[d] >= int(N_[d]))
          return false;
      return true;
    };
    auto fluid = [&](const std::array<int, 3> &e) { return inside(e) && first_dof_of[key_of(e)] >= 0; };

    // ---- the rank's box: owned bounding box + G, dilated owned mask -----------
    std::array<int, 3> blo{{0, 0, 0}}, bn{{1, 1, 1}};
    for (unsigned int d = 0; d < dim; ++d)
      {
        int mn = 1 << 30, mx = -(1 << 30);
        for (const auto &o : owned)
          {
            mn = std::min(mn, o.ijk[d]);
            mx = std::max(mx, o.ijk[d]);
          }
        if (owned.empty())
          mn = mx = 0;
        blo[d] = mn - int(G);
        bn[d]  = mx - mn + 1 + 2 * int(G);
      }
    const std::size_t nbox = std::size_t(bn[0]) * bn[1] * bn[2];
    auto box_index = [&](int i, int j, int k) {
      return std::size_t(i - blo[0]) + std::size_t(bn[0]) * (std::size_t(j - blo[1]) + std::size_t(bn[1]) * (k - blo[2]));
    };
    std::vector<char> mask(nbox, 0);
    for (const auto &o : owned)
      mask[box_index(o.ijk[0], o.ijk[1], o.ijk[2])] = 1;
    // separable Chebyshev dilation by G
    const std::array<std::size_t, 3> stride{{1, std::size_t(bn[0]), std::size_t(bn[0]) * bn[1]}};
    for (unsigned int d = 0; d < dim; ++d)
      {
        std::vector<char> out(nbox, 0);
        for (std::size_t p = 0; p < nbox; ++p)
          if (mask[p])
            {
              const int c = (p / stride[d]) % bn[d];
              for (int o = -int(G); o <= int(G); ++o)
                if (c + o >= 0 && c + o < bn[d])
                  out[p + std::ptrdiff_t(o) * std::ptrdiff_t(stride[d])] = 1;
            }
        mask.swap(out);
      }

    // ---- slots: real cells by lattice key (>= 0), ghosts by extended key (< 0) ---
    lattice_.clear();
    active_index_.clear();
    std::map<long long, unsigned int> slot_of_key;
    for (unsigned int i = 0; i < n_owned_; ++i)
      {
        slot_of_key[owned[i].key] = i;
        lattice_.push_back(owned[i].ijk);
        active_index_.push_back(owned[i].active);
      }
    const long long ext[3] = {N_[0] + 2 * G, N_[1] + 2 * G, N_[2] + 2 * G};
    auto physical = [&](std::array<int, 3> e, bool &is_ghost) {
      for (unsigned int d = 0; d < 3; ++d)
        if (periodic_[d])
          e[d] = ((e[d] % int(N_[d])) + int(N_[d])) % int(N_[d]);
      is_ghost = !fluid(e); // outside the lattice or a solid point
      if (!is_ghost)
        return std::make_pair(e, key_of(e));
      const long long gk = (e[0] + G) + ext[0] * ((e[1] + G) + ext[1] * (e[2] + G));
      return std::make_pair(e, -1 - gk);
    };
    std::vector<long long> box_key(nbox, 0);
    std::set<long long> mpi_keys;                        // real cells owned elsewhere
    std::map<long long, std::array<int, 3>> bnd_ghosts; // key -> extended coords
    for (int k = blo[2]; k < blo[2] + bn[2]; ++k)
      for (int j = blo[1]; j < blo[1] + bn[1]; ++j)
        for (int i = blo[0]; i < blo[0] + bn[0]; ++i)
          {
            const std::size_t p = box_index(i, j, k);
            if (!mask[p])
              continue;
            bool g;
            const auto [e, key] = physical({{i, j, k}}, g);
            box_key[p]          = key;
            if (slot_of_key.count(key))
              continue;
            if (g)
              bnd_ghosts[key] = e;
            else
              mpi_keys.insert(key);
          }

    // ---- boundary ghosts: mirror of the nearest fluid cell ----------------------
    // A point without a cell takes the state of the nearest fluid cell f (smallest
    // squared lattice distance; ties: fewest nonzero offset components, then smallest
    // key), mirrored across each face of f facing the point: src_d = 2 f_d - sign - e_d
    // for a wall, src_d = f_d for outflow. The wall type comes from the boundary id of
    // that face (every step from f towards the point along such a d is solid, else that
    // cell would be nearer, so the face is a boundary face). For a box this is the
    // composed reflection at faces, edges and corners; at a concave corner of a
    // lattice subset the mirror point may be solid, then f itself is used.
    const int R = int(std::ceil(std::sqrt(double(dim)) * G)); // any point of the mask has fluid this near
    struct PendingGhost
    {
      BoundaryGhost bg;
      long long     key, source_key;
    };
    std::vector<PendingGhost> pending;
    for (const auto &[key, e] : bnd_ghosts)
      {
        std::array<int, 3> f{{0, 0, 0}};
        long long best_d2 = -1, best_key = 0;
        int       best_nnz = 0;
        std::array<int, 3> lo{{0, 0, 0}}, hi{{0, 0, 0}};
        for (unsigned int d = 0; d < dim; ++d)
          {
            lo[d] = std::max(e[d] - R, 0);
            hi[d] = std::min(e[d] + R, int(N_[d]) - 1);
          }
        for (int k = lo[2]; k <= hi[2]; ++k)
          for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i)
              {
                const std::array<int, 3> c{{i, j, k}};
                const long long ck = key_of(c);
                if (first_dof_of[ck] < 0)
                  continue;
                long long d2  = 0;
                int       nnz = 0;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    d2 += 1ll * (c[d] - e[d]) * (c[d] - e[d]);
                    nnz += c[d] != e[d];
                  }
                if (best_d2 < 0 || d2 < best_d2 || (d2 == best_d2 && (nnz < best_nnz ||
                                                                        (nnz == best_nnz && ck < best_key))))
                  {
                    best_d2  = d2;
                    best_nnz = nnz;
                    best_key = ck;
                    f        = c;
                  }
              }
        AssertThrow(best_d2 > 0, ExcMessage("no fluid cell near a boundary ghost"));
        PendingGhost pg;
        BoundaryGhost &bg = pg.bg;
        std::array<int, 3> src = e;
        unsigned int flip = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const int delta = f[d] - e[d];
            if (delta == 0)
              continue;
            const int sgn = delta > 0 ? 1 : -1;
            const int id  = face_id(best_key, 2 * d + (delta > 0 ? 0 : 1));
            AssertThrow(id >= 0, ExcMessage("a boundary ghost faces a cell face without boundary id"));
            const BoundaryType t = settings.boundary[id];
            if (t == BoundaryType::slip_wall || t == BoundaryType::no_slip_wall)
              {
                src[d] = 2 * f[d] - sgn - e[d];
                flip |= 1u << d;
                const unsigned int w = bg.n_walls++;
                bg.wall_dir[w]       = d;
                bg.wall_id[w]        = id;
                bg.wall_no_slip[w]   = t == BoundaryType::no_slip_wall;
                if (t == BoundaryType::no_slip_wall)
                  {
                    bg.no_slip = true;
                    for (unsigned int k = 0; k < 3; ++k)
                      bg.wall_velocity[w][k] = settings.wall_velocity[id][k] / settings.velocity_unit;
                  }
              }
            else
              src[d] = f[d]; // outflow: copy
          }
        if (!fluid(src))
          src = f;
        bg.flip_mask  = flip;
        pg.key        = key;
        pg.source_key = key_of(src);
        if (!slot_of_key.count(pg.source_key))
          mpi_keys.insert(pg.source_key); // a source beyond the ghost layer: one more MPI ghost
        pending.push_back(pg);
      }

    std::vector<std::pair<long long, long long>> mpi_ghosts; // (first dof, key)
    for (const long long key : mpi_keys)
      mpi_ghosts.emplace_back(first_dof_of[key], key);
    std::sort(mpi_ghosts.begin(), mpi_ghosts.end());
    IndexSet ghost_dofs(dofh->n_dofs());
    for (const auto &[first, key] : mpi_ghosts)
      {
        slot_of_key[key] = lattice_.size();
        lattice_.push_back({{int(key % N_[0]), int((key / N_[0]) % N_[1]), int(key / (1ll * N_[0] * N_[1]))}});
        ghost_dofs.add_range(first, first + n_components);
      }
    n_mpi_ghost_ = mpi_ghosts.size();
    for (const auto &[key, e] : bnd_ghosts)
      {
        slot_of_key[key] = lattice_.size();
        lattice_.push_back(e);
      }
    ghost_dofs.compress();
    part = std::make_shared<Utilities::MPI::Partitioner>(owned_dofs, ghost_dofs, comm);
    bghosts_.clear();
    for (auto &pg : pending)
      {
        pg.bg.slot   = slot_of_key.at(pg.key);
        pg.bg.source = slot_of_key.at(pg.source_key);
        bghosts_.push_back(pg.bg);
      }

    // boundary ids of the real cells' faces
    slot_face_id_.assign(std::size_t(n_owned_ + n_mpi_ghost_) * 2 * dim, -1);
    for (unsigned int s = 0; s < n_owned_ + n_mpi_ghost_; ++s)
      for (unsigned int lf = 0; lf < 2 * dim; ++lf)
        slot_face_id_[std::size_t(s) * 2 * dim + lf] = face_id(key_of(lattice_[s]), lf);

    // ---- neighbour table -------------------------------------------------------
    const unsigned int W = 2 * G + 1;
    nb_.assign(std::size_t(lattice_.size()) * dim * W, -1);
    for (std::size_t p = 0; p < nbox; ++p)
      {
        if (!mask[p])
          continue;
        const unsigned int s = slot_of_key[box_key[p]];
        for (unsigned int d = 0; d < dim; ++d)
          {
            const int c = (p / stride[d]) % bn[d];
            for (int o = -int(G); o <= int(G); ++o)
              {
                if (c + o < 0 || c + o >= bn[d])
                  continue;
                const std::size_t q = p + std::ptrdiff_t(o) * std::ptrdiff_t(stride[d]);
                if (!mask[q])
                  continue;
                const int t  = slot_of_key[box_key[q]];
                int      &e2 = nb_[(std::size_t(s) * dim + d) * W + (o + int(G))];
                AssertThrow(e2 < 0 || e2 == t, ExcMessage("inconsistent neighbour table"));
                e2 = t;
              }
          }
      }

    // ---- uniform lattice: every slot at level 0, complete stencils, one face a side --
    level_.assign(lattice_.size(), 0);
    uniform_.assign(lattice_.size(), 1);
    gnb_.assign(std::size_t(lattice_.size()) * dim * 2, -1);
    goff_.assign(std::size_t(lattice_.size()) * dim * 2, 0.);
    for (unsigned int s = 0; s < lattice_.size(); ++s)
      for (unsigned int j = 0; j < dim; ++j)
        for (unsigned int side = 0; side < 2; ++side)
          {
            gnb_[(std::size_t(s) * dim + j) * 2 + side]  = neighbor(s, j, side ? 1 : -1);
            goff_[(std::size_t(s) * dim + j) * 2 + side] = side ? h_[j] : -h_[j];
          }
    std::vector<std::vector<unsigned int>> lists(std::size_t(n_owned_) * dim * 2);
    for (unsigned int s = 0; s < n_owned_; ++s)
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int side = 0; side < 2; ++side)
          {
            const int t = neighbor(s, d, side ? 1 : -1);
            AssertThrow(t >= 0, ExcMessage("face neighbour outside the patch (internal error)"));
            lists[(std::size_t(s) * dim + d) * 2 + side].push_back(t);
          }
    make_faces(lists);
  }

  template <int dim>
  void CartesianPatch<dim>::make_faces(const std::vector<std::vector<unsigned int>> &lists)
  {
    const double sub = 1. / double(1u << (dim - 1)); // share of a fine sub-face
    for (unsigned int d = 0; d < dim; ++d)
      {
        faces_[d].clear();
        cell_face_[d].clear();
        cell_face_start_[d].assign(n_owned_ + 1, 0);
        std::map<std::pair<unsigned int, unsigned int>, unsigned int> index;
        for (unsigned int s = 0; s < n_owned_; ++s)
          {
            cell_face_start_[d][s] = cell_face_[d].size();
            for (unsigned int side = 0; side < 2; ++side)
              for (const unsigned int t : lists[(std::size_t(s) * dim + d) * 2 + side])
                {
                  const unsigned int l = side ? s : t, r = side ? t : s;
                  auto [it, fresh] = index.emplace(std::make_pair(l, r), faces_[d].size());
                  if (fresh)
                    {
                      const double fl = level_[l] < level_[r] ? sub : 1.;
                      const double fr = level_[r] < level_[l] ? sub : 1.;
                      // a hanging face: the fine cell's quadrant of the coarse face, which
                      // holds the coarse face's Gauss point of the same index
                      int q = -1;
                      if (level_[l] != level_[r])
                        {
                          const auto &pf = lattice_[level_[l] > level_[r] ? l : r];
                          const int   a  = dim > 1 ? pf[(d + 1) % dim] & 1 : 0;
                          const int   b  = dim > 2 ? pf[(d + 2) % dim] & 1 : 0;
                          q              = dim == 3 ? 2 * a + b : a;
                        }
                      faces_[d].push_back({l, r, fl, fr, q});
                    }
                  cell_face_[d].push_back({it->second, side == 1});
                }
          }
        cell_face_start_[d][n_owned_] = cell_face_[d].size();
      }
  }

  // ------------------------------------------------------------------------------
  // Box domains, uniform or adaptive
  // ------------------------------------------------------------------------------
  namespace
  {
    constexpr long long no_slot_key = std::numeric_limits<long long>::min();
  }

  template <int dim>
  void CartesianPatch<dim>::rebuild_box()
  {
    const unsigned int m = max_level_;
    AssertThrow(m <= 7, ExcMessage("at most 7 refinement levels"));
    if (!dofh)
      dofh = std::make_unique<DoFHandler<dim>>(*tria);
    dofh->distribute_dofs(*fe);
    // adaptive meshes: number the cells along the octree's z-order, which depends on the
    // leaves only, not on the history of refinement and coarsening (deal.II's own cell
    // order does): a restart that rebuilds the mesh gets the same numbering, hence the
    // same block-ILU preconditioner and bitwise the same run
    if (max_level_ > 0)
      DoFRenumbering::hierarchical(*dofh);
    for (unsigned int c = 0; c < n_components; ++c)
      AssertThrow(fe->system_to_component_index(c).first == c, ExcInternalError());
    const IndexSet owned_dofs = dofh->locally_owned_dofs();
    AssertThrow(owned_dofs.is_contiguous(), ExcMessage("owned DoFs must be contiguous"));
    n_global_ = tria->n_global_active_cells();

    // fine lattice (level m)
    std::array<long long, 3> Nf{{1, 1, 1}};
    for (unsigned int d = 0; d < dim; ++d)
      Nf[d] = (long long)(N_[d]) << m;
    const long long n_fine = Nf[0] * Nf[1] * Nf[2];
    auto fine_key = [&](const std::array<long long, 3> &c) { return c[0] + Nf[0] * (c[1] + Nf[1] * c[2]); };
    auto Nk = [&](const unsigned int k, const unsigned int d) -> long long {
      return d < dim ? (long long)(N_[d]) << k : 1;
    };

    // ---- owned cells --------------------------------------------------------------
    struct Owned
    {
      types::global_dof_index first;
      long long               key; ///< fine corner key * 8 + level
      unsigned int            active, level;
      std::array<int, 3>      ijk;
    };
    std::vector<Owned> owned;
    std::vector<types::global_dof_index> dofs(n_components);
    for (const auto &cell : dofh->active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int c = 1; c < n_components; ++c)
            AssertThrow(dofs[c] == dofs[0] + c, ExcMessage("DG0 DoFs of a cell must be consecutive"));
          const unsigned int k = cell->level() - base_tria_level_;
          AssertThrow(k <= m, ExcMessage("cell above the maximum level"));
          const Point<dim>   x = cell->center();
          std::array<int, 3> ijk{{0, 0, 0}};
          std::array<long long, 3> corner{{0, 0, 0}};
          for (unsigned int d = 0; d < dim; ++d)
            {
              ijk[d]    = static_cast<int>(std::floor((x[d] - lo_[d]) / (h_[d] / double(1u << k))));
              corner[d] = (long long)(ijk[d]) << (m - k);
            }
          owned.push_back({dofs[0], fine_key(corner) * 8 + k, cell->active_cell_index(), k, ijk});
        }
    std::sort(owned.begin(), owned.end(), [](const Owned &a, const Owned &b) { return a.first < b.first; });
    n_owned_ = owned.size();

    // ---- replicated fine lattice -> (first DoF, level) of the covering leaf ----------
    std::vector<long long> mine(2 * n_owned_);
    for (unsigned int i = 0; i < n_owned_; ++i)
      {
        mine[2 * i]     = owned[i].key;
        mine[2 * i + 1] = owned[i].first;
      }
    const std::vector<long long> all = all_gather(mine, comm);
    AssertThrow(all.size() == 2 * n_global_, ExcMessage("mesh is not the expected octree"));
    std::vector<long long>   cover_first(n_fine, -1);
    std::vector<signed char> cover_level(n_fine, -1);
    for (std::size_t i = 0; i < all.size(); i += 2)
      {
        const long long    fk = all[i] >> 3;
        const unsigned int k  = all[i] & 7;
        const long long    span = 1ll << (m - k);
        std::array<long long, 3> c{{fk % Nf[0], (fk / Nf[0]) % Nf[1], fk / (Nf[0] * Nf[1])}};
        for (long long z = 0; z < (dim > 2 ? span : 1); ++z)
          for (long long y = 0; y < (dim > 1 ? span : 1); ++y)
            for (long long x = 0; x < span; ++x)
              {
                const long long q = fine_key({{c[0] + x, c[1] + y, c[2] + z}});
                AssertThrow(cover_first[q] < 0, ExcMessage("two cells on one lattice point"));
                cover_first[q] = all[i + 1];
                cover_level[q] = k;
              }
      }

    // ---- positions: same-level keys of cells and wall ghosts --------------------------
    // real cell: fine corner key * 8 + level (>= 0); wall ghost: -1 - (extended key * 8 +
    // level), extended coordinates at the ghost's level shifted by E
    const long long E = 2 * G + 2; // the farthest position looked at: 2 G outside
    auto ext_n = [&](const unsigned int k, const unsigned int d) { return d < dim ? Nk(k, d) + 2 * E : 1; };
    struct GhostInfo
    {
      BoundaryGhost      bg;
      long long          source_key;
      std::array<int, 3> pos;
      unsigned int       level;
    };
    std::map<long long, GhostInfo> ghost_info;
    // wrap periodic directions; false if outside a non-periodic side
    auto wrap = [&](const unsigned int k, std::array<long long, 3> &p) {
      bool inside = true;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const long long n = Nk(k, d);
          if (periodic_[d])
            {
              // positions lie a few cells outside at most: cheaper than a division
              while (p[d] < 0)
                p[d] += n;
              while (p[d] >= n)
                p[d] -= n;
            }
          else if (p[d] < 0 || p[d] >= n)
            inside = false;
        }
      return inside;
    };
    auto corner_key = [&](const unsigned int k, const std::array<long long, 3> &p) {
      std::array<long long, 3> c{{0, 0, 0}};
      for (unsigned int d = 0; d < dim; ++d)
        c[d] = p[d] << (m - k);
      return fine_key(c);
    };
    // the mirror (or outflow copy) inside the domain of an outside position p of level k,
    // with the wall reflections that map its state to p's
    auto mirror_of = [&](const unsigned int k, const std::array<long long, 3> &p, BoundaryGhost &bg) {
      std::array<long long, 3> q = p;
      unsigned int             flip = 0;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const long long n = Nk(k, d);
          if (periodic_[d] || (p[d] >= 0 && p[d] < n))
            continue;
          const unsigned int id = 2 * d + (p[d] >= n ? 1 : 0);
          const BoundaryType t  = btype_[id];
          if (t == BoundaryType::slip_wall || t == BoundaryType::no_slip_wall)
            {
              q[d] = p[d] < 0 ? -1 - p[d] : 2 * n - 1 - p[d];
              q[d] = std::min(std::max(q[d], 0ll), n - 1);
              flip |= 1u << d;
              const unsigned int w = bg.n_walls++;
              bg.wall_dir[w]       = d;
              bg.wall_id[w]        = id;
              bg.wall_no_slip[w]   = t == BoundaryType::no_slip_wall;
              if (t == BoundaryType::no_slip_wall)
                {
                  bg.no_slip = true;
                  for (unsigned int c = 0; c < 3; ++c)
                    bg.wall_velocity[w][c] = wall_velocity_[id][c] / velocity_unit_;
                }
            }
          else
            q[d] = p[d] < 0 ? 0 : n - 1; // outflow: copy
        }
      bg.flip_mask = flip;
      return q;
    };
    // the key of the same-level cell or wall ghost at position p of level k, or no_slot_key
    auto same_level = [&](const unsigned int k, std::array<long long, 3> p) -> long long {
      if (wrap(k, p))
        {
          const long long fk = corner_key(k, p);
          return cover_level[fk] == int(k) ? fk * 8 + k : no_slot_key;
        }
      // a wall (or outflow) ghost: mirror (copy) of the same-level cell inside
      GhostInfo                      gi;
      const std::array<long long, 3> q  = mirror_of(k, p, gi.bg);
      const long long                qk = corner_key(k, q);
      if (cover_level[qk] != int(k))
        return no_slot_key;
      long long ek = 0;
      for (int d = dim - 1; d >= 0; --d)
        ek = ek * ext_n(k, d) + (p[d] + E);
      const long long key = -1 - (ek * 8 + k);
      if (!ghost_info.count(key))
        {
          gi.source_key = qk * 8 + k;
          for (unsigned int d = 0; d < 3; ++d)
            gi.pos[d] = p[d];
          gi.level        = k;
          ghost_info[key] = gi;
        }
      return key;
    };
    // level and position of a key
    auto decode = [&](const long long key, unsigned int &k, std::array<long long, 3> &p) {
      if (key >= 0)
        {
          k                  = key & 7;
          const long long fk = key >> 3;
          p                  = {{fk % Nf[0], (fk / Nf[0]) % Nf[1], fk / (Nf[0] * Nf[1])}};
          for (unsigned int d = 0; d < dim; ++d)
            p[d] >>= (m - k);
        }
      else
        {
          const auto &gi = ghost_info.at(key);
          k              = gi.level;
          p              = {{gi.pos[0], gi.pos[1], gi.pos[2]}};
        }
    };
    // the leaf covering position p of level k (any level), or no_slot_key outside
    auto covering = [&](const unsigned int k, std::array<long long, 3> p) -> long long {
      if (!wrap(k, p))
        return no_slot_key;
      const long long          fk = corner_key(k, p);
      const unsigned int       l  = cover_level[fk];
      std::array<long long, 3> c{{fk % Nf[0], (fk / Nf[0]) % Nf[1], fk / (Nf[0] * Nf[1])}};
      for (unsigned int d = 0; d < dim; ++d)
        c[d] = (c[d] >> (m - l)) << (m - l);
      return fine_key(c) * 8 + l;
    };
    // gradient neighbour: same level, else a coarser leaf, else none
    auto gradient_key = [&](const long long key, const unsigned int j, const int o) -> long long {
      unsigned int             k;
      std::array<long long, 3> p;
      decode(key, k, p);
      p[j] += o;
      const long long t = same_level(k, p);
      if (t != no_slot_key)
        return t;
      const long long c = covering(k, p);
      return (c != no_slot_key && int(c & 7) < int(k)) ? c : no_slot_key;
    };

    // ---- the slots each owned cell needs ------------------------------------------------
    // the keys of the slots needed (collected with repetitions, then sorted and made unique)
    std::vector<long long> needed;
    auto make_unique = [&]() {
      std::sort(needed.begin(), needed.end());
      needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    };
    std::unordered_map<long long, unsigned int> slot_of;
    for (unsigned int i = 0; i < n_owned_; ++i)
      slot_of[owned[i].key] = i;
    // face neighbour keys of owned cell i per direction and side (canonical order)
    std::vector<std::vector<long long>> face_keys(std::size_t(n_owned_) * dim * 2);
    for (unsigned int i = 0; i < n_owned_; ++i)
      {
        const unsigned int       k = owned[i].level;
        std::array<long long, 3> p0{{owned[i].ijk[0], owned[i].ijk[1], owned[i].ijk[2]}};
        // faces: same level, one coarser leaf, or 2^(dim-1) finer leaves
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int side = 0; side < 2; ++side)
            {
              auto &fk = face_keys[(std::size_t(i) * dim + d) * 2 + side];
              std::array<long long, 3> q = p0;
              q[d] += side ? 1 : -1;
              const long long t = same_level(k, q);
              if (t != no_slot_key)
                fk.push_back(t);
              else
                {
                  const long long c = covering(k, q);
                  AssertThrow(c != no_slot_key, ExcInternalError());
                  const unsigned int l = c & 7;
                  if (l < k)
                    fk.push_back(c);
                  else
                    {
                      // q is refined (its corner may be finer still, away from s's face):
                      // 2:1 balance puts level k+1 cells along the face
                      wrap(k, q);
                      const unsigned int t1 = (d + 1) % dim, t2 = (d + 2) % dim;
                      const unsigned int n1 = dim > 1 ? 2 : 1, n2 = dim > 2 ? 2 : 1;
                      for (unsigned int b = 0; b < n2; ++b) // t1 fastest
                        for (unsigned int a = 0; a < n1; ++a)
                          {
                            std::array<long long, 3> f{{2 * q[0], 2 * q[1], 2 * q[2]}};
                            for (unsigned int e = dim; e < 3; ++e)
                              f[e] = 0;
                            f[d] += side ? 0 : 1;
                            if (dim > 1)
                              f[t1] += a;
                            if (dim > 2)
                              f[t2] += b;
                            const long long ft = same_level(k + 1, f);
                            AssertThrow(ft != no_slot_key, ExcMessage("the mesh is not 2:1 balanced"));
                            fk.push_back(ft);
                          }
                    }
                }
              for (const long long t : fk)
                needed.push_back(t);
            }
      }
    // the face cells: owned cells and their face neighbours (they need reconstruction
    // boxes and gradient stencils)
    std::set<long long> face_cells;
    for (unsigned int i = 0; i < n_owned_; ++i)
      {
        face_cells.insert(owned[i].key);
        for (unsigned int f = 0; f < dim * 2; ++f)
          for (const long long t : face_keys[std::size_t(i) * dim * 2 + f])
            face_cells.insert(t);
      }
    // gradient stencils of the face cells
    {
      for (const long long c : face_cells)
        for (unsigned int j = 0; j < dim; ++j)
          for (const int o : {-1, 1})
            {
              const long long t = gradient_key(c, j, o);
              if (t != no_slot_key)
                needed.push_back(t);
            }
    }
    // ---- virtual cells ----------------------------------------------------------------------
    // Every position of the reconstruction box (Chebyshev radius r) of a face cell that is
    // not a leaf of the cell's level gets a virtual cell: the volume average of the finer
    // leaves inside it (restriction) or the linear prolongation of the coarser leaf that
    // contains it (its value plus central-difference slopes, region_sources below); outside
    // a wall, the mirror of such a position.
    // WENO then runs on a uniform (partly virtual) neighbourhood everywhere.
    struct Virtual
    {
      unsigned int                             level;
      std::array<long long, 3>                 pos;
      std::vector<std::pair<long long, double>> sources; ///< (leaf key, weight), inside
      bool                                     ghost = false;
      BoundaryGhost                            bg;      ///< outside: reflections of the mirror
      unsigned int                             mirror = 0; ///< outside: index of the mirror
    };
    std::vector<Virtual>                            virtuals;
    struct KeyHash
    {
      std::size_t operator()(const std::array<long long, 4> &a) const
      {
        std::size_t h = 0;
        for (const long long v : a)
          h = h * 0x9E3779B97F4A7C15ull + std::hash<long long>()(v);
        return h;
      }
    };
    std::unordered_map<std::array<long long, 4>, unsigned int, KeyHash> virtual_index;
    virtual_index.reserve(4 * face_cells.size());
    const int r = int(G) - 1;
    // (key, weight) lists sorted by key, weights of equal keys summed in insertion order
    // (a few entries: a linear search beats a map)
    auto add_weight = [](std::vector<std::pair<long long, double>> &v, const long long key, const double w) {
      for (auto &e : v)
        if (e.first == key)
          {
            e.second += w;
            return;
          }
      v.emplace_back(key, w);
    };
    auto region_sources = [&](const unsigned int k, const std::array<long long, 3> &q) {
      std::vector<std::pair<long long, double>> src;
      const long long                           c = covering(k, q);
      if (int(c & 7) <= int(k))
        {
          // prolongation: the coarse leaf's value plus its central-difference slope along
          // each direction with two leaf neighbours (same level or coarser), evaluated at
          // the virtual cell's centre (linear, exact for linear data; the transitions lie
          // where the indicator found the solution smooth)
          add_weight(src, c, 1.);
          const unsigned int       l = c & 7;
          std::array<long long, 3> pc;
          unsigned int             lc;
          decode(c, lc, pc);
          for (unsigned int j = 0; j < dim && l < k; ++j)
            {
              const long long tm = gradient_key(c, j, -1), tp = gradient_key(c, j, 1);
              if (tm < 0 || tp < 0) // a wall ghost or none: constant along j
                continue;
              const double hl = 1. / double(1u << l);
              const double om = -0.5 * (hl + 1. / double(1u << (tm & 7)));
              const double op = 0.5 * (hl + 1. / double(1u << (tp & 7)));
              // centre of the virtual cell relative to the coarse centre, in level-0 units
              // (positions wrap periodically: use the offset inside the coarse cell)
              const long long rel   = q[j] - (pc[j] << (k - l));
              const double    delta = (rel + 0.5) / double(1u << k) - 0.5 * hl;
              add_weight(src, tp, delta / (op - om));
              add_weight(src, tm, -(delta / (op - om)));
            }
        }
      else
        {
          const long long             span = 1ll << (m - k);
          const double                w    = 1. / std::pow(double(span), double(dim));
          for (long long z = 0; z < (dim > 2 ? span : 1); ++z)
            for (long long y = 0; y < (dim > 1 ? span : 1); ++y)
              for (long long x = 0; x < span; ++x)
                add_weight(src, covering(m, {{(q[0] << (m - k)) + x, (q[1] << (m - k)) + y, (q[2] << (m - k)) + z}}), w);
        }
      std::sort(src.begin(), src.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
      return src;
    };
    std::function<unsigned int(unsigned int, const std::array<long long, 3> &)> add_virtual =
      [&](const unsigned int k, const std::array<long long, 3> &q) -> unsigned int {
      std::array<long long, 3> w      = q;
      const bool               inside = wrap(k, w);
      const std::array<long long, 4> key{{k, inside ? w[0] : q[0], inside ? w[1] : q[1], inside ? w[2] : q[2]}};
      if (const auto it = virtual_index.find(key); it != virtual_index.end())
        return it->second;
      Virtual v;
      v.level = k;
      v.pos   = inside ? w : q;
      std::array<long long, 3> mq{{0, 0, 0}};
      if (inside)
        v.sources = region_sources(k, w);
      else
        {
          v.ghost = true;
          mq      = mirror_of(k, q, v.bg);
        }
      const unsigned int index = virtuals.size();
      virtuals.push_back(v);
      virtual_index[key] = index;
      if (!inside)
        {
          const unsigned int mi = add_virtual(k, mq);
          virtuals[index].mirror = mi;
        }
      return index;
    };
    {
      // the boxes overlap (each leaf lies in up to 5^dim of them): a leaf is pushed once,
      // marked at its fine corner (leaves do not overlap)
      std::vector<char> seen(n_fine, 0);
      for (const long long u : face_cells)
        {
          unsigned int             k;
          std::array<long long, 3> p0;
          decode(u, k, p0);
          for (int z = (dim > 2 ? -r : 0); z <= (dim > 2 ? r : 0); ++z)
            for (int y = (dim > 1 ? -r : 0); y <= (dim > 1 ? r : 0); ++y)
              for (int x = -r; x <= r; ++x)
                {
                  const std::array<long long, 3> q{{p0[0] + x, p0[1] + y, p0[2] + z}};
                  const long long                t = same_level(k, q);
                  if (t == no_slot_key)
                    add_virtual(k, q);
                  else if (t < 0)
                    needed.push_back(t);
                  else if (!seen[t >> 3])
                    {
                      seen[t >> 3] = 1;
                      needed.push_back(t);
                    }
                }
        }
      for (const auto &v : virtuals)
        for (const auto &[t, w] : v.sources)
          needed.push_back(t);
    }
    // wall ghosts need their source cells
    make_unique();
    for (std::size_t i = 0, n = needed.size(); i < n; ++i)
      if (needed[i] < 0)
        needed.push_back(ghost_info.at(needed[i]).source_key);
    make_unique();

    // ---- slots: owned, MPI ghosts (by DoF), wall ghosts (by key) -----------------------
    lattice_.clear();
    level_.clear();
    active_index_.clear();
    for (const auto &o : owned)
      {
        lattice_.push_back(o.ijk);
        level_.push_back(o.level);
        active_index_.push_back(o.active);
      }
    std::vector<std::pair<long long, long long>> mpi_ghosts; // (first dof, key)
    for (const long long t : needed)
      if (t >= 0 && !slot_of.count(t))
        mpi_ghosts.emplace_back(cover_first[t >> 3], t);
    std::sort(mpi_ghosts.begin(), mpi_ghosts.end());
    IndexSet ghost_dofs(dofh->n_dofs());
    std::vector<long long> slot_keys;
    for (const auto &o : owned)
      slot_keys.push_back(o.key);
    for (const auto &[first, key] : mpi_ghosts)
      {
        slot_of[key] = lattice_.size();
        unsigned int             k;
        std::array<long long, 3> p;
        decode(key, k, p);
        lattice_.push_back({{int(p[0]), int(p[1]), int(p[2])}});
        level_.push_back(k);
        slot_keys.push_back(key);
        ghost_dofs.add_range(first, first + n_components);
      }
    n_mpi_ghost_ = mpi_ghosts.size();
    ghost_dofs.compress();
    part = std::make_shared<Utilities::MPI::Partitioner>(owned_dofs, ghost_dofs, comm);
    bghosts_.clear();
    for (const long long t : needed)
      if (t < 0)
        {
          const auto &gi = ghost_info.at(t);
          slot_of[t]     = lattice_.size();
          lattice_.push_back(gi.pos);
          level_.push_back(gi.level);
          slot_keys.push_back(t);
        }
    for (const long long t : needed)
      if (t < 0)
        {
          BoundaryGhost bg = ghost_info.at(t).bg;
          bg.slot          = slot_of.at(t);
          bg.source        = slot_of.at(ghost_info.at(t).source_key);
          bghosts_.push_back(bg);
        }
    const unsigned int first_virtual = lattice_.size();
    for (const auto &v : virtuals)
      {
        lattice_.push_back({{int(v.pos[0]), int(v.pos[1]), int(v.pos[2])}});
        level_.push_back(v.level);
        slot_keys.push_back(no_slot_key);
      }
    virtual_.clear();
    for (unsigned int i = 0; i < virtuals.size(); ++i)
      if (virtuals[i].ghost)
        {
          BoundaryGhost bg = virtuals[i].bg;
          bg.slot          = first_virtual + i;
          bg.source        = first_virtual + virtuals[i].mirror;
          bghosts_.push_back(bg);
        }
      else
        {
          VirtualCell vc;
          vc.slot = first_virtual + i;
          for (const auto &[t, w] : virtuals[i].sources)
            vc.sources.emplace_back(slot_of.at(t), w);
          virtual_.push_back(vc);
        }
    const unsigned int ns = lattice_.size();

    // boundary ids of the real cells' faces: box faces are colorized (id 2 d + upper)
    slot_face_id_.assign(std::size_t(n_owned_ + n_mpi_ghost_) * 2 * dim, -1);
    for (unsigned int s = 0; s < n_owned_ + n_mpi_ghost_; ++s)
      for (unsigned int d = 0; d < dim; ++d)
        if (!periodic_[d])
          {
            if (lattice_[s][d] == 0)
              slot_face_id_[std::size_t(s) * 2 * dim + 2 * d] = 2 * d;
            if (lattice_[s][d] == Nk(level_[s], d) - 1)
              slot_face_id_[std::size_t(s) * 2 * dim + 2 * d + 1] = 2 * d + 1;
          }

    auto slot_or = [&](const long long key) -> int {
      if (key == no_slot_key)
        return -1;
      const auto it = slot_of.find(key);
      return it == slot_of.end() ? -1 : int(it->second);
    };

    // the slot at position q of level k: a leaf or wall ghost of that level, or a virtual cell
    auto slot_at = [&](const unsigned int k, const std::array<long long, 3> &q) -> int {
      const long long t = same_level(k, q);
      if (t != no_slot_key)
        return slot_or(t);
      std::array<long long, 3> w      = q;
      const bool               inside = wrap(k, w);
      const auto it = virtual_index.find({{k, inside ? w[0] : q[0], inside ? w[1] : q[1], inside ? w[2] : q[2]}});
      return it == virtual_index.end() ? -1 : int(first_virtual + it->second);
    };

    // ---- neighbour table (same level or virtual), uniform flags -----------------------
    const unsigned int W = 2 * G + 1;
    nb_.assign(std::size_t(ns) * dim * W, -1);
    uniform_.assign(ns, 0);
    for (unsigned int s = 0; s < ns; ++s)
      {
        const unsigned int       k = level_[s];
        std::array<long long, 3> p0{{lattice_[s][0], lattice_[s][1], lattice_[s][2]}};
        for (unsigned int d = 0; d < dim; ++d)
          for (int o = -int(G); o <= int(G); ++o)
            {
              std::array<long long, 3> q = p0;
              q[d] += o;
              nb_[(std::size_t(s) * dim + d) * W + (o + int(G))] = slot_at(k, q);
            }
        bool ok = s < n_owned_; // the flag is for owned cells (output) only
        for (int z = (dim > 2 ? -r : 0); z <= (dim > 2 ? r : 0) && ok; ++z)
          for (int y = (dim > 1 ? -r : 0); y <= (dim > 1 ? r : 0) && ok; ++y)
            for (int x = -r; x <= r && ok; ++x)
              ok = slot_or(same_level(k, {{p0[0] + x, p0[1] + y, p0[2] + z}})) >= 0;
        uniform_[s] = ok ? 1 : 0;
      }

    // ---- gradient neighbours --------------------------------------------------------------
    gnb_.assign(std::size_t(ns) * dim * 2, -1);
    goff_.assign(std::size_t(ns) * dim * 2, 0.);
    for (unsigned int s = 0; s < ns; ++s)
      for (unsigned int j = 0; j < dim; ++j)
        for (unsigned int side = 0; side < 2; ++side)
          {
            if (s >= first_virtual)
              continue;
            const int t = slot_or(gradient_key(slot_keys[s], j, side ? 1 : -1));
            gnb_[(std::size_t(s) * dim + j) * 2 + side] = t;
            if (t >= 0)
              goff_[(std::size_t(s) * dim + j) * 2 + side] =
                (side ? 0.5 : -0.5) * (cell_size(s, j) + cell_size(t, j));
          }

    // ---- faces ----------------------------------------------------------------------------
    std::vector<std::vector<unsigned int>> lists(face_keys.size());
    for (std::size_t f = 0; f < face_keys.size(); ++f)
      for (const long long t : face_keys[f])
        lists[f].push_back(slot_of.at(t));
    make_faces(lists);
  }

  template <int dim>
  long long CartesianPatch<dim>::leaf_key(const unsigned int s) const
  {
    long long key = 0;
    for (int d = dim - 1; d >= 0; --d)
      key = key * ((long long)(N_[d]) << max_level_) + fine_begin(s, d);
    return key * 8 + level_[s];
  }

  template <int dim>
  bool CartesianPatch<dim>::adapt(const std::vector<signed char> &flags,
                                  LinearAlgebra::distributed::Vector<double> &U,
                                  const std::function<bool(const double *)> &admissible)
  {
    if constexpr (dim == 1)
      {
        (void)flags;
        (void)U;
        (void)admissible;
        AssertThrow(false, ExcMessage("adaptive meshes need 2 or 3 dimensions"));
        return false;
      }
    else
      {
        auto &ptria = dynamic_cast<parallel::distributed::Triangulation<dim> &>(*tria);
        AssertThrow(flags.size() == n_owned_, ExcMessage("one flag per owned cell"));
        std::vector<int> slot_of_active(tria->n_active_cells(), -1);
        for (unsigned int s = 0; s < n_owned_; ++s)
          slot_of_active[active_index_[s]] = s;
        unsigned int changes = 0;
        for (const auto &cell : tria->active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const int s = slot_of_active[cell->active_cell_index()];
              cell->clear_refine_flag();
              cell->clear_coarsen_flag();
              if (flags[s] > 0 && level_[s] < max_level_)
                {
                  cell->set_refine_flag();
                  ++changes;
                }
              else if (flags[s] < 0 && level_[s] > 0)
                {
                  cell->set_coarsen_flag();
                  ++changes;
                }
            }
        if (Utilities::MPI::sum(changes, comm) == 0)
          return false;
        // the state with the ghost values deal.II expects (locally relevant = one layer)
        IndexSet relevant;
        DoFTools::extract_locally_relevant_dofs(*dofh, relevant);
        LinearAlgebra::distributed::Vector<double> old(dofh->locally_owned_dofs(), relevant, comm);
        for (std::size_t i = 0; i < std::size_t(n_owned_) * n_components; ++i)
          old.local_element(i) = U.local_element(i);
        old.update_ghost_values();
        tria->prepare_coarsening_and_refinement();
        unsigned long long nr = 0, nc = 0;
        for (const auto &cell : tria->active_cell_iterators())
          if (cell->is_locally_owned())
            {
              nr += cell->refine_flag_set() ? 1 : 0;
              nc += cell->coarsen_flag_set() ? 1 : 0;
            }
        last_refined_   = Utilities::MPI::sum(nr, comm);
        last_coarsened_ = Utilities::MPI::sum(nc, comm);
        // limited linear prolongation: each cell carries, through the transfer, its
        // minmod slopes per direction (from the gradient neighbours, all components) and
        // its level; a child then knows it is new (its level is higher) and takes the
        // parent's value plus the slopes times its offset from the parent's centre. The
        // offsets of the 2^dim children sum to zero: conservative to round-off.
        constexpr unsigned int NC = n_components;
        const bool linear = bool(admissible);
        // carried[d < dim]: the slopes along d; carried[dim]: the level (in every component)
        std::vector<LinearAlgebra::distributed::Vector<double>> carried(linear ? dim + 1 : 0);
        if (linear)
          {
            std::vector<double> W;
            gather(U, W);
            for (auto &v : carried)
              v.reinit(dofh->locally_owned_dofs(), relevant, comm);
            for (unsigned int s = 0; s < n_owned_; ++s)
              {
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    const int m = gradient_neighbor(s, d, 0), q = gradient_neighbor(s, d, 1);
                    for (unsigned int c = 0; c < NC; ++c)
                      {
                        double sigma = 0;
                        if (m >= 0 && q >= 0)
                          {
                            const double u  = W[std::size_t(s) * NC + c];
                            const double sl = (u - W[std::size_t(m) * NC + c]) / -gradient_offset(s, d, 0);
                            const double sr = (W[std::size_t(q) * NC + c] - u) / gradient_offset(s, d, 1);
                            sigma = sl * sr > 0 ? (std::abs(sl) < std::abs(sr) ? sl : sr) : 0.;
                          }
                        carried[d].local_element(std::size_t(s) * NC + c) = sigma;
                      }
                  }
                for (unsigned int c = 0; c < NC; ++c)
                  carried[dim].local_element(std::size_t(s) * NC + c) = level_[s];
              }
            for (auto &v : carried)
              v.update_ghost_values();
          }
        std::vector<const LinearAlgebra::distributed::Vector<double> *> in{&old};
        for (const auto &v : carried)
          in.push_back(&v);
        parallel::distributed::SolutionTransfer<dim, LinearAlgebra::distributed::Vector<double>> st(*dofh);
        st.prepare_for_coarsening_and_refinement(in);
        ptria.execute_coarsening_and_refinement();
        rebuild_box();
        std::vector<LinearAlgebra::distributed::Vector<double>> out(in.size());
        std::vector<LinearAlgebra::distributed::Vector<double> *> outp;
        for (auto &v : out)
          {
            v.reinit(dofh->locally_owned_dofs(), comm);
            outp.push_back(&v);
          }
        st.interpolate(outp);
        U.reinit(part);
        for (std::size_t i = 0; i < std::size_t(n_owned_) * NC; ++i)
          U.local_element(i) = out[0].local_element(i);
        if (linear)
          for (unsigned int s = 0; s < n_owned_; ++s)
            {
              if (double(level_[s]) <= out[dim + 1].local_element(std::size_t(s) * NC))
                continue;
              // the value of sibling `sib` (bit d set: upper half along d); all 2^dim
              // siblings admissible, or the family keeps the parent's value
              double *u = &U.local_element(std::size_t(s) * NC);
              auto    sibling = [&](const unsigned int sib, double *child) {
                for (unsigned int c = 0; c < NC; ++c)
                  {
                    child[c] = u[c];
                    for (unsigned int d = 0; d < dim; ++d)
                      child[c] += out[1 + d].local_element(std::size_t(s) * NC + c) * 0.5 * cell_size(s, d) *
                                  ((sib >> d & 1u) ? 1. : -1.);
                  }
              };
              double child[NC];
              bool   ok = true;
              for (unsigned int sib = 0; sib < (1u << dim) && ok; ++sib)
                {
                  sibling(sib, child);
                  ok = admissible(child);
                }
              if (!ok)
                continue;
              unsigned int mine = 0;
              for (unsigned int d = 0; d < dim; ++d)
                mine |= (lattice_[s][d] & 1u) << d;
              sibling(mine, child);
              std::copy(child, child + NC, u);
            }
        return true;
      }
  }

  template <int dim>
  void CartesianPatch<dim>::refine_to(const std::vector<long long> &cells)
  {
    if constexpr (dim == 1)
      {
        AssertThrow(cells.empty() || max_level_ == 0, ExcMessage("adaptive meshes need 2 or 3 dimensions"));
      }
    else
      {
        // a leaf of the target at level l inside an active cell of level k < l: refine it
        std::set<long long> target(cells.begin(), cells.end());
        for (unsigned int pass = 0; pass < max_level_; ++pass)
          {
            unsigned int n = 0;
            for (const auto &cell : tria->active_cell_iterators())
              if (cell->is_locally_owned())
                {
                  // this cell's leaf key; refine unless it is a target leaf or contains none
                  const unsigned int k = cell->level() - base_tria_level_;
                  long long          key = 0;
                  bool               refine = false;
                  for (int d = dim - 1; d >= 0; --d)
                    key = key * ((long long)(N_[d]) << max_level_) +
                          ((long long)(std::floor((cell->center()[d] - lo_[d]) / (h_[d] / double(1u << k))))
                           << (max_level_ - k));
                  if (k < max_level_ && !target.count(key * 8 + k))
                    {
                      // is any target leaf of a finer level at this corner? (leaves of a
                      // refined cell include one at its lower corner)
                      for (unsigned int l = k + 1; l <= max_level_ && !refine; ++l)
                        refine = target.count(key * 8 + l) > 0;
                    }
                  if (refine)
                    {
                      cell->set_refine_flag();
                      ++n;
                    }
                }
            if (Utilities::MPI::sum(n, comm) == 0)
              break;
            tria->execute_coarsening_and_refinement();
          }
        rebuild_box();
      }
  }

  template <int dim>
  void CartesianPatch<dim>::gather(const LinearAlgebra::distributed::Vector<double> &U,
                                   std::vector<double>                             &W) const
  {
    constexpr unsigned int NC = n_components;
    U.update_ghost_values();
    const std::size_t nloc = std::size_t(n_owned_ + n_mpi_ghost_) * NC;
    AssertThrow(U.locally_owned_size() + U.get_partitioner()->n_ghost_indices() == nloc,
                ExcMessage("state vector does not match the patch"));
    W.resize(std::size_t(n_slots()) * NC);
    if (nloc > 0)
      std::copy(U.begin(), U.begin() + nloc, W.begin()); // ghosts follow the owned entries
    for (const auto &v : virtual_) // restriction / prolongation next to level changes
      for (unsigned int c = 0; c < NC; ++c)
        {
          double sum = 0;
          for (const auto &[t, w] : v.sources)
            sum += w * W[std::size_t(t) * NC + c];
          W[std::size_t(v.slot) * NC + c] = sum;
        }
    for (const auto &g : bghosts_)
      {
        const double *in  = &W[std::size_t(g.source) * NC];
        double       *out = &W[std::size_t(g.slot) * NC];
        if (g.no_slip)
          {
            // compose the wall reflections; n and the internal energy are copied
            const double n = in[0];
            double       u[3] = {0, 0, 0}, ke = 0, keg = 0;
            for (unsigned int k = 0; k < dim; ++k)
              {
                u[k] = in[1 + k] / n;
                ke += 0.5 * n * u[k] * u[k];
              }
            for (unsigned int w = 0; w < g.n_walls; ++w)
              if (g.wall_no_slip[w])
                for (unsigned int k = 0; k < dim; ++k)
                  u[k] = 2 * g.wall_velocity[w][k] - u[k];
              else
                u[g.wall_dir[w]] = -u[g.wall_dir[w]];
            out[0] = n;
            for (unsigned int k = 0; k < dim; ++k)
              {
                out[1 + k] = n * u[k];
                keg += 0.5 * n * u[k] * u[k];
              }
            out[dim + 1] = in[dim + 1] - ke + keg;
          }
        else
          for (unsigned int c = 0; c < NC; ++c)
            {
              double v = in[c];
              if (c >= 1 && c <= dim && (g.flip_mask >> (c - 1) & 1u))
                v = -v;
              out[c] = v;
            }
      }
  }

  template class CartesianPatch<1>;
  template class CartesianPatch<2>;
  template class CartesianPatch<3>;
} // namespace granhydro
