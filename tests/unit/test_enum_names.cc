// unit.enum_names: the name tables of the enums a scene chooses by name
// (base/enum_names.h). For every table:
//  - every value round-trips: to_string(value) is its name, parse_enum(name) the value;
//    the values are 0 .. N-1, so every enumerator up to the table's size has a name, and
//    the value just past it has none (to_string throws std::logic_error, no silent name);
//  - enum_pattern() is the names joined by '|', and the scene parameter the table
//    belongs to is declared with exactly that Selection: every name is accepted by the
//    ParameterHandler of declare_scene_parameters(), a wrong one refused;
//  - the declared default is a name of the table;
//  - a wrong name gives a SceneError naming the parameter and every allowed name.
#include <granhydro/base/enum_names.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/parameter_handler.h>

#include "common/test_common.h"

#include <string>
#include <vector>

using namespace granhydro;
using granhydro::testing::Checker;

namespace
{
  /// prm entered into the subsections of `path` ("Section/Name"), the name returned
  std::string enter(dealii::ParameterHandler &prm, const std::string &path, unsigned int &depth)
  {
    std::string rest = path;
    depth            = 0;
    for (std::size_t slash; (slash = rest.find('/')) != std::string::npos; rest = rest.substr(slash + 1))
      {
        prm.enter_subsection(rest.substr(0, slash));
        ++depth;
      }
    return rest;
  }

  template <typename Enum>
  void check_table(const std::string &parameter, Checker &chk)
  {
    const auto  table = enum_names(Enum{});
    std::string joined;
    bool        round_trip = true, contiguous = true;
    for (std::size_t i = 0; i < table.size(); ++i)
      {
        const auto &[value, name] = table[i];
        joined += (i ? "|" : "") + std::string(name);
        Enum back{};
        round_trip = round_trip && to_string(value) == name && parse_enum<Enum>(name, parameter) == value &&
                     enum_from_name<Enum>(name, back) && back == value;
        try
          {
            to_string(static_cast<Enum>(i)); // every enumerator 0 .. N-1 has a name
          }
        catch (const std::logic_error &)
          {
            contiguous = false;
          }
      }
    chk.check(round_trip, parameter + ": every value of the table round-trips (" + joined + ")");
    bool past_end = false;
    try
      {
        to_string(static_cast<Enum>(table.size()));
      }
    catch (const std::logic_error &)
      {
        past_end = true;
      }
    chk.check(contiguous && past_end, parameter + ": values 0.." + std::to_string(table.size() - 1) +
                                        " named, the value past the table refused");
    chk.check(enum_pattern<Enum>() == joined, parameter + ": pattern '" + enum_pattern<Enum>() + "'");

    // the declared parameter uses the table: its default is a name, every name is
    // accepted and a wrong one is refused
    dealii::ParameterHandler prm;
    scene::declare_scene_parameters(prm);
    unsigned int      depth    = 0;
    const std::string name     = enter(prm, parameter, depth);
    Enum              deflt    = {};
    const bool        has_name = enum_from_name<Enum>(prm.get(name), deflt);
    bool              accepted = true, refused = false;
    for (const auto &e : table)
      {
        try
          {
            prm.set(name, std::string(e.name));
          }
        catch (const std::exception &)
          {
            accepted = false;
          }
      }
    try
      {
        prm.set(name, std::string("no such ") + table[0].name);
      }
    catch (const std::exception &)
      {
        refused = true;
      }
    for (unsigned int d = 0; d < depth; ++d)
      prm.leave_subsection();
    chk.check(has_name && accepted && refused, parameter +
                                                 ": declared with the table's Selection (default '" +
                                                 (has_name ? to_string(deflt) : std::string("?")) + "')");

    // a wrong name: SceneError naming the parameter and every allowed name
    std::string message;
    try
      {
        parse_enum<Enum>("bogus", parameter);
      }
    catch (const SceneError &e)
      {
        message = e.what();
      }
    bool names_all = message.find("parameter '" + parameter + "'") != std::string::npos &&
                     message.find("'bogus'") != std::string::npos;
    for (const auto &e : table)
      names_all = names_all && message.find("'" + std::string(e.name) + "'") != std::string::npos;
    chk.check(names_all, parameter + ": a wrong name is refused: " + message);
  }
} // namespace

int main()
{
  Checker chk;
  check_table<physics::Model>("Material/Model", chk);
  check_table<convection::ReconstructionType>("Numerics/Reconstruction", chk);
  check_table<convection::FaceQuadrature>("Numerics/Face quadrature", chk);
  check_table<convection::FluxType>("Numerics/Flux", chk);
  for (const char *side : {"x-", "x+", "y-", "y+", "z-", "z+"})
    check_table<boundary::BoundaryType>(std::string("Domain/Boundary ") + side, chk);
  check_table<scene::DenseClosure>("Dense closure/Model", chk);
  check_table<physics::FrictionalLaw>("Dense closure/Frictional stress", chk);
  check_table<diffusion::ImplicitMethod>("Diffusion step/Integrator", chk);
  check_table<scene::Preconditioner>("Diffusion step/Preconditioner", chk);
  check_table<mesh::RefinementIndicator>("Adaptivity/Indicator", chk);
  check_table<scene::LoadBalance>("Adaptivity/Load balance", chk);

  // a list of three or more reads "'a', 'b' or 'c'", of two "'a' or 'b'"
  chk.check(enum_alternatives<convection::FluxType>() == "'musta', 'rusanov' or 'hll'" &&
              enum_alternatives<physics::Model>() == "'ideal gas' or 'granular'",
            "alternatives: " + enum_alternatives<convection::FluxType>() + "; " +
              enum_alternatives<physics::Model>());
  return chk.failed != 0;
}
