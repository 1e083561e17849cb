#pragma once
/**
 * @file version.h
 * Which granhydro this is: the project version and the git commit of the build, for
 * `granhydro --version` and the run records (<base>_summary.csv, <base>_parameters.prm).
 */
namespace granhydro
{
  /// the project version of CMakeLists.txt (project(granhydro VERSION ...)), e.g. "0.9.0"
  const char *version();

  /// the commit the library was built from: `git describe --always --dirty` at build
  /// time, or without git the commit .git/HEAD names (no "-dirty" mark then);
  /// "unknown" outside a git checkout (cmake/git_revision.cmake)
  const char *git_revision();
} // namespace granhydro
