#include <granhydro/scene/scene.h>

#include <deal.II/base/exceptions.h>

#include "parameter_tools.h"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace granhydro::scene
{
  using dealii::ParameterHandler;
  using namespace detail;

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

  namespace
  {
    /// the longest line of a scene (and -p value): deal.II formats a refused value's
    /// message in time quadratic in its length (a value padded with 1 MB of spaces took
    /// 36 s to refuse); 64 KiB is 800 lines of 80 characters
    constexpr std::size_t max_line_chars = 1u << 16;

    /// one command-line override "Section/Sub/Name=value" into prm
    void apply_override(ParameterHandler &prm, const std::string &given)
    {
      // echoed at most 200 characters long (a 100 000-character -p was echoed whole)
      const std::string where = "command line: -p '" +
                                (given.size() <= 200 ? given :
                                                       given.substr(0, 160) + "...' (" +
                                                         std::to_string(given.size()) + " characters)") +
                                (given.size() <= 200 ? "': " : ": ");
      // what a scene file cannot hold either: the printed scene (<base>_parameters.prm)
      // would read a different value
      if (given.find_first_of("\r\n") != std::string::npos)
        throw SceneError(where + "a value is one line (no line breaks)");
      if (given.size() > max_line_chars)
        throw SceneError(where + "longer than " + std::to_string(max_line_chars) +
                         " characters, the longest line a scene may hold");
      // '#' starts a comment, as in a scene file: "Time/End time=0.1 # c" sets 0.1
      const std::string o  = given.substr(0, given.find('#'));
      const auto        eq = o.find('=');
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
          std::string m = human_message(e.what());
          if (m.find("not yet declared") != std::string::npos)
            throw SceneError(where + "there is no parameter '" + trim(o.substr(0, eq)).substr(0, 200) +
                             "' (granhydro --print-parameters lists them)");
          if (m.size() > 600) // deal.II's message quotes the value
            m = m.substr(0, 600) + " ...";
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

    /// a name or value as deal.II compares it: trimmed, inner runs of blanks as one space
    std::string collapse_blanks(const std::string &x)
    {
      std::istringstream is(x);
      std::string        out;
      for (std::string w; is >> w;)
        out += (out.empty() ? "" : " ") + w;
      return out;
    }

    /// every 'subsection' closed by an 'end', every 'end' closing one: named by line (deal.II
    /// only says that the counts differ); and in a scene file (origin given) no parameter set
    /// twice with different values within one file (a repeated 'subsection Output' with
    /// another 'Directory' silently won); a value from an included file may be overridden
    void check_sections(const std::string &text, const std::string &source,
                        const std::vector<std::string> *origin)
    {
      std::istringstream                                           in(text);
      std::vector<std::pair<unsigned long, std::string>>           open;
      std::map<std::string, std::pair<std::string, unsigned long>> values;
      unsigned long                                                number = 0;
      for (std::string line; std::getline(in, line);)
        {
          ++number;
          if (line.size() > max_line_chars)
            throw SceneError("in " + place(source, origin, number) + ": the line is " +
                             std::to_string(line.size()) + " characters long; a scene line holds at most " +
                             std::to_string(max_line_chars) +
                             " (split a long expression over lines ending in a backslash)");
          const auto hash = line.find('#');
          if (hash != std::string::npos)
            line.erase(hash);
          std::istringstream is(line);
          std::string        word;
          if (!(is >> word))
            continue;
          for (char &ch : word)
            ch = std::tolower(static_cast<unsigned char>(ch));
          // (scene files only: parse_scene() of a text, the API the tests use, lets a later
          // subsection override an earlier one)
          if (origin && word == "set" && line.find('=') != std::string::npos &&
              line.find_last_not_of(" \t\r") != line.rfind('\\')) // not a continued line
            {
              std::string rest;
              std::getline(is, rest);
              const auto  eq = rest.find('=');
              std::string path;
              for (const auto &o : open)
                path += collapse_blanks(o.second) + "/";
              path += collapse_blanks(rest.substr(0, eq));
              const std::string value = collapse_blanks(rest.substr(eq + 1));
              const auto [it, fresh]  = values.emplace(path, std::make_pair(value, number));
              // the file of a line ("FILE, line N"): a file may override what it includes
              const auto file_of = [&](const unsigned long n) {
                const std::string w = place(source, origin, n);
                return w.substr(0, w.rfind(", line "));
              };
              if (!fresh && it->second.first != value && file_of(number) == file_of(it->second.second))
                {
                  const auto clip = [](const std::string &v) {
                    return v.size() <= 80 ? v : v.substr(0, 80) + "...";
                  };
                  throw SceneError("in " + place(source, origin, number) + ": parameter '" + path +
                                   "' is set again with another value ('" + clip(value) + "'; it was '" +
                                   clip(it->second.first) + "' in " +
                                   place(source, origin, it->second.second) +
                                   "): set each parameter once (a repeated subsection must not "
                                   "contradict the first; -p overrides a value)");
                }
              it->second = {value, number};
            }
          else if (word == "subsection")
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
        throw SceneError("in " + place(source, origin, open.back().first) + ": 'subsection " +
                         open.back().second + "' is never closed (an 'end' line is missing)");
    }

    /// prm declared, `text` parsed and the overrides applied; origin: "FILE, line N" of
    /// every line of the text (null: `source_name` and the line number of the text)
    void read_parameters(ParameterHandler &prm, const std::string &text, const std::string &source_name,
                         const std::vector<std::string> &overrides, const std::vector<std::string> *origin)
    {
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
    }

    /// the parameters of prm as a scene file (expanded_scene_text())
    std::string print_scene(ParameterHandler &prm, const std::string &source_name)
    {
      // the printed file does not sit beside the scene file: a mesh file named relative to
      // that becomes absolute, so the printed scene reads the same mesh from anywhere
      prm.enter_subsection("Domain");
      const std::string mesh = relative_to_scene(prm.get("Mesh file"), source_name);
      std::error_code   ec;
      const auto        absolute = std::filesystem::absolute(mesh, ec);
      if (!mesh.empty() && !ec)
        prm.set("Mesh file", absolute.lexically_normal().string());
      prm.leave_subsection();
      std::ostringstream out;
      prm.print_parameters(
        out, ParameterHandler::OutputStyle(ParameterHandler::PRM | ParameterHandler::KeepDeclarationOrder));
      return out.str();
    }

    /// the scene in `text`, validated, with the record of how it was read
    Scene parse_scene_text(const std::string &text, const std::string &source_name,
                           const std::vector<std::string> &overrides, const std::vector<std::string> *origin)
    {
      ParameterHandler prm;
      read_parameters(prm, text, source_name, overrides, origin);
      Scene s;
      try
        {
          s = scene_from(prm, source_name);
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
      s.overrides     = overrides;
      s.expanded_text = print_scene(prm, source_name);
      return s;
    }
  } // namespace

  Scene parse_scene(const std::string &text, const std::string &source_name,
                    const std::vector<std::string> &overrides)
  {
    return parse_scene_text(text, source_name, overrides, nullptr);
  }

  namespace
  {
    /// the largest scene file, also with its includes expanded
    constexpr std::uintmax_t max_scene_bytes = 16u << 20;

    /// the scene text with its 'include FILE' lines replaced by the files' texts (a path
    /// relative to the including file, as for mesh files); refuses an include cycle (a scene
    /// that included itself recursed until the stack overflowed) and nesting beyond 16;
    /// origin gets "FILE, line N" for every line of the result (messages name the real place)
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
              // an included file is a scene file: bounded like the scene itself, and so is
              // the whole expanded text
              const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
              if (ec || bytes > max_scene_bytes || out.size() + bytes > max_scene_bytes)
                throw SceneError("scene file '" + file + "': 'include " + target +
                                 "' makes the scene larger than 16 MiB (or is unreadable); a "
                                 "scene is a short parameter file");
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
    /// the text of scene file `filename` with its includes expanded (origin as for
    /// expand_includes), refused unless it is a regular file of reasonable size that sets
    /// at least one parameter
    std::string scene_file_text(const std::string &filename, std::vector<std::string> &origin)
    {
      // a scene is a regular text file of reasonable size: a directory, /dev/null or
      // /dev/zero would otherwise run the default scene or exhaust the memory
      std::error_code ec;
      const auto      status = std::filesystem::status(filename, ec);
      if (ec || !std::filesystem::exists(status))
        throw SceneError("cannot open scene file '" + filename + "': no such file");
      if (!std::filesystem::is_regular_file(status))
        throw SceneError("scene file '" + filename +
                         "' is not a regular file (a directory or a device); give a .prm file");
      if (std::filesystem::file_size(filename, ec) > max_scene_bytes || ec)
        throw SceneError("scene file '" + filename +
                         "' is larger than 16 MiB (or unreadable); a "
                         "scene is a short parameter file");
      const std::string text = expand_includes(filename, {}, origin);
      // only comments and blank lines: refuse rather than silently run every default
      std::istringstream lines(text);
      bool               statement = false;
      for (std::string line; !statement && std::getline(lines, line);)
        {
          const auto b = line.find_first_not_of(" \t\r");
          statement    = b != std::string::npos && line[b] != '#';
        }
      if (!statement)
        throw SceneError("scene file '" + filename +
                         "' sets no parameter (it is empty or holds only "
                         "comments); run granhydro without a file for the default scene");
      return text;
    }
  } // namespace

  Scene read_scene(const std::string &filename, const std::vector<std::string> &overrides)
  {
    if (filename.empty())
      return parse_scene(default_scene_text(), "<default scene>", overrides);
    std::vector<std::string> origin;
    const std::string        text = scene_file_text(filename, origin);
    return parse_scene_text(text, filename, overrides, &origin);
  }

  std::string expanded_scene_text(const std::string &filename, const std::vector<std::string> &overrides)
  {
    ParameterHandler prm;
    if (filename.empty())
      {
        read_parameters(prm, default_scene_text(), "<default scene>", overrides, nullptr);
        return print_scene(prm, "<default scene>");
      }
    std::vector<std::string> origin;
    read_parameters(prm, scene_file_text(filename, origin), filename, overrides, &origin);
    return print_scene(prm, filename);
  }
} // namespace granhydro::scene
