#!/bin/bash
# benchmarks/strong_scaling_pairs.sh BUILD_DIR [PAIRS] [SCENE]: 2-rank strong-scaling
# efficiency of a scene (default parameters/amr_blast_3d.prm; SCENE = benchmark: the
# convection benchmark BUILD_DIR/granhydro_benchmark, timed by its seconds per step, the
# median of its 3 runs; no adaptation) from PAIRS (default 10)
# alternated runs on 1 and 2 ranks: the efficiency T1 / (2 T2) per pair and of the medians,
# and the pairs in which both runs are within 5 % of their best time ("undisturbed": on a
# shared or virtual machine a foreign load slows single runs by 10-40 %, and a pair run
# back to back sees about the same host). Also the adaptation's share of the 1-rank wall
# time (the run summary's "adaptation" and "wall"). Both cores should be otherwise idle.
# TWO_AT_ONCE=1 adds to each pair two 1-rank runs started together: their mean wall T1c
# is what the machine gives a core when both are busy (memory bandwidth, the host's
# load on a virtual machine), so T1 / T1c is the machine's ceiling for the efficiency and
# T1c / (2 T2) the code's share (the efficiency = ceiling x code share).
# BOTH_CORES=1 adds to each pair a 1-rank run on core 1 (`mpirun -np 1` binds its rank to
# core 0): on a virtual machine the two cores need not be equally fast, and then the 2-rank
# run can at best reach the two cores' summed speed, 1 / T1x = 1 / T1 + 1 / T1', i.e. the
# ideal 2-rank time T1x = T1 T1' / (T1 + T1'); the efficiency against both cores is T1x / T2
# (= T1 / (2 T2) when the cores are equal).
# GATE=1 probes the cores before and after each pair (benchmarks/core_speeds.cc on each
# core: a latency-bound loop, 1/4 of core_speeds.sh's, and the throughput-bound triad,
# about 3 s in all) and calls the host fit for the pair when all four throughput-bound
# times lie within 10 % and all four latency-bound times within 5 % of the batch's median
# probe (both cores as fast as usual before and after; judged at the end, against the
# whole batch). The summary then adds the medians of the pairs on a fit host: the
# selection uses the probes only, never the pair's own times. A burst of foreign load
# between the probes escapes it: the probes are a minimum check, not a proof.
set -e
B=$(readlink -f ${1:-build}); PAIRS=${2:-10}
REPO=$(cd "$(dirname "$0")/.." && pwd)
W=$(mktemp -d /tmp/pairs.XXXX)
if [ "${3:-}" = benchmark ]; then
  [ -x $B/granhydro_benchmark ] || { echo "no granhydro_benchmark in $B" >&2; exit 1; }
  CMD="$B/granhydro_benchmark"
  # the benchmark's table line: cells ranks config updates/s/stage/core s/step MUSTA stages
  wall() { grep -hE "^[0-9]+\^[0-9]+ " "$@" | awk '{print $5}'; }
else
  SCENE=$(readlink -f ${3:-$REPO/parameters/amr_blast_3d.prm})
  [ -x $B/granhydro ] || { echo "no granhydro in $B" >&2; exit 1; }
  [ -f $SCENE ] || { echo "no scene file $SCENE" >&2; exit 1; }
  cp $SCENE $W/scene.prm
  CMD="$B/granhydro scene.prm"
  # the run summary's wall time of the logs named
  wall() { grep -hE "^  wall" "$@" | awk '{print $2}'; }
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd $W
# the summaries' awk: median of a[1..n] (sorts a)
MEDIAN='function median(a, n,   i, j, t) { for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                   return n % 2 ? a[(n + 1) / 2] : 0.5 * (a[n / 2] + a[n / 2 + 1]) }'
if [ "${GATE:-0}" = 1 ]; then
  g++ -O2 -o $W/core_speeds $REPO/benchmarks/core_speeds.cc
  # one probe: "latency0 throughput0 latency1 throughput1" (cores 0 and 1)
  probe() { for c in 0 1; do taskset -c $c $W/core_speeds 0.25 | awk '{printf "%s %s ", $2, $5}'; done; echo; }
