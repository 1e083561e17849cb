#pragma once
/**
 * @file parameter_tools.h
 * What the subsections of a scene share when they declare, parse and check their entries:
 * the side names, number lists, number formatting for messages, the declared defaults from
 * the structs' initialisers, the enum parameters by their name tables (base/enum_names.h),
 * and the error of a bad entry.
 * Private to scene/.
 */
#include <granhydro/base/enum_names.h>
#include <granhydro/scene/scene.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

namespace granhydro::scene::detail
{
  /// the sides of the box in the order of the boundary arrays (Domain/Boundary x- ...)
  inline const char *const side_names[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};

  /// decimals the code can compute with: finite and 0 or normal (a denormal such as
  /// 1e-310 loses its digits and overflows when inverted)
  inline bool usable_decimal(const double v)
  {
    return std::isfinite(v) && (v == 0 || std::abs(v) >= std::numeric_limits<double>::min());
  }
  inline const char *const usable_decimal_rule =
    "decimal values must lie within 2.2e-308 .. 1.8e308 in magnitude, or be 0";

  /// a number for a message: 6 significant digits, exponent when needed
  inline std::string fmt(const double v)
  {
    std::ostringstream os;
    os << std::setprecision(6) << v;
    return os.str();
  }

  /// a comma-separated list of `dim` or 3 numbers (the rest of the N entries `fill`)
  template <typename T, std::size_t N>
  std::array<T, N> parse_list(const std::string &text, const std::string &name, const unsigned int dim,
                              const T fill)
  {
    const auto parts = dealii::Utilities::split_string_list(text, ',');
    if (parts.size() != dim && parts.size() != 3)
      throw SceneError("parameter '" + name + "' = '" + text + "': expected " + std::to_string(dim) +
                       " comma-separated values (one per dimension) or 3");
    std::array<T, N> a;
    a.fill(fill);
    for (unsigned int i = 0; i < parts.size() && i < N; ++i)
      {
        std::istringstream is(parts[i]);
        T                  v;
        if (!(is >> v) || !(is >> std::ws).eof())
          throw SceneError("parameter '" + name + "': cannot read '" + parts[i] + "' as a number");
        if constexpr (std::is_floating_point_v<T>)
          if (!usable_decimal(v))
            throw SceneError("parameter '" + name + "': '" + parts[i] + "' is not a usable number (" +
                             usable_decimal_rule + ")");
        a[i] = v;
      }
    return a;
  }

  /// a decimal as the shortest text that reads back exactly: fixed (2600, 0.05,
  /// 1.6666666666666667) or, where shorter, scientific without padding (1e-3, 1e-10)
  inline std::string shortest_decimal(const double v)
  {
    const auto  reads_back = [v](const std::string &t) { return std::strtod(t.c_str(), nullptr) == v; };
    std::string fixed, scientific;
    for (int p = 0; p <= 17 && fixed.empty(); ++p)
      {
        std::ostringstream os;
        os << std::fixed << std::setprecision(p) << v;
        if (reads_back(os.str()))
          fixed = os.str();
      }
    for (int p = 0; p <= 17 && scientific.empty(); ++p)
      {
        std::ostringstream os;
        os << std::scientific << std::setprecision(p) << v;
        std::string t        = os.str(); // 1.5e-03 -> 1.5e-3, 2.6e+03 -> 2.6e3
        const auto  e        = t.find('e');
        std::string exponent = t.substr(e + 1), sign;
        if (exponent[0] == '-' || exponent[0] == '+')
          {
            sign     = exponent[0] == '-' ? "-" : "";
            exponent = exponent.substr(1);
          }
        exponent = exponent.substr(std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
        t        = t.substr(0, e) + "e" + sign + exponent;
        if (reads_back(t))
          scientific = t;
      }
    return fixed.empty() || (!scientific.empty() && scientific.size() < fixed.size()) ? scientific : fixed;
  }

  /// the declared default of a parameter, from the struct member's initialiser (so the two
  /// cannot disagree): a decimal by shortest_decimal(), whole numbers, true/false, the name
  /// of an enum value, a text as it is, a list as "a, b, c"
  template <typename T>
  std::string default_text(const T &v)
  {
    if constexpr (std::is_same_v<T, bool>)
      return v ? "true" : "false";
    else if constexpr (std::is_integral_v<T>)
      return std::to_string(v);
    else if constexpr (std::is_floating_point_v<T>)
      return shortest_decimal(v);
    else if constexpr (std::is_enum_v<T>)
      return to_string(v);
    else if constexpr (std::is_same_v<T, std::string>)
      return v;
    else
      {
        std::string out;
        for (const auto &x : v)
          out += (out.empty() ? "" : ", ") + default_text(x);
        return out;
      }
  }

  /// the Selection of an enum parameter: the names of its table (base/enum_names.h)
  template <typename Enum>
  dealii::Patterns::Selection selection_of()
  {
    return dealii::Patterns::Selection(enum_pattern<Enum>());
  }

  /// the value of the enum parameter `name` of the current subsection of prm, `section`/`name`
  /// named in the SceneError of a name the table does not hold
  template <typename Enum>
  Enum get_enum(dealii::ParameterHandler &prm, const std::string &section, const std::string &name)
  {
    return parse_enum<Enum>(prm.get(name), section + "/" + name);
  }

  /// a bad entry: throws SceneError "in <scene>: parameter '<param>': <msg>"
  [[noreturn]] inline void fail(const Scene &s, const std::string &param, const std::string &msg)
  {
    throw SceneError("in " + s.source + ": parameter '" + param + "': " + msg);
  }

  /// the scene in `prm` (declared by declare_scene_parameters() and parsed), validated
  Scene scene_from(dealii::ParameterHandler &prm, const std::string &source_name);

  /// a file a scene names (Domain/Mesh file) relative to the scene file, so that a scene
  /// runs from any working directory; unchanged if absolute or if the scene is not a file
  /// ("<default scene>", "<test scene>": relative to the working directory)
  inline std::string relative_to_scene(const std::string &file, const std::string &source_name)
  {
    if (!file.empty() && file[0] != '/' && !source_name.empty() && source_name[0] != '<')
      {
        const auto slash = source_name.rfind('/');
        if (slash != std::string::npos)
          return source_name.substr(0, slash + 1) + file;
      }
    return file;
  }
} // namespace granhydro::scene::detail
