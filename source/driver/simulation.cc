/**
 * @file simulation.cc
 * The composition root of a run: Simulation's model, mesh, operators, output and
 * initial state from the scene, and run_scene(), which picks the model and dimension.
 * The parts of a run: SplitStep (one time step), TimeLoop (the time loop), Checkpointing,
 * RunReport, InitialState; adapt_mesh.cc and simulation_checkpoint.cc are the root's own.
 */
#include <granhydro/driver/initial_state.h>
#include <granhydro/driver/run_records.h>
#include <granhydro/io/diagnostics.h>

#include <deal.II/base/mpi.h>

#include "simulation_instances.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace granhydro::driver
{
  using namespace dealii;

  RunSettings run_settings(const scene::Scene &scene, const unsigned int dim)
  {
    RunSettings       r;
    TimeLoopSettings &l = r.loop;
    l.end_time          = scene.end_time;
    l.fixed_time_step   = scene.fixed_time_step;
    l.output_interval   = scene.output_interval;
    l.cfl               = scene.cfl;
    l.steady_tolerance  = scene.steady_tolerance;
    l.max_wall_seconds  = scene.max_wall_seconds;
    l.progress_interval = scene.progress_interval;
    l.max_steps         = scene.max_steps;
    l.max_step_retries  = scene.max_step_retries;
    l.adapt_interval    = scene.max_level > 0 ? scene.adapt_interval : 0;
    l.profile_direction = scene.profile_direction < 0 ? dim - 1 : scene.profile_direction;
    l.convection        = scene.convection;
    l.merge_strang      = scene.merge_strang;
    l.from_checkpoint   = !scene.initial_checkpoint.empty();
    // the body force of the diffusion step (the splitting allowance of the temperature
    // repair); well-balanced gravity is not split from the convective step
    l.max_body_acceleration = (scene.well_balanced_gravity ? 0. :
                                                             std::sqrt(scene.gravity[0] * scene.gravity[0] +
                                                                       scene.gravity[1] * scene.gravity[1] +
                                                                       scene.gravity[2] * scene.gravity[2])) +
                              scene.vibration_amplitude * std::pow(2 * M_PI * scene.vibration_frequency, 2);

    RunFiles &f        = r.files;
    f.directory        = scene.output_directory;
    f.base_name        = scene.base_name;
    f.vtu              = scene.write_vtu;
    f.profiles         = scene.write_profiles;
    f.summary          = scene.write_summary;
    f.checkpoint       = scene.write_checkpoint;
    f.keep_checkpoints = scene.keep_checkpoints;
    f.history_steps    = scene.history_steps;
    f.history_seconds  = scene.history_seconds;

    RunReportSettings &p = r.report;
    p.source             = scene.source;
    p.overrides          = scene.overrides;
    p.expanded_text      = scene.expanded_text;
    p.verbose            = scene.verbose;
    p.integrator         = to_string(scene.integrator);
    p.musta              = scene.flux == convection::FluxType::musta;
    p.adaptive           = scene.max_level > 0;
    p.load_balance       = to_string(scene.load_balance);

    CheckpointIdentity &c = r.identity;
    c.cells               = scene.cells;
    c.lower               = scene.lower;
    c.upper               = scene.upper;
    c.model               = to_string(scene.model);
    c.source              = scene.source;
    c.adaptive            = scene.max_level > 0;

    AdaptationSettings &a         = r.adaptation;
    a.indicator.refine_threshold  = scene.refine_threshold;
    a.indicator.coarsen_threshold = scene.coarsen_threshold;
    a.indicator.buffer            = scene.adapt_buffer;
    a.indicator.indicator         = scene.adapt_indicator;
    a.balance_by_cost             = scene.balance_by_measured_cost(scene.diffusion_active());
    return r;
  }

  template <int dim, class Description>
  Simulation<dim, Description>::Simulation(const scene::Scene &scene, const MPI_Comm comm, std::ostream &log)
    : scene(scene)
    , comm(comm)
    , pcout(log, Utilities::MPI::this_mpi_process(comm) == 0 && scene.verbose)
    , units_(scene.units())
  {
    AssertThrow(scene.dimension == dim, ExcMessage("scene dimension mismatch"));
    const RunSettings run = run_settings(scene, dim);
    loop                  = run.loop;
    files                 = run.files;
    report                = run.report;
    identity              = run.identity;
    adaptation            = run.adaptation;
    run_report_  = std::make_unique<RunReport>(report, files, loop, adaptation, units_, dim, comm, pcout);
    checkpoints_ = std::make_unique<Checkpointing<dim>>(identity, units_, comm);
    if constexpr (std::is_same_v<Description, physics::IdealGas<dim>>)
      desc.gamma = scene.adiabatic_index;
    else
      {
        desc = Description(physics::GarzoDufty1999(scene.restitution, scene.phi_freezing,
                                                   scene.phi_close_packing, scene.guard_delta));
        if (scene.friction > 0) // mu = 0 leaves the smooth model untouched
          desc.model.set_friction(scene.friction);
        if (scene.dense_closure != scene::DenseClosure::none) // scaled units: pressure p0, time t0
          {
            physics::FrictionalStress friction;
            friction.law     = scene.frictional_stress;
            friction.sin_phi = std::sin(scene.closure_angle * M_PI / 180.);
            friction.t_f     = scene.closure_time / units_.time();
            desc.contact     = physics::ContactPressure(
                  scene.closure_F / units_.pressure(), scene.closure_phi_min, scene.phi_close_packing,
                  scene.closure_r, scene.closure_s, scene.guard_delta, friction);
          }
      }
  }

  template <int dim, class Description>
  Simulation<dim, Description>::~Simulation() = default;

  template <int dim, class Description>
  void Simulation<dim, Description>::print_header() const
  {
    const char *ax = "xyz";
    pcout << "granhydro: scene " << scene.source << "\n"
          << "  " << dim << "D, " << patch_->n_global_cells() << " cells (";
    if (!scene.mesh_file.empty())
      pcout << "mesh file " << scene.mesh_file << ", " << scene.mesh_refinements
            << " refinement(s), lattice ";
    for (unsigned int d = 0; d < dim; ++d)
      pcout << (d ? " x " : "") << patch_->cells(d);
    pcout << "), " << Utilities::MPI::n_mpi_processes(comm) << " MPI rank(s)\n"
          << "  model: " << to_string(scene.model);
    if constexpr (std::is_same_v<Description, physics::IdealGas<dim>>)
      pcout << " (gamma_a = " << desc.gamma << "; no transport, cooling or body force)\n";
    else
      pcout << " (eps = " << scene.restitution
            << (scene.friction > 0 ?
                  ", friction mu = " + std::to_string(scene.friction) + " (effective restitution " +
                    std::to_string(desc.model.effective_restitution()) + " in the cooling rate)" :
                  std::string())
            << ", Torquato chi with phi_f = " << scene.phi_freezing << ", phi_c = " << scene.phi_close_packing
            << (scene.max_free_path > 0 ?
                  "; Knudsen cap: transport coefficients scaled where the mean free path exceeds " +
                    std::to_string(scene.max_free_path) + " m" :
                  std::string())
            << ")\n";
    pcout << "  active effects (only these operators are built and run):\n";
    for (const auto &[effect, why] : scene::active_effects(scene))
      pcout << "    " << effect << "  [" << why << "]\n";
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      pcout << "  diffusion step: "
            << (scene.diffusion_active() ?
                  to_string(scene.integrator) + ", " + (scene.diagonal_flux ? "diagonal" : "full") + " flux" +
                    (scene.convection ? std::string(", Strang splitting C(dt/2) V(dt) C(dt/2)") +
                                          (scene.merge_strang ? " with adjacent C halves merged" : "") :
                                        std::string()) :
                  std::string("off (no transport, cooling, body force or dissipative wall)"))
            << "\n";
    pcout << "  numerics: " << to_string(scene.reconstruction) << " reconstruction, "
          << to_string(scene.face_quadrature) << " face quadrature, " << to_string(scene.flux) << " flux";
    if (scene.flux == convection::FluxType::musta)
      pcout << " (" << scene.musta_min_stages << " to " << scene.musta_max_stages << " stages, tol "
            << scene.musta_tolerance << ")";
    pcout << ", SSP-RK3, CFL " << scene.cfl << "\n  boundaries:";
    for (unsigned int d = 0; d < dim; ++d)
      pcout << ' ' << ax[d] << "-/+ = " << to_string(scene.boundary[2 * d]) << '/'
            << to_string(scene.boundary[2 * d + 1]);
    if (!scene.mesh_file.empty())
      pcout << " (by boundary id 0..5 of the mesh file)";
    pcout << "\n  scaled units: length " << units_.length << " m, mass " << units_.mass << " kg, velocity "
          << units_.velocity << " m/s, time " << units_.time() << " s\n";
  }

  template <int dim, class Description>
  physics::BodyForce Simulation<dim, Description>::body_force() const
  {
    physics::BodyForce f;
    for (unsigned int d = 0; d < dim; ++d) // scaled: g L0 / V0^2
      f.gravity[d] = scene.gravity[d] * units_.length / (units_.velocity * units_.velocity);
    return f;
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::setup()
  {
    const unsigned int r =
      convection::ConvectionOperator<dim, Description>::stencil_half_width(scene.reconstruction);
    patch_ = std::make_unique<mesh::CartesianPatch<dim>>(comm);
    patch_->build(scene.mesh_settings(), r + 1);
    convection::ConvectionSettings cs = scene.convection_settings();
    if (scene.well_balanced_gravity) // gravity is the convective step's (scaled units)
      cs.gravity = body_force().gravity;
    conv_desc = desc;
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      if (scene.implicit_contact_pressure) // the contact step applies p_f and gravity
        {
          conv_desc = diffusion::ContactStep<dim>::explicit_description(desc);
          diffusion::ContactStepSettings cps;
          cps.gravity = body_force().gravity;
          contact =
            std::make_unique<diffusion::ContactStep<dim>>(*patch_, desc, conv_desc, cps, units_.length);
          contact->setup();
        }
    conv = std::make_unique<convection::ConvectionOperator<dim, Description>>(*patch_, conv_desc, cs);
    conv->setup();
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      if (scene.diffusion_active())
        {
          diffusion::DiffusionSettings ds;
          ds.viscous          = scene.viscosity;
          ds.heat             = scene.heat_conduction;
          ds.cooling          = scene.cooling;
          ds.diagonal_only    = scene.diagonal_flux;
          ds.max_free_path    = scene.max_free_path / units_.length;
          ds.no_tension       = scene.cohesionless;
          ds.container_motion = scene.moving_frame().scaled(units_.length, units_.time());
          ds.body             = body_force();
          if (scene.well_balanced_gravity || scene.implicit_contact_pressure) // not this step's
            ds.body.gravity = {{0, 0, 0}};
          diff = std::make_unique<diffusion::DiffusionOperator<dim>>(*patch_, desc, ds, units_.length);
          diff->setup();
          diffusion::IntegratorSettings is;
          is.method                = scene.integrator;
          is.newton_tolerance      = scene.newton_tolerance;
          is.newton_max_iterations = scene.newton_max_iterations;
          is.linear_tolerance      = scene.linear_tolerance;
          is.inexact_newton        = scene.inexact_newton;
          is.reuse_matrix          = scene.reuse_matrix;
          is.amg                   = scene.preconditioner == scene::Preconditioner::amg;
          is.block_ilu             = scene.preconditioner == scene::Preconditioner::block_ilu;
          is.full_jacobian         = scene.full_jacobian;
          integrator               = std::make_unique<diffusion::ImplicitIntegrator<dim>>(*diff, desc, is);
        }
    split_ = std::make_unique<SplitStep<dim, Description>>(
      desc, loop.convection, units_.time(), loop.max_body_acceleration, units_.velocity, timers_, pcout);
    split_->set_operators(*patch_, *conv, integrator.get(), contact.get());
    U.reinit(patch_->partitioner());
    print_header();

    if (!scene.initial_checkpoint.empty())
      {
        output = std::make_unique<io::Output<dim, Description>>(scene.output_settings(), *patch_, desc);
        read_checkpoint(scene.initial_checkpoint);
        return;
      }

    // initial state from the scene's expressions (SI), averaged over cells
    InitialStateSettings is;
    is.packing_fraction = scene.initial_packing_fraction;
    is.temperature      = scene.initial_temperature;
    is.velocity         = scene.initial_velocity;
    is.constants        = scene::expression_constants(scene);
    is.grain_mass       = scene.grain_mass();
    is.grain_diameter   = scene.grain_diameter;
    is.quadrature       = scene.initial_quadrature;
    is.source           = scene.source;
    InitialState<dim, Description> state(is, desc, units_);
    const auto                     initial_state = [&state](const Point<dim> &x) { return state(x); };
    set_initial_state(initial_state, is.quadrature);
    // initial refinement: adapt to the initial state, then evaluate it anew on the finer
    // cells (no interpolation), up to the maximum level
    for (unsigned int k = 0; k < scene.max_level; ++k)
      {
        if (!adapt_mesh(true))
          break;
        set_initial_state(initial_state, is.quadrature);
      }
    if (scene.max_level > 0)
      pcout << "  initial refinement: " << patch_->n_global_cells() << " cells, levels 0.." << scene.max_level
            << " above " <<
        [&]() {
          std::string c;
          for (unsigned int d = 0; d < dim; ++d)
            c += (d ? " x " : "") + std::to_string(scene.cells[d]);
          return c;
        }() << "\n";
    state.check(comm);
    output = std::make_unique<io::Output<dim, Description>>(scene.output_settings(), *patch_, desc);
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::set_initial_state(const std::function<State(const Point<dim> &)> &f,
                                                       const unsigned int                              nq)
  {
    set_cell_averages(*patch_, f, nq, units_, U);
  }

  template <int dim, class Description>
  typename Simulation<dim, Description>::State
  Simulation<dim, Description>::state_si(const unsigned int s) const
  {
    State S;
    S[0] = U.local_element(std::size_t(s) * (dim + 2)) * units_.number_density();
    for (unsigned int d = 0; d < dim; ++d)
      S[1 + d] =
        U.local_element(std::size_t(s) * (dim + 2) + 1 + d) * units_.number_density() * units_.velocity;
    S[dim + 1] = U.local_element(std::size_t(s) * (dim + 2) + dim + 1) * units_.pressure();
    return S;
  }

  template <int dim, class Description>
  typename Simulation<dim, Description>::State Simulation<dim, Description>::totals() const
  {
    // one formula for the totals: the history rows and the summary use the same
    const io::StateTotals<dim> s = io::state_totals(*patch_, U, desc, units_.length, comm);
    State                      t;
    t[0] = s.n;
    for (unsigned int d = 0; d < dim; ++d)
      t[1 + d] = s.nu[d];
    t[dim + 1] = s.energy;
    return t;
  }

  template <int dim, class Description>
  RunSummary Simulation<dim, Description>::run()
  {
    const TimeLoopParts<dim, Description> parts{U,       *patch_, desc,         *conv,    integrator.get(),
                                                *split_, *output, *run_report_, adapted_, timers_};
    TimeLoopHooks                         hooks;
    hooks.adapt_mesh       = [this] { adapt_mesh(false); };
    hooks.write_checkpoint = [this](const std::string &file, const double t, const unsigned int step,
                                    const bool                                         with_history,
                                    const std::vector<std::pair<std::string, double>> &record) {
      record_ = record;
      write_checkpoint(file, t, step, with_history);
    };
    TimeLoop<dim, Description> time_loop(loop, files, report.integrator, units_, comm, pcout, parts, hooks);
    return time_loop.run(start_);
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::mesh_changed()
  {
    conv->setup();
    if (diff)
      diff->setup();
    if (contact)
      contact->setup();
    if (integrator)
      integrator->mesh_changed();
    split_->set_operators(*patch_, *conv, integrator.get(), contact.get());
  }

  namespace
  {
    /// the scene on `dim` dimensions with the model it names; started() runs once the
    /// mesh and the initial state are set up, before the first step
    template <int dim, class Description>
    int run_model(const scene::Scene &scene, const MPI_Comm comm, std::ostream &log,
                  const std::function<void()> &started)
    {
      Simulation<dim, Description> sim(scene, comm, log);
      sim.setup();
      started();
      const int sig = sim.run().interrupted_by;
      return sig ? 128 + sig : 0;
    }

    int run_any(const scene::Scene &scene, const MPI_Comm comm, std::ostream &log,
                const std::function<void()> &started)
    {
      const bool granular = scene.model == physics::Model::granular;
      switch (scene.dimension)
        {
          case 1:
            return granular ? run_model<1, physics::GranularGas<1>>(scene, comm, log, started) :
                              run_model<1, physics::IdealGas<1>>(scene, comm, log, started);
          case 2:
            return granular ? run_model<2, physics::GranularGas<2>>(scene, comm, log, started) :
                              run_model<2, physics::IdealGas<2>>(scene, comm, log, started);
          default:
            return granular ? run_model<3, physics::GranularGas<3>>(scene, comm, log, started) :
                              run_model<3, physics::IdealGas<3>>(scene, comm, log, started);
        }
    }
  } // namespace

  int run_scene(const scene::Scene &scene, const MPI_Comm comm, std::ostream &log)
  {
    return run_any(scene, comm, log, [] {});
  }

  int run_scene(const scene::Scene &scene, const MPI_Comm comm, RunRecords &records)
  {
    return run_any(scene, comm, records.log(), [&records] { records.start(); });
  }

  GRANHYDRO_SIMULATION_INSTANCES
} // namespace granhydro::driver
