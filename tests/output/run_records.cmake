# The run records (doc/user-guide.md, "Output"): <base>_parameters.prm, <base>.log and the
# summary rows that say which run it was.
#
#   cmake -DEXE=<granhydro> -DSCENE=<file.prm> -DWORKDIR=<dir> -DMODE=rerun -P run_records.cmake
#   cmake -DEXE=<granhydro> -DSCENE=<file.prm> -DWORKDIR=<dir> -DMODE=summary -DVERSION=<x.y.z>
#         -DSOURCE_DIR=<tree> [-DGIT_EXECUTABLE=<git>] -P run_records.cmake
#
# Both run SCENE shortened (Time/End time = 0.02) into WORKDIR/run.
# rerun:   the run writes run/<base>_parameters.prm and run/<base>.log (the log is exactly
#          what the run printed); the parameters file, run again from WORKDIR, gives the
#          same profiles CSV byte for byte, the same summary rows (all but wall times,
#          memory and the rows naming the run) and the same parameters again.
# summary: the rows version, git_revision, scene, overrides (one with a comma: quoted),
#          ranks, start_time; git_revision read without git equals git's; no records
#          from --check or with Output/Write summary = false.

cmake_minimum_required(VERSION 3.13)

foreach(var EXE SCENE WORKDIR MODE)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_records: -D${var}=... is required")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")

# granhydro ARGS... in WORKDIR; fails unless it exits with 0; stdout in `out`
function(granhydro)
  execute_process(COMMAND "${EXE}" ${ARGN} WORKING_DIRECTORY "${WORKDIR}" TIMEOUT 120
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "granhydro ${ARGN} exited with '${rc}':\n${stdout}\n${stderr}")
  endif()
  set(out "${stdout}" PARENT_SCOPE)
endfunction()

# the rows of a summary file as variables <prefix>_<key> and the list <prefix>_keys
# (a quoted value keeps its quotes: the rows compared here are written the same way)
function(read_summary file prefix)
  if(NOT EXISTS "${file}")
    message(FATAL_ERROR "no ${file}")
  endif()
  file(READ "${file}" text)
  string(REPLACE ";" "<semicolon>" text "${text}") # a value may hold ';' (overrides)
  string(REPLACE "\n" ";" rows "${text}")
  set(keys "")
  foreach(row IN LISTS rows)
    if(row MATCHES "^([^,]+),(.*)$" AND NOT CMAKE_MATCH_1 STREQUAL "key")
      list(APPEND keys "${CMAKE_MATCH_1}")
      string(REPLACE "<semicolon>" ";" value "${CMAKE_MATCH_2}")
      set(${prefix}_${CMAKE_MATCH_1} "${value}" PARENT_SCOPE)
    endif()
  endforeach()
  set(${prefix}_keys "${keys}" PARENT_SCOPE)
endfunction()

# the one file of `pattern` in WORKDIR (relative), else fail
function(the_file pattern var)
  file(GLOB found RELATIVE "${WORKDIR}" "${WORKDIR}/${pattern}")
  list(LENGTH found n)
  if(NOT n EQUAL 1)
    message(FATAL_ERROR "expected one file ${pattern} in ${WORKDIR}, found ${n}: ${found}")
  endif()
  set(${var} "${found}" PARENT_SCOPE)
endfunction()

set(end_time "Time/End time=0.02")
set(directory "Output/Directory=run")

