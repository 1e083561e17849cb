#pragma once
/**
 * @file errors.h
 * granhydro's one error hierarchy: what a user is told, as opposed to a bug. main.cc
 * turns each kind into a message and an exit code (2: bad input, 3: the run could not
 * go on or not write its results); any other exception is an internal error (exit 1).
 *
 *   Error
 *   ├── SceneError       bad input: names the parameter and what is allowed   exit 2
 *   ├── RunError         a run that cannot continue                            exit 3
 *   ├── OutputError      a result file could not be written                    exit 3
 *   ├── CheckpointError  a checkpoint not written, or a file that is not one
 *   └── MeshFileError    a mesh file that cannot be used
 * (the last two say what is wrong with the file; the caller names the parameter and
 * rethrows as SceneError or OutputError)
 */
#include <stdexcept>
#include <string>

namespace granhydro
{
  /// the root of the hierarchy
  class Error : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// A bad scene: names the parameter (subsection/key) and what is allowed.
  class SceneError : public Error
  {
  public:
    using Error::Error;
  };

  /// a run that cannot continue (an inadmissible state after all retries, ...)
  class RunError : public Error
  {
  public:
    using Error::Error;
  };

  /// a result file could not be written (disk full, permissions, a vanished folder): the
  /// run stops with exit code 3 and this message, never with an internal error
  class OutputError : public Error
  {
  public:
    using Error::Error;
  };

  /// a checkpoint could not be written, or a file is not a valid checkpoint
  class CheckpointError : public Error
  {
  public:
    using Error::Error;
  };

  /// a mesh file that cannot be read or used (a message for a person, naming the file)
  class MeshFileError : public Error
  {
  public:
    using Error::Error;
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
