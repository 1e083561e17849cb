#include <granhydro/physics/packing_fraction.h>
#include <granhydro/driver/simulation.h>
#include <granhydro/io/checkpoint.h>

#include <sys/resource.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <unistd.h>
#include <type_traits>
#include <limits>
#include <fstream>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace granhydro
{
  using namespace dealii;

  template <int dim, class Description>
  Simulation<dim, Description>::Simulation(const Scene &scene, const MPI_Comm comm, std::ostream &log)
    : scene(scene)
    , comm(comm)
    , pcout(log, Utilities::MPI::this_mpi_process(comm) == 0 && scene.verbose)
    , units_(scene.units())
  {
    AssertThrow(scene.dimension == dim, ExcMessage("scene dimension mismatch"));
    if constexpr (std::is_same_v<Description, physics::IdealGas<dim>>)
      desc.gamma = scene.adiabatic_index;
    else
      {
        desc = Description(physics::GarzoDufty1999(scene.restitution, scene.phi_freezing,
                                                   scene.phi_close_packing, scene.guard_delta));
        if (scene.friction > 0) // mu = 0 leaves the smooth model untouched
          desc.model.set_friction(scene.friction);
        if (scene.dense_closure != "none") // scaled units: pressure p0, time t0
          desc.contact = physics::ContactPressure(
            scene.closure_F / units_.pressure(), scene.closure_phi_min, scene.phi_close_packing,
            scene.closure_r, scene.closure_s, scene.guard_delta,
            scene.closure_time / units_.time() * std::sin(scene.closure_angle * M_PI / 180.));
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
          << "  model: " << scene.model;
    if constexpr (std::is_same_v<Description, physics::IdealGas<dim>>)
      pcout << " (gamma_a = " << desc.gamma << "; no transport, cooling or body force)\n";
    else
      pcout << " (eps = " << scene.restitution
            << (scene.friction > 0 ? ", friction mu = " + std::to_string(scene.friction) +
                                       " (effective restitution " +
                                       std::to_string(desc.model.effective_restitution()) +
                                       " in the cooling rate)" :
                                     std::string())
            << ", Torquato chi with phi_f = "
            << scene.phi_freezing << ", phi_c = " << scene.phi_close_packing
            << (scene.max_free_path > 0 ?
                  "; Knudsen cap: transport coefficients scaled where the mean free path exceeds " +
                    std::to_string(scene.max_free_path) + " m" :
                  std::string())
            << ")\n";
    pcout << "  active effects (only these operators are built and run):\n";
    for (const auto &[effect, why] : active_effects(scene))
      pcout << "    " << effect << "  [" << why << "]\n";
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      pcout << "  diffusion step: "
            << (scene.diffusion_active() ?
                  scene.integrator + ", " + (scene.diagonal_flux ? "diagonal" : "full") +
                    " flux" +
                    (scene.convection ? std::string(", Strang splitting C(dt/2) V(dt) C(dt/2)") +
                                          (scene.merge_strang ? " with adjacent C halves merged" : "") :
                                        std::string()) :
                  std::string("off (no transport, cooling, body force or dissipative wall)"))
            << "\n";
    pcout
          << "  numerics: " << to_string(scene.reconstruction) << " reconstruction, "
          << to_string(scene.face_quadrature) << " face quadrature, " << to_string(scene.flux)
          << " flux";
    if (scene.flux == FluxType::musta)
      pcout << " (" << scene.musta_min_stages << " to " << scene.musta_max_stages << " stages, tol "
            << scene.musta_tolerance << ")";
    pcout << ", SSP-RK3, CFL " << scene.cfl << "\n  boundaries:";
    for (unsigned int d = 0; d < dim; ++d)
      pcout << ' ' << ax[d] << "-/+ = " << to_string(scene.boundary[2 * d]) << '/'
            << to_string(scene.boundary[2 * d + 1]);
    if (!scene.mesh_file.empty())
      pcout << " (by boundary id 0..5 of the mesh file)";
    pcout << "\n  scaled units: length " << units_.length << " m, mass " << units_.mass
          << " kg, velocity " << units_.velocity << " m/s, time " << units_.time() << " s\n";
  }

  template <int dim, class Description>
  physics::BodyForce Simulation<dim, Description>::body_force() const
  {
    physics::BodyForce f;
    // vibrated container, scaled: A / L0, omega t0
    if (scene.vibration_amplitude > 0 && scene.vibration_frequency > 0)
      {
        f.amplitude = scene.vibration_amplitude / units_.length;
        f.omega     = 2 * M_PI * scene.vibration_frequency * units_.time();
        f.direction = scene.vibration_direction;
      }
    for (unsigned int d = 0; d < dim; ++d) // scaled: g L0 / V0^2
      f.gravity[d] = scene.gravity[d] * units_.length / (units_.velocity * units_.velocity);
    return f;
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::setup()
  {
    const unsigned int r =
      convection::ConvectionOperator<dim, Description>::stencil_half_width(scene.reconstruction);
    patch_ = std::make_unique<CartesianPatch<dim>>(comm);
    patch_->build(scene.mesh_settings(), r + 1);
    conv = std::make_unique<convection::ConvectionOperator<dim, Description>>(*patch_, desc,
                                                                              scene.convection_settings());
    conv->setup();
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      if (scene.diffusion_active())
        {
          diffusion::DiffusionSettings ds;
          ds.viscous       = scene.viscosity;
          ds.heat          = scene.heat_conduction;
          ds.cooling       = scene.cooling;
          ds.diagonal_only = scene.diagonal_flux;
          ds.max_free_path = scene.max_free_path / units_.length;
          ds.wall_restitution = scene.wall_restitution;
          ds.body = body_force();
          diff = std::make_unique<diffusion::DiffusionOperator<dim>>(*patch_, desc, ds, units_.length);
          diff->setup();
          diffusion::IntegratorSettings is;
          is.method = scene.integrator == "implicit midpoint" ? diffusion::ImplicitMethod::implicit_midpoint :
                      scene.integrator == "sdirk2"            ? diffusion::ImplicitMethod::sdirk2 :
                      scene.integrator == "rkl2"              ? diffusion::ImplicitMethod::rkl2 :
                      scene.integrator == "cost-based"        ? diffusion::ImplicitMethod::cost_based :
                      scene.integrator == "automatic"         ? diffusion::ImplicitMethod::automatic :
                      scene.integrator == "explicit euler"    ? diffusion::ImplicitMethod::explicit_euler :
                                                                diffusion::ImplicitMethod::gauss_legendre;
          is.newton_tolerance      = scene.newton_tolerance;
          is.newton_max_iterations = scene.newton_max_iterations;
          is.linear_tolerance      = scene.linear_tolerance;
          is.inexact_newton        = scene.inexact_newton;
          is.reuse_matrix          = scene.reuse_matrix;
          is.amg                   = scene.preconditioner == "amg";
          is.block_ilu             = scene.preconditioner == "block ilu";
          is.full_jacobian         = scene.full_jacobian;
          integrator = std::make_unique<diffusion::ImplicitIntegrator<dim>>(*diff, desc, is);
        }
    U.reinit(patch_->partitioner());
    print_header();

    if (!scene.initial_checkpoint.empty())
      {
        output = std::make_unique<io::Output<dim, Description>>(scene.output_settings(), *patch_, desc);
        read_checkpoint(scene.initial_checkpoint);
        return;
      }

    // initial state from the scene's expressions (SI), averaged over cells
    const auto constants = expression_constants(scene);
    const std::string vars = dim == 1 ? "x" : (dim == 2 ? "x,y" : "x,y,z");
    FunctionParser<dim> phi(1), T(1);
    phi.initialize(vars, scene.initial_packing_fraction, constants);
    T.initialize(vars, scene.initial_temperature, constants);
    auto vexpr = Utilities::split_string_list(scene.initial_velocity, ';');
    vexpr.resize(dim);
    FunctionParser<dim> vel(dim);
    vel.initialize(vars, vexpr, constants);
    const double m = scene.grain_mass(), sigma = scene.grain_diameter;
    bool         bad_phi = false, bad_T = false;
    const auto initial_state = [&](const Point<dim> &x) {
        const double p = phi.value(x), t = T.value(x);
        bad_phi        = bad_phi || !(p > 0);
        bad_T          = bad_T || !(t > 0);
        const double n = 6. * p / (M_PI * sigma * sigma * sigma);
        double       u[3];
        for (unsigned int d = 0; d < dim; ++d)
          u[d] = vel.value(x, d);
        State Us;
        Us[0] = n;
        double ke = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            Us[1 + d] = m * n * u[d];
            ke += 0.5 * m * n * u[d] * u[d];
          }
        Us[dim + 1] = ke + n * t * desc.heat_capacity();
        if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>) // contact potential
          Us[dim + 1] += desc.contact.energy_density(n * units_.length * units_.length * units_.length) *
                         units_.pressure();
        // this Us is in SI with a *mass* momentum; convert to number momentum below
        for (unsigned int d = 0; d < dim; ++d)
          Us[1 + d] /= m;
        return Us;
      };
    set_initial_state(initial_state, scene.initial_quadrature);
    // initial refinement: adapt to the initial state, then evaluate it anew on the finer
    // cells (no interpolation), up to the maximum level
    for (unsigned int k = 0; k < scene.max_level; ++k)
      {
        if (!adapt_mesh(true))
          break;
        set_initial_state(initial_state, scene.initial_quadrature);
      }
    if (scene.max_level > 0)
      pcout << "  initial refinement: " << patch_->n_global_cells() << " cells, levels 0.."
            << scene.max_level << " above " << [&]() {
                 std::string c;
                 for (unsigned int d = 0; d < dim; ++d)
                   c += (d ? " x " : "") + std::to_string(scene.cells[d]);
                 return c;
               }() << "\n";
    if (Utilities::MPI::logical_or(bad_phi, comm))
      throw SceneError("in " + scene.source + ": parameter 'Initial state/Packing fraction' "
                       "must be positive everywhere in the domain");
    if (Utilities::MPI::logical_or(bad_T, comm))
      throw SceneError("in " + scene.source + ": parameter 'Initial state/Temperature' must be "
                       "positive everywhere in the domain");
    output = std::make_unique<io::Output<dim, Description>>(scene.output_settings(), *patch_, desc);
  }

  template <int dim, class Description>
  std::int64_t Simulation<dim, Description>::lattice_key(const unsigned int s) const
  {
    return patch_->leaf_key(s);
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::write_checkpoint(const std::string &file, const double t,
                                                      const unsigned int step, const bool with_history) const
  {
    constexpr unsigned int NC = dim + 2;
    const unsigned int     n  = patch_->n_owned();
    typename diffusion::ImplicitIntegrator<dim>::History history;
    if (with_history && integrator)
      history = integrator->history();
    const unsigned int  NV = history.matrix_valid ? 2 * NC : NC; // values per row
    std::vector<double> mine(std::size_t(n) * (NV + 1));
    for (unsigned int s = 0; s < n; ++s)
      {
        mine[s * (NV + 1)] = double(lattice_key(s));
        for (unsigned int c = 0; c < NC; ++c)
          mine[s * (NV + 1) + 1 + c] = U.local_element(std::size_t(s) * NC + c);
        if (history.matrix_valid)
          for (unsigned int c = 0; c < NC; ++c)
            mine[s * (NV + 1) + 1 + NC + c] = history.state[std::size_t(s) * NC + c];
      }
    const auto  all = Utilities::MPI::gather(comm, mine, 0);
    std::string error;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::vector<std::pair<double, const double *>> rows;
        for (const auto &part : all)
          for (std::size_t i = 0; i < part.size(); i += NV + 1)
            rows.emplace_back(part[i], &part[i + 1]);
        std::sort(rows.begin(), rows.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
        io::CheckpointHeader h;
        h.dim          = dim;
        h.n_components = NC;
        h.n_values     = NV;
        for (unsigned int d = 0; d < 3; ++d)
          {
            h.cells[d] = d < dim ? scene.cells[d] : 1;
            h.lower[d] = d < dim ? scene.lower[d] : 0;
            h.upper[d] = d < dim ? scene.upper[d] : 0;
          }
        h.length   = units_.length;
        h.mass     = units_.mass;
        h.velocity = units_.velocity;
        h.time     = t;
        h.step     = step;
        h.n_cells  = rows.size();
        h.convection_owed = owed_;
        h.outputs  = output ? output->count() : 0;
        std::snprintf(h.model, sizeof(h.model), "%s", scene.model.c_str());
        auto &hh        = h.history;
        hh.rkl2_blocked = history.rkl2_blocked;
        hh.matrix_valid = history.matrix_valid;
        if (history.matrix_valid)
          {
            hh.matrix_age     = history.matrix_age;
            hh.matrix_coupled = history.matrix_coupled;
            hh.matrix_stages  = history.matrix_N.size();
            hh.matrix_t       = history.matrix_t;
            hh.matrix_dt      = history.matrix_dt;
            for (unsigned int i = 0; i < history.matrix_N.size(); ++i)
              for (unsigned int j = 0; j < history.matrix_N.size(); ++j)
                hh.matrix_N[i * history.matrix_N.size() + j] = history.matrix_N[i][j];
          }
        std::vector<std::int64_t> keys(rows.size());
        std::vector<double>       values(rows.size() * NV);
        for (std::size_t i = 0; i < rows.size(); ++i)
          {
            keys[i] = std::int64_t(rows[i].first);
            std::copy(rows[i].second, rows[i].second + NV, &values[i * NV]);
          }
        try
          {
            io::write_checkpoint_file(file, h, keys, values);
          }
        catch (const io::CheckpointError &e)
          {
            error = e.what();
          }
      }
    // every rank stops together (a throw on rank 0 alone would leave the others waiting)
    error = Utilities::MPI::broadcast(comm, error, 0);
    if (!error.empty())
      throw io::OutputError(error);
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::read_checkpoint(const std::string &file)
  {
    constexpr unsigned int NC   = dim + 2;
    const std::string      what = "in " + scene.source + ": parameter 'Initial state/Checkpoint': '" +
                             file + "' ";
    io::CheckpointData data;
    try
      {
        data = io::read_checkpoint_file(file);
      }
    catch (const io::CheckpointError &e)
      {
        throw SceneError(what + e.what());
      }
    const io::CheckpointHeader      &h    = data.header;
    const std::vector<std::int64_t> &keys = data.keys;
    const std::vector<double>       &values = data.values;
    const unsigned int               NV     = h.n_values;
    if (scene.max_level > 0 && h.dim == dim)
      {
        patch_->refine_to(std::vector<long long>(keys.begin(), keys.end()));
        mesh_changed();
        U.reinit(patch_->partitioner());
      }
    bool same_mesh = h.dim == dim && h.n_components == int(NC) && h.n_cells == patch_->n_global_cells();
    for (unsigned int d = 0; d < dim; ++d)
      same_mesh = same_mesh && h.cells[d] == scene.cells[d] &&
                  std::abs(h.lower[d] - scene.lower[d]) <= 1e-12 * std::abs(scene.upper[d] - scene.lower[d]) &&
                  std::abs(h.upper[d] - scene.upper[d]) <= 1e-12 * std::abs(scene.upper[d] - scene.lower[d]);
    if (!same_mesh)
      throw SceneError(what + "was written for another mesh (dimension, Domain/Cells, corners or "
                              "Adaptivity/Maximum level differ)");
    if (std::string(h.model) != scene.model)
      throw SceneError(what + "was written with 'Material/Model = " + std::string(h.model) + "'");
    // values are in the writer's scaled units: convert only if ours differ (restart with the
    // same material is then bitwise exact)
    const bool   same_units = h.length == units_.length && h.mass == units_.mass && h.velocity == units_.velocity;
    const double sn = std::pow(units_.length / h.length, 3); // n' = n L'^3 / L^3
    const double sm = sn * units_.velocity / h.velocity;
    const double se = (h.mass * h.velocity * h.velocity / std::pow(h.length, 3)) / units_.pressure();
    std::map<std::int64_t, unsigned int> slot_of;
    for (unsigned int s = 0; s < patch_->n_owned(); ++s)
      slot_of[lattice_key(s)] = s;
    std::size_t found = 0;
    // the implicit step's history (a checkpoint between output times): only with the same
    // units and an integrator that keeps one
    const bool with_history = h.history.matrix_valid && same_units && integrator;
    typename diffusion::ImplicitIntegrator<dim>::History history;
    if (with_history)
      history.state.resize(std::size_t(patch_->n_owned()) * NC);
    for (std::uint64_t i = 0; i < h.n_cells; ++i)
      {
        const auto it = slot_of.find(keys[i]);
        if (it == slot_of.end())
          continue;
        ++found;
        for (unsigned int c = 0; c < NC; ++c)
          {
            const double f = same_units ? 1. : (c == 0 ? sn : (c == NC - 1 ? se : sm));
            U.local_element(std::size_t(it->second) * NC + c) = values[i * NV + c] * f;
            if (with_history)
              history.state[std::size_t(it->second) * NC + c] = values[i * NV + NC + c];
          }
      }
    if (Utilities::MPI::sum(found, comm) != patch_->n_global_cells() || found != patch_->n_owned())
      throw SceneError(what + "does not hold every cell of the mesh");
    start_time_ = same_units ? h.time : h.time * h.length / h.velocity / units_.time();
    start_step_ = h.step;
    owed_       = same_units ? h.convection_owed : h.convection_owed * h.length / h.velocity / units_.time();
    if (integrator && same_units)
      {
        history.rkl2_blocked = h.history.rkl2_blocked;
        if (with_history)
          {
            history.matrix_valid   = true;
            history.matrix_coupled = h.history.matrix_coupled;
            history.matrix_age     = h.history.matrix_age;
            history.matrix_t       = h.history.matrix_t;
            history.matrix_dt      = h.history.matrix_dt;
            const unsigned int ns  = h.history.matrix_stages;
            history.matrix_N.assign(ns, std::vector<double>(ns));
            for (unsigned int a = 0; a < ns; ++a)
              for (unsigned int b = 0; b < ns; ++b)
                history.matrix_N[a][b] = h.history.matrix_N[a * ns + b];
          }
        integrator->restore(history);
      }
    output->resume(h.outputs, start_time());
    pcout << "  initial state: checkpoint " << file << " (t = " << start_time() << " s, step "
          << start_step_ << (with_history ? ", with the implicit step's history" : "") << ")\n";
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::set_initial_state(const std::function<State(const Point<dim> &)> &f,
                                          const unsigned int nq)
  {
    // SI -> scaled: n [1/m^3] * L^3; number momentum n u [1/(m^2 s)] * L^3 / V; nE [J/m^3] / p0
    const double nscale = 1. / units_.number_density(), mscale = nscale / units_.velocity,
                 escale = 1. / units_.pressure();
    const QGauss<1> q1(nq);
    for (unsigned int s = 0; s < patch_->n_owned(); ++s)
      {
        State avg;
        avg.fill(0.);
        const auto &ijk = patch_->lattice(s);
        const unsigned int nq2 = dim > 1 ? nq : 1, nq3 = dim > 2 ? nq : 1;
        for (unsigned int a = 0; a < nq; ++a)
          for (unsigned int b = 0; b < nq2; ++b)
            for (unsigned int c = 0; c < nq3; ++c)
              {
                Point<dim>         x;
                const unsigned int id[3] = {a, b, c};
                double             w     = 1;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    x[d] = patch_->lower(d) + (ijk[d] + q1.point(id[d])[0]) * patch_->cell_size(s, d);
                    w *= q1.weight(id[d]);
                  }
                const State v = f(x);
                for (unsigned int k = 0; k < dim + 2; ++k)
                  avg[k] += w * v[k];
              }
        U.local_element(std::size_t(s) * (dim + 2)) = avg[0] * nscale;
        for (unsigned int d = 0; d < dim; ++d)
          U.local_element(std::size_t(s) * (dim + 2) + 1 + d) = avg[1 + d] * mscale;
        U.local_element(std::size_t(s) * (dim + 2) + dim + 1) = avg[dim + 1] * escale;
      }
  }

  template <int dim, class Description>
  typename Simulation<dim, Description>::State Simulation<dim, Description>::state_si(const unsigned int s) const
  {
    State S;
    S[0] = U.local_element(std::size_t(s) * (dim + 2)) * units_.number_density();
    for (unsigned int d = 0; d < dim; ++d)
      S[1 + d] = U.local_element(std::size_t(s) * (dim + 2) + 1 + d) * units_.number_density() *
                 units_.velocity;
    S[dim + 1] = U.local_element(std::size_t(s) * (dim + 2) + dim + 1) * units_.pressure();
    return S;
  }

  template <int dim, class Description>
  typename Simulation<dim, Description>::State Simulation<dim, Description>::totals() const
  {
    State t;
    t.fill(0.);
    for (unsigned int s = 0; s < patch_->n_owned(); ++s)
      {
        const double v = patch_->cell_volume(s) / std::pow(units_.length, dim);
        for (unsigned int c = 0; c < dim + 2; ++c)
          t[c] += U.local_element(std::size_t(s) * (dim + 2) + c) * v;
      }
    for (unsigned int c = 0; c < dim + 2; ++c)
      t[c] = Utilities::MPI::sum(t[c], comm);
    return t;
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::mesh_changed()
  {
    conv->setup();
    if (diff)
      diff->setup();
    if (integrator)
      integrator->mesh_changed();
  }

  template <int dim, class Description>
  bool Simulation<dim, Description>::adapt_mesh(const bool initial)
  {
    constexpr unsigned int NC = dim + 2;
    const CartesianPatch<dim> &P = *patch_;
    const unsigned int n_owned = P.n_owned();
    std::vector<double> W;
    P.gather(U, W);
    // indicator: largest normalised jump of n and p across the cell's faces
    std::vector<double> n(P.n_slots()), p(P.n_slots());
    for (unsigned int s = 0; s < P.n_slots(); ++s)
      {
        State S;
        std::copy(&W[std::size_t(s) * NC], &W[std::size_t(s + 1) * NC], S.begin());
        n[s] = S[0];
        p[s] = desc.pressure(S);
      }
    auto jump = [](const double a, const double b) {
      const double lo = std::min(a, b);
      return lo > 0 ? std::abs(a - b) / lo : std::numeric_limits<double>::infinity();
    };
    // Loehner's indicator: the second difference over the first differences along each
    // direction (gradient neighbours: same level or coarser), in [0, 1], ~1 at
    // discontinuities and kinks, ~h |a''| / |a'| in smooth regions
    auto loehner = [&](const std::vector<double> &a, const unsigned int s, const unsigned int d) {
      const int m = P.gradient_neighbor(s, d, 0), q = P.gradient_neighbor(s, d, 1);
      if (m < 0 || q < 0)
        return 0.;
      // the neighbours' values at the distance h_s (linear along the line of centres)
      const double h = P.cell_size(s, d), dm = -P.gradient_offset(s, d, 0), dq = P.gradient_offset(s, d, 1);
      const double sm = (a[s] - a[m]) * h / dm, sq = (a[q] - a[s]) * h / dq;
      const double den = std::abs(sq) + std::abs(sm) + 0.05 * (std::abs(a[q]) + 2 * std::abs(a[s]) + std::abs(a[m]));
      return den > 0 ? std::abs(sq - sm) / den : 0.;
    };
    Vector mark(P.partitioner()); // component 0: 1 = refine
    std::vector<double> eta(n_owned, 0.);
    for (unsigned int s = 0; s < n_owned; ++s)
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (scene.adapt_indicator == "second differences")
            eta[s] = std::max({eta[s], loehner(n, s, d), loehner(p, s, d)});
          else
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                {
                  const unsigned int t = P.across(d, *cf);
                  eta[s] = std::max({eta[s], jump(n[s], n[t]), jump(p[s], p[t])});
                }
            }
        mark.local_element(std::size_t(s) * NC) = eta[s] > scene.refine_threshold ? 1. : 0.;
      }
    // buffer: the refine mark spreads over face neighbours, one layer per pass
    for (unsigned int pass = 0; pass < scene.adapt_buffer; ++pass)
      {
        mark.update_ghost_values();
        std::vector<char> next(n_owned, 0);
        for (unsigned int s = 0; s < n_owned; ++s)
          for (unsigned int d = 0; d < dim && !next[s]; ++d)
            {
              const auto [b, e] = P.cell_faces(d, s);
              for (auto cf = b; cf != e; ++cf)
                if (const unsigned int t = P.across(d, *cf);
                    P.is_cell(t) && mark.local_element(std::size_t(t) * NC) > 0)
                  next[s] = 1;
            }
        mark.zero_out_ghost_values();
        for (unsigned int s = 0; s < n_owned; ++s)
          if (next[s])
            mark.local_element(std::size_t(s) * NC) = 1.;
      }
    std::vector<signed char> flags(n_owned, 0);
    for (unsigned int s = 0; s < n_owned; ++s)
      if (mark.local_element(std::size_t(s) * NC) > 0)
        flags[s] = 1;
      else if (!initial && eta[s] < scene.coarsen_threshold)
        flags[s] = -1;
    // new children: limited linear prolongation where all siblings stay admissible
    const auto admissible = [this](const double *u) {
      State S;
      std::copy(u, u + NC, S.begin());
      return desc.admissible(S);
    };
    if (!patch_->adapt(flags, U, admissible))
      return false;
    mesh_changed();
    ++adaptations;
    refined_cells += patch_->last_refined();
    coarsened_cells += patch_->last_coarsened();
    max_cells = std::max<unsigned long long>(max_cells, patch_->n_global_cells());
    return true;
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::repair(Vector &V)
  {
    // a cooling pile under the dense closure may end a part of the step with T slightly
    // below zero (GranularGas::admissible): set T to the floor there, counted
    if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
      if (desc.contact.active)
        for (unsigned int s = 0; s < patch_->n_owned(); ++s)
          {
            State   S;
            double *u = &V.local_element(std::size_t(s) * (dim + 2));
            std::copy(u, u + dim + 2, S.begin());
            const double added = desc.repair_temperature(S);
            if (added > 0)
              {
                ++temperature_repairs;
                max_repair = std::max(max_repair, added / S[0]);
                u[dim + 1] = S[dim + 1];
              }
          }
  }

  template <int dim, class Description>
  bool Simulation<dim, Description>::convect(Vector &V, const double h, const unsigned int pieces)
  {
    using clock   = std::chrono::steady_clock;
    const auto c0 = clock::now();
    bool       ok = true;
    for (unsigned int i = 0; i < pieces && ok; ++i)
      {
        ok = conv->ssp_rk3_step(V, h / pieces);
        if (ok)
          repair(V);
        ok = ok && conv->admissible(V);
      }
    conv_seconds += std::chrono::duration<double>(clock::now() - c0).count();
    return ok;
  }

  template <int dim, class Description>
  bool Simulation<dim, Description>::synchronised_state(Vector &V)
  {
    V = U;
    if (owed_ > 0 && !convect(V, owed_))
      {
        V = U;
        return false;
      }
    return true;
  }

  template <int dim, class Description>
  bool Simulation<dim, Description>::advance(const double t, const double dt, const bool sync,
                                             const double max_convective_step)
  {
    using clock = std::chrono::steady_clock;
    if (!integrator) // nothing is ever owed without the diffusion step
      return convect(U, dt);
    if (scene.convection)
      {
        // the owed half of the previous step merged with this step's first half, in
        // pieces of at most max_convective_step (the CFL limit)
        const double h      = owed_ + 0.5 * dt;
        const double limit  = max_convective_step > 0 ? max_convective_step : dt;
        const auto   pieces = static_cast<unsigned int>(std::max(1., std::ceil(h / limit * (1 - 1e-12))));
        convective_pieces += pieces;
        if (!convect(U, h, pieces))
          return false;
      }
    const auto c0       = clock::now();
    const auto switches = integrator->statistics().switches_to_midpoint;
    const bool ok       = integrator->step(U, t, dt);
    diff_seconds += std::chrono::duration<double>(clock::now() - c0).count();
    if (integrator->statistics().switches_to_midpoint > switches)
      pcout << "  diffusion step: Gauss-Legendre Newton iteration did not converge, step "
            << (ok ? "done with implicit midpoint" : "failed with both methods") << " (dt = "
            << dt * units_.time() << " s)\n";
    if (!ok)
      return false;
    repair(U);
    if (scene.convection && sync)
      {
        ++convective_pieces;
        if (!convect(U, 0.5 * dt))
          return false;
      }
    return true;
  }

  namespace
  {
    /// the summary is written whole to a temporary file and renamed: one per process, so
    /// that two runs sharing an output folder never rename each other's file away (the
    /// last one to finish leaves its summary)
    std::string summary_tmp(const std::string &file)
    {
      return file + ".tmp." + std::to_string(::getpid());
    }

    std::string hms(double s)
    {
      const long          k = std::lround(std::max(0., s));
      std::ostringstream os;
      os << std::setfill('0') << std::setw(2) << k / 3600 << ':' << std::setw(2) << (k / 60) % 60
         << ':' << std::setw(2) << k % 60;
      return os.str();
    }
  } // namespace

  namespace
  {
    unsigned long sigterm_at_step(); // test hook, below
  } // namespace

  template <int dim, class Description>
  RunSummary Simulation<dim, Description>::run()
  {
    using clock = std::chrono::steady_clock;
    const auto   start = clock::now();
    RunSummary   sum;
    const double t0    = units_.time();
    const double t_end = scene.end_time / t0;
    const double dt_fixed = scene.fixed_time_step / t0;
    const double interval = scene.output_interval / t0;
    double       t = start_time_, next_output = interval > 0 ? interval : t_end;
    // the output times after a restart are the ones the uninterrupted run would have
    // chosen (same additions), so the time steps and results are identical
    while (interval > 0 && t >= next_output * (1 - 1e-12) && next_output < t_end)
      next_output = std::min(next_output + interval, t_end);
    conv_seconds = diff_seconds = adapt_seconds = 0;
    temperature_repairs = 0;
    convective_pieces   = 0;
    max_repair          = 0;
    unsigned int step = start_step_;
    // Numerics/Strang splitting = merged: adjacent convective half-steps of the splitting
    // are taken as one (advance())
    const bool merge = integrator && scene.convection && scene.merge_strang;
    if (owed_ > 0 && !merge) // a checkpoint of a merged run restarted with symmetric steps
      {
        if (!convect(U, owed_))
          throw RunError("the convective half-step owed by the checkpoint failed");
        owed_ = 0;
      }
    bool         have_steady_reference = false, wall_limited = false;
    double       steady_ke = 0, steady_com = 0;
    const std::string checkpoint = scene.output_file(".checkpoint");
    // interrupted: the checkpoint keeps the integrator's history instead (between output
    // times the uninterrupted run keeps it too)
    int  interrupted_by = 0;
    auto write_checkpoint_now = [&]() {
      if (integrator && !interrupted_by) // a restart starts here: the integrator forgets its history too
        integrator->restart_point();
      if (scene.write_checkpoint)
        write_checkpoint(checkpoint, t, step, interrupted_by != 0);
    };
    auto         last_progress = start;
    std::string  why;
    if (!conv->admissible(U, &why))
      throw RunError("initial state is inadmissible (n <= 0 or T <= 0): " + why);
    // a summary that says "running" after the process has gone means it died (killed,
    // out of memory): never a stale "completed" from an earlier run in the folder
    if (scene.write_summary && Utilities::MPI::this_mpi_process(comm) == 0)
      {
        const std::string file = scene.output_file("_summary.csv");
        const std::string tmp = summary_tmp(file);
        std::ofstream(tmp) << "key,value\nstatus,running\n";
        std::error_code ec;
        std::filesystem::rename(tmp, file, ec);
      }
    // a run from the scene's initial state writes it; a restart (even from the t = 0
    // checkpoint) has it already
    if (step == 0 && scene.initial_checkpoint.empty())
      {
        output->write(U, t * t0, 0);
        write_checkpoint_now();
      }
    Vector backup(U);
    const double mass0 = totals()[0];
    // largest body force per unit mass [m/s^2]: gravity plus the container's acceleration
    const double g_eff = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                                   scene.gravity[2] * scene.gravity[2]) +
                         scene.vibration_amplitude * std::pow(2 * M_PI * scene.vibration_frequency, 2);
    double       min_dt = std::numeric_limits<double>::infinity(), max_dt = 0, min_cut_dt = min_dt;
    double       min_cfl = std::numeric_limits<double>::infinity(), min_cfl_t = 0;
    // final output, statistics, summary line and summary.csv: at the end time, at a
    // steady state, or (status failed/overpacking) with the last admissible state
    auto finish = [&](const std::string &status) {
      if (!(status == "steady" && t < t_end * (1 - 1e-12))) // a steady stop has just written its output
        {
          // stopped between output times (signal, wall time, failure) with convective
          // time owed: the output shows the synchronised state, the checkpoint keeps the
          // state and the owed time, so that a restart continues exactly
          if (owed_ > 0)
            {
              Vector V;
              if (!synchronised_state(V))
                pcout << "  the convective half-step owed at the stop failed: the final output "
                         "shows the state before it\n";
              output->write(V, t * t0, step);
            }
          else
            output->write(U, t * t0, step);
          write_checkpoint_now();
        }
      sum.steps              = step;
      sum.min_dt_si          = (std::isfinite(min_dt) ? min_dt : (std::isfinite(min_cut_dt) ? min_cut_dt : 0)) * t0;
      sum.max_dt_si          = max_dt * t0;
      sum.min_cfl_dt_si      = std::isfinite(min_cfl) ? min_cfl * t0 : 0;
      sum.min_cfl_dt_time_si = min_cfl_t * t0;
      sum.mass_drift         = std::abs(totals()[0] - mass0) / mass0;
      sum.cells              = patch_->n_global_cells();
      sum.max_cells          = std::max<unsigned long long>(max_cells, sum.cells);
      sum.adaptations        = adaptations;
      sum.refined_cells      = refined_cells;
      sum.coarsened_cells    = coarsened_cells;
    sum.temperature_repairs = Utilities::MPI::sum(temperature_repairs, comm);
    sum.convective_steps    = convective_pieces; // the same on every rank
    sum.max_temperature_repair = Utilities::MPI::max(max_repair, comm);
      sum.ranks              = Utilities::MPI::n_mpi_processes(comm);
      {
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        const double bytes    = 1024. * usage.ru_maxrss; // Linux: kilobytes
        sum.peak_memory_max   = Utilities::MPI::max(bytes, comm);
        sum.peak_memory_total = Utilities::MPI::sum(bytes, comm);
      }
      sum.time_si            = t * t0;
      sum.wall_seconds       = std::chrono::duration<double>(clock::now() - start).count();
      sum.convection_seconds = Utilities::MPI::max(conv_seconds, comm);
      sum.adaptation_seconds = Utilities::MPI::max(adapt_seconds, comm);
      sum.convection         = conv->global_statistics();
      sum.diffusion_active   = integrator != nullptr;
      if (integrator)
        {
          sum.diffusion         = integrator->global_statistics();
          sum.diffusion_seconds = Utilities::MPI::max(diff_seconds, comm);
        }

      const auto  &cs = sum.convection;
      const double nr = Utilities::MPI::n_mpi_processes(comm);
      pcout << "run summary: " << sum.steps << " steps to t = " << sum.time_si << " s, "
            << sum.rejected_steps << " rejected (retried with half dt)\n"
            << "  wall " << sum.wall_seconds << " s, convection " << sum.convection_seconds << " s, "
            << cs.cell_updates / std::max(sum.convection_seconds, 1e-30) / nr
            << " cell-updates/s per RK stage per core";
      if (integrator && scene.convection)
        pcout << ", " << sum.convective_steps << " SSP-RK3 steps ("
              << (scene.merge_strang ? "merged" : "symmetric") << " Strang splitting)";
      pcout << "\n"
            << "  flux points " << cs.flux.points;
      if (scene.flux == FluxType::musta)
        pcout << ", MUSTA stages/point " << double(cs.flux.stages) / std::max<double>(cs.flux.points, 1)
              << ", MUSTA fallbacks to Rusanov " << cs.flux.fallbacks;
      pcout << "\n  positivity: reconstructions reset to the cell average (cell x direction x stage) "
            << cs.limited_cells << ", cell updates redone first order (a posteriori) "
            << cs.fallback_cells << "\n";
      if (integrator)
        {
          const auto &ds = sum.diffusion;
          pcout << "  diffusion step: " << sum.diffusion_seconds << " s, " << ds.steps << " steps, "
                << ds.newton_iterations << " Newton iterations ("
                << double(ds.newton_iterations) / std::max<double>(ds.steps, 1) << "/step), "
                << ds.linear_iterations << " GMRES iterations ("
                << double(ds.linear_iterations) / std::max<double>(ds.newton_iterations, 1)
                << "/Newton), " << ds.newton_failures
                << " Newton failures, " << ds.linear_failures << " GMRES failures, "
                << ds.switches_to_midpoint << " switches to implicit midpoint, "
                << ds.full_jacobian_retries << " retries with the fully coupled Jacobian";
          if (ds.explicit_substeps)
            pcout << ", " << ds.explicit_substeps << " explicit sub-steps";
          if (ds.rkl2_steps)
            pcout << "\n    RKL2: " << ds.rkl2_steps << " steps, " << ds.rkl2_stages << " stages ("
                  << double(ds.rkl2_stages) / ds.rkl2_steps << "/step), " << ds.rkl2_seconds << " s ("
                  << ds.rkl2_seconds / ds.rkl2_steps << " s/step); implicit: " << ds.implicit_steps
                  << " steps, " << ds.implicit_seconds << " s ("
                  << ds.implicit_seconds / std::max<double>(ds.implicit_steps, 1) << " s/step); "
                  << ds.rkl2_fallbacks << " failed RKL2 steps redone implicitly";
          if (ds.jacobians)
            pcout << "\n    of which: " << ds.jacobian_seconds << " s in " << ds.jacobians
                  << " Jacobians (finite differences + Newton matrix; kept for " << ds.matrix_reuses
                  << " further steps, " << ds.stale_matrix_retries << " steps redone with a fresh one), "
                  << ds.preconditioner_seconds
                  << " s in preconditioner set-ups, " << ds.linear_seconds << " s in GMRES (rank 0)";
          pcout << "\n";
        }
      if (sum.diffusion_active && std::isfinite(sum.diffusion.min_explicit_dt))
        pcout << "  time step: " << sum.min_dt_si << " .. " << sum.max_dt_si
              << " s; explicit diffusive limit down to " << sum.diffusion.min_explicit_dt * t0
              << " s (at t = " << sum.diffusion.min_explicit_dt_time * t0 << " s); steps up to "
              << sum.diffusion.max_dt_over_explicit << " x that limit\n";
      pcout << "  mass drift " << sum.mass_drift << " (relative)\n";
      pcout << "  memory: peak resident " << sum.peak_memory_max / 1048576. << " MiB (largest rank), "
            << sum.peak_memory_total / 1024. / std::max<double>(sum.max_cells, 1)
            << " KiB per cell (all ranks, at the most cells)\n";
      if (sum.diffusion.friction_dissipation > 0)
        pcout << "  frictional dissipation (dense closure, work of mu_f lost to heat): "
              << friction_dissipation_si(sum) << (dim == 3 ? " J" : dim == 2 ? " J/m" : " J/m^2")
              << "\n";
      if (scene.max_level > 0)
        pcout << "  adaptive mesh: " << sum.adaptations << " adaptations, " << sum.refined_cells
              << " cells refined, " << sum.coarsened_cells << " coarsened; " << sum.cells
              << " cells at the end, at most " << sum.max_cells << "; adaptation " << sum.adaptation_seconds
              << " s\n";
      if (sum.temperature_repairs > 0)
        pcout << "  temperature floor: " << sum.temperature_repairs
              << " cell updates of a cooling dense pile ended with T < " << physics::GranularGas<dim>::temperature_floor
              << " (scaled) and were set to it; largest thermal-energy deficit "
              << sum.max_temperature_repair * units_.energy() << " J per grain (README, 'Dense closure')\n";
      if (scene.write_summary)
        write_summary(sum, status);
      if (scene.write_vtu || scene.write_profiles || scene.write_summary)
        {
          pcout << "  output in " << scene.output_directory << "/:";
          if (scene.write_vtu)
            pcout << " " << scene.base_name << ".pvd (ParaView)";
          if (scene.write_profiles)
            pcout << " " << scene.base_name << "_profiles.csv";
          if (scene.write_summary)
            pcout << " " << scene.base_name << "_summary.csv";
          pcout << "\n";
        }
    };
    while (t < t_end * (1 - 1e-12) && (scene.max_steps == 0 || step < scene.max_steps))
      {
        // adaptation on absolute step numbers: a restarted run adapts where the
        // uninterrupted one did
        if (scene.max_level > 0 && step % scene.adapt_interval == 0 && step > 0)
          {
            const auto c0 = clock::now();
            adapt_mesh(false);
            adapt_seconds += std::chrono::duration<double>(clock::now() - c0).count();
          }
        double dt = dt_fixed, dt_cfl = 0;
        if (scene.convection) // the convective CFL limits the step; diffusion never does
          {
            const double rate = conv->max_rate(U);
            if (!(rate > 0) || !std::isfinite(rate))
              throw RunError("no finite wave speed at t = " + std::to_string(t * t0) + " s");
            dt_cfl = scene.cfl / rate;
            dt     = dt_fixed > 0 ? std::min(dt_cfl, dt_fixed) : dt_cfl;
            if (dt_cfl < min_cfl)
              {
                min_cfl   = dt_cfl;
                min_cfl_t = t;
              }
            // merged splitting: the step's convective part is the owed half plus dt/2;
            // keep it within the CFL limit by shortening dt (the step after is then back
            // at the limit). Where the limit fell by more than that allows, the
            // convective part is split into pieces instead (advance())
            const double room = 2 * (dt_cfl - owed_); // the longest dt with owed + dt/2 <= dt_cfl
            if (merge && owed_ > 0 && room >= 0.5 * dt)
              dt = std::min(dt, room);
          }
        const double dt_uncut = dt;
        dt = std::min(dt, t_end - t);
        dt = std::min(dt, next_output - t);
        // merged Strang splitting: the closing C(dt/2) is owed to the next step, except
        // at output and end times and before the step limit (a checkpoint between output
        // times stores the owed time, so a restart continues exactly)
        const bool last_step = scene.max_steps > 0 && step + 1 >= scene.max_steps;
        auto       sync_at   = [&](const double h) {
          return !merge || last_step || t + h >= next_output * (1 - 1e-12);
        };
        if (backup.get_partitioner() != U.get_partitioner())
          backup.reinit(U.get_partitioner()); // the mesh changed
        backup          = U;
        unsigned int tries = 0;
        while (true)
          {
            if constexpr (std::is_same_v<Description, physics::GranularGas<dim>>)
              {
                // the splitting-error allowance of the temperature repair (GranularGas)
                desc.repair_energy = 10 * std::pow(g_eff * dt * t0 / units_.velocity, 2);
              }
            // a retried step (halved dt) also halves its convective pieces
            if (advance(t, dt, sync_at(dt), tries == 0 ? dt_cfl : dt) && conv->admissible(U, &why))
              break;
            why.clear();
            conv->admissible(U, &why); // where and what, for the message
            if (why.empty())
              why = conv->failure();
            if (why.empty() && integrator)
              why = integrator->failure();
            ++sum.rejected_steps;
            if (++tries > scene.max_step_retries)
              {
                std::ostringstream os;
                os << "step " << step << " at t = " << t * t0 << " s stays inadmissible (n <= 0, "
                   << "T <= 0 or phi >= phi_c) after " << scene.max_step_retries
                   << " retries with halved time step (last dt = " << dt * t0 << " s)";
                if (!why.empty())
                  os << "; first bad " << why;
                os << ". Lower 'Numerics/CFL number' or use a more diffusive reconstruction"
               << (integrator ? ", or check the diffusion step (Newton failures: " +
                                  std::to_string(integrator->statistics().newton_failures) + ")" :
                                std::string())
               << ".";
                // the run ends cleanly: the last admissible state (no mass lost) is written
                // as the final output, checkpoint and summary, then the run stops
                U = backup;
                const std::string packing = overpacking_report(U);
                std::string       message = os.str();
                if (!packing.empty())
                  message = "over-packing at t = " + std::to_string(t * t0) + " s: " + packing +
                            " Kinetic theory gives no pressure to a pile at rest (T -> 0), so a "
                            "settling layer reaches phi_c in finite time; switch on 'Dense "
                            "closure/Model = johnson-jackson' (README, 'Dense closure'). Details: " +
                            message;
                finish(packing.empty() ? "failed" : "overpacking");
                pcout << "  the last admissible state (t = " << t * t0
                      << " s) is the final output\n";
                throw RunError(message);
              }
            pcout << "  step " << step << ": inadmissible state, retrying with dt = " << dt * t0 / 2
                  << " s" << (why.empty() ? std::string() : " (" + why + ")") << "\n";
            U  = backup;
            dt = dt / 2;
          }
        owed_ = sync_at(dt) ? 0 : 0.5 * dt;
        t += dt;
        ++step;
        // a step cut short to land on an output or end time says nothing about the
        // scheme's step; halved (retried) steps do and are kept
        if (tries == 0 && dt < dt_uncut)
          min_cut_dt = std::min(min_cut_dt, dt);
        else
          min_dt = std::min(min_dt, dt);
        max_dt = std::max(max_dt, dt);
        if (t >= next_output * (1 - 1e-12))
          {
            if (t < t_end * (1 - 1e-12))
              {
                output->write(U, t * t0, step);
                write_checkpoint_now();
              }
            next_output = interval > 0 ? std::min(next_output + interval, t_end) : t_end;
            if (scene.steady_tolerance > 0 && interval > 0)
              {
                // steady state: total kinetic energy and centre of mass along the profile
                // direction both change by less than the tolerance over one output interval
                const unsigned int pd = scene.profile_direction < 0 ? dim - 1 : scene.profile_direction;
                double             v[3] = {0, 0, 0}; // kinetic energy, n x_pd, n
                for (unsigned int s = 0; s < patch_->n_owned(); ++s)
                  {
                    const double *u = &U.local_element(std::size_t(s) * (dim + 2));
                    const double  vol = patch_->cell_volume(s);
                    double        m2 = 0;
                    for (unsigned int d = 0; d < dim; ++d)
                      m2 += u[1 + d] * u[1 + d];
                    v[0] += 0.5 * m2 / u[0] * vol;
                    v[1] += u[0] * patch_->center(s)[pd] * vol;
                    v[2] += u[0] * vol;
                  }
                Utilities::MPI::sum(ArrayView<const double>(v, 3), comm, ArrayView<double>(v, 3));
                const double ke = v[0], com = v[1] / v[2];
                const double L  = patch_->cell_size(pd) * patch_->cells(pd);
                if (have_steady_reference && std::abs(ke - steady_ke) <= scene.steady_tolerance * ke &&
                    std::abs(com - steady_com) <= scene.steady_tolerance * L)
                  {
                    pcout << "  steady state at t = " << t * t0 << " s: kinetic energy and centre of mass "
                          << "changed by " << std::abs(ke - steady_ke) / ke << " and "
                          << std::abs(com - steady_com) / L << " (relative) over the last "
                          << scene.output_interval << " s (Time/Steady state tolerance = "
                          << scene.steady_tolerance << ")\n";
                    sum.steady = true;
                    break;
                  }
                have_steady_reference = true;
                steady_ke             = ke;
                steady_com            = com;
              }
          }
        // SIGTERM / SIGINT (every rank stops after the same step). Test hook (README,
        // "Checkpoints"): GRANHYDRO_SIGTERM_AT_STEP=K sends SIGTERM to every rank after step
        // K, so that a test interrupts at a known step
        if (sigterm_at_step() > 0 && step == sigterm_at_step())
          std::raise(SIGTERM);
        interrupted_by = Utilities::MPI::max(int(stop_signal()), comm);
        if (interrupted_by)
          {
            pcout << "  " << (interrupted_by == SIGINT ? "SIGINT" : "SIGTERM") << " received: stopping at t = "
                  << t * t0 << " s, step " << step << " (final output, checkpoint and summary follow)\n";
            break;
          }
        const auto now = clock::now();
        if (scene.max_wall_seconds > 0 &&
            Utilities::MPI::max(std::chrono::duration<double>(now - start).count(), comm) >
              scene.max_wall_seconds)
          {
            pcout << "  wall time limit (Time/Maximum wall time = " << scene.max_wall_seconds
                  << " s) reached at t = " << t * t0 << " s, step " << step << "\n";
            wall_limited = true;
            break;
          }
        if (std::chrono::duration<double>(now - last_progress).count() >= scene.progress_interval)
          {
            last_progress       = now;
            const double wall   = std::chrono::duration<double>(now - start).count();
            const double frac   = t / t_end;
            // rate and ETA from this run's own steps and time (a restart starts mid-way);
            // with Time/Maximum steps the run ends at whichever comes first
            const double done   = (t - start_time_) / std::max(t_end - start_time_, 1e-300);
            const double rate   = (step - start_step_) / std::max(wall, 1e-12);
            double       eta    = wall * (1 - done) / std::max(done, 1e-12);
            if (scene.max_steps > 0 && rate > 0)
              eta = std::min(eta, (double(scene.max_steps) - step) / rate);
            pcout << "  t = " << std::scientific << std::setprecision(4) << t * t0 << " s ("
                  << std::fixed << std::setprecision(1) << 100 * frac << " %)  dt = "
                  << std::scientific << std::setprecision(3) << dt * t0 << " s  step " << step
                  << "  " << std::fixed << std::setprecision(1) << rate << " steps/s  ETA "
                  << hms(eta) << std::defaultfloat << std::setprecision(6) << "\n";
          }
      }
    // Time/Maximum steps reached before the end time: say so, not "completed"
    const bool step_limited = !sum.steady && !wall_limited && !interrupted_by && t < t_end * (1 - 1e-12);
    if (step_limited)
      pcout << "  step limit (Time/Maximum steps = " << scene.max_steps << ") reached at t = " << t * t0
            << " s of " << scene.end_time << " s\n";
    sum.interrupted_by = interrupted_by;
    finish(sum.steady ? "steady" :
           interrupted_by ? (interrupted_by == SIGINT ? "interrupted (SIGINT)" : "interrupted (SIGTERM)") :
           wall_limited ? "wall time limit" :
           step_limited ? "maximum steps" :
                          "completed");
    return sum;
  }

  template <int dim, class Description>
  std::string Simulation<dim, Description>::overpacking_report(const Vector &V) const
  {
    if constexpr (!std::is_same_v<Description, physics::GranularGas<dim>>)
      {
        (void)V;
        return {};
      }
    else
      {
        constexpr unsigned int NC    = dim + 2;
        const double           phi_c = desc.phi_c;
        // local: max phi and its cell; grains in cells with phi >= 0.99 phi_c; all grains
        double       max_phi = 0, dense = 0, all = 0;
        unsigned int where = 0, n_dense = 0;
        for (unsigned int s = 0; s < patch_->n_owned(); ++s)
          {
            const double n   = V.local_element(std::size_t(s) * NC);
            const double phi = physics::packing_fraction(n);
            all += n;
            if (phi > max_phi)
              {
                max_phi = phi;
                where   = s;
              }
            if (phi >= 0.99 * phi_c)
              {
                dense += n;
                ++n_dense;
              }
          }
        const auto mm = Utilities::MPI::min_max_avg(max_phi, comm);
        if (mm.max < 0.99 * phi_c)
          return {};
        // the centre of the densest cell, from its owner
        double x[3] = {0, 0, 0};
        if (Utilities::MPI::this_mpi_process(comm) == mm.max_index)
          for (unsigned int d = 0; d < dim; ++d)
            x[d] = patch_->center(where)[d];
        Utilities::MPI::sum(ArrayView<const double>(x, 3), comm, ArrayView<double>(x, 3));
        const double dense_sum = Utilities::MPI::sum(dense, comm), all_sum = Utilities::MPI::sum(all, comm);
        const unsigned int n_dense_sum = Utilities::MPI::sum(n_dense, comm);
        std::ostringstream os;
        os << "the packing fraction reached close packing (phi_c = " << phi_c
           << "): the last admissible state has phi = " << std::setprecision(8) << mm.max
           << std::setprecision(6) << " at x = (";
        for (unsigned int d = 0; d < dim; ++d)
          os << (d ? ", " : "") << x[d];
        os << ") m, and " << n_dense_sum << " cell(s) at phi >= " << 0.99 * phi_c << " hold "
           << 100 * dense_sum / all_sum << " % of the grains.";
        return os.str();
      }
  }

  template <int dim, class Description>
  void Simulation<dim, Description>::write_summary(const RunSummary &sum, const std::string &status) const
  {
    if (Utilities::MPI::this_mpi_process(comm) != 0)
      return;
    std::error_code ec;
    std::filesystem::create_directories(scene.output_directory, ec);
    const std::string file = scene.output_file("_summary.csv");
    const std::string tmp  = summary_tmp(file);
    std::ofstream     out(tmp);
    if (!out)
      throw RunError("cannot write " + file + " (Output/Directory)");
    const double t0 = units_.time();
    const auto  &cs = sum.convection;
    const auto  &ds = sum.diffusion;
    out << std::setprecision(10) << "key,value\n"
        << "status," << status << "\n"
        << "dimension," << dim << "\n"
        << "cells," << sum.cells << "\n"
        << "max_cells," << sum.max_cells << "\n"
        << "adaptations," << sum.adaptations << "\n"
        << "refined_cells," << sum.refined_cells << "\n"
        << "coarsened_cells," << sum.coarsened_cells << "\n"
        << "ranks," << sum.ranks << "\n"
        << "time," << sum.time_si << "\n"
        << "steps," << sum.steps << "\n"
        << "rejected_steps," << sum.rejected_steps << "\n"
        << "steady," << (sum.steady ? 1 : 0) << "\n"
        << "wall_seconds," << sum.wall_seconds << "\n"
        << "convection_seconds," << sum.convection_seconds << "\n"
        << "convective_steps," << sum.convective_steps << "\n"
        << "diffusion_seconds," << sum.diffusion_seconds << "\n"
        << "min_dt," << sum.min_dt_si << "\n"
        << "max_dt," << sum.max_dt_si << "\n"
        << "min_cfl_dt," << sum.min_cfl_dt_si << "\n"
        << "min_cfl_dt_time," << sum.min_cfl_dt_time_si << "\n"
        << "mass_drift," << sum.mass_drift << "\n"
        << "peak_memory_bytes_max_rank," << sum.peak_memory_max << "\n"
        << "peak_memory_bytes_all_ranks," << sum.peak_memory_total << "\n"
        << "temperature_repairs," << sum.temperature_repairs << "\n"
        << "max_temperature_repair_J," << sum.max_temperature_repair * units_.energy() << "\n"
        << "flux_points," << cs.flux.points << "\n"
        << "musta_stages," << cs.flux.stages << "\n"
        << "limited_reconstructions," << cs.limited_cells << "\n"
        << "first_order_fallbacks," << cs.fallback_cells << "\n"
        << "diffusion_steps," << ds.steps << "\n"
        << "newton_iterations," << ds.newton_iterations << "\n"
        << "gmres_iterations," << ds.linear_iterations << "\n"
        << "jacobians," << ds.jacobians << "\n"
        << "matrix_reuses," << ds.matrix_reuses << "\n"
        << "rkl2_steps," << ds.rkl2_steps << "\n"
        << "rkl2_stages," << ds.rkl2_stages << "\n"
        << "rkl2_fallbacks," << ds.rkl2_fallbacks << "\n"
        << "rkl2_seconds," << ds.rkl2_seconds << "\n"
        << "implicit_steps," << ds.implicit_steps << "\n"
        << "implicit_seconds," << ds.implicit_seconds << "\n"
        << "stale_matrix_retries," << ds.stale_matrix_retries << "\n"
        << "jacobian_seconds," << ds.jacobian_seconds << "\n"
        << "preconditioner_seconds," << ds.preconditioner_seconds << "\n"
        << "gmres_seconds," << ds.linear_seconds << "\n"
        << "newton_failures," << ds.newton_failures << "\n"
        << "gmres_failures," << ds.linear_failures << "\n"
        << "switches_to_midpoint," << ds.switches_to_midpoint << "\n"
        << "full_jacobian_retries," << ds.full_jacobian_retries << "\n"

        << "explicit_substeps," << ds.explicit_substeps << "\n"
        << "min_explicit_dt," << (std::isfinite(ds.min_explicit_dt) ? ds.min_explicit_dt * t0 : 0) << "\n"
        << "min_explicit_dt_time," << ds.min_explicit_dt_time * t0 << "\n"
        << "max_dt_over_explicit," << ds.max_dt_over_explicit << "\n"
        << "friction_dissipation_J," << friction_dissipation_si(sum) << "\n";
    out.close();
    std::filesystem::rename(tmp, file, ec);
    if (ec)
      throw RunError("cannot write " + file + ": " + ec.message());
  }

  template <int dim>
  int run_dim(const Scene &scene, const MPI_Comm comm, std::ostream &log)
  {
    if (scene.model == "granular")
      {
        Simulation<dim, physics::GranularGas<dim>> sim(scene, comm, log);
        sim.setup();
        const int sig = sim.run().interrupted_by;
        return sig ? 128 + sig : 0;
      }
    Simulation<dim> sim(scene, comm, log);
    sim.setup();
    const int sig = sim.run().interrupted_by;
    return sig ? 128 + sig : 0;
  }

  namespace
  {
    volatile std::sig_atomic_t stop_requested = 0;

    unsigned long sigterm_at_step()
    {
      static const unsigned long k = [] {
        const char *v = std::getenv("GRANHYDRO_SIGTERM_AT_STEP");
        return v ? std::strtoul(v, nullptr, 10) : 0UL;
      }();
      return k;
    }

    extern "C" void on_stop_signal(const int sig)
    {
      stop_requested = sig;
      std::signal(sig, SIG_DFL); // a second signal ends the process at once
    }
  } // namespace

  void install_stop_signal_handlers()
  {
    std::signal(SIGTERM, on_stop_signal);
    std::signal(SIGINT, on_stop_signal);
  }

  int stop_signal() { return stop_requested; }

  int run_scene(const Scene &scene, const MPI_Comm comm, std::ostream &log)
  {
    switch (scene.dimension)
      {
        case 1:
          return run_dim<1>(scene, comm, log);
        case 2:
          return run_dim<2>(scene, comm, log);
        default:
          return run_dim<3>(scene, comm, log);
      }
  }

  template class Simulation<1, physics::IdealGas<1>>;
  template class Simulation<2, physics::IdealGas<2>>;
  template class Simulation<3, physics::IdealGas<3>>;
  template class Simulation<1, physics::GranularGas<1>>;
  template class Simulation<2, physics::GranularGas<2>>;
  template class Simulation<3, physics::GranularGas<3>>;
} // namespace granhydro