if(MODE STREQUAL "rerun")
  granhydro(-p "${end_time}" -p "${directory}" "${SCENE}")
  set(printed "${out}")
  the_file("run/*_parameters.prm" prm)
  string(REGEX REPLACE "^run/(.*)_parameters.prm$" "\\1" base "${prm}")
  foreach(f "${base}.log" "${base}_profiles.csv" "${base}_summary.csv")
    if(NOT EXISTS "${WORKDIR}/run/${f}")
      message(FATAL_ERROR "the run wrote no run/${f}")
    endif()
  endforeach()
  file(READ "${WORKDIR}/run/${base}.log" log)
  if(NOT log STREQUAL printed OR NOT log MATCHES "run summary:")
    message(FATAL_ERROR "run/${base}.log is not what the run printed:\n--- log ---\n${log}\n"
                        "--- printed ---\n${printed}")
  endif()

  # run the parameters file again (same working directory, so the same Output/Directory)
  file(RENAME "${WORKDIR}/run" "${WORKDIR}/first")
  granhydro("first/${base}_parameters.prm")

  file(READ "${WORKDIR}/first/${base}_profiles.csv" profiles_1)
  file(READ "${WORKDIR}/run/${base}_profiles.csv" profiles_2)
  string(REGEX MATCHALL "\n" rows "${profiles_1}")
  list(LENGTH rows n_rows)
  if(n_rows LESS 10)
    message(FATAL_ERROR "first/${base}_profiles.csv has only ${n_rows} lines")
  endif()
  if(NOT profiles_1 STREQUAL profiles_2)
    message(FATAL_ERROR "the run of first/${base}_parameters.prm wrote a different ${base}_profiles.csv "
                        "(diff ${WORKDIR}/first/${base}_profiles.csv ${WORKDIR}/run/${base}_profiles.csv)")
  endif()

  read_summary("${WORKDIR}/first/${base}_summary.csv" one)
  read_summary("${WORKDIR}/run/${base}_summary.csv" two)
  if(NOT one_keys STREQUAL two_keys)
    message(FATAL_ERROR "the summaries have different rows:\n${one_keys}\n${two_keys}")
  endif()
  if(NOT one_time STREQUAL "0.02" OR NOT one_status STREQUAL "completed")
    message(FATAL_ERROR "the first run ended at t = '${one_time}' with status '${one_status}' "
                        "(expected 0.02, completed: the -p override applied)")
  endif()
  set(compared 0)
  foreach(key IN LISTS one_keys)
    # wall times, memory and the rows naming the run differ from run to run
    if(key MATCHES "_seconds$|^peak_memory|^start_time$|^scene$|^overrides$")
      continue()
    endif()
    if(NOT one_${key} STREQUAL two_${key})
      message(FATAL_ERROR "summary row ${key}: '${one_${key}}' in the first run, '${two_${key}}' "
                          "in the run of its parameters file")
    endif()
    math(EXPR compared "${compared} + 1")
  endforeach()
  if(NOT two_scene STREQUAL "first/${base}_parameters.prm" OR NOT two_overrides STREQUAL "")
    message(FATAL_ERROR "the second run names scene '${two_scene}', overrides '${two_overrides}'")
  endif()

  # the parameters file of the second run holds the same parameters (only the comments
  # naming the scene differ), and the first one the overridden end time
  foreach(run first run)
    file(READ "${WORKDIR}/${run}/${base}_parameters.prm" text)
    string(REGEX REPLACE "(^|\n)[ \t]*#[^\n]*" "" settings_${run} "${text}")
  endforeach()
  if(NOT settings_first STREQUAL settings_run)
    message(FATAL_ERROR "the second run's ${base}_parameters.prm sets other parameters than the first's")
  endif()
  if(NOT settings_first MATCHES "\n[ ]*set End time *= 0.02 ")
    message(FATAL_ERROR "first/${base}_parameters.prm does not set the overridden end time")
  endif()
  message(STATUS "the parameters file reproduces the run: profiles identical, ${compared} summary rows equal")

