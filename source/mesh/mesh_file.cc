#include <granhydro/base/errors.h>
#include <granhydro/mesh/mesh_file.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_in.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace granhydro::mesh
{
  using namespace dealii;

  namespace
  {
    bool ends_with(const std::string &s, const std::string &suffix)
    {
      return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
    }
  } // namespace

  namespace
  {
    /// what GridIn would trust blindly: the format version, counts that announce more
    /// entries than the file has lines (a count of 1e12 made it allocate until bad_alloc),
    /// and negative physical tags (boundary ids; -1 silently became another boundary)
    void prescan_mesh_file(const std::string &filename, const bool msh)
    {
      std::ifstream            in(filename);
      std::vector<std::string> lines;
      for (std::string line; std::getline(in, line);)
        lines.push_back(line);
      const auto bad = [&](const std::size_t i, const std::string &what) {
        throw MeshFileError("cannot read '" + filename + "' as " + (msh ? "a gmsh" : "a ucd") +
                            " mesh: line " + std::to_string(i + 1) + ": " + what);
      };
      const auto count_at = [&](const std::size_t i) {
        std::istringstream is(i < lines.size() ? lines[i] : std::string());
        long long          n = -1;
        if (!(is >> n) || n < 0)
          bad(i, "expected a count");
        if (std::size_t(n) > lines.size() - i - 1)
          bad(i, "announces " + std::to_string(n) + " entries, but only " +
                   std::to_string(lines.size() - i - 1) + " lines follow");
        return std::size_t(n);
      };
      if (!msh) // ucd: the first line that is not a comment holds the node and cell counts
        {
          for (std::size_t i = 0; i < lines.size(); ++i)
            if (!lines[i].empty() && lines[i][0] != '#')
              {
                std::istringstream is(lines[i]);
                long long          nn = -1, nc = -1;
                if (!(is >> nn >> nc) || nn < 0 || nc < 0 ||
                    std::size_t(nn) + std::size_t(nc) > lines.size() - i - 1)
                  bad(i, "node and cell counts do not match the file (" +
                           std::to_string(lines.size() - i - 1) + " lines follow)");
                return;
              }
          return;
        }
      for (std::size_t i = 0; i < lines.size(); ++i)
        {
          const std::string &l = lines[i];
          if (l.rfind("$MeshFormat", 0) == 0)
            {
              std::istringstream is(i + 1 < lines.size() ? lines[i + 1] : std::string());
              std::string        version;
              int                binary = -1;
              if (!(is >> version >> binary) || version != "2.2" || binary != 0)
                bad(i + 1, "gmsh format '" + (i + 1 < lines.size() ? lines[i + 1] : std::string()) +
                             "': only format 2.2 ASCII is read (export with gmsh -format msh22)");
            }
          else if (l.rfind("$Nodes", 0) == 0)
            count_at(i + 1);
          else if (l.rfind("$Elements", 0) == 0)
            {
              const std::size_t n = count_at(i + 1);
              for (std::size_t k = 0; k < n; ++k)
                {
                  std::istringstream is(lines[i + 2 + k]);
                  long long          id, type, ntags, tag;
                  if (!(is >> id >> type >> ntags))
                    bad(i + 2 + k, "cannot read the element");
                  for (long long t = 0; t < ntags; ++t)
                    if (!(is >> tag) || tag < 0)
                      bad(i + 2 + k, "element tags (physical id = boundary id, elementary id) must "
                                     "be non-negative integers");
                }
            }
        }
    }
  } // namespace

  template <int dim>
  void read_mesh_file(const std::string &filename, Triangulation<dim> &tria)
  {
    const bool msh = ends_with(filename, ".msh"), inp = ends_with(filename, ".inp");
    if (!msh && !inp)
      throw MeshFileError("'" + filename +
                          "' has an unknown extension (expected .msh for "
                          "gmsh or .inp for ucd)");
    // a mesh is a regular file of bounded size: a link to /dev/zero or /dev/urandom was
    // read until the memory ran out (the prescan keeps every line)
    std::error_code ec;
    const auto      status = std::filesystem::status(filename, ec);
    if (ec || !std::filesystem::exists(status))
      throw MeshFileError("cannot open '" + filename + "': no such file");
    if (!std::filesystem::is_regular_file(status))
      throw MeshFileError("'" + filename +
                          "' is not a regular file (a directory or a "
                          "device); give a .msh or .inp file");
    const std::uintmax_t bytes = std::filesystem::file_size(filename, ec);
    if (ec || bytes > max_mesh_file_bytes)
      throw MeshFileError("'" + filename + "' is larger than " + std::to_string(max_mesh_file_bytes >> 20) +
                          " MiB (or unreadable); give a coarser mesh and refine it with "
                          "'Domain/Mesh refinements'");
    std::ifstream in(filename);
    if (!in)
      throw MeshFileError("cannot open '" + filename + "'");
    prescan_mesh_file(filename, msh);
    GridIn<dim> gi;
    gi.attach_triangulation(tria);
    try
      {
        if (msh)
          gi.read_msh(in);
        else
          gi.read_ucd(in);
      }
    catch (const std::exception &e)
      {
        throw MeshFileError("cannot read '" + filename + "' as " + (msh ? "a gmsh" : "a ucd") +
                            " mesh: " + human_message(e.what()));
      }
    if (tria.n_active_cells() == 0)
      throw MeshFileError("'" + filename + "' has no cells");
  }

  template <int dim>
  MeshFileInfo inspect_mesh(const Triangulation<dim> &tria)
  {
    MeshFileInfo info;
    // bounding box of every cell; the first cell sets the size all others must have
    struct Box
    {
      Point<dim> lo, hi;
    };
    std::vector<Box> boxes;
    for (const auto &cell : tria.active_cell_iterators())
      {
        Box b{cell->vertex(0), cell->vertex(0)};
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int d = 0; d < dim; ++d)
            {
              b.lo[d] = std::min(b.lo[d], cell->vertex(v)[d]);
              b.hi[d] = std::max(b.hi[d], cell->vertex(v)[d]);
            }
        boxes.push_back(b);
      }
    const Box &ref = boxes[0];
    double     tol = 1e300;
    for (unsigned int d = 0; d < dim; ++d)
      {
        info.cell_size[d] = ref.hi[d] - ref.lo[d];
        tol               = std::min(tol, 1e-8 * info.cell_size[d]);
      }
    if (!(tol > 0))
      throw MeshFileError("a cell has zero extent");
    for (unsigned int d = 0; d < dim; ++d)
      {
        info.lower[d] = ref.lo[d];
        info.upper[d] = ref.hi[d];
      }
    for (const auto &b : boxes)
      for (unsigned int d = 0; d < dim; ++d)
        {
          info.lower[d] = std::min(info.lower[d], b.lo[d]);
          info.upper[d] = std::max(info.upper[d], b.hi[d]);
        }

    auto where = [](const auto &cell) {
      std::ostringstream os;
      os << "the cell centred at (" << cell->center() << ")";
      return os.str();
    };
    // every cell: a box (each vertex at its own corner) of the reference size on the lattice
    std::map<std::array<long long, 3>, unsigned int> occupied;
    unsigned int                                     index = 0;
    for (const auto &cell : tria.active_cell_iterators())
      {
        const Box &b = boxes[index++];
        for (unsigned int d = 0; d < dim; ++d)
          if (std::abs((b.hi[d] - b.lo[d]) - info.cell_size[d]) > tol)
            throw MeshFileError(where(cell) + " is not congruent with the first cell: all "
                                              "cells must be axis-aligned boxes of the same size");
        std::set<unsigned int> corners;
        for (const unsigned int v : cell->vertex_indices())
          {
            unsigned int mask = 0;
            for (unsigned int d = 0; d < dim; ++d)
              {
                const double x = cell->vertex(v)[d];
                if (std::abs(x - b.hi[d]) <= tol)
                  mask |= 1u << d;
                else if (std::abs(x - b.lo[d]) > tol)
                  throw MeshFileError(where(cell) + " is not an axis-aligned box");
              }
            corners.insert(mask);
          }
        double volume = 1;
        for (unsigned int d = 0; d < dim; ++d)
          volume *= info.cell_size[d];
        // a wrong vertex order (a twisted box) has all corners but not the box's volume
        if (corners.size() != cell->n_vertices() || std::abs(cell->measure() - volume) > 1e-6 * volume)
          throw MeshFileError(where(cell) + " is not an axis-aligned box (or its vertices "
                                            "are not in the format's order)");
        std::array<long long, 3> ijk{{0, 0, 0}};
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double q = (b.lo[d] - info.lower[d]) / info.cell_size[d];
            ijk[d]         = std::llround(q);
            if (std::abs(q - ijk[d]) > 1e-6)
              throw MeshFileError(where(cell) + " is not on the lattice of the other cells "
                                                "(its corner is not a whole number of cell sizes from the "
                                                "lower corner of the mesh)");
          }
        if (!occupied.emplace(ijk, 0).second)
          throw MeshFileError(where(cell) + " overlaps another cell");
      }
    for (unsigned int d = 0; d < dim; ++d)
      info.lattice[d] = std::llround((info.upper[d] - info.lower[d]) / info.cell_size[d]);
    info.n_cells             = boxes.size();
    const std::size_t stride = boxes.size() / 262144 + 1;
    for (std::size_t i = 0; i < boxes.size(); i += stride)
      {
        std::array<double, 3> c{{0, 0, 0}};
        for (unsigned int d = 0; d < dim; ++d)
          c[d] = 0.5 * (boxes[i].lo[d] + boxes[i].hi[d]);
        info.centres.push_back(c);
      }

    // boundary faces: ids in range, and no boundary face between two cells (which would
    // mean duplicated vertices, i.e. cells not connected)
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const types::boundary_id id = cell->face(f)->boundary_id();
            const auto [d, upper]       = face_direction(cell, f);
            if (id >= 2 * dim)
              throw MeshFileError("boundary id " + std::to_string(id) + " on a face of " + where(cell) +
                                  ": ids must lie in 0 .. " + std::to_string(2 * dim - 1) +
                                  " (0 = 'Boundary x-', 1 = 'Boundary x+', 2 = 'Boundary y-', ...)");
            std::array<long long, 3> n{{0, 0, 0}};
            for (unsigned int k = 0; k < dim; ++k)
              n[k] = std::llround((cell->center()[k] - 0.5 * info.cell_size[k] - info.lower[k]) /
                                  info.cell_size[k]);
            n[d] += upper ? 1 : -1;
            if (occupied.count(n))
              throw MeshFileError(where(cell) + " and its neighbour do not share their face "
                                                "(duplicated vertices?): the mesh must be conforming");
            info.id_direction.emplace(id, d);
          }
    return info;
  }

  MeshFileInfo check_mesh_file(const std::string &filename, const unsigned int dim)
  {
    if (dim == 2)
      {
        Triangulation<2> tria;
        read_mesh_file(filename, tria);
        return inspect_mesh(tria);
      }
    if (dim == 3)
      {
        Triangulation<3> tria;
        read_mesh_file(filename, tria);
        return inspect_mesh(tria);
      }
    throw MeshFileError("mesh files need 'Dimension' 2 or 3");
  }

  template void         read_mesh_file(const std::string &, Triangulation<2> &);
  template void         read_mesh_file(const std::string &, Triangulation<3> &);
  template MeshFileInfo inspect_mesh(const Triangulation<2> &);
  template MeshFileInfo inspect_mesh(const Triangulation<3> &);
} // namespace granhydro::mesh