fi
printf "%5s %10s %10s %11s %14s\n" pair "1 rank s" "2 ranks s" efficiency "adaptation 1r"
for i in $(seq 1 $PAIRS); do
  [ "${GATE:-0}" = 1 ] && probe_before=$(probe)
  for np in 1 2; do
    mpirun -np $np $CMD > log.$np 2>&1 || { echo "run failed (log in $W/log.$np)" >&2; exit 1; }
    wall log.$np > wall.$np
    [ -s wall.$np ] || { echo "the run printed no time (log in $W/log.$np)" >&2; exit 1; }
    grep -E "adaptation [0-9.e+-]+ s" log.$np | sed 's/.*adaptation //; s/ s$//' > adapt.$np || echo 0 > adapt.$np
  done
  t1=$(cat wall.1); t2=$(cat wall.2); a1=$(cat adapt.1); a1=${a1:-0}
  echo "$t1 $t2 $a1" >> pairs.txt
  awk -v i=$i '{printf "%5d %10.4g %10.4g %11.3f %14.2f\n", i, $1, $2, $1 / (2 * $2), $3}' <(tail -1 pairs.txt)
  if [ "${GATE:-0}" = 1 ]; then
    probe_after=$(probe)
    echo "$t1 $t2 $probe_before $probe_after" >> gate.txt
    echo "      probes (latency, throughput s; core 0, core 1) before: $probe_before after: $probe_after"
  fi
  if [ "${BOTH_CORES:-0}" = 1 ]; then
    taskset -c 1 mpirun -np 1 --bind-to none $CMD > log.c1 2>&1 || { echo "run failed (log in $W/log.c1)" >&2; exit 1; }
    t1b=$(wall log.c1)
    echo "$t1 $t1b $t2" >> cores.txt
    awk '{x = $1 * $2 / ($1 + $2); printf "%5s 1 rank on core 1: %.4g s (core 0 / core 1 speed %.3f); both cores ideal %.4g s, efficiency against both cores %.3f\n", "", $2, $2 / $1, x, x / $3}' <(tail -1 cores.txt)
  fi
  if [ "${TWO_AT_ONCE:-0}" = 1 ]; then
    # (unbound: two separate `mpirun -np 1` would both bind their rank to core 0)
    mpirun -np 1 --bind-to none $CMD > log.a 2>&1 & pa=$!
    mpirun -np 1 --bind-to none $CMD > log.b 2>&1 & pb=$!
    wait $pa && wait $pb || { echo "run failed (logs in $W/log.a, log.b)" >&2; exit 1; }
    tc=$(wall log.a log.b | awk '{s += $1; n++} END {if (n == 2) print s / 2}')
    [ -n "$tc" ] || { echo "a 1-rank run at once printed no time (logs in $W/log.a, log.b)" >&2; exit 1; }
    echo "$t1 $t2 $tc" >> once.txt
    awk -v i=$i '{printf "%5s two 1-rank runs at once: %.4g s; machine ceiling T1/T1c %.3f, code share T1c/(2 T2) %.3f\n", "", $3, $1 / $3, $3 / (2 * $2)}' <(tail -1 once.txt)
  fi
done
awk "$MEDIAN"'
  { n++; t1[n] = $1; t2[n] = $2; e[n] = $1 / (2 * $2); s[n] = $3 / $1; if (n == 1 || $1 < b1) b1 = $1; if (n == 1 || $2 < b2) b2 = $2 }
  END {
    for (i = 1; i <= n; ++i) { c1[i] = t1[i]; c2[i] = t2[i]; ce[i] = e[i]; cs[i] = s[i] }
    m1 = median(c1, n); m2 = median(c2, n)
    printf "medians: 1 rank %.4g s, 2 ranks %.4g s, efficiency %.3f; per-pair median %.3f; adaptation %.1f %% of the 1-rank wall (median)\n", m1, m2, m1 / (2 * m2), median(ce, n), 100 * median(cs, n)
    k = 0; list = ""
    for (i = 1; i <= n; ++i) if (t1[i] <= 1.05 * b1 && t2[i] <= 1.05 * b2) { k++; u[k] = e[i]; list = list sprintf(" %.3f", e[i]) }
    if (k > 0) printf "undisturbed pairs (both within 5 %% of their best): %d:%s, median %.3f\n", k, list, median(u, k)
    else print "no undisturbed pair"
  }' pairs.txt
# (median() sorts its array: the pooled probes al, aq are copies of the per-pair l, q)
[ -f gate.txt ] && awk "$MEDIAN"'
  { n++; t1[n] = $1; t2[n] = $2; for (j = 0; j < 4; ++j) { l[n, j] = $(3 + 2 * j); q[n, j] = $(4 + 2 * j); al[4 * (n - 1) + j + 1] = l[n, j]; aq[4 * (n - 1) + j + 1] = q[n, j] } }
  END { bl = median(al, 4 * n); bq = median(aq, 4 * n); k = 0; list = ""
        for (i = 1; i <= n; ++i) { fit = 1; for (j = 0; j < 4; ++j) if (l[i, j] > 1.05 * bl || q[i, j] > 1.10 * bq) fit = 0
                                   if (fit) { k++; a[k] = t1[i]; b[k] = t2[i]; e[k] = t1[i] / (2 * t2[i]); list = list sprintf(" %d", i) } }
        printf "probes: median latency-bound %.3f s, throughput-bound %.3f s; ", bl, bq
        if (k == 0) { print "no pair on a fit host"; exit }
        printf "%d pairs on a fit host (%s ): medians 1 rank %.4g s, 2 ranks %.4g s, efficiency %.3f; per-pair median %.3f\n", k, list, median(a, k), median(b, k), median(a, k) / (2 * median(b, k)), median(e, k) }' gate.txt
[ -f cores.txt ] && awk "$MEDIAN"'
  { n++; a[n] = $1; b[n] = $2; c[n] = $3; r[n] = $2 / $1; e[n] = $1 * $2 / ($1 + $2) / $3 }
  END { ma = median(a, n); mb = median(b, n); mc = median(c, n)
        printf "both cores: medians 1 rank core 0 %.4g s, core 1 %.4g s (speed ratio per pair, median %.3f), 2 ranks %.4g s: efficiency against both cores %.3f (of the medians), per-pair median %.3f\n", ma, mb, median(r, n), mc, ma * mb / (ma + mb) / mc, median(e, n) }' cores.txt
[ -f once.txt ] && awk "$MEDIAN"'
  { n++; c[n] = $1 / $3; k[n] = $3 / (2 * $2) }
  END { printf "two at once: machine ceiling T1/T1c median %.3f, code share T1c/(2 T2) median %.3f\n", median(c, n), median(k, n) }' once.txt
rm -rf $W
