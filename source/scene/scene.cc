#include <granhydro/scene/scene.h>
#include <granhydro/mesh/mesh_file.h>
#include <granhydro/io/checkpoint.h>
#include <granhydro/physics/garzo_dufty.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <type_traits>
#include <sstream>
#include <vector>

namespace granhydro
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;

  namespace
  {
    const char *side_names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};

    /// decimals the code can compute with: finite and 0 or normal (a denormal such as
    /// 1e-310 loses its digits and overflows when inverted)
    bool usable_decimal(const double v)
    {
      return std::isfinite(v) && (v == 0 || std::abs(v) >= std::numeric_limits<double>::min());
    }
    const char *const usable_decimal_rule =
      "decimal values must lie within 2.2e-308 .. 1.8e308 in magnitude, or be 0";

    /// a number for a message: 6 significant digits, exponent when needed
    std::string fmt(const double v)
    {
      std::ostringstream os;
      os << std::setprecision(6) << v;
      return os.str();
    }


    template <typename T, std::size_t N>
    std::array<T, N> parse_list(const std::string &text,
                                const std::string &name,
                                const unsigned int dim,
                                const T             fill)
    {
      const auto parts = dealii::Utilities::split_string_list(text, ',');
      if (parts.size() != dim && parts.size() != 3)
        throw SceneError("parameter '" + name + "' = '" + text + "': expected " +
                         std::to_string(dim) +
                         " comma-separated values (one per dimension) or 3");
      std::array<T, N> a;
      a.fill(fill);
      for (unsigned int i = 0; i < parts.size() && i < N; ++i)
        {
          std::istringstream is(parts[i]);
          T                  v;
          if (!(is >> v) || !(is >> std::ws).eof())
            throw SceneError("parameter '" + name + "': cannot read '" + parts[i] +
                             "' as a number");
          if constexpr (std::is_floating_point_v<T>)
            if (!usable_decimal(v))
              throw SceneError("parameter '" + name + "': '" + parts[i] + "' is not a usable number (" +
                               usable_decimal_rule + ")");
          a[i] = v;
        }
      return a;
    }
  } // namespace

  std::string to_string(ReconstructionType t)
  {
    switch (t)
      {
        case ReconstructionType::first_order:
          return "first order";
        case ReconstructionType::muscl:
          return "muscl";
        case ReconstructionType::weno3:
          return "weno3";
        default:
          return "weno5";
      }
  }
  std::string to_string(FluxType t)
  {
    return t == FluxType::musta ? "musta" : (t == FluxType::rusanov ? "rusanov" : "hll");
  }
  std::string to_string(FaceQuadrature q)
  {
    return q == FaceQuadrature::gauss ? "gauss" : "midpoint";
  }
  std::string to_string(BoundaryType b)
  {
    return b == BoundaryType::periodic     ? "periodic" :
           b == BoundaryType::slip_wall    ? "slip wall" :
           b == BoundaryType::no_slip_wall ? "no-slip wall" :
                                             "outflow";
  }

  double Scene::grain_mass() const
  {
    return material_density * M_PI * std::pow(grain_diameter, 3) / 6.;
  }

  std::vector<std::pair<std::string, std::string>> active_effects(const Scene &s)
  {
    std::vector<std::pair<std::string, std::string>> e;
    auto num = [](double v) {
      std::ostringstream os;
      os << v;
      return os.str();
    };
    if (s.convection)
      e.emplace_back("convection", "Effects/Convection = true");
    if (s.max_level > 0)
      e.emplace_back("adaptive mesh refinement", "Adaptivity/Maximum level = " + std::to_string(s.max_level) +
                                                   ", every " + std::to_string(s.adapt_interval) + " steps");
    if (s.model != "granular")
      return e;
    if (s.viscosity)
      e.emplace_back("viscous stress", "granular model, Effects/Viscosity = true");
    if (s.heat_conduction)
      e.emplace_back("heat conduction", "granular model, Effects/Heat conduction = true");
    if (s.cooling && s.restitution < 1 && s.friction == 0)
      e.emplace_back("inelastic cooling", "restitution " + num(s.restitution) + " < 1");
    if (s.cooling && s.friction > 0)
      e.emplace_back("inelastic cooling, frictional grains",
                     "restitution " + num(s.restitution) + ", Material/Friction coefficient = " +
                       num(s.friction) + ": effective restitution " +
                       num(physics::GarzoDufty1999::effective_restitution(s.restitution, s.friction)) +
                       " in the cooling rate");
    if (s.dense_closure != "none")
      e.emplace_back("dense closure: contact pressure" +
                       std::string(s.closure_time > 0 && s.viscosity ? " and frictional viscosity" : ""),
                     "Dense closure/Model = " + s.dense_closure + ", F = " + num(s.closure_F) +
                       " Pa, phi_min = " + num(s.closure_phi_min));
    double g2 = 0;
    for (unsigned int d = 0; d < s.dimension; ++d)
      g2 += s.gravity[d] * s.gravity[d];
    if (g2 > 0)
      e.emplace_back("gravity", "|g| = " + num(std::sqrt(g2)) + " m/s^2");
    if (s.vibration_amplitude > 0 && s.vibration_frequency > 0)
      {
        const double w = 2 * M_PI * s.vibration_frequency;
        e.emplace_back("wall vibration (inertial body force)",
                       "A = " + num(s.vibration_amplitude) + " m, f = " + num(s.vibration_frequency) +
                         " Hz, A w^2 = " + num(s.vibration_amplitude * w * w) + " m/s^2");
      }
    const char *sides[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    for (unsigned int i = 0; i < 2 * s.dimension; ++i)
      if (s.wall_restitution[i] < 1)
        e.emplace_back(std::string("dissipative wall ") + sides[i],
                       "wall restitution " + num(s.wall_restitution[i]) + " < 1");
    return e;
  }

  std::map<std::string, double> expression_constants(const Scene &s)
  {
    // t: the initial state is the state at t = 0 (documented for the expressions)
    std::map<std::string, double> constants{{"pi", M_PI}, {"t", 0.}};
    for (const auto &c : dealii::Utilities::split_string_list(s.initial_constants, ','))
      {
        const auto kv = dealii::Utilities::split_string_list(c, '=');
        if (kv.size() != 2)
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': expected "
                           "'name=value' pairs, got '" + c + "'");
        const std::string &name = kv[0];
        bool ident = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_');
        for (const char ch : name)
          ident = ident && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_');
        if (!ident)
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': '" + name +
                           "' is not a name (a letter or '_', then letters, digits or '_')");
        if (name == "x" || name == "y" || name == "z" || name == "t" || name == "pi")
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': '" + name +
                           "' is reserved (the variables x, y, z, t and the constant pi)");
        if (constants.count(name))
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': '" + name +
                           "' is defined twice");
        double             v;
        std::istringstream is(kv[1]);
        if (constants.size() > 1000)
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': more than "
                           "1000 constants; an initial state needs a few");
        if (!(is >> v) || !(is >> std::ws).eof() || !usable_decimal(v))
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': cannot read "
                           "the value of '" + name + "' ('" + kv[1] + "' is not a finite number)");
        constants[name] = v;
      }
    return constants;
  }

  bool Scene::diffusion_active() const
  {
    if (model != "granular")
      return false;
    bool g = false;
    for (unsigned int d = 0; d < dimension; ++d)
      g = g || gravity[d] != 0 || wall_restitution[2 * d] < 1 || wall_restitution[2 * d + 1] < 1;
    g = g || (vibration_amplitude > 0 && vibration_frequency > 0);
    return viscosity || heat_conduction || (cooling && (restitution < 1 || friction > 0)) || g;
  }

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
    c.boundary              = boundary;
    c.length_unit           = units().length;
    return c;
  }

  MeshSettings Scene::mesh_settings() const
  {
    MeshSettings m;
    m.mesh_file        = mesh_file;
    m.mesh_refinements = mesh_refinements;
    m.lower            = lower;
    m.upper            = upper;
    m.cells            = cells;
    m.max_level        = max_level;
    m.boundary         = boundary;
    m.wall_velocity    = wall_velocity;
    m.velocity_unit    = units().velocity;
    return m;
  }

  io::OutputSettings Scene::output_settings() const
  {
    io::OutputSettings o;
    o.directory           = output_directory;
    o.base_name           = base_name;
    o.write_vtu           = write_vtu;
    o.write_profiles      = write_profiles;
    o.write_checkpoint    = write_checkpoint;
    o.profile_direction   = profile_direction;
    o.section_direction   = section_direction;
    o.units               = units();
    o.vibration_amplitude = vibration_amplitude;
    o.vibration_frequency = vibration_frequency;
    o.vibration_direction = vibration_direction;
    return o;
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
    prm.declare_entry("Dimension", "2", Patterns::Integer(1, 3),
                      "Number of resolved space dimensions (1, 2 or 3). Unresolved "
                      "directions are homogeneous.");
    prm.enter_subsection("Domain");
    {
      prm.declare_entry("Mesh file", "", Patterns::Anything(),
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
                        "With a mesh file 'Lower corner', 'Upper corner' and 'Cells' are ignored.");
      prm.declare_entry("Mesh refinements", "0", Patterns::Integer(0, 8),
                        "Global refinements of the mesh file's coarse cells (each halves the "
                        "cell size).");
      prm.declare_entry("Lower corner", "0, 0, 0", Patterns::Anything(),
                        "Lower corner of the box [m], one value per dimension (extra ignored; "
                        "ignored with a 'Mesh file').");
      prm.declare_entry("Upper corner", "0.1, 0.1, 0.1", Patterns::Anything(),
                        "Upper corner of the box [m] (ignored with a 'Mesh file').");
      prm.declare_entry("Cells", "100, 100, 1", Patterns::Anything(),
                        "Number of cells per direction (uniform Cartesian mesh; ignored with "
                        "a 'Mesh file').");
      for (const char *s : side_names)
        {
          prm.declare_entry(std::string("Boundary ") + s, "slip wall",
                            Patterns::Selection("periodic|slip wall|no-slip wall|outflow"),
                            std::string("Boundary condition on the ") + s +
                              " side: periodic (both sides of a direction), slip wall "
                              "(reflecting, no tangential stress), no-slip wall (velocity "
                              "of the wall imposed, wall shear stress kept: doc/physics.md 5.1, "
                              "P10), outflow (transmissive, zero-gradient ghost state).");
          prm.declare_entry(std::string("Wall velocity ") + s, "0, 0, 0", Patterns::Anything(),
                            std::string("Velocity of the ") + s +
                              " wall [m/s] (no-slip walls; tangential only).");
          prm.declare_entry(std::string("Wall restitution ") + s, "1", Patterns::Double(0, 1),
                            std::string("Grain-wall restitution eps_w of the ") + s +
                              " wall: 1 = elastic (adiabatic), < 1 = dissipative wall with "
                              "the heat flux q_w = (1 - eps_w) p_w sqrt(2T/(pi m)) "
                              "(doc/physics.md 5.2, contact theorem; granular model).");
        }
    }
    prm.leave_subsection();

    prm.enter_subsection("Dense closure");
    {
      prm.declare_entry("Model", "none", Patterns::Selection("none|johnson-jackson"),
                        "Contact/frictional stresses of the dense regime (granular model; the "
                        "paper has none). 'johnson-jackson': pressure p_f ~ F (phi - phi_min)^r "
                        "/ (phi_c - phi)^s from a contact potential in the energy (T stays "
                        "positive on expansion) and shear viscosity mu_f = t_f sin(theta_f) p_f. "
                        "Without it a pile cooling at rest reaches phi_c in finite time and the "
                        "run stops with a diagnostic (README, 'Dense closure').");
      prm.declare_entry("Coefficient", "0.05", Patterns::Double(0, Patterns::Double::max_double_value),
                        "F [Pa] (Johnson, Nott & Jackson 1990; MFIX/OpenFOAM default 0.05).");
      prm.declare_entry("Minimum packing fraction", "0.62", Patterns::Double(0, 1),
                        "phi_min: no contact stress below it. Default 0.62 for smooth "
                        "(frictionless) spheres, whose enduring contact network only forms "
                        "next to random close packing, so a settled pile sits at 0.62-0.64; "
                        "0.5 is Johnson-Jackson's value for frictional grains (piles at about "
                        "0.58). README, 'Dense closure'.");
      prm.declare_entry("Exponent r", "2", Patterns::Double(1, 10), "r (default 2, at least 1).");
      prm.declare_entry("Exponent s", "5", Patterns::Double(1.5, 20), "s (default 5, above 1).");
      prm.declare_entry("Viscosity time", "0.5", Patterns::Double(0, Patterns::Double::max_double_value),
                        "t_f [s] of the frictional viscosity mu_f = t_f sin(theta_f) p_f "
                        "(OpenFOAM's Johnson-Jackson choice 0.5 s; 0 switches mu_f off).");
      prm.declare_entry("Friction angle", "28.5", Patterns::Double(0, 90),
                        "theta_f [degrees] of the frictional viscosity.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Material");
    {
      prm.declare_entry("Model", "ideal gas", Patterns::Selection("ideal gas|granular"),
                        "Constitutive model. 'ideal gas': verification model (p = n T, "
                        "no transport), the dilute elastic limit of granular gases. "
                        "'granular': hard spheres, p = n T Z(phi) with Torquato's pair "
                        "correlation and Garzo-Dufty (1999) transport (doc/physics.md 2, 3).");
      prm.declare_entry("Restitution coefficient", "1", Patterns::Double(0, 1),
                        "Normal coefficient of restitution eps of grain-grain collisions "
                        "(granular model; 0.5 <= eps <= 1).");
      prm.declare_entry("Friction coefficient", "0", Patterns::Double(0, 1),
                        "Coulomb friction coefficient mu between grains (granular model; 0 = "
                        "smooth spheres). The cooling rate uses Chialvo & Sundaresan's (2013) "
                        "effective restitution e_eff = eps - (3/2) mu exp(-3 mu); pressure and "
                        "transport keep eps (README, 'Frictional grains').");
      prm.declare_entry("Freezing packing fraction", "0.49", Patterns::Double(0, 1),
                        "phi_f of Torquato's pair correlation (granular model).");
      prm.declare_entry("Close packing fraction", "0.64", Patterns::Double(0, 1),
                        "phi_c, random close packing: chi has its pole here (granular model).");
      prm.declare_entry("Close packing guard", "1e-3", Patterns::Double(0, 0.1),
                        "delta: chi is continued linearly (C1) beyond phi_c - delta, so "
                        "coefficients stay finite (doc/physics.md 2, guard).");
      prm.declare_entry("Maximum mean free path", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Knudsen cap L [m] (granular model; 0 = off, the paper's model): where "
                        "the mean free path l = 1/(sqrt(2) pi n sigma^2) exceeds L, the "
                        "transport coefficients eta, gamma, kappa, mu are scaled by L/l, so the "
                        "diffusivities stay below ~L sqrt(T/m) instead of diverging as n -> 0 "
                        "(doc/physics.md P14). Hydrodynamics has no meaning there anyway; use a few "
                        "cell sizes for scenes with near-vacuum.");
      prm.declare_entry("Grain diameter", "1e-3", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Grain diameter sigma [m].");
      prm.declare_entry("Material density", "2600", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Material density rho_s [kg/m^3]; grain mass m = rho_s pi sigma^3 / 6.");
      prm.declare_entry("Adiabatic index", "1.6666666666666667", Patterns::Double(1, 3),
                        "Adiabatic index gamma_a of the ideal-gas model (5/3 = dilute "
                        "elastic grains, internal energy 3T/2 per grain).");
    }
    prm.leave_subsection();

    prm.enter_subsection("Initial state");
    {
      prm.declare_entry("Packing fraction", "0.01", Patterns::Anything(),
                        "Expression in x, y, z [m] (and t = 0, pi, constants) for the "
                        "packing fraction phi = n pi sigma^3 / 6 (> 0).");
      prm.declare_entry("Velocity", "0; 0; 0", Patterns::Anything(),
                        "Expressions for the velocity components [m/s], separated by ';' "
                        "(one per dimension or 3).");
      prm.declare_entry("Temperature", "1e-8", Patterns::Anything(),
                        "Expression for the granular temperature T [J] (energy units, > 0).");
      prm.declare_entry("Constants", "", Patterns::Anything(),
                        "Constants for the expressions, 'name=value, name=value'.");
      prm.declare_entry("Quadrature points", "3", Patterns::Integer(1, 8),
                        "Gauss points per direction used to average the initial state "
                        "over each cell (finite-volume cell averages).");
      prm.declare_entry("Checkpoint", "", Patterns::Anything(),
                        "A checkpoint file written by an earlier run of the same mesh "
                        "(Output/Write checkpoint): the state, time and step are read from "
                        "it and the run continues to 'Time/End time' (any number of MPI "
                        "ranks). The expressions above are then ignored. Empty: start from "
                        "the expressions at t = 0.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Numerics");
    {
      prm.declare_entry("Reconstruction", "weno5",
                        Patterns::Selection("first order|muscl|weno3|weno5"),
                        "Reconstruction of the conservative variables to face points: "
                        "weno5 (paper section 4, Jiang-Shu weights), weno3, muscl (MC "
                        "limiter), first order.");
      prm.declare_entry("Face quadrature", "gauss", Patterns::Selection("gauss|midpoint"),
                        "gauss: 2 Gauss points per face direction (paper eq. 4.6, "
                        "Titarev-Toro), midpoint: one point per face (face average used "
                        "as point value, second order on nonlinear fluxes).");
      prm.declare_entry("No-slip wall flux", "mirror", Patterns::Selection("mirror|pressure"),
                        "Convective flux through no-slip walls. mirror: the numerical flux "
                        "between the cell and its mirror ghost (velocity reflected about the "
                        "wall velocity), mass and energy parts set to 0; its tangential "
                        "momentum part is a numerical wall friction that shrinks with the "
                        "mesh. pressure: the paper's eq. 6.1a, zero mass and energy flux and "
                        "only the wall pressure (the normal momentum of the same flux) - no "
                        "tangential momentum; the wall shear stress then comes from the "
                        "diffusion step alone.");
      prm.declare_entry("Flux", "musta", Patterns::Selection("musta|rusanov|hll"),
                        "Numerical flux: musta (multi-stage FORCE, paper eqs. 4.7-4.9 with "
                        "dx/dt in the dissipation term, doc/physics.md P12), rusanov, hll.");
      prm.declare_entry("MUSTA maximum stages", "4", Patterns::Integer(1, 20),
                        "Cap on the number of FORCE stages of the MUSTA flux (1 = FORCE).");
      prm.declare_entry("MUSTA minimum stages", "2", Patterns::Integer(1, 2),
                        "2: the stopping rule compares the fluxes of consecutive stages, so "
                        "every face takes at least 2 stages. 1: after the first stage a face "
                        "keeps the FORCE flux where the change of a further stage, estimated "
                        "as S_max |U_R - U_L| for mass, momentum and energy, is below the "
                        "tolerance (smooth regions): 35-40 % less convective time, larger "
                        "errors (README, 'Cost of the diffusion step and of the convective "
                        "kernel').");
      prm.declare_entry("MUSTA tolerance", "0.01", Patterns::Double(0, 1),
                        "Stopping rule: stop when the FORCE flux changes between stages by "
                        "less than this in mass, momentum (as a vector) and energy, each "
                        "relative to max(|F|, S_max (|U_L| + |U_R|)/2) (paper: 1 %).");
      prm.declare_entry("MUSTA local CFL", "0.9", Patterns::Double(0, 1),
                        "Local Courant number of the MUSTA predictor stages (Titarev-Toro).");
      prm.declare_entry("CFL number", "0.4", Patterns::Double(0, 1),
                        "Courant number: dt = CFL / max_cells sum_d (|u_d| + c)/dx_d.");
      prm.declare_entry("Fixed time step", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Fixed time step [s]; 0 = from the CFL number. A fixed step is "
                        "still reduced if it would exceed the CFL limit.");
      prm.declare_entry("Reference velocity", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Velocity unit of the internal scaled units [m/s]; 0 = sqrt(g sigma), "
                        "g = 9.81 m/s^2.");
      prm.declare_entry("Strang splitting", "merged", Patterns::Selection("merged|symmetric"),
                        "How the convective step C and the diffusion step V are composed "
                        "(eq. 3.5). symmetric: C(dt/2) V(dt) C(dt/2) every step. merged: the "
                        "same scheme with adjacent convective halves taken as one step, "
                        "C(dt0/2) V(dt0) C((dt0 + dt1)/2) V(dt1) ... C(dtn/2), synchronised at "
                        "every output time: half the convective work, second order as well.");
      prm.declare_entry("Maximum step retries", "6", Patterns::Integer(0, 30),
                        "A step whose result is inadmissible (n <= 0 or T <= 0) is retried "
                        "with half the time step at most this many times, then the run stops.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Effects");
    {
      prm.declare_entry("Convection", "true", Patterns::Bool(),
                        "Run the convective step C (Euler part, paper section 4).");
      prm.declare_entry("Viscosity", "true", Patterns::Bool(),
                        "Viscous stress (shear and bulk viscosity; granular model).");
      prm.declare_entry("Heat conduction", "true", Patterns::Bool(),
                        "Heat flux q = -kappa grad T - mu grad n (granular model).");
      prm.declare_entry("Cooling", "true", Patterns::Bool(),
                        "Inelastic cooling -(3/2) n T zeta0 (granular model, eps < 1).");
      prm.declare_entry("Diffusive flux", "full", Patterns::Selection("full|diagonal"),
                        "full: all cross-derivative terms (doc/physics.md 4.3); diagonal: only "
                        "D_ii d_i U as in the paper's eq. 5.6.");
      prm.declare_entry("Gravity", "0, 0, 0", Patterns::Anything(),
                        "Body force per unit mass g [m/s^2], one value per dimension "
                        "(e.g. 0, -9.81 in 2D). Granular model only.");
      prm.declare_entry("Vibration amplitude", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Amplitude A [m] of the container motion s(t) = A sin(2 pi f t) e_s. "
                        "The equations are solved in the container frame (all walls at rest) "
                        "with the inertial body force g + A (2 pi f)^2 sin(2 pi f t) e_s "
                        "(doc/physics.md 5.3); output velocities and kinetic energy densities are in "
                        "the lab frame (container velocity ds/dt added).");
      prm.declare_entry("Vibration frequency", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Frequency f [Hz] of the container motion.");
      prm.declare_entry("Vibration direction", "y", Patterns::Selection("x|y|z"),
                        "Direction e_s of the container motion.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Diffusion step");
    {
      prm.declare_entry("Integrator", "cost-based",
                        Patterns::Selection("gauss-legendre|implicit midpoint|sdirk2|rkl2|cost-based|automatic|explicit euler"),
                        "Time integrator of the diffusion/source step V: 2-stage Gauss-Legendre "
                        "(order 4, A-stable), implicit midpoint (order 2, A-stable), sdirk2 "
                        "(Alexander's 2-stage SDIRK, order 2, L-stable: damps stiff modes; stages "
                        "solved one after the other), rkl2 (Runge-Kutta-Legendre super-time-"
                        "stepping, order 2, explicit: ~sqrt(dt / explicit limit) evaluations), "
                        "cost-based (per step the cheaper of sdirk2 and rkl2 by a deterministic "
                        "cost model), automatic (Gauss-Legendre, "
                        "implicit midpoint when its Newton iteration fails), or the sub-cycled "
                        "explicit Euler baseline.");
      prm.declare_entry("Newton tolerance", "1e-10", Patterns::Double(0, 1),
                        "Modified Newton stops when dt * |change of stage slopes| is below "
                        "this times the cell's own scale in every cell: its density, "
                        "sqrt(2 n E) for momenta, its energy density (at least 1e-3 of that "
                        "component's largest value in the domain).");
      prm.declare_entry("Newton maximum iterations", "25", Patterns::Integer(1, 200),
                        "Cap on modified Newton iterations; a step that does not converge is "
                        "retried with half the time step.");
      prm.declare_entry("Linear solver tolerance", "1e-12", Patterns::Double(0, 1),
                        "Relative residual of Trilinos GMRES (with Linear forcing = "
                        "eisenstat-walker: the smallest one it may ask for).");
      prm.declare_entry("Linear forcing", "eisenstat-walker", Patterns::Selection("eisenstat-walker|fixed"),
                        "GMRES tolerance per Newton iteration: eisenstat-walker (inexact Newton, "
                        "Eisenstat & Walker 1996 choice 2: 0.9 (|r_k|/|r_k-1|)^2 in [Linear solver "
                        "tolerance, 0.1]; the Newton tolerance stays the accuracy control) or "
                        "fixed (always Linear solver tolerance).");
      prm.declare_entry("Reuse Newton matrix", "true", Patterns::Bool(),
                        "Keep the Newton matrix and its preconditioner for up to 8 further steps "
                        "while the previous step converged in <= 4 Newton iterations per stage "
                        "and dt changed by <= 10 %; a step whose iteration then fails is redone "
                        "with a fresh matrix (counted in the summary).");
      prm.declare_entry("Preconditioner", "block ilu", Patterns::Selection("block ilu|ilu|amg"),
                        "Newton matrix and preconditioner of GMRES: block ilu (granhydro's "
                        "block-sparse matrix, one dense block per pair of neighbouring cells, "
                        "with block ILU(0): the leanest and fastest), ilu (Trilinos Epetra "
                        "matrix with Ifpack ILU(0)) or amg (Trilinos Epetra matrix with ML).");
      prm.declare_entry("Jacobian", "lagged", Patterns::Selection("lagged|full"),
                        "Cross-derivative terms in the Newton matrix: lagged (deferred "
                        "correction; a step whose iteration stalls is redone fully coupled) "
                        "or full (always fully coupled, 19-point stencil in 3D).");
    }
    prm.leave_subsection();

    prm.enter_subsection("Adaptivity");
    {
      prm.declare_entry("Maximum level", "0", Patterns::Integer(0, 7),
                        "Adaptive octree refinement (p4est): cells may be refined this many "
                        "levels above Domain/Cells; 0 = uniform mesh. Box domains in 2D and 3D.");
      prm.declare_entry("Indicator", "jumps", Patterns::Selection("jumps|second differences"),
                        "Refinement indicator, from the number density n and the pressure p: "
                        "'jumps' = the largest normalised jump across the cell's faces, "
                        "|a_L - a_R| / min(a_L, a_R); 'second differences' = Loehner's "
                        "indicator |a_R - 2 a + a_L| / (|a_R - a| + |a - a_L| + 0.05 (|a_R| + "
                        "2 |a| + |a_L|)) per direction, in [0, 1]: high at shocks, contacts and "
                        "kinks, low in smooth regions (a rarefaction fan stays coarse).");
      prm.declare_entry("Refine threshold", "0.05", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Refine a cell where the indicator exceeds this.");
      prm.declare_entry("Coarsen threshold", "0.01", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Coarsen a family of cells where the indicator of all of them stays below "
                        "this (must be below the refine threshold).");
      prm.declare_entry("Interval", "5", Patterns::Integer(1),
                        "Time steps between adaptations.");
      prm.declare_entry("Buffer", "2", Patterns::Integer(0, 8),
                        "Layers of cells around a cell flagged for refinement that are refined too, "
                        "so that a shock stays in the fine region until the next adaptation.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Time");
    {
      prm.declare_entry("End time", "0.2", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Simulated end time [s].");
      prm.declare_entry("Maximum wall time", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Stop cleanly (final output, checkpoint, summary.csv with status "
                        "'wall time limit') after this many wall-clock seconds; 0 = no limit. "
                        "Restart from the checkpoint to go on.");
      prm.declare_entry("Maximum steps", "0", Patterns::Integer(0),
                        "Stop after this many steps (0 = no limit).");
      prm.declare_entry("Steady state tolerance", "0", Patterns::Double(0, 1),
                        "Stop before the end time once a steady state is reached: the total "
                        "kinetic energy and the mean height (centre of mass) change by less "
                        "than this fraction between two output times (needs Output/Interval "
                        "> 0; 0 = off).");
    }
    prm.leave_subsection();

    prm.enter_subsection("Output");
    {
      prm.declare_entry("Directory", "output", Patterns::Anything(),
                        "Directory for VTU/PVTU/PVD and CSV files (created if missing).");
      prm.declare_entry("Base name", "solution", Patterns::FileName(),
                        "Base name of output files.");
      prm.declare_entry("Interval", "0", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Simulated time between outputs [s]; 0 = initial and final state only.");
      prm.declare_entry("Write VTU", "true", Patterns::Bool(), "Write VTU/PVTU + PVD for ParaView.");
      prm.declare_entry("Write checkpoint", "true", Patterns::Bool(),
                        "Write <Directory>/<Base name>.checkpoint at every output time and at "
                        "the end (replaced atomically), for 'Initial state/Checkpoint'.");
      prm.declare_entry("Write summary", "true", Patterns::Bool(),
                        "Write summary.csv at the end of the run: one 'key,value' line per "
                        "figure of the run summary (cells, steps, wall times, smallest and "
                        "largest time step, the explicit diffusive limit, Newton/GMRES "
                        "iterations, mass drift), for scripts such as tools/work_precision.py.");
      prm.declare_entry("Write profiles", "true", Patterns::Bool(),
                        "Write profiles.csv: averages over the directions other than the "
                        "profile direction.");
      prm.declare_entry("Profile direction", "auto", Patterns::Selection("auto|x|y|z"),
                        "Direction of the profiles; auto = the last resolved direction.");
      prm.declare_entry("Cross-section direction", "none", Patterns::Selection("none|x|y|z"),
                        "3D scenes: also write cross_section.csv, the averages along this "
                        "direction as a map over the other two (e.g. x for the chute: the "
                        "velocity field across the channel, paper fig. 8).");
      prm.declare_entry("Progress interval", "5", Patterns::Double(0, Patterns::Double::max_double_value),
                        "Wall-clock seconds between progress lines (0 = every step).");
      prm.declare_entry("Verbose", "true", Patterns::Bool(), "Print the run log.");
    }
    prm.leave_subsection();
  }

  std::string default_scene_text()
  {
    return R"(# granhydro default scene: a cylindrical blast in a dilute elastic granular
# gas (ideal-gas limit), 2D, 100 x 100 cells, slip walls. Runs in seconds.
set Dimension = 2
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 0.1, 0.1
  set Cells = 100, 100
  set Boundary x- = slip wall
  set Boundary x+ = slip wall
  set Boundary y- = slip wall
  set Boundary y+ = slip wall
end
subsection Material
  set Model = ideal gas
  set Grain diameter = 1e-3
  set Material density = 2600
end
subsection Initial state
  set Packing fraction = if((x-0.05)^2 + (y-0.05)^2 < 0.02^2, 0.02, 0.01)
  set Velocity = 0; 0
  set Temperature = if((x-0.05)^2 + (y-0.05)^2 < 0.02^2, 1e-7, 1e-8)
end
subsection Time
  set End time = 0.15
end
subsection Output
  set Directory = output
  set Interval = 0.03
end
)";
  }

  Scene scene_from(ParameterHandler &prm, const std::string &source_name);
  Scene parse_scene_text(const std::string &text, const std::string &source_name,
                         const std::vector<std::string> &overrides,
                         const std::vector<std::string> *origin);

  namespace
  {
    /// one command-line override "Section/Sub/Name=value" into prm
    void apply_override(ParameterHandler &prm, const std::string &o)
    {
      const std::string where = "command line: -p '" + o + "': ";
      const auto        eq    = o.find('=');
      if (eq == std::string::npos || eq == 0)
        throw SceneError(where + "expected \"Section/Name=value\" (e.g. -p \"Time/End time=0.1\")");
      const auto trim = [](std::string x) {
        const auto b = x.find_first_not_of(" \t"), e = x.find_last_not_of(" \t");
        return b == std::string::npos ? std::string() : x.substr(b, e - b + 1);
      };
      std::vector<std::string> path;
      std::string              rest = o.substr(0, eq);
      for (std::size_t slash; (slash = rest.find('/')) != std::string::npos; rest = rest.substr(slash + 1))
        path.push_back(trim(rest.substr(0, slash)));
      const std::string name = trim(rest), value = trim(o.substr(eq + 1));
      for (const auto &p : path)
        prm.enter_subsection(p);
      try
        {
          prm.set(name, value);
        }
      catch (const dealii::ExceptionBase &e)
        {
          for (std::size_t i = 0; i < path.size(); ++i)
            prm.leave_subsection();
          const std::string m = human_message(e.what());
          if (m.find("not yet declared") != std::string::npos)
            throw SceneError(where + "there is no parameter '" + trim(o.substr(0, eq)) +
                             "' (granhydro --print-parameters lists them)");
          throw SceneError(where + m);
        }
      for (std::size_t i = 0; i < path.size(); ++i)
        prm.leave_subsection();
    }
  } // namespace

  namespace
  {
    /// "FILE, line N" of line `number` (1-based) of the parsed text
    std::string place(const std::string &source, const std::vector<std::string> *origin,
                      const unsigned long number)
    {
      if (origin && number >= 1 && number <= origin->size())
        return (*origin)[number - 1];
      return source + ", line " + std::to_string(number);
    }

    /// a deal.II parse message with its place in our words ("Line <N> of file <input
    /// string>" -> the real file and line) and without unprintable bytes
    std::string parse_message(const std::string &m, const std::string &source,
                              const std::vector<std::string> *origin)
    {
      std::string out = source + ": " + m;
      const auto  a   = m.find("Line <");
      const auto  b   = m.find("> of file <input string>");
      if (a != std::string::npos && b != std::string::npos && b > a)
        out = place(source, origin, std::strtoul(m.c_str() + a + 6, nullptr, 10)) + m.substr(b + 24);
      for (char &ch : out)
        if (static_cast<unsigned char>(ch) < 32 || static_cast<unsigned char>(ch) > 126)
          ch = '?';
      if (out.size() > 400)
        out = out.substr(0, 400) + " ...";
      return out;
    }

    /// every 'subsection' closed by an 'end', every 'end' closing one: named by line (deal.II
    /// only says that the counts differ)
    void check_sections(const std::string &text, const std::string &source,
                        const std::vector<std::string> *origin)
    {
      std::istringstream                                  in(text);
      std::vector<std::pair<unsigned long, std::string>> open;
      unsigned long                                       number = 0;
      for (std::string line; std::getline(in, line);)
        {
          ++number;
          const auto hash = line.find('#');
          if (hash != std::string::npos)
            line.erase(hash);
          std::istringstream is(line);
          std::string        word;
          if (!(is >> word))
            continue;
          for (char &ch : word)
            ch = std::tolower(static_cast<unsigned char>(ch));
          if (word == "subsection")
            {
              std::string name;
              std::getline(is >> std::ws, name);
              open.emplace_back(number, name);
            }
          else if (word == "end")
            {
              if (open.empty())
                throw SceneError("in " + place(source, origin, number) +
                                 ": 'end' without an open 'subsection'");
              open.pop_back();
            }
        }
      if (!open.empty())
        throw SceneError("in " + place(source, origin, open.back().first) +
                         ": 'subsection " + open.back().second +
                         "' is never closed (an 'end' line is missing)");
    }
  } // namespace

  Scene parse_scene(const std::string &text, const std::string &source_name,
                    const std::vector<std::string> &overrides)
  {
    return parse_scene_text(text, source_name, overrides, nullptr);
  }

  Scene parse_scene_text(const std::string &text, const std::string &source_name,
                         const std::vector<std::string> &overrides,
                         const std::vector<std::string> *origin)
  {
    ParameterHandler prm;
    declare_scene_parameters(prm);
    check_sections(text, source_name, origin);
    try
      {
        prm.parse_input_from_string(text, /*last_line=*/"", /*skip_undefined=*/false);
      }
    catch (const dealii::ExceptionBase &e)
      {
        throw SceneError("in " + parse_message(human_message(e.what()), source_name, origin));
      }
    catch (const std::exception &e)
      {
        throw SceneError("in " + parse_message(human_message(e.what()), source_name, origin));
      }
    for (const auto &o : overrides)
      apply_override(prm, o);

    try
      {
        return scene_from(prm, source_name);
      }
    catch (const SceneError &e)
      {
        const std::string m = e.what();
        if (m.rfind("in ", 0) == 0)
          throw;
        throw SceneError("in " + source_name + ": " + m);
      }
    catch (const dealii::ExceptionBase &e)
      {
        // a value that passes the pattern but does not convert (e.g. 1e-310, below the
        // smallest normal double): name the entry deal.II names
        const std::string m = human_message(e.what());
        const auto        a = m.find("for entry <"), b = m.find('>', a == std::string::npos ? 0 : a);
        const std::string entry = a != std::string::npos && b != std::string::npos ?
                                    m.substr(a + 11, b - a - 11) :
                                    std::string("?");
        throw SceneError("in " + source_name + ": parameter '" + entry + "': " + m + " (" +
                         usable_decimal_rule + ")");
      }
  }

  Scene scene_from(ParameterHandler &prm, const std::string &source_name)
  {
    Scene s;
    s.source    = source_name;
    s.dimension = prm.get_integer("Dimension");
    const unsigned int dim = s.dimension;

    prm.enter_subsection("Domain");
    s.mesh_file        = prm.get("Mesh file");
    s.mesh_refinements = prm.get_integer("Mesh refinements");
    if (!s.mesh_file.empty() && s.mesh_file[0] != '/' && !source_name.empty() &&
        source_name[0] != '<')
      {
        // relative to the scene file, so that a scene runs from any working directory
        const auto slash = source_name.rfind('/');
        if (slash != std::string::npos)
          s.mesh_file = source_name.substr(0, slash + 1) + s.mesh_file;
      }
    s.lower = parse_list<double, 3>(prm.get("Lower corner"), "Domain/Lower corner", dim, 0.);
    s.upper = parse_list<double, 3>(prm.get("Upper corner"), "Domain/Upper corner", dim, 1.);
    {
      const auto c = parse_list<double, 3>(prm.get("Cells"), "Domain/Cells", dim, 1.);
      for (unsigned int d = 0; d < 3; ++d)
        {
          if (d < dim && (c[d] < 1 || c[d] != std::floor(c[d]) || c[d] > 1e6))
            throw SceneError("parameter 'Domain/Cells': entry " + std::to_string(d + 1) +
                             " must be a whole number between 1 and 1e6");
          s.cells[d] = d < dim ? static_cast<unsigned int>(c[d]) : 1;
        }
    }
    for (unsigned int i = 0; i < 6; ++i)
      {
        const std::string v = prm.get(std::string("Boundary ") + side_names[i]);
        s.boundary[i] = v == "periodic"     ? BoundaryType::periodic :
                        v == "slip wall"    ? BoundaryType::slip_wall :
                        v == "no-slip wall" ? BoundaryType::no_slip_wall :
                                              BoundaryType::outflow;
        s.wall_velocity[i] = parse_list<double, 3>(prm.get(std::string("Wall velocity ") + side_names[i]),
                                                   std::string("Domain/Wall velocity ") + side_names[i], dim, 0.);
        s.wall_restitution[i] = prm.get_double(std::string("Wall restitution ") + side_names[i]);
      }
    prm.leave_subsection();

    prm.enter_subsection("Material");
    s.model            = prm.get("Model");
    s.grain_diameter   = prm.get_double("Grain diameter");
    s.material_density = prm.get_double("Material density");
    s.adiabatic_index  = prm.get_double("Adiabatic index");
    s.restitution       = prm.get_double("Restitution coefficient");
    s.friction          = prm.get_double("Friction coefficient");
    s.phi_freezing      = prm.get_double("Freezing packing fraction");
    s.phi_close_packing = prm.get_double("Close packing fraction");
    s.guard_delta       = prm.get_double("Close packing guard");
    s.max_free_path     = prm.get_double("Maximum mean free path");
    prm.leave_subsection();

    prm.enter_subsection("Dense closure");
    s.dense_closure   = prm.get("Model");
    s.closure_F       = prm.get_double("Coefficient");
    s.closure_phi_min = prm.get_double("Minimum packing fraction");
    s.closure_r       = prm.get_double("Exponent r");
    s.closure_s       = prm.get_double("Exponent s");
    s.closure_time    = prm.get_double("Viscosity time");
    s.closure_angle   = prm.get_double("Friction angle");
    prm.leave_subsection();

    prm.enter_subsection("Initial state");
    s.initial_packing_fraction = prm.get("Packing fraction");
    s.initial_velocity         = prm.get("Velocity");
    s.initial_temperature      = prm.get("Temperature");
    s.initial_constants        = prm.get("Constants");
    s.initial_quadrature       = prm.get_integer("Quadrature points");
    s.initial_checkpoint       = prm.get("Checkpoint");
    prm.leave_subsection();

    prm.enter_subsection("Numerics");
    {
      const std::string r = prm.get("Reconstruction");
      s.reconstruction    = r == "first order" ? ReconstructionType::first_order :
                            r == "muscl"       ? ReconstructionType::muscl :
                            r == "weno3"       ? ReconstructionType::weno3 :
                                                 ReconstructionType::weno5;
      s.face_quadrature =
        prm.get("Face quadrature") == "gauss" ? FaceQuadrature::gauss : FaceQuadrature::midpoint;
      s.no_slip_pressure_flux = prm.get("No-slip wall flux") == "pressure";
      const std::string f = prm.get("Flux");
      s.flux = f == "musta" ? FluxType::musta : (f == "rusanov" ? FluxType::rusanov : FluxType::hll);
      s.musta_max_stages   = prm.get_integer("MUSTA maximum stages");
      s.musta_tolerance    = prm.get_double("MUSTA tolerance");
      s.musta_min_stages   = prm.get_integer("MUSTA minimum stages");
      s.musta_local_cfl    = prm.get_double("MUSTA local CFL");
      s.cfl                = prm.get_double("CFL number");
      s.fixed_time_step    = prm.get_double("Fixed time step");
      s.reference_velocity = prm.get_double("Reference velocity");
      s.max_step_retries   = prm.get_integer("Maximum step retries");
      s.merge_strang       = prm.get("Strang splitting") == "merged";
    }
    prm.leave_subsection();

    prm.enter_subsection("Effects");
    s.convection      = prm.get_bool("Convection");
    s.viscosity       = prm.get_bool("Viscosity");
    s.heat_conduction = prm.get_bool("Heat conduction");
    s.cooling         = prm.get_bool("Cooling");
    s.diagonal_flux   = prm.get("Diffusive flux") == "diagonal";
    s.gravity         = parse_list<double, 3>(prm.get("Gravity"), "Effects/Gravity", dim, 0.);
    s.vibration_amplitude = prm.get_double("Vibration amplitude");
    s.vibration_frequency = prm.get_double("Vibration frequency");
    {
      const std::string v  = prm.get("Vibration direction");
      s.vibration_direction = v == "x" ? 0 : (v == "y" ? 1 : 2);
    }
    prm.leave_subsection();

    prm.enter_subsection("Diffusion step");
    s.integrator            = prm.get("Integrator");
    s.newton_tolerance      = prm.get_double("Newton tolerance");
    s.newton_max_iterations = prm.get_integer("Newton maximum iterations");
    s.linear_tolerance      = prm.get_double("Linear solver tolerance");
    s.inexact_newton        = prm.get("Linear forcing") == "eisenstat-walker";
    s.reuse_matrix          = prm.get_bool("Reuse Newton matrix");
    s.preconditioner        = prm.get("Preconditioner");
    s.full_jacobian         = prm.get("Jacobian") == "full";
    prm.leave_subsection();

    prm.enter_subsection("Adaptivity");
    s.max_level         = prm.get_integer("Maximum level");
    s.adapt_indicator   = prm.get("Indicator");
    s.refine_threshold  = prm.get_double("Refine threshold");
    s.coarsen_threshold = prm.get_double("Coarsen threshold");
    s.adapt_interval    = prm.get_integer("Interval");
    s.adapt_buffer      = prm.get_integer("Buffer");
    prm.leave_subsection();

    prm.enter_subsection("Time");
    s.end_time  = prm.get_double("End time");
    s.max_steps = prm.get_integer("Maximum steps");
    s.max_wall_seconds = prm.get_double("Maximum wall time");
    s.steady_tolerance = prm.get_double("Steady state tolerance");
    prm.leave_subsection();

    prm.enter_subsection("Output");
    s.output_directory = prm.get("Directory");
    s.base_name        = prm.get("Base name");
    s.output_interval  = prm.get_double("Interval");
    s.write_vtu        = prm.get_bool("Write VTU");
    s.write_profiles   = prm.get_bool("Write profiles");
    s.write_checkpoint = prm.get_bool("Write checkpoint");
    s.write_summary    = prm.get_bool("Write summary");
    {
      const std::string p = prm.get("Profile direction");
      s.profile_direction = p == "auto" ? -1 : (p == "x" ? 0 : (p == "y" ? 1 : 2));
    }
    {
      const std::string c = prm.get("Cross-section direction");
      s.section_direction = c == "none" ? -1 : (c == "x" ? 0 : (c == "y" ? 1 : 2));
    }
    s.progress_interval = prm.get_double("Progress interval");
    s.verbose           = prm.get_bool("Verbose");
    prm.leave_subsection();

    validate(s);
    return s;
  }

  namespace
  {
    /// the scene text with its 'include FILE' lines replaced by the files' texts (a path
    /// relative to the including file, as for mesh files); refuses an include cycle (a scene
    /// that included itself recursed until the stack overflowed) and nesting beyond 16
    /// the scene text with every 'include FILE' line replaced by that file's text; origin
    /// gets "FILE, line N" for every line of the result (messages name the real place)
    std::string expand_includes(const std::string &file, std::vector<std::string> chain,
                                std::vector<std::string> &origin)
    {
      std::error_code ec;
      const auto      canon = std::filesystem::weakly_canonical(file, ec).string();
      for (const auto &c : chain)
        if (c == canon)
          throw SceneError("scene file '" + chain.front() + "' includes '" + file +
                           "' again (an include cycle); remove that 'include' line");
      chain.push_back(canon);
      if (chain.size() > 16)
        throw SceneError("scene file '" + chain.front() + "': includes nested deeper than 16 files");
      std::ifstream in(file);
      if (!in)
        throw SceneError("cannot open scene file '" + file + "'");
      std::string  out;
      unsigned int number = 0;
      for (std::string line; std::getline(in, line);)
        {
          ++number;
          std::istringstream is(line);
          std::string        word, target;
          if (is >> word && word == "include" && is >> target)
            {
              std::filesystem::path path(target);
              if (path.is_relative())
                path = std::filesystem::path(file).parent_path() / path;
              if (!std::filesystem::is_regular_file(path, ec))
                throw SceneError("scene file '" + file + "': 'include " + target +
                                 "' does not name a readable file (paths are relative to the "
                                 "including file)");
              out += expand_includes(path.string(), chain, origin);
              out += '\n';
              origin.push_back(file + ", line " + std::to_string(number));
            }
          else
            {
              out += line + '\n';
              origin.push_back(file + ", line " + std::to_string(number));
            }
        }
      return out;
    }
  } // namespace

  namespace
  {
    /// the initial state at the cell centres of a box domain (at most 64 per direction):
    /// packing fraction in (0, phi_c - guard) for the granular model (> 0 for the ideal
    /// gas), temperature > 0, all finite. Empty if fine, else "parameter|message".
    template <int dim>
    std::string sample_initial_state(const Scene &s, const std::map<std::string, double> &constants,
                                     const std::vector<std::array<double, 3>> &mesh_centres)
    {
      const std::string vars = dim == 1 ? "x" : (dim == 2 ? "x,y" : "x,y,z");
      dealii::FunctionParser<dim> phi(1), T(1), u(dim);
      phi.initialize(vars, s.initial_packing_fraction, constants);
      T.initialize(vars, s.initial_temperature, constants);
      auto vel = dealii::Utilities::split_string_list(s.initial_velocity, ';');
      vel.resize(dim);
      u.initialize(vars, vel, constants);
      std::array<unsigned int, 3> m{{1, 1, 1}};
      std::size_t                 total = 1;
      for (unsigned int d = 0; d < dim; ++d)
        total *= (m[d] = std::min(s.cells[d], 64u));
      if (!mesh_centres.empty()) // a mesh file: its coarse cell centres
        total = mesh_centres.size();
      const bool   granular = s.model == "granular";
      const double phi_max  = s.phi_close_packing - s.guard_delta;
      for (std::size_t k = 0; k < total; ++k)
        {
          dealii::Point<dim> x;
          std::size_t        r = k;
          for (unsigned int d = 0; d < dim; ++d)
            {
              x[d] = mesh_centres.empty() ? s.lower[d] + (r % m[d] + 0.5) * (s.upper[d] - s.lower[d]) / m[d] :
                                            mesh_centres[k][d];
              r /= m[d];
            }
          std::ostringstream where;
          where << " at x = " << x;
          const double p = phi.value(x), t = T.value(x);
          if (!std::isfinite(p) || !(p > 0))
            return "Initial state/Packing fraction|must be positive and finite everywhere: " +
                   fmt(p) + where.str();
          if (!(p >= 1e-12))
            return "Initial state/Packing fraction|must be at least 1e-12 (the scaled density "
                   "would underflow): " + fmt(p) + where.str();
          if (granular && !(p < phi_max))
            return "Initial state/Packing fraction|must stay below phi_c - guard = " +
                   fmt(phi_max) + " (Material/Close packing fraction, Close packing "
                                             "guard): " + fmt(p) + where.str();
          if (!std::isfinite(t) || !(t > 0))
            return "Initial state/Temperature|must be positive and finite everywhere: " +
                   fmt(t) + where.str();
          if (!(std::sqrt(t / s.grain_mass()) <= 1e4))
            return "Initial state/Temperature|gives a thermal speed sqrt(T/m) of " +
                   fmt(std::sqrt(t / s.grain_mass())) + " m/s; allowed up to 1e4 m/s: " + fmt(t) +
                   " J" + where.str();
          for (unsigned int d = 0; d < dim; ++d)
            if (!std::isfinite(u.value(x, d)) || !(std::abs(u.value(x, d)) <= 1e4))
              return "Initial state/Velocity|must be finite and within 1e4 m/s everywhere" + where.str();
        }
      return {};
    }
  } // namespace

  Scene read_scene(const std::string &filename, const std::vector<std::string> &overrides)
  {
    if (filename.empty())
      return parse_scene(default_scene_text(), "<default scene>", overrides);
    // a scene is a regular text file of reasonable size: a directory, /dev/null or
    // /dev/zero would otherwise run the default scene or exhaust the memory
    std::error_code ec;
    const auto      status = std::filesystem::status(filename, ec);
    if (ec || !std::filesystem::exists(status))
      throw SceneError("cannot open scene file '" + filename + "': no such file");
    if (!std::filesystem::is_regular_file(status))
      throw SceneError("scene file '" + filename +
                       "' is not a regular file (a directory or a device); give a .prm file");
    constexpr std::uintmax_t max_bytes = 16u << 20;
    if (std::filesystem::file_size(filename, ec) > max_bytes || ec)
      throw SceneError("scene file '" + filename + "' is larger than 16 MiB (or unreadable); a "
                       "scene is a short parameter file");
    std::vector<std::string> origin;
    const std::string        text = expand_includes(filename, {}, origin);
    // only comments and blank lines: refuse rather than silently run every default
    std::istringstream lines(text);
    bool               statement = false;
    for (std::string line; !statement && std::getline(lines, line);)
      {
        const auto b = line.find_first_not_of(" \t\r");
        statement    = b != std::string::npos && line[b] != '#';
      }
    if (!statement)
      throw SceneError("scene file '" + filename + "' sets no parameter (it is empty or holds only "
                       "comments); run granhydro without a file for the default scene");
    return parse_scene_text(text, filename, overrides, &origin);
  }

  void validate(const Scene &s)
  {
    const unsigned int dim = s.dimension;
    auto fail = [&](const std::string &param, const std::string &msg) {
      throw SceneError("in " + s.source + ": parameter '" + param + "': " + msg);
    };
    const bool mesh = !s.mesh_file.empty();
    MeshFileInfo mesh_info;
    if (mesh)
      {
        if (dim == 1)
          fail("Domain/Mesh file", "mesh files need 'Dimension' 2 or 3");
        try
          {
            mesh_info = check_mesh_file(s.mesh_file, dim);
          }
        catch (const std::exception &e)
          {
            fail("Domain/Mesh file", e.what());
          }
        for (unsigned int i = 0; i < 2 * dim; ++i)
          if (s.boundary[i] == BoundaryType::periodic)
            fail("Domain/Mesh file", std::string("periodic boundaries are not available with a "
                                                 "mesh file ('Boundary ") + side_names[i] +
                                       "' = periodic); use walls or outflow");
        // a wall moves only tangentially: check against the faces' geometric directions
        for (const auto &[id, d] : mesh_info.id_direction)
          if (s.wall_velocity[id][d] != 0)
            fail("Domain/Wall velocity " + std::string(side_names[id]),
                 "a wall moves only tangentially: the mesh has faces with boundary id " +
                   std::to_string(id) + " normal to " + std::string(1, "xyz"[d]) +
                   ", so the " + std::string(1, "xyz"[d]) + " component must be 0");
        double total = mesh_info.n_cells;
        for (unsigned int r = 0; r < s.mesh_refinements; ++r)
          total *= 1u << dim;
        if (total > 5e7)
          fail("Domain/Mesh refinements", "more than 5e7 cells in total");
      }
    if (s.max_level > 0)
      {
        if (mesh)
          fail("Adaptivity/Maximum level", "adaptive meshes need a box domain (no 'Domain/Mesh "
                                           "file'); set it to 0 for a mesh file");
        if (dim == 1)
          fail("Adaptivity/Maximum level", "adaptive meshes need 'Dimension' 2 or 3; set it to 0 "
                                           "in 1D");
        if (!(s.coarsen_threshold < s.refine_threshold))
          fail("Adaptivity/Coarsen threshold", "must be below 'Adaptivity/Refine threshold' (" +
                                                 std::to_string(s.refine_threshold) + ")");
        double total = 1;
        for (unsigned int d = 0; d < dim; ++d)
          total *= double(s.cells[d]) * double(1u << s.max_level);
        if (total > 2e8)
          fail("Adaptivity/Maximum level", "the finest lattice (Domain/Cells times 2^level per "
                                           "direction) would have more than 2e8 points");
      }
    for (unsigned int d = 0; d < dim && !mesh; ++d)
      {
        // coordinates up to 1e6 m (a corner at 1e308 overflowed the cell size), cells of at
        // least 1e-3 grain diameters (below that a run creeps at a vanishing time step)
        if (!(std::abs(s.lower[d]) <= 1e6))
          fail("Domain/Lower corner", "coordinates must lie within +-1e6 m");
        if (!(std::abs(s.upper[d]) <= 1e6))
          fail("Domain/Upper corner", "coordinates must lie within +-1e6 m");
        if (!(s.upper[d] > s.lower[d]))
          fail("Domain/Upper corner", "must exceed 'Domain/Lower corner' in direction " +
                                        std::string(1, "xyz"[d]));
        if (!((s.upper[d] - s.lower[d]) / s.cells[d] >= 1e-3 * s.grain_diameter))
          fail("Domain/Cells", "cells along " + std::string(1, "xyz"[d]) +
                                 " would be smaller than 1e-3 grain diameters (" +
                                 fmt((s.upper[d] - s.lower[d]) / s.cells[d]) + " m)");
        const bool plo = s.boundary[2 * d] == BoundaryType::periodic;
        const bool phi = s.boundary[2 * d + 1] == BoundaryType::periodic;
        if (plo != phi)
          fail(std::string("Domain/Boundary ") + side_names[2 * d + (plo ? 1 : 0)],
               "periodic boundaries come in pairs: set both '" + std::string(side_names[2 * d]) +
                 "' and '" + side_names[2 * d + 1] + "' to periodic");
        const unsigned int need =
          s.reconstruction == ReconstructionType::weno5 ? 3 :
          (s.reconstruction == ReconstructionType::first_order ? 1 : 2);
        if (!plo && s.cells[d] < need)
          fail("Domain/Cells", "direction " + std::string(1, "xyz"[d]) +
                                 " has walls and needs at least " + std::to_string(need) +
                                 " cells for reconstruction '" + to_string(s.reconstruction) + "'");
      }
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
              fail("Domain/Wall velocity " + side, "|v| = " + fmt(std::abs(s.wall_velocity[i][k])) +
                                                     " m/s; allowed up to 1e4 m/s");
            if (k >= dim && s.wall_velocity[i][k] != 0) // it would be ignored
              fail("Domain/Wall velocity " + side, "its " + std::string(1, "xyz"[k]) +
                                                     " component names a direction the " +
                                                     std::to_string(dim) + "D scene does not resolve");
          }
        if (vmax != 0 && s.boundary[i] != BoundaryType::no_slip_wall)
          fail("Domain/Wall velocity " + side, "only no-slip walls move (the boundary is " +
                                                 to_string(s.boundary[i]) + ")");
        if (!(vmax <= 1e4))
          fail("Domain/Wall velocity " + side, "|v| = " + fmt(vmax) + " m/s; allowed up to 1e4 m/s");
        if (!mesh && s.wall_velocity[i][d] != 0)
          fail("Domain/Wall velocity " + side, "a wall moves only tangentially: its component "
                                               "along " + std::string(1, "xyz"[d]) + " must be 0");
        if (s.wall_restitution[i] < 1 &&
            (s.boundary[i] == BoundaryType::periodic || s.boundary[i] == BoundaryType::outflow))
          fail("Domain/Wall restitution " + side, "only walls dissipate (the boundary is " +
                                                    to_string(s.boundary[i]) + ")");
        if (s.wall_restitution[i] < 1 && s.model != "granular")
          fail("Domain/Wall restitution " + side, "dissipative walls need 'Material/Model = granular'");
      }
    double total = 1;
    for (unsigned int d = 0; d < dim; ++d)
      total *= s.cells[d];
    if (!mesh && total > 5e7)
      fail("Domain/Cells", "more than 5e7 cells in total");
    if (s.end_time <= 0)
      fail("Time/End time", "must be positive");
    if (s.output_interval > 0 && s.end_time / s.output_interval > 1e5)
      fail("Output/Interval", "would write more than 1e5 outputs before 'Time/End time' (" +
                                fmt(s.end_time) + " s)");
    if (s.fixed_time_step > 0 && s.end_time / s.fixed_time_step > 1e9)
      fail("Numerics/Fixed time step", "would need more than 1e9 steps to 'Time/End time' (" +
                                         fmt(s.end_time) + " s)");
    if (!(s.cfl >= 1e-3 && s.cfl <= 1))
      fail("Numerics/CFL number", "must lie in [1e-3, 1] (SSP-RK3 stability; smaller steps only "
                                  "creep: use 'Numerics/Fixed time step' for a tiny fixed step)");
    if (!(s.linear_tolerance > 0))
      fail("Diffusion step/Linear solver tolerance", "must be positive (GMRES cannot reach 0)");
    if (s.musta_local_cfl <= 0 || s.musta_local_cfl > 1)
      fail("Numerics/MUSTA local CFL", "must lie in (0, 1]");
    if (s.musta_tolerance <= 0)
      fail("Numerics/MUSTA tolerance", "must be positive");
    if (!(s.grain_diameter >= 1e-9 && s.grain_diameter <= 10))
      fail("Material/Grain diameter", fmt(s.grain_diameter) + " m; allowed 1e-9 .. 10 m (the "
                                      "internal units are built on it)");
    if (s.material_density <= 0)
      fail("Material/Material density", "must be positive");
    if (s.adiabatic_index <= 1)
      fail("Material/Adiabatic index", "must exceed 1");
    if (s.model == "granular")
      {
        if (s.restitution < 0.5 || s.restitution > 1)
          fail("Material/Restitution coefficient",
               "must lie in [0.5, 1] (Garzo-Dufty coefficients are verified positive there)");
        if (!(s.friction >= 0 && s.friction <= 1))
          fail("Material/Friction coefficient", "must lie in [0, 1] (0: smooth spheres)");
        // the densest packing of equal spheres is pi / (3 sqrt 2) = 0.7405
        if (!(s.phi_close_packing <= M_PI / (3 * std::sqrt(2.))))
          fail("Material/Close packing fraction", "must not exceed 0.7405, the densest packing of "
                                                  "equal spheres (random close packing: 0.63-0.64)");
        if (!(s.phi_freezing > 0))
          fail("Material/Freezing packing fraction", "must be positive (0.49 for hard spheres)");
        if (!(s.phi_freezing < s.phi_close_packing))
          fail("Material/Freezing packing fraction", "must be below 'Close packing fraction'");
        if (!(s.guard_delta > 0))
          fail("Material/Close packing guard", "must be positive (default 1e-3)");
        if (!(s.guard_delta < s.phi_close_packing - s.phi_freezing))
          fail("Material/Close packing guard", "must be smaller than phi_c - phi_f");
        if (s.dense_closure != "none")
          {
            if (!(s.closure_F > 0))
              fail("Dense closure/Coefficient", "must be positive");
            if (!(s.closure_phi_min < s.phi_close_packing - s.guard_delta))
              fail("Dense closure/Minimum packing fraction",
                   "must be below phi_c - delta (Material/Close packing fraction minus guard)");
          }
      }
    else
      {
        if (s.restitution != 1)
          fail("Material/Restitution coefficient",
               "the ideal-gas model is elastic; use 'Model = granular' for eps < 1");
        if (s.friction != 0)
          fail("Material/Friction coefficient",
               "the ideal-gas model has smooth grains; use 'Model = granular' for mu > 0");
        for (unsigned int d = 0; d < dim; ++d)
          if (s.gravity[d] != 0)
            fail("Effects/Gravity", "the ideal-gas verification model has no body force; use "
                                    "'Material/Model = granular'");
      }
    // body forces beyond any centrifuge (1e6 m/s^2 = 1e5 g) only overflow the scaled units
    {
      double g2 = 0;
      for (unsigned int d = 0; d < dim; ++d)
        g2 += s.gravity[d] * s.gravity[d];
      if (!(std::sqrt(g2) <= 1e6))
        fail("Effects/Gravity", "|g| = " + fmt(std::sqrt(g2)) + " m/s^2; allowed up to 1e6 m/s^2");
      const double a = s.vibration_amplitude * std::pow(2 * M_PI * s.vibration_frequency, 2);
      if (!(a <= 1e6))
        fail("Effects/Vibration amplitude", "the container's acceleration A (2 pi f)^2 = " + fmt(a) +
                                              " m/s^2; allowed up to 1e6 m/s^2");
    }
    // the scaled units keep the state's numbers near 1; a velocity unit far from the
    // default sqrt(g sigma) moves them towards the fixed thresholds (floors, tolerances)
    if (s.reference_velocity > 0)
      {
        const double v0 = std::sqrt(9.81 * s.grain_diameter);
        if (!(s.reference_velocity >= 1e-3 * v0 && s.reference_velocity <= 1e3 * v0))
          fail("Numerics/Reference velocity", fmt(s.reference_velocity) + " m/s; allowed 0 (= sqrt(g sigma) = " +
                                                fmt(v0) + " m/s) or within 1e-3 .. 1e3 times that");
      }
    if ((s.vibration_amplitude > 0) != (s.vibration_frequency > 0))
      fail("Effects/Vibration frequency", "a vibrated container needs both a positive "
                                          "'Vibration amplitude' and 'Vibration frequency'");
    if (s.vibration_amplitude > 0 && s.vibration_direction >= dim)
      fail("Effects/Vibration direction", "names a direction the " + std::to_string(dim) +
                                            "D scene does not resolve");
    if (s.vibration_amplitude > 0 && s.model != "granular")
      fail("Effects/Vibration amplitude", "a vibrated container needs 'Material/Model = granular'");
    if (s.dense_closure != "none" && s.model != "granular")
      fail("Dense closure/Model", "a dense closure needs 'Material/Model = granular'");
    if (!s.convection && s.fixed_time_step <= 0)
      fail("Numerics/Fixed time step", "must be positive when 'Effects/Convection' is off (the "
                                       "convective CFL then sets no time step)");
    if (!s.convection && !s.diffusion_active())
      fail("Effects/Convection", "with convection off the scene must have an active diffusion "
                                 "step (granular model with transport, cooling or gravity)");
    if (s.output_directory.empty())
      fail("Output/Directory", "must not be empty");
    if (s.output_directory.size() > 1024)
      fail("Output/Directory", "a path of " + std::to_string(s.output_directory.size()) +
                                 " characters; allowed up to 1024");
    for (const auto &part : std::filesystem::path(s.output_directory))
      if (part.string().size() > 255)
        fail("Output/Directory", "a folder name of " + std::to_string(part.string().size()) +
                                   " characters; file systems allow up to 255");
    {
      // a file name, not a path: no '/', no leading '.', at most 100 characters of
      // letters, digits, '_', '-', '.'
      const std::string &b  = s.base_name;
      bool               ok = !b.empty() && b.size() <= 100 && b[0] != '.';
      for (const char ch : b)
        ok = ok && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.');
      if (!ok)
        fail("Output/Base name", "'" + b + "' must be 1..100 characters of letters, digits, '_', "
                                 "'-' or '.', not starting with '.' (a file name, not a path: "
                                 "use 'Output/Directory' for folders)");
      // the output folder, or the nearest folder above it that exists, must be writable
      std::error_code       ec;
      std::filesystem::path dir = std::filesystem::absolute(s.output_directory, ec);
      while (!dir.empty() && !std::filesystem::exists(dir, ec) && dir.has_parent_path() &&
             dir.parent_path() != dir)
        dir = dir.parent_path();
      if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
        fail("Output/Directory", "'" + dir.string() + "' exists and is not a folder");
      if (std::filesystem::exists(dir, ec) && ::access(dir.c_str(), W_OK) != 0)
        fail("Output/Directory", "'" + dir.string() + "' is not writable");
      // access() trusts permissions: a folder (e.g. under /proc) may still refuse new entries
      if (std::filesystem::is_directory(dir, ec))
        {
          std::string probe = (dir / ".granhydro_probe_XXXXXX").string();
          if (::mkdtemp(&probe[0]) == nullptr)
            fail("Output/Directory", "cannot create folders in '" + dir.string() + "': " +
                                       std::strerror(errno));
          ::rmdir(probe.c_str());
        }
    }
    if (s.section_direction >= 0 && dim != 3)
      fail("Output/Cross-section direction", "cross sections need a 3D scene");
    if (s.profile_direction >= static_cast<int>(dim))
      fail("Output/Profile direction", "names a direction the " + std::to_string(dim) +
                                         "D scene does not resolve");
    const auto vel = dealii::Utilities::split_string_list(s.initial_velocity, ';');
    if (vel.size() != dim && vel.size() != 3)
      fail("Initial state/Velocity", "expected " + std::to_string(dim) +
                                       " (or 3) expressions separated by ';', got " +
                                       std::to_string(vel.size()));
    // expressions: let muParser check the syntax now, before any work
    auto check_expr = [&](const std::string &param, const std::string &expr) {
      // one expression: a ',' outside parentheses would make muParser return the last of
      // several values and silently drop the others
      {
        int depth = 0;
        for (const char ch : expr)
          {
            depth += ch == '(' ? 1 : (ch == ')' ? -1 : 0);
            if (ch == ',' && depth == 0)
              fail(param, "'" + expr + "' holds several expressions separated by ','; give one "
                          "(commas only inside function calls such as if(x < 0.1, a, b))");
          }
      }
      // muParser prints its own diagnostics to std::cerr; keep them out of the message
      std::ostringstream quiet;
      auto *old_buf = std::cerr.rdbuf(quiet.rdbuf());
      struct Restore
      {
        std::streambuf *b;
        ~Restore() { std::cerr.rdbuf(b); }
      } restore{old_buf};
      try
        {
          const auto constants = expression_constants(s);
          // the variables the run will offer: x (1D), x,y (2D), x,y,z (3D)
          double v = 0;
          if (dim == 1)
            {
              dealii::FunctionParser<1> f(1);
              f.initialize("x", expr, constants);
              v = f.value(dealii::Point<1>(s.lower[0]));
            }
          else if (dim == 2)
            {
              dealii::FunctionParser<2> f(1);
              f.initialize("x,y", expr, constants);
              v = f.value(dealii::Point<2>(s.lower[0], s.lower[1]));
            }
          else
            {
              dealii::FunctionParser<3> f(1);
              f.initialize("x,y,z", expr, constants);
              v = f.value(dealii::Point<3>(s.lower[0], s.lower[1], s.lower[2]));
            }
          if (!std::isfinite(v))
            fail(param, "expression '" + expr + "' is not finite at the lower corner");
        }
      catch (const SceneError &)
        {
          throw;
        }
      catch (const std::exception &e)
        {
          fail(param, "cannot parse expression '" + expr + "' (variables: " +
                        std::string(dim == 1 ? "x" : (dim == 2 ? "x, y" : "x, y, z")) +
                        "): " + human_message(e.what()));
        }
      catch (...) // muParser's own ParserError is not a std::exception
        {
          fail(param, "cannot parse expression '" + expr + "' (variables: " +
                        std::string(dim == 1 ? "x" : (dim == 2 ? "x, y" : "x, y, z")) +
                        "; check it and 'Initial state/Constants')");
        }
    };
    check_expr("Initial state/Packing fraction", s.initial_packing_fraction);
    check_expr("Initial state/Temperature", s.initial_temperature);
    if (!s.initial_checkpoint.empty())
      {
        // the whole file verified (size, checksum, values), then what it means for this scene
        const std::string cp = "'" + s.initial_checkpoint + "' ";
        io::CheckpointData d;
        try
          {
            d = io::read_checkpoint_file(s.initial_checkpoint);
          }
        catch (const io::CheckpointError &e)
          {
            fail("Initial state/Checkpoint", cp + e.what());
          }
        const auto &h = d.header;
        if (h.dim != int(s.dimension))
          fail("Initial state/Checkpoint", cp + "holds a " + std::to_string(h.dim) +
                                             "D state; the scene is " + std::to_string(s.dimension) + "D");
        if (std::string(h.model) != s.model)
          fail("Initial state/Checkpoint",
               cp + "was written with 'Material/Model = " + std::string(h.model) + "'");
        const double t_si = h.time * h.length / h.velocity;
        if (!(t_si < s.end_time * (1 - 1e-12)))
          fail("Initial state/Checkpoint", cp + "is at t = " + fmt(t_si) +
                                             " s, not before 'Time/End time' = " + fmt(s.end_time) +
                                             " s; raise the end time to continue the run");
      }
    for (const auto &v : vel)
      check_expr("Initial state/Velocity", v);
    // the whole initial state, sampled at the cell centres (of the box, or of the mesh
    // file's coarse cells), unless a checkpoint gives it
    if (s.initial_checkpoint.empty())
      {
        std::ostringstream quiet;
        auto *old_buf = std::cerr.rdbuf(quiet.rdbuf());
        std::string bad;
        try
          {
            const auto constants = expression_constants(s);
            bad = dim == 1 ? sample_initial_state<1>(s, constants, mesh_info.centres) :
                  dim == 2 ? sample_initial_state<2>(s, constants, mesh_info.centres) :
                             sample_initial_state<3>(s, constants, mesh_info.centres);
          }
        catch (...)
          {
            bad = "Initial state/Packing fraction|an expression cannot be evaluated inside the domain";
          }
        std::cerr.rdbuf(old_buf);
        if (!bad.empty())
          fail(bad.substr(0, bad.find('|')), bad.substr(bad.find('|') + 1));
      }
  }
} // namespace granhydro
