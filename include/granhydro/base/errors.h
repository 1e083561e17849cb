#pragma once
/**
 * @file errors.h
 * Errors every layer may raise for bad input. main.cc turns them into a message that
 * names the parameter and a non-zero exit.
 */
#include <stdexcept>
#include <string>

namespace granhydro
{
  /// A bad scene: names the parameter (subsection/key) and what is allowed.
  class SceneError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// the human part of a deal.II exception text (after "Additional information:", before
  /// the stack trace, whitespace runs collapsed), for messages to users
  inline std::string human_message(const std::string &what)
  {
    std::string       msg = what;
    const std::string key = "Additional information:";
    const auto        pos = msg.find(key);
    if (pos != std::string::npos)
      msg = msg.substr(pos + key.size());
    const auto st = msg.find("Stacktrace:");
    if (st != std::string::npos)
      msg = msg.substr(0, st);
    // collapse whitespace runs
    std::string out;
    bool        space = false;
    for (const char c : msg)
      {
        if (c == ' ' || c == '\n' || c == '\t')
          space = true;
        else
          {
            if (space && !out.empty())
              out += ' ';
            out += c;
            space = false;
          }
      }
    return out;
  }
} // namespace granhydro
