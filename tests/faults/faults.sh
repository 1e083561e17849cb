#!/bin/bash
# Fault tests (ctests faults.*): what a run does when the world goes wrong.
#   faults.sh <granhydro> <scene.prm> <work dir> <mode> [launcher...]
# The scene must use the implicit step with a kept Newton matrix (the 1D dense collapse
# with Integrator = sdirk2) and write checkpoints at its output times.
# Modes:
#   sigterm    SIGTERM after step K (test hook GRANHYDRO_SIGTERM_AT_STEP=K, which raises the
#              real signal): exit 143, summary status "interrupted (SIGTERM)", a checkpoint
#              with the implicit step's history; the restart from it ends in the state of
#              the uninterrupted run bit for bit (state digests of the final checkpoints).
#              A restart from the t = 0 checkpoint does not write the t = 0 output again.
#   disk_full  (a) the 3rd checkpoint write fails half-way with ENOSPC (test hook
#              GRANHYDRO_FAIL_CHECKPOINT_WRITE=3): exit 3 naming the OS reason, the 2nd
#              checkpoint stays in place and verifies, no .tmp is left, the summary never
#              says "completed"; (b) a real OS limit (ulimit -f: every write beyond 8 KiB
#              fails with EFBIG, "File too large"): exit 3, no crash, never "completed", and any checkpoint
#              left verifies.
#   corrupt    every kind of damaged checkpoint is refused with exit 2 by --check and by
#              the run, naming 'Initial state/Checkpoint': truncated, one flipped bit in
#              the header / in the part table / in a value, appended bytes, empty, not a
#              checkpoint, the older formats v3 and v4, and (with valid checksums) a NaN
#              value, a negative density, a time of -1e300, a time beyond the end time, a
#              cell count of 2^40, a run record without its end, and (written by 2 or more
#              ranks) a cell in two parts.
# Environment: FAULTS_KINDS (corrupt: a subset of the kinds), FAULTS_NO_ULIMIT=1 (disk_full:
# skip (b), which several ranks on one node cannot run: Open MPI's shared memory hits the
# limit inside MPI_Init).
set -u
exe=$1; scene=$2; work=$3; mode=$4; shift 4
launcher=("$@")
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
run() { "${launcher[@]}" "$exe" "$@"; }
digest() { "$exe" --checkpoint-info "$1" | sed -n 's/.*state digest //p'; }
status() { sed -n 's/^status,//p' "$1"; }
# a crash in a log (mpirun's own note on a rank's non-zero exit, "the job has been
# aborted", is not one)
crashed() { grep -v "Per user-direction, the job has been aborted" "$1" | grep -qiE "internal error|Stacktrace|Aborted|MPI_ABORT|bad_alloc"; }

case $mode in
sigterm)
  run -p "Output/Directory=full" "$scene" > full.log 2>&1 || { cat full.log; fail "uninterrupted run"; }
  steps=$("$exe" --checkpoint-info full/solution.checkpoint | sed -n 's/.* step \([0-9]*\),.*/\1/p')
  k=$((steps / 3))
  GRANHYDRO_SIGTERM_AT_STEP=$k run -p "Output/Directory=int" "$scene" > int.log 2>&1
  rc=$?
  [ $rc -eq 143 ] || { cat int.log; fail "interrupted run: exit $rc, expected 143"; }
  [ "$(status int/solution_summary.csv)" = "interrupted (SIGTERM)" ] || fail "summary status '$(status int/solution_summary.csv)'"
  "$exe" --checkpoint-info int/solution.checkpoint > info.txt || { cat info.txt; fail "interrupt checkpoint does not verify"; }
  grep -q "step $k," info.txt || { cat info.txt; fail "interrupt checkpoint is not at step $k"; }
  grep -q "kept Newton matrix" info.txt || { cat info.txt; fail "interrupt checkpoint lacks the implicit step's history (the test needs a kept matrix at step $k)"; }
  cp int/solution.checkpoint int.checkpoint
  run -p "Output/Directory=int" -p "Initial state/Checkpoint=int.checkpoint" "$scene" > restart.log 2>&1 || { cat restart.log; fail "restart"; }
  a=$(digest full/solution.checkpoint); b=$(digest int/solution.checkpoint)
  echo "final state digest: uninterrupted $a, interrupted + restarted $b"
  [ -n "$a" ] && [ "$a" = "$b" ] || fail "the restarted run does not end in the uninterrupted state"
  [ "$(status int/solution_summary.csv)" = "$(status full/solution_summary.csv)" ] || fail "final status differs"
  # restart from the t = 0 checkpoint (kept as .bak of the second): no duplicate t = 0 block
  run -p "Output/Directory=zero" -p "Time/End time=0.005" "$scene" > zero.log 2>&1 || { cat zero.log; fail "short run"; }
  cp zero/solution.checkpoint.bak zero0.checkpoint
  "$exe" --checkpoint-info zero0.checkpoint | grep -q " step 0," || fail "the .bak of the first output is not the t = 0 checkpoint"
  # a fresh folder holding what the run had written up to t = 0 (header + t = 0 block)
  rm -rf zero3 && mkdir zero3
  { head -n 1 zero/solution_profiles.csv; grep -E '^0,' zero/solution_profiles.csv; } > zero3/solution_profiles.csv
  run -p "Output/Directory=zero3" -p "Time/End time=0.005" -p "Initial state/Checkpoint=zero0.checkpoint" "$scene" > zero3.log 2>&1 || { cat zero3.log; fail "restart from t = 0"; }
  c=$(grep -cE '^0,' zero3/solution_profiles.csv); d=$(grep -cE '^0,' zero/solution_profiles.csv)
  echo "t = 0 profile rows: uninterrupted $d, restarted from the t = 0 checkpoint $c"
  [ "$c" = "$d" ] || fail "restart from t = 0 wrote the t = 0 profile again"
  cmp -s zero/solution_profiles.csv zero3/solution_profiles.csv || fail "restart from t = 0: profiles differ from the uninterrupted run"
  ;;
