#!/bin/bash
# Checkpoints across rank counts (ctests checkpoint.ranks_* and mpi.checkpoint_ranks_*):
#   checkpoint_ranks.sh <granhydro> <scene.prm> <work dir> <W> <R> <continue: yes|no> [mpiexec...]
# 1. the scene uninterrupted on 1 rank: its final state digest and step count S (with
#    CHECKPOINT_RANKS_REFERENCE=<work dir of another test of the same scene>: that test's
#    uninterrupted run, run once for all rank pairs);
# 2. on W ranks, stopped by SIGTERM after step K = S/2 (test hook GRANHYDRO_SIGTERM_AT_STEP):
#    a checkpoint of W parts (one per rank) at step K;
# 3. round trip: restarted on R ranks with Time/Maximum steps = K, the run stops at once
#    and writes its final checkpoint (R parts): its state digest must be the digest of the
#    W-rank checkpoint, bit for bit (each rank read exactly its cells, an adaptive mesh was
#    rebuilt from the leaves in the file);
# 4. with continue = yes (a scene whose results do not depend on the rank count: convection
#    only), restarted on R ranks to the end: the final digest must be the uninterrupted
#    1-rank run's, bit for bit.
set -u
exe=$1; scene=$2; work=$3; W=$4; R=$5; cont=$6; shift 6
mpiexec=("$@")
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
run() { local np=$1; shift; if [ ${#mpiexec[@]} -gt 0 ]; then "${mpiexec[@]}" -n "$np" "$exe" "$@"; else "$exe" "$@"; fi; }
# --checkpoint-info of a checkpoint once into <name>_info.txt (each start of granhydro costs
# its MPI start-up); digest and fields are read from that text
info() { "$exe" --checkpoint-info "$1" > "$2_info.txt"; }
digest() { sed -n 's/.*state digest //p' "$1_info.txt"; }
field() { sed -n "s/.* $2 \([0-9]*\).*/\1/p" "$1_info.txt" | head -1; }

if [ -n "${CHECKPOINT_RANKS_REFERENCE:-}" ]; then
  # the uninterrupted 1-rank run of the same scene by the same executable, made once by
  # the ctest fixture's setup test (ctest runs it first, also for a single test)
  full=$CHECKPOINT_RANKS_REFERENCE/full/solution.checkpoint
  [ -f "$full" ] || fail "no uninterrupted run at $full (its setup test failed?)"
  echo "the uninterrupted 1-rank run: $full"
else
  run 1 -p "Output/Directory=full" "$scene" > full.log 2>&1 || { cat full.log; fail "uninterrupted run"; }
  full=full/solution.checkpoint
fi
info "$full" full || { cat full_info.txt; fail "the uninterrupted run's checkpoint does not verify"; }
a=$(digest full); s=$(field full step)
k=$((s / 2))
GRANHYDRO_SIGTERM_AT_STEP=$k run "$W" -p "Output/Directory=int" "$scene" > int.log 2>&1
rc=$?
[ $rc -eq 143 ] || { cat int.log; fail "interrupted run on $W ranks: exit $rc, expected 143"; }
c=int/solution.checkpoint
cp $c int.checkpoint
info int.checkpoint int || { cat int_info.txt; fail "the $W-rank checkpoint does not verify"; }
[ "$(field int parts)" = "$W" ] || { cat int_info.txt; fail "the $W-rank checkpoint does not have $W parts"; }
[ "$(field int step)" = "$k" ] || { cat int_info.txt; fail "the checkpoint is not at step $k"; }
b=$(digest int)

run "$R" -p "Output/Directory=trip" -p "Time/Maximum steps=$k" -p "Initial state/Checkpoint=int.checkpoint" \
  "$scene" > trip.log 2>&1 || { cat trip.log; fail "restart on $R ranks (no step)"; }
info trip/solution.checkpoint trip || { cat trip_info.txt; fail "the $R-rank checkpoint does not verify"; }
t=$(digest trip)
echo "step $k: written on $W ranks $b, read on $R ranks and written again $t ($(field trip parts) parts)"
[ -n "$b" ] && [ "$b" = "$t" ] || fail "the state read on $R ranks is not the state written on $W ranks"
[ "$(field trip parts)" = "$R" ] || fail "the $R-rank checkpoint does not have $R parts"

if [ "$cont" = yes ]; then
  run "$R" -p "Output/Directory=cont" -p "Initial state/Checkpoint=int.checkpoint" "$scene" > cont.log 2>&1 ||
    { cat cont.log; fail "restart on $R ranks"; }
  info cont/solution.checkpoint cont || { cat cont_info.txt; fail "the continued run's checkpoint does not verify"; }
  e=$(digest cont)
  echo "final state: uninterrupted (1 rank) $a, stopped on $W ranks + restarted on $R ranks $e"
  [ -n "$a" ] && [ "$a" = "$e" ] || fail "the restarted run does not end in the uninterrupted state"
fi
echo PASS
