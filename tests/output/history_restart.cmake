# The run's history (<base>_history.csv) and restarts with --resume (doc/user-guide.md,
# "Output" and "Checkpoints and restarts").
#
#   cmake -DEXE=<granhydro> -DSCENE=<file.prm> -DWORKDIR=<dir> -DMODE=<mode> -DPYTHON=<python3>
#         [-DLAUNCHER="mpiexec;-n;2"] -P history_restart.cmake
#
# SCENE: a small closed scene with the implicit step (tests/data/faults_1d.prm: the 1D
# dense collapse with SDIRK2), run to End time = 0.05 s.
# summary: the history's last row has the summary's final mass, total energy, time and
#          step; the parts of the energy add up to the total in every row; the mass stays
#          (closed box); with 'History interval = 0.004 s' one row after each multiple of
#          0.004 s; a single segment counted from step 0.
# restart: SIGTERM after step K (test hook GRANHYDRO_SIGTERM_AT_STEP), then --resume with
#          no -p: the history of the two segments is byte for byte the uninterrupted
#          run's, and the summary's whole-run counts are the uninterrupted run's, with 2
#          segments. Resuming from an earlier checkpoint in a folder whose history runs
#          further drops the later rows and writes them again (byte for byte the same);
#          so it does after a row torn by a kill.
#          A checkpoint of format v5 (made from a v6 one) restarts, and the summary says
#          it counts from its step.
# fresh:   --resume without a checkpoint starts from the initial state (the same history
#          as a plain run), --resume without a scene file and bad values of
#          'Output/History interval' and 'Output/Keep checkpoints' exit 2 naming them.
# keep:    'Output/Keep checkpoints = 2' keeps exactly 2 numbered checkpoints, the two
#          most recent, the latest identical to <base>.checkpoint; the default 1 none.
# ranks:   the history on the ranks of LAUNCHER equals the 1-rank history: counts and
#          words exactly, numbers to 2.2e-13 of the column's scale (the state is bitwise
#          the same on a convective scene; only the sums over the 1920 cells run in
#          another order: at most ~1920 x 1.1e-16)

cmake_minimum_required(VERSION 3.13)

foreach(var EXE SCENE WORKDIR MODE PYTHON)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "history_restart: -D${var}=... is required")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")
set(end_time "Time/End time=0.05")

# granhydro ARGS... in WORKDIR (with LAUNCHER when launched is set); the exit code must be
# `expect`; stdout and stderr together in `out`
function(run_expect expect)
  set(cmd "${EXE}" ${ARGN})
  if(launched AND LAUNCHER)
    set(cmd ${LAUNCHER} "${EXE}" ${ARGN})
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${run_env} ${cmd} WORKING_DIRECTORY "${WORKDIR}" TIMEOUT 200
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT rc STREQUAL "${expect}")
    message(FATAL_ERROR "granhydro ${ARGN} exited with '${rc}', expected ${expect}:\n${stdout}\n${stderr}")
  endif()
  set(out "${stdout}${stderr}" PARENT_SCOPE)
endfunction()

# the rows of a summary file as variables <prefix>_<key>
function(read_summary file prefix)
  file(STRINGS "${file}" rows)
  foreach(row IN LISTS rows)
    if(row MATCHES "^([^,]+),(.*)$")
      set(${prefix}_${CMAKE_MATCH_1} "${CMAKE_MATCH_2}" PARENT_SCOPE)
    endif()
  endforeach()
endfunction()

# python3 -c CODE ARGS...: numbers CMake cannot compare (it has no floating point)
function(check_with_python code)
  execute_process(COMMAND "${PYTHON}" -c "${code}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${o}${e}")
  endif()
  message(STATUS "${o}")
endfunction()

# the same file, byte for byte
function(same_file a b what)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORKDIR}/${a}" "${WORKDIR}/${b}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what}: ${a} and ${b} differ (diff ${WORKDIR}/${a} ${WORKDIR}/${b})")
  endif()
  file(SIZE "${WORKDIR}/${a}" bytes)
  message(STATUS "${what}: ${a} = ${b} byte for byte (${bytes} bytes)")
endfunction()

