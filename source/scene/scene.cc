#include <granhydro/mesh/mesh_file.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <cmath>
#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  convection::ConvectionSettings Scene::convection_settings() const
  {
    convection::ConvectionSettings c;
    c.reconstruction        = reconstruction;
    c.face_quadrature       = face_quadrature;
    c.flux                  = flux;
    c.musta_max_stages      = musta_max_stages;
    c.musta_min_stages      = musta_min_stages;
    c.musta_tolerance       = musta_tolerance;
    c.musta_local_cfl       = musta_local_cfl;
    c.no_slip_pressure_flux = no_slip_pressure_flux;
    c.no_wall_tension       = model == physics::Model::granular && cohesionless;
    c.length_unit           = units().length;
    return c;
  }

  mesh::MeshSettings Scene::mesh_settings() const
  {
    mesh::MeshSettings m;
    m.mesh_file        = mesh_file;
    m.mesh_refinements = mesh_refinements;
    m.lower            = lower;
    m.upper            = upper;
    m.cells            = cells;
    m.max_level        = max_level;
    for (unsigned int i = 0; i < m.walls.size(); ++i)
      m.walls[i] = {boundary[i], wall_velocity[i], wall_restitution[i]};
    m.velocity_unit = units().velocity;
    return m;
  }

  io::OutputSettings Scene::output_settings() const
  {
    io::OutputSettings o;
    o.directory         = output_directory;
    o.base_name         = base_name;
    o.write_vtu         = write_vtu;
    o.write_profiles    = write_profiles;
    o.write_checkpoint  = write_checkpoint;
    o.vtu_files         = vtu_files_per_output;
    o.profile_direction = profile_direction;
    o.section_direction = section_direction;
    o.units             = units();
    o.container_motion  = moving_frame();
    return o;
  }

  boundary::MovingFrame Scene::moving_frame() const
  {
    boundary::MovingFrame f;
    if (vibration_amplitude > 0 && vibration_frequency > 0)
      {
        f.amplitude = vibration_amplitude;
        f.omega     = 2 * M_PI * vibration_frequency;
        f.direction = vibration_direction;
      }
    return f;
  }

  Units Scene::units() const
  {
    Units u;
    u.length   = grain_diameter;
    u.mass     = grain_mass();
    u.velocity = reference_velocity > 0 ? reference_velocity : std::sqrt(9.81 * grain_diameter);
    return u;
  }

  void declare_scene_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Dimension", default_text(Scene().dimension), Patterns::Integer(1, 3),
                      "Number of resolved space dimensions (1, 2 or 3). Unresolved "
                      "directions are homogeneous.");
    // the order of the subsections is the order of --print-parameters
    DomainParameters::declare_parameters(prm);
    DenseClosureParameters::declare_parameters(prm);
    MaterialParameters::declare_parameters(prm);
    InitialStateParameters::declare_parameters(prm);
    NumericsParameters::declare_parameters(prm);
    EffectsParameters::declare_parameters(prm);
    DiffusionStepParameters::declare_parameters(prm);
    AdaptivityParameters::declare_parameters(prm);
    TimeParameters::declare_parameters(prm);
    OutputParameters::declare_parameters(prm);
  }

  Scene detail::scene_from(ParameterHandler &prm, const std::string &source_name)
  {
    Scene s;
    s.source               = source_name;
    s.dimension            = prm.get_integer("Dimension");
    const unsigned int dim = s.dimension;
    // the first entry that does not convert names the error: keep this order
    s.DomainParameters::parse_parameters(prm, dim, source_name);
    s.MaterialParameters::parse_parameters(prm);
    s.DenseClosureParameters::parse_parameters(prm);
    s.InitialStateParameters::parse_parameters(prm);
    s.NumericsParameters::parse_parameters(prm);
    s.EffectsParameters::parse_parameters(prm, dim);
    s.DiffusionStepParameters::parse_parameters(prm);
    s.AdaptivityParameters::parse_parameters(prm);
    s.TimeParameters::parse_parameters(prm);
    s.OutputParameters::parse_parameters(prm);

    validate(s);
    return s;
  }

  namespace
  {
    /// the end time against the output interval and the fixed time step
    void check_step_counts(const Scene &s)
    {
      if (s.output_interval > 0 && s.end_time / s.output_interval > 1e5)
        fail(s, "Output/Interval",
             "would write more than 1e5 outputs before 'Time/End time' (" + fmt(s.end_time) + " s)");
      // the steady state is tested at output times: without them the tolerance did nothing
      if (s.steady_tolerance > 0 && !(s.output_interval > 0))
        fail(s, "Time/Steady state tolerance",
             "needs 'Output/Interval' > 0 (the steady state is "
             "tested once per output interval); set an interval "
             "or the tolerance to 0");
      if (s.fixed_time_step > 0 && s.end_time / s.fixed_time_step > 1e9)
        fail(s, "Numerics/Fixed time step",
             "would need more than 1e9 steps to 'Time/End time' (" + fmt(s.end_time) + " s)");
    }

    /// what the effects need from the material and from each other
    void check_effect_combinations(const Scene &s)
    {
      if (s.dense_closure != DenseClosure::none && s.model != physics::Model::granular)
        fail(s, "Dense closure/Model", "a dense closure needs 'Material/Model = granular'");
      if (!s.convection && s.fixed_time_step <= 0)
        fail(s, "Numerics/Fixed time step",
             "must be positive when 'Effects/Convection' is off (the "
             "convective CFL then sets no time step)");
      if (!s.convection && !s.diffusion_active())
        fail(s, "Effects/Convection",
             "with convection off the scene must have an active diffusion "
             "step (granular model with transport, cooling or gravity)");
    }
  } // namespace

  /// The checks run in a fixed order: a scene with several faults is refused with the
  /// message of the first, the same whatever the layout of the code.
  void validate(const Scene &s)
  {
    const mesh::MeshFileInfo mesh_info = DomainParameters::check_mesh(s);
    AdaptivityParameters::check(s);
    DomainParameters::check_box(s);
    DomainParameters::check_walls(s);
    DomainParameters::check_cell_count(s);
    TimeParameters::check(s);
    check_step_counts(s);
    NumericsParameters::check_cfl(s);
    DiffusionStepParameters::check(s);
    NumericsParameters::check_musta(s);
    MaterialParameters::check(s);
    DenseClosureParameters::check(s);
    EffectsParameters::check_body_force(s);
    NumericsParameters::check_reference_velocity(s);
    NumericsParameters::check_gravity_scheme(s);
    NumericsParameters::check_contact_pressure(s);
    EffectsParameters::check_vibration(s);
    check_effect_combinations(s);
    OutputParameters::check(s);
    InitialStateParameters::check(s, mesh_info.centres, mesh_info.n_cells);
  }
} // namespace granhydro::scene
