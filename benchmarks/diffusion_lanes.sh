#!/bin/bash
# The diffusion step against the convective half (summary.csv timers of the same run) on
# the 1D vibrated bed and parameters/bouncing_bed-ci.prm, before/after:
#   old      - an earlier build (OLD_DIR), the scene without the Knudsen cap
#   lanes    - this build, the same scene (the vectorised residual: results bit for bit old's)
#   lanes+kn - this build, the scene as committed (Maximum mean free path = 1 grain diameter)
#
#   benchmarks/diffusion_lanes.sh OLD_DIR [ROUNDS]
#
# OLD_DIR holds the earlier build's granhydro and libgranhydro_core.so (run with
# LD_LIBRARY_PATH=OLD_DIR). One process at a time, interleaved per round, so that a noisy
# shared machine hits all configurations alike; prints the medians over the rounds.
set -e
OLD=$(cd "$1" && pwd); ROUNDS=${2:-3}
REPO=$(cd "$(dirname "$0")/.." && pwd); NEW=$REPO/build/granhydro
OUT=$PWD/bench-diffusion-lanes; mkdir -p $OUT; cd $OUT
echo "scene,config,round,wall,convection,diffusion,steps,rkl2_stages" > results.csv
for r in $(seq $ROUNDS); do
  for scene in vibrated_bed_1d bouncing_bed-ci; do
    for c in old lanes lanes+kn; do
      d=out-$scene-$c; rm -rf $d
      set -- -p "Output/Directory=$d" -p "Output/Write VTU=false"
      [ $c != lanes+kn ] && set -- "$@" -p "Material/Maximum mean free path=0"
      if [ $c = old ]; then LD_LIBRARY_PATH=$OLD $OLD/granhydro "$@" $REPO/parameters/$scene.prm > $d.log 2>&1
      else $NEW "$@" $REPO/parameters/$scene.prm > $d.log 2>&1; fi
      s=$(ls $d/*_summary.csv)
      g() { grep "^$1," $s | cut -d, -f2; }
      echo "$scene,$c,$r,$(g wall_seconds),$(g convection_seconds),$(g diffusion_seconds),$(g steps),$(g rkl2_stages)" >> results.csv
    done
  done
  echo "round $r done" >&2
done
/usr/bin/python3 - <<'PY'
import csv, statistics as st
rows = list(csv.DictReader(open("results.csv")))
print("scene             config      wall_s  convection_s  diffusion_s  diff/conv  steps  rkl2_stages  (medians of %d)"
      % len({r["round"] for r in rows}))
for sc in ["vibrated_bed_1d", "bouncing_bed-ci"]:
    for c in ["old", "lanes", "lanes+kn"]:
        rr = [r for r in rows if r["scene"] == sc and r["config"] == c]
        m = lambda k: st.median(float(r[k]) for r in rr)
        print("%-17s %-9s %8.3f %13.3f %12.3f %10.2f %6s %12s" % (sc, c, m("wall"), m("convection"), m("diffusion"),
              m("diffusion") / m("convection"), rr[0]["steps"], rr[0]["rkl2_stages"]))
PY
