// unit.scene_defaults: every default is written once. A scene's struct is default
// constructed (the member initialisers) and compared, field by field, with the same
// struct parsed from a ParameterHandler that read no input (the declared defaults of
// declare_scene_parameters()): every field must agree, so changing one side only fails.
// The fields are taken by structured bindings: a field added to a subsection's struct
// without adding it here does not compile (the count of the bindings is the count of the
// fields).
#include <granhydro/scene/scene.h>

#include <deal.II/base/parameter_handler.h>

#include "common/test_common.h"

#include <array>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>

using namespace granhydro;
using granhydro::testing::Checker;

namespace
{
  template <typename T>
  std::string show(const T &v)
  {
    std::ostringstream os;
    os.precision(17);
    if constexpr (std::is_enum_v<T>)
      os << to_string(v);
    else if constexpr (std::is_same_v<T, std::string>)
      os << "'" << v << "'";
    else if constexpr (std::is_arithmetic_v<T>)
      os << v;
    else // std::array
      {
        os << "{";
        for (std::size_t i = 0; i < v.size(); ++i)
          os << (i ? ", " : "") << show(v[i]);
        os << "}";
      }
    return os.str();
  }

  /// the fields of `a` and `b` (tuples of references) compared one by one, named by `names`
  template <typename Tuple, std::size_t N>
  void compare(const std::string &section, const Tuple &a, const Tuple &b, const char *const (&names)[N],
               Checker &chk)
  {
    static_assert(std::tuple_size_v<Tuple> == N, "one name per field");
    std::apply(
      [&](const auto &...x) {
        std::apply(
          [&](const auto &...y) {
            std::size_t i = 0;
            (chk.check(x == y, section + "/" + names[i++] + ": struct " + show(x) + ", declared " + show(y)),
             ...);
          },
          b);
      },
      a);
  }

  // one function per subsection: its fields as a tuple of references, in declaration order
  auto fields(const scene::DomainParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h] = p;
    return std::tie(a, b, c, d, e, f, g, h);
  }
  auto fields(const scene::MaterialParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h, i, j, k] = p;
    return std::tie(a, b, c, d, e, f, g, h, i, j, k);
  }
  auto fields(const scene::DenseClosureParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h] = p;
    return std::tie(a, b, c, d, e, f, g, h);
  }
  auto fields(const scene::InitialStateParameters &p)
  {
    const auto &[a, b, c, d, e, f] = p;
    return std::tie(a, b, c, d, e, f);
  }
  auto fields(const scene::NumericsParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h, i, j, k, l, m, n, o] = p;
    return std::tie(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o);
  }
  auto fields(const scene::EffectsParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h, i] = p;
    return std::tie(a, b, c, d, e, f, g, h, i);
  }
  auto fields(const scene::DiffusionStepParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h] = p;
    return std::tie(a, b, c, d, e, f, g, h);
  }
  auto fields(const scene::AdaptivityParameters &p)
  {
    const auto &[a, b, c, d, e, f, g] = p;
    return std::tie(a, b, c, d, e, f, g);
  }
  auto fields(const scene::TimeParameters &p)
  {
    const auto &[a, b, c, d] = p;
    return std::tie(a, b, c, d);
  }
  auto fields(const scene::OutputParameters &p)
  {
    const auto &[a, b, c, d, e, f, g, h, i, j, k, l, m, n, o] = p;
    return std::tie(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o);
  }

  template <typename Parameters, std::size_t N>
  void check_section(const std::string &section, const scene::Scene &declared, const char *const (&names)[N],
                     Checker &chk)
  {
    const Parameters defaults{};
    compare(section, fields(defaults), fields(static_cast<const Parameters &>(declared)), names, chk);
  }
} // namespace

int main()
{
  Checker                  chk;
  dealii::ParameterHandler prm;
  scene::declare_scene_parameters(prm);
  // as scene_from() parses, without the validation (the declared defaults alone are not
  // a scene that runs: no initial state that suits every model)
  scene::Scene s;
  s.dimension = prm.get_integer("Dimension");
  s.DomainParameters::parse_parameters(prm, s.dimension, "<test scene>");
  s.MaterialParameters::parse_parameters(prm);
  s.DenseClosureParameters::parse_parameters(prm);
  s.InitialStateParameters::parse_parameters(prm);
  s.NumericsParameters::parse_parameters(prm);
  s.EffectsParameters::parse_parameters(prm, s.dimension);
  s.DiffusionStepParameters::parse_parameters(prm);
  s.AdaptivityParameters::parse_parameters(prm);
  s.TimeParameters::parse_parameters(prm);
  s.OutputParameters::parse_parameters(prm);

  chk.check(scene::Scene().dimension == s.dimension, "Dimension: struct " +
                                                       std::to_string(scene::Scene().dimension) +
                                                       ", declared " + std::to_string(s.dimension));
  check_section<scene::DomainParameters>("Domain", s,
                                         {"mesh_file", "mesh_refinements", "lower", "upper", "cells",
                                          "boundary", "wall_velocity", "wall_restitution"},
                                         chk);
  check_section<scene::MaterialParameters>("Material", s,
                                           {"model", "grain_diameter", "material_density", "adiabatic_index",
                                            "restitution", "friction", "phi_freezing", "phi_close_packing",
                                            "guard_delta", "max_free_path", "cohesionless"},
                                           chk);
  check_section<scene::DenseClosureParameters>("Dense closure", s,
                                               {"dense_closure", "closure_F", "closure_phi_min", "closure_r",
                                                "closure_s", "frictional_stress", "closure_time",
                                                "closure_angle"},
                                               chk);
  check_section<scene::InitialStateParameters>("Initial state", s,
                                               {"initial_packing_fraction", "initial_velocity",
                                                "initial_temperature", "initial_constants",
                                                "initial_quadrature", "initial_checkpoint"},
                                               chk);
  check_section<scene::NumericsParameters>(
    "Numerics", s,
    {"reconstruction", "face_quadrature", "no_slip_pressure_flux", "flux", "musta_max_stages",
     "musta_min_stages", "musta_tolerance", "musta_local_cfl", "cfl", "fixed_time_step", "reference_velocity",
     "max_step_retries", "merge_strang", "well_balanced_gravity", "implicit_contact_pressure"},
    chk);
  check_section<scene::EffectsParameters>("Effects", s,
                                          {"convection", "viscosity", "heat_conduction", "cooling",
                                           "diagonal_flux", "gravity", "vibration_amplitude",
                                           "vibration_frequency", "vibration_direction"},
                                          chk);
  check_section<scene::DiffusionStepParameters>("Diffusion step", s,
                                                {"integrator", "newton_tolerance", "newton_max_iterations",
                                                 "linear_tolerance", "inexact_newton", "reuse_matrix",
                                                 "preconditioner", "full_jacobian"},
                                                chk);
  check_section<scene::AdaptivityParameters>("Adaptivity", s,
                                             {"max_level", "adapt_indicator", "refine_threshold",
                                              "coarsen_threshold", "adapt_interval", "adapt_buffer",
                                              "load_balance"},
                                             chk);
  check_section<scene::TimeParameters>(
    "Time", s, {"end_time", "max_steps", "max_wall_seconds", "steady_tolerance"}, chk);
  check_section<scene::OutputParameters>(
    "Output", s,
    {"output_directory", "base_name", "output_interval", "write_vtu", "write_profiles", "write_checkpoint",
     "write_summary", "profile_direction", "section_direction", "vtu_files_per_output", "history_steps",
     "history_seconds", "keep_checkpoints", "progress_interval", "verbose"},
    chk);
  return chk.failed != 0;
}