disk_full)
  GRANHYDRO_FAIL_CHECKPOINT_WRITE=3 run -p "Output/Directory=inj" "$scene" > inj.log 2>&1
  rc=$?
  [ $rc -eq 3 ] || { cat inj.log; fail "injected ENOSPC: exit $rc, expected 3"; }
  grep -q "No space left on device" inj.log || { cat inj.log; fail "the message does not give the OS reason"; }
  crashed inj.log && { cat inj.log; fail "crash text"; }
  "$exe" --checkpoint-info inj/solution.checkpoint > info.txt || { cat info.txt; fail "the checkpoint left in place does not verify"; }
  ls inj/*.tmp > /dev/null 2>&1 && fail "a .tmp file was left behind"
  # a run stopped with exit 3 before its final summary says so (it stayed "running")
  [ "$(status inj/solution_summary.csv)" = "failed" ] || fail "summary status '$(status inj/solution_summary.csv)', expected failed"
  grep -q "the previous checkpoint 'inj/solution.checkpoint' is kept" inj.log || { cat inj.log; fail "the message does not say the previous checkpoint is kept"; }
  echo "injected failure: exit 3, checkpoint kept: $(grep ' step ' info.txt)"
  # the first checkpoint write fails: there is no previous checkpoint to keep, and the
  # message must not claim one (it said "the previous checkpoint is kept")
  GRANHYDRO_FAIL_CHECKPOINT_WRITE=1 run -p "Output/Directory=inj1" "$scene" > inj1.log 2>&1
  rc=$?
  [ $rc -eq 3 ] || { cat inj1.log; fail "injected ENOSPC at the first checkpoint: exit $rc, expected 3"; }
  grep -q "there is no previous checkpoint" inj1.log || { cat inj1.log; fail "the first failed checkpoint write claims a previous one"; }
  [ "$(status inj1/solution_summary.csv)" = "failed" ] || fail "summary status '$(status inj1/solution_summary.csv)', expected failed"
  # a real write limit from the OS (FAULTS_NO_ULIMIT=1 skips it: with several ranks on one
  # node, Open MPI's shared-memory segments themselves exceed the limit in MPI_Init)
  if [ -z "${FAULTS_NO_ULIMIT:-}" ]; then
    # (PMIx's shared-memory store would hit the limit inside MPI_Init: use its hash store)
    ( ulimit -f 16; PMIX_MCA_gds=hash run -p "Output/Directory=lim" "$scene" > lim.log 2>&1 ); rc=$?
    [ $rc -eq 3 ] || { cat lim.log; fail "file size limit: exit $rc, expected 3"; }
    crashed lim.log && { cat lim.log; fail "crash text"; }
    if [ -f lim/solution_summary.csv ]; then
      [ "$(status lim/solution_summary.csv)" = "failed" ] || fail "summary status '$(status lim/solution_summary.csv)', expected failed"
    fi
    grep -q "An input/output error has occurred" lim.log && { cat lim.log; fail "deal.II's generic ExcIO text instead of the OS reason"; }
    if [ -f lim/solution.checkpoint ]; then
      "$exe" --checkpoint-info lim/solution.checkpoint > /dev/null || fail "file size limit left an invalid checkpoint"
    fi
    echo "file size limit: exit 3: $(grep 'run stopped' lim.log | head -1)"
  fi
  ;;
corrupt)
  run -p "Output/Directory=good" -p "Time/End time=0.05" "$scene" > good.log 2>&1 || { cat good.log; fail "run"; }
  g=good/solution.checkpoint
  size=$(stat -c %s $g)
  head -c $((size / 2)) $g > truncated.ck
  cp $g flip_header.ck; printf '\x55' | dd of=flip_header.ck bs=1 seek=40 conv=notrunc status=none
  # the part table: the row count of part 0 (after magic 24, header 4336 (format v6: 240
  # and the run record of 4096), part count 8, offset 8)
  cp $g flip_table.ck; printf '\x55' | dd of=flip_table.ck bs=1 seek=$((24 + 4336 + 8 + 8)) conv=notrunc status=none
  cp $g flip_value.ck; printf '\x7f' | dd of=flip_value.ck bs=1 seek=$((size - 30)) conv=notrunc status=none
  cp $g appended.ck; printf 'garbage' >> appended.ck
  : > empty.ck
  printf 'not a checkpoint\n' > text.ck
  { printf 'granhydro checkpoint v3\n'; tail -c +25 $g; } > old_format.ck
  { printf 'granhydro checkpoint v4\n'; tail -c +25 $g; } > old_format_v4.ck
  # semantic damage behind valid checksums (a buggy writer): rewrite and re-sign
  python3 - "$g" <<'EOF2' || fail "python3 could not craft the checkpoints"
import struct, sys
src = open(sys.argv[1], 'rb').read()
magic = len(b"granhydro checkpoint v6\n")
assert src.startswith(b"granhydro checkpoint v6\n")
hdr = 240 + 4096  # sizeof(CheckpointHeader) on x86-64: the v5 fields and the run record
PART = struct.Struct('<QQqqQ')  # offset, rows, first key, last key, checksum
def fnv(b, h=14695981039346656037):
    for x in b:
        h = ((h ^ x) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h
n_parts = struct.unpack_from('<Q', src, magic + hdr)[0]
table = magic + hdr + 8
head_end = table + n_parts * PART.size  # the head checksum is stored here
parts = [list(PART.unpack_from(src, table + p * PART.size)) for p in range(n_parts)]
nv = struct.unpack_from('<i', src, magic + 152)[0]  # n_values (after model[16])
row = 8 + 8 * nv
def sign(b, name):
    """every part's checksum and the head's checksum recomputed"""
    b = bytearray(b)
    for p in range(n_parts):
        off, rows = parts[p][0], parts[p][1]
        parts[p][4] = fnv(bytes(b[off:off + rows * row])) if rows else 14695981039346656037
        parts[p][2] = struct.unpack_from('<q', b, off)[0] if rows else -1
        parts[p][3] = struct.unpack_from('<q', b, off + (rows - 1) * row)[0] if rows else -1
        PART.pack_into(b, table + p * PART.size, *parts[p])
    struct.pack_into('<Q', b, head_end, fnv(bytes(b[:head_end])))
    open(name, 'wb').write(bytes(b))
# header: int32 dim, n_components; uint64 cells[3]; double lower[3], upper[3];
# double length, mass, velocity, time; uint64 step, n_cells, outputs; ...
off_time = magic + 8 + 24 + 48 + 24
off_ncells = off_time + 8 + 8
first_value = parts[0][0] + 8
b = bytearray(src); struct.pack_into('<d', b, first_value, float('nan')); sign(b, 'nan_value.ck')
b = bytearray(src); struct.pack_into('<d', b, first_value, -1.0); sign(b, 'negative_density.ck')
b = bytearray(src); struct.pack_into('<d', b, off_time, -1e300); sign(b, 'time_negative.ck')
b = bytearray(src); struct.pack_into('<d', b, off_time, 1e300); sign(b, 'time_future.ck')
b = bytearray(src); struct.pack_into('<Q', b, off_ncells, 1 << 40); sign(b, 'cells_huge.ck')
# an unknown material model behind valid checksums (--checkpoint-info reported it valid)
b = bytearray(src); b[magic + 136:magic + 152] = b'foo'.ljust(16, b'\0'); sign(b, 'model_unknown.ck')
# the run record (format v6) without its terminating NUL
b = bytearray(src); b[magic + 240:magic + hdr] = b'x' * (hdr - 240); sign(b, 'run_record.ck')
# a cell in two parts (with two or more parts): one part's last key replaced by another
# part's last key where that keeps the part's keys increasing
if n_parts >= 2:
    for a, c in ((0, 1), (1, 0)):
        if parts[c][1] < 2:
            continue
        ka = parts[a][3]
        before_last = struct.unpack_from('<q', src, parts[c][0] + (parts[c][1] - 2) * row)[0]
        if ka > before_last and ka != parts[c][3]:
            b = bytearray(src); struct.pack_into('<q', b, parts[c][0] + (parts[c][1] - 1) * row, ka)
            sign(b, 'duplicate_key.ck')
            break
# the unmodified file re-signed must stay valid (the offsets above are right)
sign(src, 'resigned.ck')
EOF2
  cmp -s resigned.ck $g || fail "re-signing the unmodified checkpoint changed it (test offsets wrong)"
  kinds="truncated flip_header flip_table flip_value appended empty text old_format old_format_v4 nan_value
         negative_density time_negative time_future cells_huge model_unknown run_record"
  [ -f duplicate_key.ck ] && kinds="$kinds duplicate_key"
  kinds=${FAULTS_KINDS:-$kinds} # a subset (the multi-rank ctest)
  for f in $kinds; do
    # --check verifies every part; a key in two parts (behind valid checksums only a buggy
    # writer makes it) is found by the run, which merges the parts' keys
    hows="--check run"; [ $f = duplicate_key ] && hows=run
    for how in $hows; do
      rm -rf out_$f; mkdir out_$f
      if [ $how = --check ]; then
        run --check -p "Output/Directory=out_$f" -p "Initial state/Checkpoint=$f.ck" "$scene" > $f.log 2>&1
      else
        run -p "Output/Directory=out_$f" -p "Initial state/Checkpoint=$f.ck" "$scene" > $f.log 2>&1
      fi
      rc=$?
      [ $rc -eq 2 ] || { cat $f.log; fail "$f ($how): exit $rc, expected 2"; }
      grep -q "Initial state/Checkpoint" $f.log || { cat $f.log; fail "$f ($how): message does not name the parameter"; }
      crashed $f.log && { cat $f.log; fail "$f ($how): crash text"; }
      [ -z "$(ls -A out_$f)" ] || fail "$f ($how): files written: $(ls out_$f)"
    done
    echo "$f: refused: $(grep -o "Checkpoint.*" $f.log | head -1 | cut -c1-150)"
  done
  "$exe" --checkpoint-info model_unknown.ck > info_model.txt 2>&1 && { cat info_model.txt; fail "--checkpoint-info accepts an unknown model"; }
  grep -q "unknown material model 'foo'" info_model.txt || { cat info_model.txt; fail "--checkpoint-info does not name the unknown model"; }
  # a valid checkpoint of another mesh: --check refuses it as the run does (it passed --check)
  run -p "Output/Directory=other" -p "Time/End time=0.05" -p "Domain/Cells=30" "$scene" > other.log 2>&1 || { cat other.log; fail "run with 30 cells"; }
  for how in --check run; do
    rm -rf out_other; mkdir out_other
    if [ $how = --check ]; then
      run --check -p "Output/Directory=out_other" -p "Initial state/Checkpoint=other/solution.checkpoint" "$scene" > foreign.log 2>&1
    else
      run -p "Output/Directory=out_other" -p "Initial state/Checkpoint=other/solution.checkpoint" "$scene" > foreign.log 2>&1
    fi
    rc=$?
    [ $rc -eq 2 ] || { cat foreign.log; fail "checkpoint of another mesh ($how): exit $rc, expected 2"; }
    grep -q "Initial state/Checkpoint.*another mesh" foreign.log || { cat foreign.log; fail "checkpoint of another mesh ($how): message"; }
  done
  echo "checkpoint of another mesh: refused by --check and the run: $(grep -o "another mesh.*" foreign.log | head -1)"
  ;;
*) fail "unknown mode '$mode' (sigterm, disk_full, corrupt)";;
esac
echo "PASS ($mode)"
