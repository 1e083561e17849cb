#include <granhydro/mesh/cartesian_patch.h>
#include <granhydro/mesh/mesh_file.h>

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <cmath>
#include <map>
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
  double CartesianPatch<dim>::cell_volume() const
  {
    double v = 1;
    for (unsigned int d = 0; d < dim; ++d)
      v *= h_[d];
    return v;
  }

  template <int dim>
  Point<dim> CartesianPatch<dim>::center(const unsigned int s) const
  {
    Point<dim> p;
    for (unsigned int d = 0; d < dim; ++d)
      p[d] = lo_[d] + (lattice_[s][d] + 0.5) * h_[d];
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
  void CartesianPatch<dim>::build(const Scene &scene, const unsigned int ghost_width)
  {
    G = ghost_width;
    for (unsigned int i = 0; i < 6; ++i)
      btype_[i] = scene.boundary[i];
    dofh.reset();
    tria = make_triangulation<dim>(comm);

    if (scene.mesh_file.empty())
      {
        // ---- mesh: coarse box refined globally L times (p4est) -----------------
        for (unsigned int d = 0; d < 3; ++d)
          {
            N_[d]        = d < dim ? scene.cells[d] : 1;
            lo_[d]       = d < dim ? scene.lower[d] : 0;
            h_[d]        = d < dim ? (scene.upper[d] - scene.lower[d]) / N_[d] : 1;
            periodic_[d] = d < dim ? scene.boundary[2 * d] == BoundaryType::periodic : true;
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
            p1[d]  = scene.lower[d];
            p2[d]  = scene.upper[d];
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
      }
    else
      {
        // ---- mesh file: the lattice is the bounding box at the fine cell size ----
        if constexpr (dim == 1)
          {
            AssertThrow(false, ExcMessage("mesh files need 2 or 3 dimensions"));
          }
        else
          {
            Triangulation<dim> coarse;
            read_mesh_file(scene.mesh_file, coarse);
            const MeshFileInfo info = inspect_mesh(coarse);
            for (unsigned int d = 0; d < 3; ++d)
              {
                N_[d]  = d < dim ? info.lattice[d] << scene.mesh_refinements : 1;
                lo_[d] = d < dim ? info.lower[d] : 0;
                // the same expression as for the box: a box read from a file gets bitwise
                // the same cell size and centres as the generated one
                h_[d]        = d < dim ? (info.upper[d] - info.lower[d]) / N_[d] : 1;
                periodic_[d] = d >= dim;
              }
            tria->copy_triangulation(coarse);
            tria->refine_global(scene.mesh_refinements);
          }
      }
    const long long n_lattice = 1ll * N_[0] * N_[1] * N_[2];
    n_global_                 = tria->n_global_active_cells();

    fe   = std::make_unique<FESystem<dim>>(FE_DGQ<dim>(0), n_components);
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
    const int nranks = Utilities::MPI::n_mpi_processes(comm);
    auto all_gather = [&](const std::vector<long long> &mine) {
      std::vector<int> counts(nranks), displs(nranks);
      int mycount = mine.size();
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
    };
    std::vector<long long> first_dof_of(n_lattice, -1); // -1: solid lattice point
    {
      std::vector<long long> mine(2 * n_owned_);
      for (unsigned int i = 0; i < n_owned_; ++i)
        {
          mine[2 * i]     = owned[i].key;
          mine[2 * i + 1] = owned[i].first;
        }
      const auto all = all_gather(mine);
      AssertThrow(all.size() == 2 * n_global_, ExcMessage("mesh is not the expected lattice"));
      for (std::size_t i = 0; i < all.size(); i += 2)
        {
          AssertThrow(all[i] >= 0 && all[i] < n_lattice && first_dof_of[all[i]] < 0,
                      ExcMessage("two cells on one lattice point"));
          first_dof_of[all[i]] = all[i + 1];
        }
    }
    std::vector<long long> bfaces = all_gather(my_faces);
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
            const BoundaryType t = scene.boundary[id];
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
                      bg.wall_velocity[w][k] = scene.wall_velocity[id][k] / scene.units().velocity;
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
