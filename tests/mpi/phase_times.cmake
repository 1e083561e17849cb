# The wall time by phase (doc/user-guide.md, "Output"): SCENE run on NP ranks (launcher
# MPIEXEC, flag -n) into WORKDIR/run with the extra -p overrides in OVERRIDES (a list);
# its summary has <phase>_min_seconds, _avg_seconds and _max_seconds for every phase, and
#   min <= avg <= max                  the statistics over the ranks (deal.II's
#                                      Utilities::MPI::MinMaxAvg: least, sum / ranks, largest)
#   part <= its phase (min, avg, max)  on every rank a part lies inside its phase (halo
#                                      waits and admissibility votes inside convection;
#                                      Jacobians, preconditioner set-ups and GMRES inside the
#                                      diffusion step), and least, mean and largest keep that order
#   sum of the phases' avg <= wall avg the phases that split the run (convection, diffusion,
#                                      adaptation, output) do not overlap on a rank and lie
#                                      inside its wall time; the mean over the ranks is linear
#   other_min_seconds >= 0             the same on each rank (other = wall - those phases)
# with 1 us allowed for the 10 significant digits of the file; the phases of PHASES (a list)
# took time on some rank (max > 0); the log ends its run summary with the table.
#
#   cmake -DEXE=<granhydro> -DMPIEXEC=<mpiexec> -DNP=2 -DSCENE=<file.prm> -DWORKDIR=<dir>
#         "-DOVERRIDES=<key=value;...>" "-DPHASES=convection;diffusion;..." -P phase_times.cmake

cmake_minimum_required(VERSION 3.13)

foreach(var EXE MPIEXEC NP SCENE WORKDIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "phase_times: -D${var}=... is required")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")
set(args "${SCENE}" -p "Output/Directory=run")
foreach(o IN LISTS OVERRIDES)
  list(APPEND args -p "${o}")
endforeach()
execute_process(COMMAND "${MPIEXEC}" -n ${NP} "${EXE}" ${args} WORKING_DIRECTORY "${WORKDIR}" TIMEOUT 240
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "granhydro on ${NP} ranks exited with '${rc}':\n${out}\n${err}")
endif()

# a non-negative number as printed in the summary (0.786747808, 1.5e-05) in whole ns
function(to_ns value var)
  if(NOT value MATCHES "^([0-9]+)(\\.([0-9]*))?([eE]([-+]?[0-9]+))?$")
    message(FATAL_ERROR "not a non-negative number: '${value}'")
  endif()
  set(int "${CMAKE_MATCH_1}")
  set(digits "${CMAKE_MATCH_1}${CMAKE_MATCH_3}000000000000000000000")
  set(exp 0)
  if(NOT "${CMAKE_MATCH_5}" STREQUAL "")
    math(EXPR exp "${CMAKE_MATCH_5}")
  endif()
  string(LENGTH "${int}" n)
  math(EXPR keep "${n} + ${exp} + 9") # the digits before the point of value * 1e9
  if(keep LESS 1)
    set(${var} 0 PARENT_SCOPE)
    return()
  endif()
  string(SUBSTRING "${digits}" 0 ${keep} ns)
  string(REGEX MATCH "[1-9][0-9]*" ns "${ns}") # no leading zeros
  if(ns STREQUAL "")
    set(ns 0)
  endif()
  set(${var} ${ns} PARENT_SCOPE)
endfunction()

file(STRINGS "${WORKDIR}/run/solution_summary.csv" rows)
foreach(row IN LISTS rows)
  if(row MATCHES "^([a-z_0-9]+)_(min|avg|max)_seconds,(.*)$")
    to_ns("${CMAKE_MATCH_3}" ns)
    set(t_${CMAKE_MATCH_1}_${CMAKE_MATCH_2} ${ns})
    list(APPEND phases ${CMAKE_MATCH_1})
  elseif(row MATCHES "^status,(.*)$")
    set(status "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(REMOVE_DUPLICATES phases)

set(problems "")
if(NOT status STREQUAL "completed")
  string(APPEND problems "  status '${status}', expected 'completed'\n")
endif()
foreach(p wall convection halo_wait admissibility_vote diffusion jacobian preconditioner gmres adaptation output other)
  if(NOT p IN_LIST phases)
    string(APPEND problems "  no rows ${p}_{min,avg,max}_seconds\n")
  endif()
endforeach()
set(tol 1000) # ns: the file's 10 significant digits
foreach(p IN LISTS phases)
  math(EXPR a "${t_${p}_min} - ${tol}")
  math(EXPR b "${t_${p}_avg} - ${tol}")
  if(a GREATER t_${p}_avg OR b GREATER t_${p}_max)
    string(APPEND problems "  ${p}: min ${t_${p}_min} avg ${t_${p}_avg} max ${t_${p}_max} ns not in order\n")
  endif()
endforeach()
foreach(pair convection:halo_wait convection:admissibility_vote diffusion:jacobian diffusion:preconditioner
             diffusion:gmres)
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 whole)
  list(GET pair 1 part)
  foreach(s min avg max)
    math(EXPR a "${t_${part}_${s}} - ${tol}")
    if(a GREATER t_${whole}_${s})
      string(APPEND problems "  ${part}_${s} ${t_${part}_${s}} ns > ${whole}_${s} ${t_${whole}_${s}} ns\n")
    endif()
  endforeach()
endforeach()
math(EXPR split "${t_convection_avg} + ${t_diffusion_avg} + ${t_adaptation_avg} + ${t_output_avg} - 4 * ${tol}")
if(split GREATER t_wall_avg)
  string(APPEND problems "  the phases' means add up to ${split} ns, more than the mean wall time ${t_wall_avg} ns\n")
endif()
foreach(p IN LISTS PHASES)
  if(NOT t_${p}_max GREATER 0)
    string(APPEND problems "  phase ${p} took no time on any rank\n")
  endif()
endforeach()
if(NOT out MATCHES "wall time by phase over ${NP} ranks \\[s\\]:\n[^\n]*phase +min +avg +max +% of wall\n +wall \\(whole run\\)")
  string(APPEND problems "  no table of the phases in the log\n")
endif()
if(problems)
  message(FATAL_ERROR "phase times on ${NP} ranks:\n${problems}\nlog:\n${out}")
endif()
message(STATUS "phase times on ${NP} ranks: wall ${t_wall_avg} ns (mean), convection ${t_convection_avg}, "
               "diffusion ${t_diffusion_avg}, gmres ${t_gmres_avg}, adaptation ${t_adaptation_avg}, output ${t_output_avg}")
