#!/bin/bash
# Summary test (ctest mpi.summary_ranks):
#   summary_ranks.sh <granhydro> <scene.prm> <work dir> <mpiexec> RANKS...
# runs the scene on each number of ranks and compares the run summaries
# (<base>_summary.csv) line by line with the first. Everything that describes the
# solution must be byte-identical: the state is the same on N ranks, so the counts of
# steps, retries, flux points, MUSTA stages, Newton/GMRES work and the mass drift must be
# too. Allowed to differ (named here, they depend on the machine or the partition):
# wall and phase times (*_seconds), peak memory, the rank count, the start time and the
# overrides (they name the output folder).
set -u
exe=$1; scene=$2; work=$3; mpiexec=$4; shift 4
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
allowed='^([a-z0-9_]*_seconds|peak_memory_bytes_max_rank|peak_memory_bytes_all_ranks|ranks|start_time|overrides),'
first=""
for n in "$@"; do
  "$mpiexec" -n "$n" --oversubscribe "$exe" -p "Output/Directory=r$n" -p "Output/Write VTU=false" \
    "$scene" > "r$n.log" 2>&1 || { echo "FAIL: the run on $n ranks failed"; tail -5 "r$n.log"; exit 1; }
  grep -Ev "$allowed" "r$n/solution_summary.csv" > "r$n.compared"
  grep -q '^status,completed' "r$n.compared" || { echo "FAIL: $n ranks: status is not completed"; exit 1; }
  if [ -z "$first" ]; then
    first=$n
  elif ! diff "r$first.compared" "r$n.compared"; then
    echo "FAIL: the summary on $n ranks differs from $first rank(s) (lines above)"; exit 1
  fi
done
echo "summaries on $* ranks identical apart from: $allowed ($(wc -l < "r$first.compared") lines compared)"
exit 0
