#include <granhydro/mesh/mesh_file.h>
#include <granhydro/scene/domain.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void DomainParameters::declare_parameters(ParameterHandler &prm)
  {
    const DomainParameters defaults;
    prm.enter_subsection("Domain");
    {
      prm.declare_entry("Mesh file", default_text(defaults.mesh_file), Patterns::Anything(),
                        "Coarse mesh read with deal.II's GridIn instead of the box: gmsh "
                        "(.msh, e.g. format 2.2 ASCII) or ucd (.inp); 2D and 3D only. A relative "
                        "name is taken relative to the directory of the scene file. All cells "
                        "must be congruent axis-aligned boxes with vertices on one lattice "
                        "(axis-aligned blocks, e.g. a silo with an outlet; meshes/); the "
                        "lattice points of the bounding box without a cell are solid. The "
                        "boundary id of each boundary face selects the entries below: id 0 = "
                        "'Boundary x-', 1 = 'x+', 2 = 'y-', 3 = 'y+', 4 = 'z-', 5 = 'z+' (with "
                        "'Wall velocity' and 'Wall restitution' of the same name), whatever the "
                        "face's direction (deal.II's colorize convention: a box read from a "
                        "file behaves exactly like the generated box). Faces the file gives no "
                        "id get id 0. Periodic boundaries are not available with a mesh file. "
                        "With a mesh file 'Lower corner', 'Upper corner' and 'Cells' are ignored. "
                        "The file must be a regular file of at most 256 MiB; as for a box, its "
                        "vertices lie within +-1e6 m, its cells (after 'Mesh refinements') are at "
                        "least 1e-3 grain diameters, and it spans at least 2 cells per direction "
                        "(1 with first-order reconstruction).");
      prm.declare_entry("Mesh refinements", default_text(defaults.mesh_refinements), Patterns::Integer(0, 8),
                        "Global refinements of the mesh file's coarse cells (each halves the "
                        "cell size).");
      prm.declare_entry("Lower corner", default_text(defaults.lower), Patterns::Anything(),
                        "Lower corner of the box [m], one value per dimension (extra ignored; "
                        "ignored with a 'Mesh file').");
      prm.declare_entry("Upper corner", default_text(defaults.upper), Patterns::Anything(),
                        "Upper corner of the box [m] (ignored with a 'Mesh file').");
      prm.declare_entry("Cells", default_text(defaults.cells), Patterns::Anything(),
                        "Number of cells per direction (uniform Cartesian mesh; ignored with "
                        "a 'Mesh file').");
      for (unsigned int i = 0; i < 6; ++i)
        {
          const char *const s = side_names[i];
          prm.declare_entry(std::string("Boundary ") + s, to_string(defaults.boundary[i]),
                            selection_of<boundary::BoundaryType>(),
                            std::string("Boundary condition on the ") + s +
                              " side: periodic (both sides of a direction), slip wall "
                              "(reflecting, no tangential stress), no-slip wall (velocity "
                              "of the wall imposed, wall shear stress kept: doc/physics.md 5.1, "
                              "P10), outflow (transmissive, zero-gradient ghost state).");
          prm.declare_entry(
            std::string("Wall velocity ") + s, default_text(defaults.wall_velocity[i]), Patterns::Anything(),
            std::string("Velocity of the ") + s + " wall [m/s] (no-slip walls; tangential only).");
          prm.declare_entry(std::string("Wall restitution ") + s, default_text(defaults.wall_restitution[i]),
                            Patterns::Double(0, 1),
                            std::string("Grain-wall restitution eps_w of the ") + s +
                              " wall: 1 = elastic (adiabatic), < 1 = dissipative wall with "
                              "the heat flux q_w = (1 - eps_w) p_w sqrt(2T/(pi m)) "
                              "(doc/physics.md 5.2, contact theorem; granular model).");
        }
    }
    prm.leave_subsection();
  }

  void DomainParameters::parse_parameters(ParameterHandler &prm, const unsigned int dim,
                                          const std::string &source_name)
  {
    prm.enter_subsection("Domain");
    mesh_file        = relative_to_scene(prm.get("Mesh file"), source_name);
    mesh_refinements = prm.get_integer("Mesh refinements");
    lower            = parse_list<double, 3>(prm.get("Lower corner"), "Domain/Lower corner", dim, 0.);
    upper            = parse_list<double, 3>(prm.get("Upper corner"), "Domain/Upper corner", dim, 1.);
    {
      const auto c = parse_list<double, 3>(prm.get("Cells"), "Domain/Cells", dim, 1.);
      for (unsigned int d = 0; d < 3; ++d)
        {
          if (d < dim && (c[d] < 1 || c[d] != std::floor(c[d]) || c[d] > 1e6))
            throw SceneError("parameter 'Domain/Cells': entry " + std::to_string(d + 1) +
                             " must be a whole number between 1 and 1e6");
          cells[d] = d < dim ? static_cast<unsigned int>(c[d]) : 1;
        }
    }
    for (unsigned int i = 0; i < 6; ++i)
      {
        boundary[i] =
          get_enum<boundary::BoundaryType>(prm, "Domain", std::string("Boundary ") + side_names[i]);
        wall_velocity[i] =
          parse_list<double, 3>(prm.get(std::string("Wall velocity ") + side_names[i]),
                                std::string("Domain/Wall velocity ") + side_names[i], dim, 0.);
        wall_restitution[i] = prm.get_double(std::string("Wall restitution ") + side_names[i]);
      }
    prm.leave_subsection();
  }

  mesh::MeshFileInfo DomainParameters::check_mesh(const Scene &s)
  {
    const unsigned int dim  = s.dimension;
    const bool         mesh = !s.mesh_file.empty();
    mesh::MeshFileInfo mesh_info;
    if (mesh)
      {
        if (dim == 1)
          fail(s, "Domain/Mesh file", "mesh files need 'Dimension' 2 or 3");
        try
          {
            mesh_info = mesh::check_mesh_file(s.mesh_file, dim);
          }
        catch (const std::exception &e)
          {
            fail(s, "Domain/Mesh file", e.what());
          }
        for (unsigned int i = 0; i < 2 * dim; ++i)
          if (s.boundary[i] == boundary::BoundaryType::periodic)
            fail(s, "Domain/Mesh file",
                 std::string("periodic boundaries are not available with a "
                             "mesh file ('Boundary ") +
                   side_names[i] + "' = periodic); use walls or outflow");
        // a wall moves only tangentially: check against the faces' geometric directions
        for (const auto &[id, d] : mesh_info.id_direction)
          if (s.wall_velocity[id][d] != 0)
            fail(s, "Domain/Wall velocity " + std::string(side_names[id]),
                 "a wall moves only tangentially: the mesh has faces with boundary id " + std::to_string(id) +
                   " normal to " + std::string(1, "xyz"[d]) + ", so the " + std::string(1, "xyz"[d]) +
                   " component must be 0");
        double total = mesh_info.n_cells;
        for (unsigned int r = 0; r < s.mesh_refinements; ++r)
          total *= 1u << dim;
        if (total > 5e7)
          fail(s, "Domain/Mesh refinements", "more than 5e7 cells in total");
        // the limits of a box (check_box) on the mesh file's vertices and cells: a box
        // scaled by 1e-300 stepped at dt ~ 1e-300 s forever, scaled by 1e300 it ended in nan
        const double refine = std::ldexp(1., -int(s.mesh_refinements));
        for (unsigned int d = 0; d < dim; ++d)
          {
            const std::string axis(1, "xyz"[d]);
            if (!(std::abs(mesh_info.lower[d]) <= 1e6 && std::abs(mesh_info.upper[d]) <= 1e6))
              fail(s, "Domain/Mesh file",
                   "vertex coordinates must lie within +-1e6 m (as the "
                   "corners of a box); along " +
                     axis + " the mesh spans " + fmt(mesh_info.lower[d]) + " .. " + fmt(mesh_info.upper[d]) +
                     " m");
            const double h = mesh_info.cell_size[d] * refine;
            if (!(h >= 1e-3 * s.grain_diameter))
              fail(s, s.mesh_refinements > 0 ? "Domain/Mesh refinements" : "Domain/Mesh file",
                   "cells along " + axis + " would be smaller than 1e-3 grain diameters (" + fmt(h) +
                     " m after " + std::to_string(s.mesh_refinements) +
                     " refinements); cells must be at least 1e-3 'Material/Grain diameter', as in a box");
            // the reconstruction's stencil (a mesh file has no periodic sides): the lattice
            // spanned by the mesh, after the refinements, at least 2 cells wide unless first
            // order (a single cell ran with MUSCL and WENO5 where the box refuses it; the box
            // asks 3 for WENO5, but 2 coarse cells of a mesh file run with it: the silo's
            // outlet, parameters/silo-ci.prm)
            const unsigned int need = s.reconstruction == convection::ReconstructionType::first_order ? 1 : 2;
            const double       n    = double(mesh_info.lattice[d]) / refine;
            if (n < need)
              fail(s, "Domain/Mesh file",
                   "the mesh spans " + fmt(n) + " cell(s) along " + axis +
                     " (after 'Domain/Mesh refinements'), reconstruction '" + to_string(s.reconstruction) +
                     "' needs at least " + std::to_string(need) +
                     " between walls; refine the mesh "
                     "or choose another 'Numerics/Reconstruction'");
          }
      }
    return mesh_info;
  }

  void DomainParameters::check_box(const Scene &s)
  {
    const unsigned int dim  = s.dimension;
    const bool         mesh = !s.mesh_file.empty();
    for (unsigned int d = 0; d < dim && !mesh; ++d)
      {
        // coordinates up to 1e6 m (a corner at 1e308 overflowed the cell size), cells of at
        // least 1e-3 grain diameters (below that a run creeps at a vanishing time step)
        if (!(std::abs(s.lower[d]) <= 1e6))
          fail(s, "Domain/Lower corner", "coordinates must lie within +-1e6 m");
        if (!(std::abs(s.upper[d]) <= 1e6))
          fail(s, "Domain/Upper corner", "coordinates must lie within +-1e6 m");
        if (!(s.upper[d] > s.lower[d]))
          fail(s, "Domain/Upper corner",
               "must exceed 'Domain/Lower corner' in direction " + std::string(1, "xyz"[d]));
        if (!((s.upper[d] - s.lower[d]) / s.cells[d] >= 1e-3 * s.grain_diameter))
          fail(s, "Domain/Cells",
               "cells along " + std::string(1, "xyz"[d]) + " would be smaller than 1e-3 grain diameters (" +
                 fmt((s.upper[d] - s.lower[d]) / s.cells[d]) + " m)");
        const bool plo = s.boundary[2 * d] == boundary::BoundaryType::periodic;
        const bool phi = s.boundary[2 * d + 1] == boundary::BoundaryType::periodic;
        if (plo != phi)
          fail(s, std::string("Domain/Boundary ") + side_names[2 * d + (plo ? 1 : 0)],
               "periodic boundaries come in pairs: set both '" + std::string(side_names[2 * d]) + "' and '" +
                 side_names[2 * d + 1] + "' to periodic");
        const unsigned int need = s.reconstruction == convection::ReconstructionType::weno5 ?
                                    3 :
                                    (s.reconstruction == convection::ReconstructionType::first_order ? 1 : 2);
        if (!plo && s.cells[d] < need)
          fail(s, "Domain/Cells",
               "direction " + std::string(1, "xyz"[d]) + " has walls and needs at least " +
                 std::to_string(need) + " cells for reconstruction '" + to_string(s.reconstruction) + "'");
      }
  }

  void DomainParameters::check_walls(const Scene &s)
  {
    const unsigned int dim  = s.dimension;
    const bool         mesh = !s.mesh_file.empty();
    for (unsigned int i = 0; i < 2 * dim; ++i)
      {
        const std::string side = side_names[i];
        const unsigned    d    = i / 2;
        double            vmax = 0;
        for (unsigned int k = 0; k < dim; ++k)
          vmax = std::max(vmax, std::abs(s.wall_velocity[i][k]));
        for (unsigned int k = 0; k < 3; ++k)
          {
            if (!(std::abs(s.wall_velocity[i][k]) <= 1e4))
              fail(s, "Domain/Wall velocity " + side,
                   "|v| = " + fmt(std::abs(s.wall_velocity[i][k])) + " m/s; allowed up to 1e4 m/s");
            if (k >= dim && s.wall_velocity[i][k] != 0) // it would be ignored
              fail(s, "Domain/Wall velocity " + side,
                   "its " + std::string(1, "xyz"[k]) + " component names a direction the " +
                     std::to_string(dim) + "D scene does not resolve");
          }
        if (vmax != 0 && s.boundary[i] != boundary::BoundaryType::no_slip_wall)
          fail(s, "Domain/Wall velocity " + side,
               "only no-slip walls move (the boundary is " + to_string(s.boundary[i]) + ")");
        if (!(vmax <= 1e4))
          fail(s, "Domain/Wall velocity " + side, "|v| = " + fmt(vmax) + " m/s; allowed up to 1e4 m/s");
        if (!mesh && s.wall_velocity[i][d] != 0)
          fail(s, "Domain/Wall velocity " + side,
               "a wall moves only tangentially: its component "
               "along " +
                 std::string(1, "xyz"[d]) + " must be 0");
        if (s.wall_restitution[i] < 1 && (s.boundary[i] == boundary::BoundaryType::periodic ||
                                          s.boundary[i] == boundary::BoundaryType::outflow))
          fail(s, "Domain/Wall restitution " + side,
               "only walls dissipate (the boundary is " + to_string(s.boundary[i]) + ")");
        if (s.wall_restitution[i] < 1 && s.model != physics::Model::granular)
          fail(s, "Domain/Wall restitution " + side, "dissipative walls need 'Material/Model = granular'");
      }
  }

  void DomainParameters::check_cell_count(const Scene &s)
  {
    const unsigned int dim   = s.dimension;
    const bool         mesh  = !s.mesh_file.empty();
    double             total = 1;
    for (unsigned int d = 0; d < dim; ++d)
      total *= s.cells[d];
    if (!mesh && total > 5e7)
      fail(s, "Domain/Cells", "more than 5e7 cells in total");
  }
} // namespace granhydro::scene
