# Runs granhydro on SCENE inside an empty WORKDIR and asserts exit code 0 and the
# line "status,<STATUS>" in WORKDIR/solution_summary.csv.
#   cmake -DEXE=<granhydro> -DSCENE=<file.prm> -DWORKDIR=<dir> -DSTATUS=<status> -P check_summary_status.cmake
file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")
execute_process(COMMAND "${EXE}" "${SCENE}" WORKING_DIRECTORY "${WORKDIR}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "granhydro exited with '${rc}' (expected 0):\n${out}\n${err}")
endif()
if(NOT EXISTS "${WORKDIR}/solution_summary.csv")
  message(FATAL_ERROR "no solution_summary.csv written:\n${out}")
endif()
file(STRINGS "${WORKDIR}/solution_summary.csv" lines REGEX "^status,")
if(NOT lines STREQUAL "status,${STATUS}")
  message(FATAL_ERROR "solution_summary.csv has '${lines}', expected 'status,${STATUS}'")
endif()
message(STATUS "solution_summary.csv: ${lines}")