# the summary rows that count the run: a resumed run's whole-run figures must equal the
# uninterrupted run's exactly (wall times, memory and the rows naming the run excepted)
set(counted_rows status time steps rejected_steps convective_steps diffusion_steps newton_iterations
    gmres_iterations rkl2_steps implicit_steps flux_points limited_reconstructions first_order_fallbacks
    newton_failures gmres_failures temperature_repairs continuation_cells contact_negative_thermal_cells
    contact_wall_pressure_floors cell_steps min_dt max_dt mass_drift
    final_mass_kg final_total_energy_J)

if(MODE STREQUAL "summary")
  run_expect(0 -p "${end_time}" -p "Output/Directory=run" -p "Output/History interval=0.004 s" "${SCENE}")
  read_summary("${WORKDIR}/run/solution_summary.csv" s)
  if(NOT s_segments STREQUAL "1" OR NOT s_counted_from_step STREQUAL "0")
    message(FATAL_ERROR "a single run: segments '${s_segments}', counted_from_step '${s_counted_from_step}'")
  endif()
  # the summary writes 10 significant digits: a value v rounded to them is within
  # 0.5e-9 |v| / (leading digit) <= 5e-10 |v| of v, so the last row (17 digits) must agree
  # with it to 5e-10 relative. Energy parts: each row's total is the sum of the parts to
  # round-off (1e-12: four numbers of 17 digits, their sums over ~40 cells); the mass of
  # the closed column stays to 1e-12 (the mass drift the suite allows)
  check_with_python([=[
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = dict(r.split(',', 1) for r in open(sys.argv[2]).read().split('\n')[1:] if r)
last, dt_h = rows[-1], 0.004
def rel(a, b): return abs(a - b) / abs(b)
for col, key in (('mass', 'final_mass_kg'), ('total_energy', 'final_total_energy_J'), ('time', 'time')):
    assert rel(float(last[col]), float(s[key])) <= 5e-10, (col, last[col], s[key])
assert last['step'] == s['steps'], (last['step'], s['steps'])
assert rows[0]['step'] == '0' and float(rows[0]['time']) == 0
m0 = float(rows[0]['mass'])
for r in rows:
    parts = sum(float(r[p + '_energy']) for p in ('kinetic', 'thermal', 'contact'))
    assert rel(parts, float(r['total_energy'])) <= 1e-12, r
    assert rel(float(r['mass']), m0) <= 1e-12, r
    assert 0 < float(r['max_packing_fraction']) < 0.65 and float(r['min_temperature']) > 0, r
    assert r['integrator'] == 'sdirk2', r['integrator']
steps = [int(r['step']) for r in rows]
assert steps == sorted(set(steps)), steps
# one row after the first step at or past each multiple of 0.004 s (the steps are not
# shortened to land on it), then the final row at 0.05 s
k = [math.floor(float(r['time']) / dt_h * (1 + 1e-12)) for r in rows[1:-1]]
assert k == list(range(1, 13)), k
assert int(rows[-1]['newton_iterations']) == int(s['newton_iterations']) > 0
assert int(rows[-1]['gmres_iterations']) == int(s['gmres_iterations']) > 0
print('history: %d rows; last row = summary (mass %s, energy %s, step %s) within 5e-10' %
      (len(rows), last['mass'], last['total_energy'], last['step']))
]=] "${WORKDIR}/run/solution_history.csv" "${WORKDIR}/run/solution_summary.csv")

