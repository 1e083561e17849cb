#include <granhydro/io/state_checkpoint.h>
#include <granhydro/scene/initial_state.h>
#include <granhydro/scene/scene.h>

#include "parameter_tools.h"

#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <cctype>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

namespace granhydro
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;
  using namespace scene_detail;

  void InitialStateParameters::declare_parameters(ParameterHandler &prm)
  {
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
                        "the expressions at t = 0. 'granhydro --resume' sets it to the scene's "
                        "own <Directory>/<Base name>.checkpoint when that exists.");
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
              fail(s, param, "'" + expr + "' holds several expressions separated by ','; give one "
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
            fail(s, param, "expression '" + expr + "' is not finite at the lower corner");
        }
      catch (const SceneError &)
        {
          throw;
        }
      catch (const std::exception &e)
        {
          fail(s, param, "cannot parse expression '" + expr + "' (variables: " +
                           std::string(dim == 1 ? "x" : (dim == 2 ? "x, y" : "x, y, z")) +
                           "): " + human_message(e.what()));
        }
      catch (...) // muParser's own ParserError is not a std::exception
        {
          fail(s, param, "cannot parse expression '" + expr + "' (variables: " +
                           std::string(dim == 1 ? "x" : (dim == 2 ? "x, y" : "x, y, z")) +
                           "; check it and 'Initial state/Constants')");
        }
    }

    /// a checkpoint to start from: the whole file verified (size, checksum, values), then
    /// what it means for this scene
    void check_checkpoint(const Scene &s)
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
        fail(s, "Initial state/Checkpoint", cp + "holds a " + std::to_string(h.dim) +
                                              "D state; the scene is " + std::to_string(s.dimension) + "D");
      if (std::string(h.model) != s.model)
        fail(s, "Initial state/Checkpoint",
                cp + "was written with 'Material/Model = " + std::string(h.model) + "'");
      const double t_si = h.time * h.length / h.velocity;
      if (!(t_si < s.end_time * (1 - 1e-12)))
        fail(s, "Initial state/Checkpoint", cp + "is at t = " + fmt(t_si) +
                                              " s, not before 'Time/End time' = " + fmt(s.end_time) +
                                              " s; raise the end time to continue the run");
    }
  } // namespace

  void InitialStateParameters::check(const Scene &s,
                                     const std::vector<std::array<double, 3>> &mesh_centres)
  {
    const unsigned int dim = s.dimension;
    const auto vel = dealii::Utilities::split_string_list(s.initial_velocity, ';');
    if (vel.size() != dim && vel.size() != 3)
      fail(s, "Initial state/Velocity", "expected " + std::to_string(dim) +
                                          " (or 3) expressions separated by ';', got " +
                                          std::to_string(vel.size()));
    check_expression(s, "Initial state/Packing fraction", s.initial_packing_fraction);
    check_expression(s, "Initial state/Temperature", s.initial_temperature);
    if (!s.initial_checkpoint.empty())
      check_checkpoint(s);
    for (const auto &v : vel)
      check_expression(s, "Initial state/Velocity", v);
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
            bad = dim == 1 ? sample_initial_state<1>(s, constants, mesh_centres) :
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
} // namespace granhydro
