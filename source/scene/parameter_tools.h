#pragma once
/**
 * @file parameter_tools.h
 * What the subsections of a scene share when they parse and check their entries: the
 * side names, number lists, number formatting for messages, and the error of a bad entry.
 * Private to scene/.
 */
#include <granhydro/scene/scene.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

namespace granhydro::scene_detail
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
} // namespace granhydro::scene_detail