elseif(MODE STREQUAL "restart")
  set(hist "Output/History interval=3 steps")
  run_expect(0 -p "${end_time}" -p "Output/Directory=full" -p "${hist}" -p "Output/Keep checkpoints=10" "${SCENE}")
  read_summary("${WORKDIR}/full/solution_summary.csv" full)
  # K: about a third of the steps, a multiple of the history interval (the interrupted
  # segment's last row is then one the uninterrupted run writes too)
  math(EXPR k "${full_steps} / 9 * 3")
  # the scene as a file of its own, so that --resume needs no -p (it includes the base
  # scene and overrides what it sets: a value set twice in one file is refused)
  set(scene_text "include ${SCENE}")
  file(WRITE "${WORKDIR}/int.prm" "${scene_text}\nsubsection Time\n  set End time = 0.05\nend\n"
             "subsection Output\n  set Directory = int\n  set History interval = 3 steps\nend\n")
  set(run_env GRANHYDRO_SIGTERM_AT_STEP=${k})
  run_expect(143 int.prm)
  set(run_env "")
  read_summary("${WORKDIR}/int/solution_summary.csv" part)
  if(NOT part_status STREQUAL "interrupted (SIGTERM)" OR NOT part_steps STREQUAL "${k}")
    message(FATAL_ERROR "the interrupted run: status '${part_status}', steps '${part_steps}' (expected ${k})")
  endif()
  run_expect(0 --resume int.prm)
  if(NOT out MATCHES "--resume: continuing from the checkpoint int/solution.checkpoint")
    message(FATAL_ERROR "--resume does not say it continues from int/solution.checkpoint:\n${out}")
  endif()
  same_file(full/solution_history.csv int/solution_history.csv "history of 2 segments (SIGTERM at step ${k})")
  read_summary("${WORKDIR}/int/solution_summary.csv" whole)
  foreach(key IN LISTS counted_rows)
    if(NOT full_${key} STREQUAL whole_${key})
      message(FATAL_ERROR "summary row ${key}: '${full_${key}}' uninterrupted, '${whole_${key}}' in 2 segments")
    endif()
  endforeach()
  if(NOT whole_segments STREQUAL "2" OR NOT full_segments STREQUAL "1" OR NOT whole_counted_from_step STREQUAL "0")
    message(FATAL_ERROR "segments '${full_segments}' / '${whole_segments}' (expected 1 / 2), counted from "
                        "'${whole_counted_from_step}'")
  endif()
  message(STATUS "summary of 2 segments: steps ${whole_steps}, Newton ${whole_newton_iterations}, GMRES "
                 "${whole_gmres_iterations}, rejected ${whole_rejected_steps}: the uninterrupted run's")

  # resume from an earlier checkpoint (the one of 0.02 s, kept by Keep checkpoints) in a
  # copy of the finished folder: the rows after it are dropped, then written again
  file(GLOB kept RELATIVE "${WORKDIR}/full" "${WORKDIR}/full/solution_checkpoint_*.checkpoint")
  list(SORT kept)
  list(GET kept 1 earlier) # 0: t = 0, 1: 0.02 s, 2: 0.04 s, 3: the end (outputs every 0.02 s)
  file(COPY "${WORKDIR}/full/" DESTINATION "${WORKDIR}/back")
  file(COPY_FILE "${WORKDIR}/back/${earlier}" "${WORKDIR}/back/solution.checkpoint")
  file(WRITE "${WORKDIR}/back.prm" "${scene_text}\nsubsection Time\n  set End time = 0.05\nend\n"
             "subsection Output\n  set Directory = back\n  set History interval = 3 steps\nend\n")
  run_expect(0 --resume back.prm)
  same_file(full/solution_history.csv back/solution_history.csv "history resumed at ${earlier}")

  # the same where the history ends in a row torn by a kill in the middle of its write:
  # the rows up to the checkpoint's step, then half a row (its step field whole and
  # below the checkpoint's step, so only the count of its fields tells it is torn)
  file(COPY "${WORKDIR}/full/" DESTINATION "${WORKDIR}/torn")
  file(COPY_FILE "${WORKDIR}/torn/${earlier}" "${WORKDIR}/torn/solution.checkpoint")
  check_with_python([=[
import sys
step = int(sys.argv[2][len('solution_checkpoint_'):-len('.checkpoint')])
lines = open(sys.argv[1]).read().split('\n')
kept = [lines[0]] + [l for l in lines[1:] if l and int(l.split(',')[2]) <= step]
open(sys.argv[1], 'w').write('\n'.join(kept) + '\n' + '0.001,0.0001,1,28.6')
print('history cut to %d rows up to step %d and a torn row' % (len(kept) - 1, step))
]=] "${WORKDIR}/torn/solution_history.csv" "${earlier}")
  string(REPLACE "set Directory = back" "set Directory = torn" torn_text "${scene_text}\nsubsection Time\n  set End time = 0.05\nend\n"
         "subsection Output\n  set Directory = back\n  set History interval = 3 steps\nend\n")
  file(WRITE "${WORKDIR}/torn.prm" "${torn_text}")
  run_expect(0 --resume torn.prm)
  same_file(full/solution_history.csv torn/solution_history.csv "history with a torn last row resumed at ${earlier}")

  # a checkpoint of format v5 (the v6 one without its run record): still read; the summary
  # counts from its step
  check_with_python([=[
import struct, sys
src = open(sys.argv[1], 'rb').read()
assert src.startswith(b'granhydro checkpoint v6\n')
magic, hdr, record = 24, 240, 4096
PART = struct.Struct('<QQqqQ')
def fnv(b, h=14695981039346656037):
    for x in b:
        h = ((h ^ x) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h
n = struct.unpack_from('<Q', src, magic + hdr + record)[0]
table = magic + hdr + record + 8
parts = [list(PART.unpack_from(src, table + p * PART.size)) for p in range(n)]
body = src[table + n * PART.size + 8:]
head = b'granhydro checkpoint v5\n' + src[magic:magic + hdr] + struct.pack('<Q', n)
for p in parts:
    p[0] -= record
    head += PART.pack(*p)
open(sys.argv[2], 'wb').write(head + struct.pack('<Q', fnv(head)) + body)
print('wrote a v5 checkpoint of %d parts' % n)
]=] "${WORKDIR}/full/${earlier}" "${WORKDIR}/v5.checkpoint")
  run_expect(0 --checkpoint-info v5.checkpoint)
  if(NOT out MATCHES "format v5" OR NOT out MATCHES "run record: none")
    message(FATAL_ERROR "--checkpoint-info of the v5 file:\n${out}")
  endif()
  string(REGEX REPLACE ".* step ([0-9]+),.*" "\\1" v5_step "${out}")
  run_expect(0 -p "${end_time}" -p "Output/Directory=v5" -p "Initial state/Checkpoint=v5.checkpoint" "${SCENE}")
  read_summary("${WORKDIR}/v5/solution_summary.csv" v5)
  if(NOT v5_counted_from_step STREQUAL "${v5_step}" OR NOT v5_segments STREQUAL "1" OR
     NOT v5_final_total_energy_J STREQUAL full_final_total_energy_J OR NOT v5_steps STREQUAL full_steps)
    message(FATAL_ERROR "restart from the v5 checkpoint (step ${v5_step}): counted_from_step "
                        "'${v5_counted_from_step}', segments '${v5_segments}', steps '${v5_steps}', energy "
                        "'${v5_final_total_energy_J}' (uninterrupted '${full_final_total_energy_J}')")
  endif()
  message(STATUS "a v5 checkpoint of step ${v5_step} restarts to the uninterrupted end state; counted from its step")

elseif(MODE STREQUAL "fresh")
  run_expect(0 -p "${end_time}" -p "Output/Directory=plain" "${SCENE}")
  run_expect(0 --resume -p "${end_time}" -p "Output/Directory=resumed" "${SCENE}")
  if(NOT out MATCHES "--resume: no checkpoint resumed/solution.checkpoint yet: starting from the initial state")
    message(FATAL_ERROR "--resume without a checkpoint does not say it starts from the initial state:\n${out}")
  endif()
  same_file(plain/solution_history.csv resumed/solution_history.csv "--resume without a checkpoint")
  read_summary("${WORKDIR}/resumed/solution_summary.csv" r)
  if(NOT r_segments STREQUAL "1")
    message(FATAL_ERROR "--resume without a checkpoint: segments '${r_segments}'")
  endif()
  run_expect(2 --resume)
  if(NOT out MATCHES "--resume needs a scene file")
    message(FATAL_ERROR "--resume without a scene: ${out}")
  endif()
  foreach(bad "10" "abc steps" "-1 s" "1.5 steps" "0 steps" "2 minutes" "1 s 2")
    run_expect(2 --check -p "Output/History interval=${bad}" "${SCENE}")
    if(NOT out MATCHES "parameter 'Output/History interval'" OR NOT out MATCHES "allowed: 'N steps'")
      message(FATAL_ERROR "History interval '${bad}': ${out}")
    endif()
  endforeach()
  foreach(bad "0" "two" "1001" "2.5")
    run_expect(2 --check -p "Output/Keep checkpoints=${bad}" "${SCENE}")
    if(NOT out MATCHES "parameter 'Output/Keep checkpoints'" OR NOT out MATCHES "1..1000")
      message(FATAL_ERROR "Keep checkpoints '${bad}': ${out}")
    endif()
  endforeach()
  run_expect(0 --check -p "Output/History interval=off" "${SCENE}")
  run_expect(0 -p "${end_time}" -p "Output/Directory=off" -p "Output/History interval=0" "${SCENE}")
  if(EXISTS "${WORKDIR}/off/solution_history.csv")
    message(FATAL_ERROR "History interval = 0 wrote a history")
  endif()
  message(STATUS "--resume without a checkpoint starts from the initial state; bad values refused")

elseif(MODE STREQUAL "keep")
  run_expect(0 -p "Time/End time=0.04" -p "Output/Interval=0.01" -p "Output/Directory=two"
             -p "Output/Keep checkpoints=2" "${SCENE}")
  file(GLOB kept RELATIVE "${WORKDIR}/two" "${WORKDIR}/two/solution_checkpoint_*.checkpoint")
  list(LENGTH kept n)
  list(SORT kept)
  read_summary("${WORKDIR}/two/solution_summary.csv" s)
  # 5 checkpoints written (t = 0, 0.01, 0.02, 0.03 and the end): the last two stay
  string(LENGTH "${s_steps}" digits)
  set(last "${s_steps}")
  while(digits LESS 8)
    set(last "0${last}")
    math(EXPR digits "${digits} + 1")
  endwhile()
  if(NOT n EQUAL 2 OR NOT "solution_checkpoint_${last}.checkpoint" IN_LIST kept)
    message(FATAL_ERROR "Keep checkpoints = 2 kept ${n}: ${kept} (expected 2, the last of step ${s_steps})")
  endif()
  list(GET kept 0 older)
  run_expect(0 --checkpoint-info "two/${older}")
  if(NOT out MATCHES "time 0\\.0(29999|3)")
    message(FATAL_ERROR "the older kept checkpoint is not the one of t = 0.03 s:\n${out}")
  endif()
  same_file("two/solution_checkpoint_${last}.checkpoint" two/solution.checkpoint "the latest kept checkpoint")
  run_expect(0 -p "Time/End time=0.04" -p "Output/Interval=0.01" -p "Output/Directory=one" "${SCENE}")
  file(GLOB none "${WORKDIR}/one/solution_checkpoint_*")
  if(none)
    message(FATAL_ERROR "Keep checkpoints = 1 kept numbered checkpoints: ${none}")
  endif()
  message(STATUS "Keep checkpoints = 2: ${kept}; = 1: only solution.checkpoint")

elseif(MODE STREQUAL "ranks")
  if(NOT LAUNCHER)
    message(FATAL_ERROR "history_restart: MODE=ranks needs -DLAUNCHER=...")
  endif()
  run_expect(0 -p "Output/Directory=one" -p "Output/History interval=1 steps" "${SCENE}")
  set(launched 1)
  run_expect(0 -p "Output/Directory=many" -p "Output/History interval=1 steps" "${SCENE}")
  check_with_python([=[
import csv, sys
a = list(csv.reader(open(sys.argv[1])))
b = list(csv.reader(open(sys.argv[2])))
assert a[0] == b[0] and len(a) == len(b), (len(a), len(b))
# a column's scale: its largest magnitude over the rows; for the momentum, whose sum
# cancels to ~0 in the symmetric blast, mass times the largest speed (the size of the
# terms summed, which sets the round-off)
scale = {}
for r in a[1:]:
    for name, x in zip(a[0], r):
        try:
            scale[name] = max(scale.get(name, 0), abs(float(x)))
        except ValueError:
            pass
    p = float(r[a[0].index('mass')]) * float(r[a[0].index('max_speed')])
    for name in a[0]:
        if name.startswith('momentum_'):
            scale[name] = max(scale[name], p)
# a sum of N terms in another order differs by at most ~N eps of the sum of magnitudes:
# N = 1920 cells, eps = 1.1e-16 -> 2.2e-13
worst = 0
for ra, rb in zip(a[1:], b[1:]):
    for name, x, y in zip(a[0], ra, rb):
        if name in ('step', 'integrator', 'rejected_steps') or name.endswith(('_steps', '_stages', '_iterations')):
            assert x == y, (name, x, y)
        elif x != y:
            assert x != 'nan' and y != 'nan', (name, x, y)
            d = abs(float(x) - float(y)) / scale[name]
            worst = max(worst, d)
            assert d <= 2.2e-13, (name, x, y, d)
print('%d history rows: the ranks equal 1 rank (counts exactly, largest difference %.1e of the scale)' % (len(a) - 1, worst))
]=] "${WORKDIR}/one/solution_history.csv" "${WORKDIR}/many/solution_history.csv")
else()
  message(FATAL_ERROR "history_restart: unknown MODE '${MODE}' (summary, restart, fresh, keep, ranks)")
endif()
