#!/bin/bash
# Restart test (ctest verify.restart_after_kill):
#   restart_after_kill.sh <granhydro> <scene.prm> <work dir> [launcher...]
# 1. runs the scene uninterrupted and keeps its final checkpoint;
# 2. runs it again, kills it with SIGKILL after its second checkpoint (mid-run), and
#    restarts it from that checkpoint ('Initial state/Checkpoint');
# 3. the restarted run must end in the same state, bit for bit: the final checkpoint
#    files (time, step, output count, every cell's state) must be identical but for the
#    run record in the header (format v6: 4096 bytes after the magic line of 24 bytes and
#    the 240 bytes of the rest of the header), which counts wall times and segments, and
#    the checksum of the head that covers it (8 bytes after the part table). The time
#    steps depend only on the state and the output times, which a restart reproduces.
# The checkpoint is replaced atomically (written to .tmp, renamed), so a kill at any
# moment leaves a complete file.
set -u
exe=$1; scene=$2; work=$3; shift 3
launcher=("$@")
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

# the scene's output folder and VTU switch overridden with -p (a scene sets each
# parameter once: an appended second 'subsection Output' with another value is refused)
cp "$scene" scene.prm
"${launcher[@]}" "$exe" -p "Output/Directory=full" -p "Output/Write VTU=false" scene.prm > full.log 2>&1 || { echo "uninterrupted run failed"; cat full.log; exit 1; }

# own session/process group, so SIGKILL reaches mpirun and every rank. The test hook
# GRANHYDRO_HOLD_AFTER_CHECKPOINT=2 makes the run wait after its second checkpoint (the
# first is the initial state) until it is killed: the kill lands mid-run at a known
# checkpoint however fast or loaded the machine is.
GRANHYDRO_HOLD_AFTER_CHECKPOINT=2 setsid "${launcher[@]}" "$exe" -p "Output/Directory=killed" -p "Output/Write VTU=false" scene.prm > killed.log 2>&1 &
pid=$!
ck=killed/solution.checkpoint
for i in $(seq 1 3000); do
  grep -q "holding after checkpoint" killed.log && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.1
done
if ! grep -q "holding after checkpoint" killed.log; then
  echo "the run did not reach its second checkpoint"; cat killed.log; kill -KILL -- -$pid 2>/dev/null; exit 1
fi
kill -KILL -- -$pid 2>/dev/null || kill -KILL $pid
wait $pid 2>/dev/null
echo "killed the run (SIGKILL) after its second checkpoint"
cp "$ck" killed.checkpoint

"${launcher[@]}" "$exe" -p "Output/Directory=killed" -p "Output/Write VTU=false" \
  -p "Initial state/Checkpoint=$PWD/killed.checkpoint" scene.prm > restart.log 2>&1 || { echo "restart failed"; cat restart.log; exit 1; }
grep "initial state: checkpoint" restart.log
grep "run summary" full.log restart.log
parts=$("$exe" --checkpoint-info full/solution.checkpoint | sed -n 's/^ *parts \([0-9]*\).*/\1/p')
table=$((24 + 240 + 4096))          # the part count, then 40 bytes per part
body=$((table + 8 + 40 * parts + 8)) # after the head's checksum
if [ -n "$parts" ] && cmp -n $((24 + 240)) full/solution.checkpoint killed/solution.checkpoint &&
   cmp -i $table -n $((8 + 40 * parts)) full/solution.checkpoint killed/solution.checkpoint &&
   cmp -i $body full/solution.checkpoint killed/solution.checkpoint; then
  echo "restarted run ends in the same state as the uninterrupted one (bitwise)"
else
  echo "FAIL: the restarted run differs from the uninterrupted one"; exit 1
fi
# the profiles written after the restart continue the file: same number of lines
a=$(wc -l < full/solution_profiles.csv); b=$(wc -l < killed/solution_profiles.csv)
echo "solution_profiles.csv lines: uninterrupted $a, killed + restarted $b"
[ "$a" -le "$b" ] || { echo "FAIL: solution_profiles.csv lost lines"; exit 1; }
exit 0