elseif(MODE STREQUAL "summary")
  foreach(var VERSION SOURCE_DIR)
    if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
      message(FATAL_ERROR "run_records: -D${var}=... is required with MODE=summary")
    endif()
  endforeach()
  # an override with a comma: the row is quoted (RFC 4180)
  set(constants "Initial state/Constants=unused_a=1, unused_b=2")
  string(TIMESTAMP before "%Y-%m-%dT%H:%M:%SZ" UTC)
  granhydro(-p "${end_time}" -p "${directory}" -p "${constants}" "${SCENE}")
  string(TIMESTAMP after "%Y-%m-%dT%H:%M:%SZ" UTC)
  the_file("run/*_summary.csv" summary)
  read_summary("${WORKDIR}/${summary}" s)
  foreach(key version git_revision scene overrides ranks start_time)
    if(NOT key IN_LIST s_keys)
      message(FATAL_ERROR "${summary} has no row '${key}'")
    endif()
  endforeach()
  set(problems "")
  if(NOT s_version STREQUAL VERSION)
    string(APPEND problems "  version '${s_version}', expected '${VERSION}'\n")
  endif()
  if(NOT s_scene STREQUAL SCENE)
    string(APPEND problems "  scene '${s_scene}', expected '${SCENE}'\n")
  endif()
  set(expected "\"${end_time};${directory};${constants}\"")
  if(NOT s_overrides STREQUAL expected)
    string(APPEND problems "  overrides '${s_overrides}', expected '${expected}'\n")
  endif()
  if(NOT s_ranks STREQUAL "1")
    string(APPEND problems "  ranks '${s_ranks}', expected 1\n")
  endif()
  if(NOT s_start_time MATCHES "^[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]T[0-9][0-9]:[0-9][0-9]:[0-9][0-9]Z$"
     OR s_start_time STRLESS before OR s_start_time STRGREATER after)
    string(APPEND problems "  start_time '${s_start_time}', expected ISO 8601 UTC within ${before} .. ${after}\n")
  endif()
  # the commit: in a git checkout never "unknown"; read from .git/HEAD without git the
  # same commit as git describe names (without its "-dirty")
  execute_process(COMMAND "${CMAKE_COMMAND}" -DSOURCE_DIR=${SOURCE_DIR} -P ${CMAKE_CURRENT_LIST_DIR}/../../cmake/git_revision.cmake
                  OUTPUT_VARIABLE without_git OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(EXISTS "${SOURCE_DIR}/.git")
    # a commit (5e8f60f, 5e8f60f-dirty) or, once there are tags, v1.0 or v1.0-3-g5e8f60f
    if(s_git_revision STREQUAL "unknown" OR NOT s_git_revision MATCHES "^[0-9A-Za-z._/-]+$")
      string(APPEND problems "  git_revision '${s_git_revision}' in a git checkout\n")
    endif()
    if(NOT without_git MATCHES "^[0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f]$")
      string(APPEND problems "  cmake/git_revision.cmake without git gives '${without_git}'\n")
    endif()
    if(GIT_EXECUTABLE AND EXISTS "${GIT_EXECUTABLE}")
      execute_process(COMMAND "${GIT_EXECUTABLE}" rev-parse --short=7 HEAD WORKING_DIRECTORY "${SOURCE_DIR}"
                      OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE)
      if(NOT without_git STREQUAL head)
        string(APPEND problems "  .git/HEAD read without git gives '${without_git}', git '${head}'\n")
      endif()
    endif()
  elseif(NOT s_git_revision STREQUAL "unknown" OR NOT without_git STREQUAL "unknown")
    string(APPEND problems "  git_revision '${s_git_revision}' outside a git checkout\n")
  endif()
  granhydro(--version)
  if(NOT out MATCHES "^granhydro ${s_version} \\(git ${s_git_revision}\\)")
    string(APPEND problems "  granhydro --version says '${out}'\n")
  endif()
  if(problems)
    message(FATAL_ERROR "${summary}:\n${problems}")
  endif()

  # no records from --check or with Output/Write summary = false
  granhydro(--check -p "${end_time}" -p "Output/Directory=checked" "${SCENE}")
  granhydro(-p "${end_time}" -p "Output/Directory=quiet" -p "Output/Write summary=false" "${SCENE}")
  file(GLOB records "${WORKDIR}/checked/*" "${WORKDIR}/quiet/*_parameters.prm" "${WORKDIR}/quiet/*.log"
       "${WORKDIR}/quiet/*_summary.csv")
  if(records)
    message(FATAL_ERROR "run records written by --check or with Output/Write summary = false: ${records}")
  endif()
  if(NOT EXISTS "${WORKDIR}/quiet")
    message(FATAL_ERROR "the run with Output/Write summary = false wrote nothing at all (no quiet/)")
  endif()
  message(STATUS "${summary}: version ${s_version}, git ${s_git_revision}, scene ${s_scene}, "
                 "overrides ${s_overrides}, ranks ${s_ranks}, start ${s_start_time}")
else()
  message(FATAL_ERROR "run_records: MODE must be rerun or summary, not '${MODE}'")
endif()
