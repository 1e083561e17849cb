# The git commit of the source tree, for granhydro --version and the run records.
#
#   cmake -DSOURCE_DIR=<tree> [-DGIT_EXECUTABLE=<git>] [-DOUTPUT=<header>] -P git_revision.cmake
#
# With git: `git describe --always --dirty` (e.g. 5e8f60f or 5e8f60f-dirty). Without git
# (the README's install line does not install it) the commit is read from the files:
# .git/HEAD (.git may be a file "gitdir: ..." in a worktree), the branch's ref file or
# packed-refs (in the common git directory of a worktree), abbreviated to 7 hex digits
# as git abbreviates them; whether the tree is modified cannot be told then, so there
# is no "-dirty". "unknown" only outside a git checkout.
#
# OUTPUT: a header defining GRANHYDRO_GIT_REVISION, rewritten only when the value
# changes (the build runs this every time; an unchanged commit recompiles nothing).
# Without OUTPUT the revision is printed (tests/output/run_records.cmake compares both ways).

set(revision "unknown")
if(GIT_EXECUTABLE AND EXISTS "${GIT_EXECUTABLE}")
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty
                  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0 AND out MATCHES "^[0-9A-Za-z._/-]+$")
    set(revision "${out}")
  endif()
endif()

# the files git reads: the first line of a file, stripped
function(first_line file var)
  file(STRINGS "${file}" lines LIMIT_COUNT 1)
  string(STRIP "${lines}" line)
  set(${var} "${line}" PARENT_SCOPE)
endfunction()

if(revision STREQUAL "unknown")
  set(git_dir "${SOURCE_DIR}/.git")
  if(EXISTS "${git_dir}" AND NOT IS_DIRECTORY "${git_dir}") # a worktree: "gitdir: <dir>"
    first_line("${git_dir}" line)
    string(REGEX REPLACE "^gitdir:[ \t]*" "" git_dir "${line}")
    get_filename_component(git_dir "${git_dir}" ABSOLUTE BASE_DIR "${SOURCE_DIR}")
  endif()
  if(EXISTS "${git_dir}/HEAD")
    set(common_dir "${git_dir}") # where the refs live (a worktree's commondir)
    if(EXISTS "${git_dir}/commondir")
      first_line("${git_dir}/commondir" line)
      get_filename_component(common_dir "${line}" ABSOLUTE BASE_DIR "${git_dir}")
    endif()
    first_line("${git_dir}/HEAD" head)
    set(sha "")
    if(head MATCHES "^ref:[ \t]*(.+)$")
      set(ref "${CMAKE_MATCH_1}")
      foreach(dir "${git_dir}" "${common_dir}")
        if(sha STREQUAL "" AND EXISTS "${dir}/${ref}")
          first_line("${dir}/${ref}" sha)
        endif()
      endforeach()
      if(sha STREQUAL "" AND EXISTS "${common_dir}/packed-refs")
        file(STRINGS "${common_dir}/packed-refs" packed REGEX " ${ref}$")
        if(packed MATCHES "^([0-9a-f]+) ")
          set(sha "${CMAKE_MATCH_1}")
        endif()
      endif()
    else()
      set(sha "${head}") # a detached HEAD holds the commit itself
    endif()
    if(sha MATCHES "^[0-9a-f]+$" AND NOT sha MATCHES "^0+$")
      string(SUBSTRING "${sha}" 0 7 revision)
    endif()
  endif()
endif()

if(NOT OUTPUT)
  execute_process(COMMAND "${CMAKE_COMMAND}" -E echo "${revision}") # to stdout
  return()
endif()
set(text "// written by cmake/git_revision.cmake at build time\n#define GRANHYDRO_GIT_REVISION \"${revision}\"\n")
set(old "")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
