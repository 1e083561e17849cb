#!/bin/bash
# benchmarks/core_speeds.sh [ROUNDS]: is this machine fit for a strong-scaling measurement?
# Times a latency-bound and a throughput-bound loop (benchmarks/core_speeds.cc) on each core
# in turn, ROUNDS (default 3) times. On an idle machine with equal cores both columns agree
# between the cores to a few per cent; when one core's throughput-bound time is well above
# the other's, the host is taking that core's throughput, and a 2-rank run (which needs both
# cores) is measured against 1-rank runs bound to core 0: T1 / (2 T2) then understates the
# code (see strong_scaling_pairs.sh, BOTH_CORES=1).
set -e
REPO=$(cd "$(dirname "$0")/.." && pwd)
W=$(mktemp -d /tmp/cores.XXXX)
g++ -O2 -o $W/core_speeds $REPO/benchmarks/core_speeds.cc
for r in $(seq 1 ${1:-3}); do
  for c in $(seq 0 $(($(nproc) - 1))); do
    echo "round $r core $c: $(taskset -c $c $W/core_speeds | sed 's/  (.*//')"
  done
done
rm -rf $W
