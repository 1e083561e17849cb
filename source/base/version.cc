#include <granhydro/base/version.h>

// written at every build by cmake/git_revision.cmake (rewritten only when the commit
// changes, so that a build at the same commit recompiles nothing)
#include <granhydro_revision.h>

#ifndef GRANHYDRO_VERSION
#  define GRANHYDRO_VERSION "unknown"
#endif
#ifndef GRANHYDRO_GIT_REVISION
#  define GRANHYDRO_GIT_REVISION "unknown"
#endif

namespace granhydro
{
  const char *version()
  {
    return GRANHYDRO_VERSION;
  }

  const char *git_revision()
  {
    return GRANHYDRO_GIT_REVISION;
  }
} // namespace granhydro
