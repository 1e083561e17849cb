#!/bin/bash
# Cost of writing a checkpoint, before/after: wall time of write_state_checkpoint and the
# peak resident memory of each rank during the write above its resident memory before it.
#
#   benchmarks/checkpoint_write.sh OLD_DIR [CELLS] [RANKS] [ROUNDS]
#
# OLD_DIR holds an earlier build (granhydro and libgranhydro_core.so). The 3D
# sedimentation-ci scene on CELLS (default "50, 200, 50": 5e5 cells) runs one step on
# RANKS (2) ranks with the old and the new build, interleaved, ROUNDS (3) times. A shim
# (benchmarks/checkpoint_write_shim.cc, LD_PRELOAD) wraps io::write_state_checkpoint,
# whose signature both builds share: it resets the peak resident size (clear_refs),
# times the call between two barriers and prints a "CKPT rank ..." line per call; the
# final checkpoint's lines are kept. Both runs must give the same state digest.
set -e
OLD=$(cd "$1" && pwd); CELLS=${2:-"50, 200, 50"}; RANKS=${3:-2}; ROUNDS=${4:-3}
REPO=$(cd "$(dirname "$0")/.." && pwd); NEW=$REPO/build
OUT=$PWD/bench-checkpoint; mkdir -p $OUT; cd $OUT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpicxx -O2 -std=c++17 -fPIC -shared -I$REPO/include $REPO/benchmarks/checkpoint_write_shim.cc -o shim.so -ldl
for i in $(seq 1 $ROUNDS); do
  for which in old new; do
    B=$OLD; [ $which = new ] && B=$NEW
    rm -rf out-$which
    mpirun -n $RANKS -x LD_PRELOAD=$OUT/shim.so -x LD_LIBRARY_PATH=$B $B/granhydro -p "Domain/Cells=$CELLS" \
      -p "Time/Maximum steps=1" -p "Output/Directory=out-$which" -p "Output/Write VTU=false" \
      $REPO/parameters/sedimentation-ci.prm > $which-$i.log 2>&1
    for r in $(seq 0 $((RANKS - 1))); do echo "$which $i: $(grep "CKPT rank $r " $which-$i.log | tail -1)"; done
    echo "$which $i: $($B/granhydro --checkpoint-info out-$which/solution.checkpoint | grep digest)"
  done
done | tee results.txt
