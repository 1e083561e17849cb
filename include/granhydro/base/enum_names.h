#pragma once
/**
 * @file enum_names.h
 * One name table per enum, written once beside the enum; everything else derives from it:
 * the pattern of a deal.II Patterns::Selection, to_string(), and the value of a name
 * (parse_enum(), which refuses an unknown name with a SceneError naming the parameter and
 * what is allowed). In the spirit of ryujin's DECLARE_ENUM, without a macro.
 *
 * A table is a function enum_names(E) in the enum's own namespace (found by
 * argument-dependent lookup), returning a std::array of {value, name} pairs (made by
 * enum_table()), every value of the enum once, in the order the Selection lists them:
 *
 *   enum class FaceQuadrature { gauss, midpoint };
 *   constexpr auto enum_names(FaceQuadrature)
 *   {
 *     return enum_table(EnumName{FaceQuadrature::gauss, "gauss"},
 *                       EnumName{FaceQuadrature::midpoint, "midpoint"});
 *   }
 *   static_assert(check_enum_names(enum_names(FaceQuadrature{})));
 *
 * The values of a table must be 0, 1, ..., N - 1 in some order (enumerators counted from
 * 0 without gaps, each named once) and the names distinct and non-empty:
 * check_enum_names() says so at compile time where the table is declared; a value
 * outside the table (an enumerator added without its name) makes to_string() throw
 * rather than print a wrong name (ctest unit.enum_names round-trips every table).
 */
#include <granhydro/base/errors.h>

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace granhydro
{
  /// one entry of a name table: an enum value and its name in scene files
  template <typename Enum>
  struct EnumName
  {
    Enum        value;
    const char *name;
  };
  template <typename Enum>
  EnumName(Enum, const char *) -> EnumName<Enum>;

  /// the table of the entries given, as a std::array
  template <typename Enum, typename... Rest>
  constexpr std::array<EnumName<Enum>, 1 + sizeof...(Rest)> enum_table(const EnumName<Enum> &first,
                                                                       const Rest &...rest)
  {
    return {{first, rest...}};
  }

  namespace enum_names_detail
  {
    /// true if Enum has a name table (enum_names(Enum) found by argument-dependent lookup)
    template <typename Enum, typename = void>
    struct has_names : std::false_type
    {};
    template <typename Enum>
    struct has_names<Enum, std::void_t<decltype(enum_names(Enum{}))>> : std::is_enum<Enum>
    {};
  } // namespace enum_names_detail

  template <typename Enum>
  inline constexpr bool has_enum_names = enum_names_detail::has_names<Enum>::value;

  /// the values 0 .. N-1, each once, and distinct non-empty names (use in a static_assert
  /// beside the table)
  template <typename Enum, std::size_t N>
  constexpr bool check_enum_names(const std::array<EnumName<Enum>, N> &table)
  {
    for (std::size_t i = 0; i < N; ++i)
      {
        const auto v = static_cast<std::size_t>(table[i].value);
        if (v >= N || table[i].name == nullptr || table[i].name[0] == '\0')
          return false;
        for (std::size_t j = 0; j < i; ++j)
          if (table[j].value == table[i].value ||
              std::string_view(table[j].name) == std::string_view(table[i].name))
            return false;
      }
    return true;
  }

  /// the names in table order joined by '|': the pattern of Patterns::Selection
  template <typename Enum, typename = std::enable_if_t<has_enum_names<Enum>>>
  std::string enum_pattern()
  {
    std::string out;
    for (const auto &e : enum_names(Enum{}))
      out += (out.empty() ? "" : "|") + std::string(e.name);
    return out;
  }

  /// the name of a value; a value the table does not hold (an enumerator added without
  /// its name) throws std::logic_error, never a wrong name
  template <typename Enum, typename = std::enable_if_t<has_enum_names<Enum>>>
  std::string to_string(const Enum value)
  {
    for (const auto &e : enum_names(Enum{}))
      if (e.value == value)
        return e.name;
    throw std::logic_error("enum value " + std::to_string(static_cast<long long>(value)) +
                           " has no name in its table (base/enum_names.h)");
  }

  /// true and `value` set if `name` is one of the table's names (exactly, as deal.II's
  /// Selection hands it over)
  template <typename Enum, typename = std::enable_if_t<has_enum_names<Enum>>>
  bool enum_from_name(const std::string &name, Enum &value)
  {
    for (const auto &e : enum_names(Enum{}))
      if (name == e.name)
        {
          value = e.value;
          return true;
        }
    return false;
  }

  /// the names as a list for a message: 'a', 'b' or 'c'
  template <typename Enum, typename = std::enable_if_t<has_enum_names<Enum>>>
  std::string enum_alternatives()
  {
    const auto  table = enum_names(Enum{});
    std::string out;
    for (std::size_t i = 0; i < table.size(); ++i)
      out += std::string(i == 0 ? "" : (i + 1 == table.size() ? " or " : ", ")) + "'" + table[i].name + "'";
    return out;
  }

  /// the value named `name`; SceneError "parameter '<parameter>' = '<name>': expected one
  /// of 'a', 'b' or 'c'" if there is none
  template <typename Enum, typename = std::enable_if_t<has_enum_names<Enum>>>
  Enum parse_enum(const std::string &name, const std::string &parameter)
  {
    Enum value{};
    if (!enum_from_name(name, value))
      throw SceneError("parameter '" + parameter + "' = '" + name + "': expected one of " +
                       enum_alternatives<Enum>());
    return value;
  }
} // namespace granhydro
