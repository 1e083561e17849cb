# Bad-input test driver (tests/CMakeLists.txt, "bad input" block).
#
#   cmake -DEXE=<granhydro> -DSCENE=<file.prm> -DWORKDIR=<dir> -P check_bad_input.cmake
#
# The first line of SCENE must be   # expect: <CMake regex>
# The test passes only if granhydro, run on SCENE inside an empty WORKDIR,
#   - exits normally (no timeout, no signal) with exit code exactly 2 (bad input),
#   - writes a message to stderr that matches the regex (which names the parameter),
#   - shows no sign of a crash ("internal error", "Stacktrace", "Aborted", ...),
#   - leaves WORKDIR empty (a bad scene is refused before any work is done).

cmake_minimum_required(VERSION 3.13)

foreach(var EXE SCENE WORKDIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "check_bad_input: -D${var}=... is required "
                        "(usage: cmake -DEXE=<granhydro> -DSCENE=<file.prm> -DWORKDIR=<dir> -P check_bad_input.cmake)")
  endif()
endforeach()
if(NOT EXISTS "${EXE}")
  message(FATAL_ERROR "check_bad_input: executable '${EXE}' does not exist")
endif()
if(NOT EXISTS "${SCENE}")
  message(FATAL_ERROR "check_bad_input: scene file '${SCENE}' does not exist")
endif()

# ---- expected message: first line '# expect: <regex>' ------------------------
file(READ "${SCENE}" scene_text)
string(FIND "${scene_text}" "\n" eol)
if(eol EQUAL -1)
  set(first_line "${scene_text}")
else()
  string(SUBSTRING "${scene_text}" 0 ${eol} first_line)
endif()
string(REGEX REPLACE "\r$" "" first_line "${first_line}")
if(NOT first_line MATCHES "^#[ \t]*expect:[ \t]*(.*[^ \t])[ \t]*$")
  message(FATAL_ERROR "check_bad_input: the first line of '${SCENE}' must be "
                      "'# expect: <regex>' (the message that names the bad parameter), got:\n"
                      "  ${first_line}")
endif()
set(expect "${CMAKE_MATCH_1}")

# ---- run in a fresh, empty working directory ----------------------------------
file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")
execute_process(
  COMMAND "${EXE}" "${SCENE}"
  WORKING_DIRECTORY "${WORKDIR}"
  TIMEOUT 30
  RESULT_VARIABLE result
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)

set(problems "")
if(NOT result MATCHES "^[0-9]+$")
  # CMake reports a timeout or a signal as a string ("Process terminated due to timeout", ...)
  list(APPEND problems "the program did not exit normally: '${result}'")
elseif(result EQUAL 0)
  list(APPEND problems "the program accepted the bad scene (exit code 0)")
elseif(NOT result EQUAL 2)
  list(APPEND problems "exit code ${result}, expected 2 (bad input)")
endif()
if(NOT err MATCHES "${expect}")
  list(APPEND problems "stderr does not match the expected regex")
endif()
foreach(bad "internal error" "Stacktrace" "Aborted" "terminate called" "MPI_ABORT")
  string(FIND "${err}" "${bad}" pos)
  if(NOT pos EQUAL -1)
    list(APPEND problems "stderr contains '${bad}' (crash instead of a clean refusal)")
  endif()
endforeach()

# ---- nothing may be left behind -------------------------------------------------
file(GLOB_RECURSE leftovers LIST_DIRECTORIES true RELATIVE "${WORKDIR}" "${WORKDIR}/*")
set(leftover_text "(empty)")
if(leftovers)
  string(REPLACE ";" ", " leftover_text "${leftovers}")
  list(APPEND problems "the run left files/directories in the working directory: ${leftover_text}")
endif()

if(problems)
  # indent captured output so that CMake prints it verbatim (not as reflowed paragraphs)
  foreach(v err out)
    string(REGEX REPLACE "\n$" "" ${v}_shown "${${v}}")
    string(REPLACE "\n" "\n    " ${v}_shown "    ${${v}_shown}")
  endforeach()
  set(report "")
  foreach(p IN LISTS problems)
    string(APPEND report "  - ${p}\n")
  endforeach()
  message(FATAL_ERROR
    "bad input '${SCENE}' was not refused properly:\n${report}"
    "expected: exit code 2, no crash, empty working directory, stderr matching\n"
    "  ${expect}\n"
    "got: exit code '${result}'\n"
    "--- stderr ---\n${err_shown}\n"
    "--- stdout ---\n${out_shown}\n"
    "--- working directory ${WORKDIR} ---\n    ${leftover_text}\n")
endif()
message(STATUS "bad input refused as expected (exit 2): ${err}")
