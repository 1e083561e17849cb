#include <granhydro/base/units.h>
#include <granhydro/io/state_checkpoint.h>
#include <granhydro/scene/initial_state.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include "parameter_tools.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace detail;

  void InitialStateParameters::declare_parameters(ParameterHandler &prm)
  {
    const InitialStateParameters defaults;
    prm.enter_subsection("Initial state");
    {
      prm.declare_entry("Packing fraction", default_text(defaults.initial_packing_fraction),
                        Patterns::Anything(),
                        "Expression in x, y, z [m] (and t = 0, pi, constants) for the "
                        "packing fraction phi = n pi sigma^3 / 6 (> 0).");
      prm.declare_entry("Velocity", default_text(defaults.initial_velocity), Patterns::Anything(),
                        "Expressions for the velocity components [m/s], separated by ';' "
                        "(one per dimension or 3).");
      prm.declare_entry("Temperature", default_text(defaults.initial_temperature), Patterns::Anything(),
                        "Expression for the granular temperature T [J] (energy units, > 0): at "
                        "least 1e-12 m V0^2 (V0 the velocity unit), and it must survive the "
                        "conversion to the conserved energy beside the kinetic energy.");
      prm.declare_entry("Constants", default_text(defaults.initial_constants), Patterns::Anything(),
                        "Constants for the expressions, 'name=value, name=value' (names other "
                        "than x, y, z, t, pi and the expressions' functions such as sin).");
      prm.declare_entry("Quadrature points", default_text(defaults.initial_quadrature),
                        Patterns::Integer(1, 8),
                        "Gauss points per direction used to average the initial state "
                        "over each cell (finite-volume cell averages).");
      prm.declare_entry("Checkpoint", default_text(defaults.initial_checkpoint), Patterns::Anything(),
                        "A checkpoint file written by an earlier run of the same mesh "
                        "(Output/Write checkpoint): the state, time and step are read from "
                        "it and the run continues to 'Time/End time' (any number of MPI "
                        "ranks). The expressions above are then ignored. Empty: start from "
                        "the expressions at t = 0. A path relative to the working directory; "
                        "--check matches its mesh (cells, corners) against the scene's. "
                        "'granhydro --resume' sets it to the scene's own "
                        "<Directory>/<Base name>.checkpoint when that exists.");
    }
    prm.leave_subsection();
  }

  void InitialStateParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Initial state");
    initial_packing_fraction = prm.get("Packing fraction");
    initial_velocity         = prm.get("Velocity");
    initial_temperature      = prm.get("Temperature");
    initial_constants        = prm.get("Constants");
    initial_quadrature       = prm.get_integer("Quadrature points");
    initial_checkpoint       = prm.get("Checkpoint");
    prm.leave_subsection();
  }

  std::map<std::string, double> expression_constants(const Scene &s)
  {
    // t: the initial state is the state at t = 0 (documented for the expressions)
    std::map<std::string, double> constants{{"pi", M_PI}, {"t", 0.}};
    for (const auto &c : dealii::Utilities::split_string_list(s.initial_constants, ','))
      {
        const auto kv = dealii::Utilities::split_string_list(c, '=');
        if (kv.size() != 2)
          throw SceneError("in " + s.source +
                           ": parameter 'Initial state/Constants': expected "
                           "'name=value' pairs, got '" +
                           c + "'");
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
        // the expressions' functions (muParser's and deal.II's): a constant 'sin' was
        // accepted and then shadowed or was shadowed by the function
        static const std::set<std::string> functions = {
          "sin",   "cos",  "tan",   "asin",      "acos",  "atan", "sinh",  "cosh", "tanh", "asinh", "acosh",
          "atanh", "log2", "log10", "log",       "ln",    "exp",  "sqrt",  "sign", "rint", "abs",   "min",
          "max",   "sum",  "avg",   "if",        "int",   "ceil", "floor", "cot",  "csc",  "sec",   "pow",
          "erf",   "erfc", "rand",  "rand_seed", "atan2", "fmod", "_pi",   "_e"};
        if (functions.count(name))
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': '" + name +
                           "' is the name of a function of the expressions; choose another name");
        if (constants.count(name))
          throw SceneError("in " + s.source + ": parameter 'Initial state/Constants': '" + name +
                           "' is defined twice");
        double             v;
        std::istringstream is(kv[1]);
        if (constants.size() > 1000)
          throw SceneError("in " + s.source +
                           ": parameter 'Initial state/Constants': more than "
                           "1000 constants; an initial state needs a few");
        if (!(is >> v) || !(is >> std::ws).eof() || !usable_decimal(v))
          throw SceneError("in " + s.source +
                           ": parameter 'Initial state/Constants': cannot read "
                           "the value of '" +
                           name + "' ('" + kv[1] + "' is not a finite number)");
        constants[name] = v;
      }
    return constants;
  }

  namespace
  {
    /// the initial state at the cell centres of a box domain (at most 64 per direction):
    /// packing fraction in (0, phi_c - guard) for the granular model (> 0 for the ideal
    /// gas), temperature > 0, all finite. Empty if fine, else "parameter|message".
    template <int dim>
    std::string sample_initial_state(const Scene &s, const std::map<std::string, double> &constants,
                                     const std::vector<std::array<double, 3>> &mesh_centres)
    {
      const std::string           vars = dim == 1 ? "x" : (dim == 2 ? "x,y" : "x,y,z");
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
      const bool   granular = s.model == physics::Model::granular;
      const double phi_max  = s.phi_close_packing - s.guard_delta;
      // transport without the Knudsen cap in a nearly empty granular cell: the mean free
      // path (and the diffusivities) diverge as phi -> 0 and the implicit step's Newton
      // iteration stalls (a box at phi = 1e-12 under gravity stopped at step 0; it runs with
      // the cap)
      const bool uncapped =
        granular && s.diffusion_active() && (s.viscosity || s.heat_conduction) && !(s.max_free_path > 0);
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
            return "Initial state/Packing fraction|must be positive and finite everywhere: " + fmt(p) +
                   where.str();
          if (!(p >= 1e-12))
            return "Initial state/Packing fraction|must be at least 1e-12 (the scaled density "
                   "would underflow): " +
                   fmt(p) + where.str();
          if (uncapped && p < 1e-6)
            return "Material/Maximum mean free path|is 0 (off), but the packing fraction is " + fmt(p) +
                   where.str() +
                   ": below 1e-6 the uncapped transport coefficients diverge with the "
                   "mean free path and the implicit step cannot follow; set a Knudsen cap (e.g. the "
                   "grain diameter or a few cell sizes) or raise 'Initial state/Packing fraction'";
          if (granular && !(p < phi_max))
            return "Initial state/Packing fraction|must stay below phi_c - guard = " + fmt(phi_max) +
                   " (Material/Close packing fraction, Close packing "
                   "guard): " +
                   fmt(p) + where.str();
          if (!std::isfinite(t) || !(t > 0))
            return "Initial state/Temperature|must be positive and finite everywhere: " + fmt(t) +
                   where.str();
          if (!(std::sqrt(t / s.grain_mass()) <= 1e4))
            return "Initial state/Temperature|gives a thermal speed sqrt(T/m) of " +
                   fmt(std::sqrt(t / s.grain_mass())) + " m/s; allowed up to 1e4 m/s: " + fmt(t) + " J" +
                   where.str();
          for (unsigned int d = 0; d < dim; ++d)
            if (!std::isfinite(u.value(x, d)) || !(std::abs(u.value(x, d)) <= 1e4))
              return "Initial state/Velocity|must be finite and within 1e4 m/s everywhere" + where.str();
          // the state as the run stores it (Simulation::set_initial_state: scaled number
          // density, number momentum and total energy) and T back from it: T = 1e-30 J at
          // 1e3 m/s was lost against the kinetic energy and the run stopped at step 0
          const Units  un    = s.units();
          const double c     = granular ? 1.5 : 1. / (s.adiabatic_index - 1.);
          const double n     = 6. * p / (M_PI * std::pow(s.grain_diameter, 3)); // [1/m^3]
          const double ns    = n / un.number_density();
          double       ke_si = 0, ke_s = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double v = u.value(x, d), mom = n * v / (un.number_density() * un.velocity);
              ke_si += 0.5 * s.grain_mass() * n * v * v;
              ke_s += 0.5 * mom * mom / ns;
            }
          const double Es = (ke_si + c * n * t) / un.pressure();
          const double Ts = (Es - ke_s) / (c * ns), back = Ts * un.energy();
          if (!(std::abs(back - t) <= 1e-6 * t) || !(std::abs(Ts) >= 1e-300))
            return "Initial state/Temperature|" + fmt(t) + " J" + where.str() +
                   " does not survive the conversion to the conserved variables (read back: " + fmt(back) +
                   " J): the thermal energy n T is lost against the kinetic energy n m "
                   "|u|^2 / 2 = " +
                   fmt(ke_si / n) +
                   " J per grain (or the scaled value underflows); "
                   "raise the temperature or lower 'Initial state/Velocity' (T / (m |u|^2) must "
                   "stay above about 1e-9)";
          // the temperature in the internal units (grain mass times V0^2): T = 1e-30 J
          // under gravity went negative in the first implicit step
          if (!(t / un.energy() >= 1e-12))
            return "Initial state/Temperature|" + fmt(t) + " J" + where.str() +
                   " is below 1e-12 of the internal energy unit m V0^2 = " + fmt(un.energy()) +
                   " J (a thermal speed below 1e-6 V0, V0 = " + fmt(un.velocity) +
                   " m/s: sqrt(9.81 m/s^2 sigma) or 'Numerics/Reference velocity'): it is lost to "
                   "round-off in the first steps; allowed down to " +
                   fmt(1e-12 * un.energy()) + " J";
        }
      return {};
    }

    /// one expression of the initial state: muParser checks the syntax now, before any work
    void check_expression(const Scene &s, const std::string &param, const std::string &expr)
    {
      const unsigned int dim = s.dimension;
      // one expression: a ',' outside parentheses would make muParser return the last of
      // several values and silently drop the others
      {
        int depth = 0;
        for (const char ch : expr)
          {
            depth += ch == '(' ? 1 : (ch == ')' ? -1 : 0);
            if (ch == ',' && depth == 0)
              fail(s, param,
                   "'" + expr +
                     "' holds several expressions separated by ','; give one "
                     "(commas only inside function calls such as if(x < 0.1, a, b))");
          }
      }
      // every number written in the expression usable, as a plain value must be (a
      // subnormal such as 1e-310 inside an expression was accepted)
      for (std::size_t i = 0; i < expr.size(); ++i)
        {
          const unsigned char ch = expr[i], before = i > 0 ? expr[i - 1] : ' ';
          if (!(std::isdigit(ch) || (ch == '.' && i + 1 < expr.size() &&
                                     std::isdigit(static_cast<unsigned char>(expr[i + 1])))) ||
              std::isalnum(before) || before == '_' || before == '.')
            continue;
          char        *end = nullptr;
          const double v   = std::strtod(expr.c_str() + i, &end);
          if (!usable_decimal(v))
            fail(s, param,
                 "the number '" + std::string(expr.c_str() + i, static_cast<const char *>(end)) + "' in '" +
                   expr + "' is not usable (" + usable_decimal_rule + ")");
          i = std::size_t(end - expr.c_str()) - 1;
        }
      // muParser prints its own diagnostics to std::cerr; keep them out of the message
      std::ostringstream quiet;
      auto              *old_buf = std::cerr.rdbuf(quiet.rdbuf());
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
            fail(s, param, "expression '" + expr + "' is not finite at the lower corner");
        }
      catch (const SceneError &)
        {
          throw;
        }
      catch (const std::exception &e)
        {
          fail(s, param,
               "cannot parse expression '" + expr +
                 "' (variables: " + std::string(dim == 1 ? "x" : (dim == 2 ? "x, y" : "x, y, z")) +
                 "): " + human_message(e.what()));
        }
      catch (...) // muParser's own ParserError is not a std::exception
        {
          fail(s, param,
               "cannot parse expression '" + expr +
                 "' (variables: " + std::string(dim == 1 ? "x" : (dim == 2 ? "x, y" : "x, y, z")) +
                 "; check it and 'Initial state/Constants')");
        }
    }

    /// a checkpoint to start from: the whole file verified (size, checksum, values), then
    /// what it means for this scene
    void check_checkpoint(const Scene &s, const unsigned long long mesh_cells)
    {
      const std::string cp = "'" + s.initial_checkpoint + "' ";
      // every rank verifies its share of the parts (every part is verified once)
      std::unique_ptr<io::CheckpointReader> d;
      try
        {
          d = std::make_unique<io::CheckpointReader>(s.initial_checkpoint);
          io::verify_checkpoint(*d, MPI_COMM_WORLD);
        }
      catch (const io::CheckpointError &e)
        {
          fail(s, "Initial state/Checkpoint", cp + e.what());
        }
      const auto &h = d->header();
      if (h.dim != int(s.dimension))
        fail(s, "Initial state/Checkpoint",
             cp + "holds a " + std::to_string(h.dim) + "D state; the scene is " +
               std::to_string(s.dimension) + "D");
      if (std::string(h.model) != to_string(s.model))
        fail(s, "Initial state/Checkpoint",
             cp + "was written with 'Material/Model = " + std::string(h.model) + "'");
      // the mesh, as the run matches it (Simulation::read_checkpoint): a checkpoint of another
      // mesh passed --check and was refused by the run
      {
        bool        same = h.n_components == int(s.dimension) + 2;
        std::string what;
        for (unsigned int d = 0; d < s.dimension; ++d)
          {
            const double tol = 1e-12 * std::abs(s.upper[d] - s.lower[d]);
            if (!what.empty())
              break;
            if (h.cells[d] != s.cells[d])
              what = "'Domain/Cells' differ (the checkpoint's mesh has " + std::to_string(h.cells[d]) +
                     " along " + std::string(1, "xyz"[d]) + ")";
            else if (!(std::abs(h.lower[d] - s.lower[d]) <= tol && std::abs(h.upper[d] - s.upper[d]) <= tol))
              what = "the corners differ (the checkpoint's box spans " + fmt(h.lower[d]) + " .. " +
                     fmt(h.upper[d]) + " m along " + std::string(1, "xyz"[d]) + ")";
          }
        double coarse = 1; // the cells of the scene's mesh before adaptive refinement
        if (mesh_cells > 0)
          {
            coarse = double(mesh_cells);
            for (unsigned int r = 0; r < s.mesh_refinements; ++r)
              coarse *= 1u << s.dimension;
          }
        else
          for (unsigned int d = 0; d < s.dimension; ++d)
            coarse *= s.cells[d];
        const double finest = coarse * std::ldexp(1., int(s.dimension * s.max_level));
        if (what.empty() && s.max_level == 0 && double(h.n_cells) != coarse)
          what = "it holds " + std::to_string(h.n_cells) + " cells, the scene's mesh " + fmt(coarse) +
                 (mesh_cells > 0 ? " ('Domain/Mesh file', 'Domain/Mesh refinements')" : "");
        if (what.empty() && s.max_level > 0 && !(double(h.n_cells) >= coarse && double(h.n_cells) <= finest))
          what = "it holds " + std::to_string(h.n_cells) + " cells, the scene's adaptive mesh " +
                 fmt(coarse) + " .. " + fmt(finest) + " ('Adaptivity/Maximum level')";
        if (!same || !what.empty())
          fail(s, "Initial state/Checkpoint",
               cp +
                 "was written for another mesh: " + (what.empty() ? "another number of components" : what));
      }
      const double t_si = h.time * h.length / h.velocity;
      if (!(t_si < s.end_time * (1 - 1e-12)))
        fail(s, "Initial state/Checkpoint",
             cp + "is at t = " + fmt(t_si) + " s, not before 'Time/End time' = " + fmt(s.end_time) +
               " s; raise the end time to continue the run");
    }
  } // namespace

  void InitialStateParameters::check(const Scene &s, const std::vector<std::array<double, 3>> &mesh_centres,
                                     const unsigned long long mesh_cells)
  {
    const unsigned int dim = s.dimension;
    const auto         vel = dealii::Utilities::split_string_list(s.initial_velocity, ';');
    if (vel.size() != dim && vel.size() != 3)
      fail(s, "Initial state/Velocity",
           "expected " + std::to_string(dim) + " (or 3) expressions separated by ';', got " +
             std::to_string(vel.size()));
    check_expression(s, "Initial state/Packing fraction", s.initial_packing_fraction);
    check_expression(s, "Initial state/Temperature", s.initial_temperature);
    if (!s.initial_checkpoint.empty())
      check_checkpoint(s, mesh_cells);
    for (const auto &v : vel)
      check_expression(s, "Initial state/Velocity", v);
    // the whole initial state, sampled at the cell centres (of the box, or of the mesh
    // file's coarse cells), unless a checkpoint gives it
    if (s.initial_checkpoint.empty())
      {
        std::ostringstream quiet;
        auto              *old_buf = std::cerr.rdbuf(quiet.rdbuf());
        std::string        bad;
        try
          {
            const auto constants = expression_constants(s);
            bad                  = dim == 1 ? sample_initial_state<1>(s, constants, mesh_centres) :
                                   dim == 2 ? sample_initial_state<2>(s, constants, mesh_centres) :
                                              sample_initial_state<3>(s, constants, mesh_centres);
          }
        catch (...)
          {
            bad = "Initial state/Packing fraction|an expression cannot be evaluated inside the domain";
          }
        std::cerr.rdbuf(old_buf);
        if (!bad.empty())
          fail(s, bad.substr(0, bad.find('|')), bad.substr(bad.find('|') + 1));
      }
  }
} // namespace granhydro::scene
