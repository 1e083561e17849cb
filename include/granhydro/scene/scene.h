#pragma once
/**
 * @file scene.h
 * A scene: everything a run needs, read from a deal.II ParameterHandler file
 * in SI units, validated before any work is done (README, "Running scenes"; scenes and
 * effects"). Internally the code works in scaled units (struct Units).
 */
#include <deal.II/base/parameter_handler.h>

#include <granhydro/base/errors.h>
#include <granhydro/base/units.h>
#include <granhydro/boundary/boundary_conditions.h>
#include <granhydro/convection/settings.h>
#include <granhydro/io/settings.h>
#include <granhydro/mesh/settings.h>

#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granhydro
{
  struct Scene
  {
    std::string source = "<default scene>";
    unsigned int dimension = 1;

    // Domain
    /// coarse mesh file (gmsh .msh or ucd .inp; empty: the box Lower/Upper corner, Cells),
    /// a relative name resolved against the scene file's directory (mesh/mesh_file.h)
    std::string  mesh_file;
    unsigned int mesh_refinements = 0; ///< global refinements of the file's coarse mesh
    std::array<double, 3>       lower{{0, 0, 0}}, upper{{1, 1, 1}};
    std::array<unsigned int, 3> cells{{1, 1, 1}};
    /// boundary[2*d] lower side, boundary[2*d+1] upper side of direction d; with a mesh
    /// file, boundary[i] applies to the faces with boundary id i (whatever their direction)
    std::array<BoundaryType, 6> boundary{};
    /// tangential velocity of each wall [m/s] (no-slip walls), 3 components
    std::array<std::array<double, 3>, 6> wall_velocity{};
    /// grain-wall restitution eps_w of each wall (1 = elastic/adiabatic, doc/physics.md 5.2)
    std::array<double, 6> wall_restitution{{1, 1, 1, 1, 1, 1}};

    // Material
    std::string model = "ideal gas";
    double grain_diameter   = 1e-3;
    double material_density = 2600;
    double adiabatic_index  = 5. / 3.;
    double restitution      = 1.;    // eps (granular model)
    double friction         = 0.;    // mu, grain-grain Coulomb friction (granular model)
    double phi_freezing     = 0.49;  // phi_f of Torquato's chi
    double phi_close_packing = 0.64; // phi_c
    double guard_delta      = 1e-3;  // C1 continuation of chi beyond phi_c - delta
    double max_free_path    = 0;     // [m] Knudsen cap of the transport coefficients; 0 = off

    // Dense closure (optional, off by default; physics/contact_pressure.h)
    std::string dense_closure = "none"; // none | johnson-jackson
    double      closure_F       = 0.05; // [Pa]
    double      closure_phi_min = 0.5;
    double      closure_r       = 2;
    double      closure_s       = 5;
    double      closure_time    = 0.5;  // t_f [s] of mu_f = t_f sin(theta_f) p_f
    double      closure_angle   = 28.5; // theta_f [degrees]

    // Initial state (FunctionParser expressions in x, y, z [m], SI values)
    std::string initial_packing_fraction = "0.01";
    std::string initial_velocity         = "0; 0; 0";
    std::string initial_temperature      = "1e-8";
    std::string initial_constants        = "";
    unsigned int initial_quadrature      = 3;
    std::string  initial_checkpoint      = ""; // restart/initial state from this file

    // Numerics
    ReconstructionType reconstruction = ReconstructionType::weno5;
    FaceQuadrature     face_quadrature = FaceQuadrature::gauss;
    /// convective flux through no-slip walls: false = the numerical flux between the cell and
    /// its mirror ghost (mass and energy set to 0); true = the paper's eq. 6.1a: zero mass and
    /// energy flux and only the wall pressure on the normal momentum (no tangential part)
    bool               no_slip_pressure_flux = false;
    FluxType           flux            = FluxType::musta;
    unsigned int musta_max_stages = 4;
    /// 2: the 1 % rule compares stages (at least 2); 1: also a first-stage test on the jump
    unsigned int musta_min_stages = 2;
    double       musta_tolerance  = 0.01;
    double       musta_local_cfl  = 0.9;
    double       cfl              = 0.4;
    double       fixed_time_step  = 0;   // [s], 0: from CFL
    double       reference_velocity = 0; // [m/s], 0: sqrt(g sigma), g = 9.81
    unsigned int max_step_retries = 6;
    /// Strang splitting with the diffusion step: merged (the closing C(dt/2) of a step and
    /// the opening one of the next taken as one convective step, synchronised at output
    /// times) or symmetric (C(dt/2) V(dt) C(dt/2) every step)
    bool         merge_strang     = true;

    // Effects (granular model) and body force
    bool                  convection      = true;
    bool                  viscosity       = true;
    bool                  heat_conduction = true;
    bool                  cooling         = true;
    bool                  diagonal_flux   = false; // paper's D_ii-only flux (5.6)
    std::array<double, 3> gravity{{0, 0, 0}};      // [m/s^2]
    double       vibration_amplitude = 0;          // [m], container displacement A sin(w t)
    double       vibration_frequency = 0;          // [Hz]
    unsigned int vibration_direction = 1;

    // Diffusion step
    std::string  integrator         = "cost-based";
    double       newton_tolerance   = 1e-10;
    unsigned int newton_max_iterations = 25;
    double       linear_tolerance   = 1e-12;
    bool         inexact_newton     = true; ///< Linear forcing = eisenstat-walker
    bool         reuse_matrix       = true; ///< Reuse Newton matrix
    std::string  preconditioner     = "block ilu";
    bool         full_jacobian      = false;

    /// true if the implicit diffusion/source step V runs (granular model only)
    bool diffusion_active() const;

    // Adaptivity (box domains in 2D/3D)
    unsigned int max_level         = 0;    ///< refinement levels above Domain/Cells; 0 = uniform
    std::string  adapt_indicator   = "jumps"; ///< jumps | second differences
    double       refine_threshold  = 0.05; ///< refine where the indicator exceeds this
    double       coarsen_threshold = 0.01; ///< coarsen where it stays below this
    unsigned int adapt_interval    = 5;    ///< steps between adaptations
    unsigned int adapt_buffer      = 2;    ///< the refine flag spreads over this many cell layers

    // Time
    double       end_time  = 1;
    unsigned int max_steps = 0;
    double       max_wall_seconds = 0; ///< 0 = no limit
    double       steady_tolerance = 0; // stop when KE and centre of mass change less per output interval

    // Output
    std::string  output_directory = "output";
    std::string  base_name        = "solution";
    /// a file of this run in the output directory: <Directory>/<Base name><suffix>
    /// (".pvd", ".checkpoint", "_profiles.csv", "_cross_section.csv", "_summary.csv"), so
    /// that two runs with different base names can share one directory
    std::string output_file(const std::string &suffix) const
    {
      return output_directory + "/" + base_name + suffix;
    }
    double       output_interval  = 0;
    bool         write_vtu        = true;
    bool         write_profiles   = true;
    bool         write_checkpoint = true;
    bool         write_summary    = true;
    int          profile_direction = -1; // -1: last dimension
    int          section_direction = -1; // 3D: average along this direction into a 2D map, -1: off
    double       progress_interval = 5;  // wall seconds
    bool         verbose           = true;

    Units units() const;
    /// what the convective step needs (convection/settings.h)
    convection::ConvectionSettings convection_settings() const;
    /// what the mesh needs (mesh/settings.h)
    MeshSettings mesh_settings() const;
    /// what the output needs (io/settings.h)
    io::OutputSettings output_settings() const;
    double grain_mass() const;
  };

  /// declare every parameter with its default, pattern and documentation
  void declare_scene_parameters(dealii::ParameterHandler &prm);

  /// the embedded default scene (a 2D cylindrical blast in the ideal-gas limit)
  std::string default_scene_text();

  /**
   * Read a scene from a file ("" = embedded default), validate it and
   * return it. Throws SceneError naming the offending parameter.
   */
  /// overrides: "Section/Name=value" (nested sections joined by '/'), applied after the
  /// file as if its last lines set them (command line -p)
  Scene read_scene(const std::string &filename, const std::vector<std::string> &overrides = {});

  /// the same from a string in .prm syntax (tests)
  Scene parse_scene(const std::string &text, const std::string &source_name,
                    const std::vector<std::string> &overrides = {});

  /// the effects the scene activates, each with the reason (README, "Running scenes")
  std::vector<std::pair<std::string, std::string>> active_effects(const Scene &scene);

  /// pi and the scene's 'Initial state/Constants' for the expressions; throws SceneError
  std::map<std::string, double> expression_constants(const Scene &scene);

  /// check every impossible combination; throws SceneError
  void validate(const Scene &scene);

  std::string to_string(ReconstructionType);
  std::string to_string(FluxType);
  std::string to_string(FaceQuadrature);
  std::string to_string(BoundaryType);
} // namespace granhydro
