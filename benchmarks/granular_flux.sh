#!/bin/bash
# The granular MUSTA flux on 4 Gauss points at once (GranularGas's convective formulas
# templated on the vector type, AVX2 without FMA: bit for bit the scalar flux), before and
# after, on the paper's sedimentation column (parameters/sedimentation.prm with a 4 x 100 x 4
# cross-section of the same 2 mm x 1 mm x 2 mm cells; to END seconds, default 0.1 s):
#   old   - an earlier build (OLD_DIR), MUSTA minimum stages 2 (the default)
#   new   - this build, the same scene (results bit for bit old's: the profiles are compared)
#   new1  - this build, MUSTA minimum stages 1 (as parameters/sedimentation.prm sets it)
#
#   benchmarks/granular_flux.sh OLD_DIR [ROUNDS] [END]
#
# OLD_DIR holds the earlier build's granhydro and libgranhydro_core.so (run with
# LD_LIBRARY_PATH=OLD_DIR). One process at a time, interleaved per round; medians printed.
set -e
OLD=$(cd "$1" && pwd); ROUNDS=${2:-3}; END=${3:-0.1}
REPO=$(cd "$(dirname "$0")/.." && pwd); NEW=$REPO/build/granhydro
OUT=$PWD/bench-granular-flux; mkdir -p $OUT; cd $OUT
echo "config,round,wall,convection,diffusion,steps,flux_points,musta_stages" > results.csv
for r in $(seq $ROUNDS); do
  for c in old new new1; do
    d=out-$c; rm -rf $d
    set -- -p "Output/Directory=$d" -p "Output/Write VTU=false" -p "Time/End time=$END" \
      -p "Domain/Upper corner=0.008,0.1,0.008" -p "Domain/Cells=4,100,4"
    if [ $c = new1 ]; then set -- "$@" -p "Numerics/MUSTA minimum stages=1"
    else set -- "$@" -p "Numerics/MUSTA minimum stages=2"; fi
    if [ $c = old ]; then LD_LIBRARY_PATH=$OLD $OLD/granhydro "$@" $REPO/parameters/sedimentation.prm > $d.log 2>&1
    else $NEW "$@" $REPO/parameters/sedimentation.prm > $d.log 2>&1; fi
    s=$(ls $d/*_summary.csv)
    g() { grep "^$1," $s | cut -d, -f2; }
    echo "$c,$r,$(g wall_seconds),$(g convection_seconds),$(g diffusion_seconds),$(g steps),$(g flux_points),$(g musta_stages)" >> results.csv
  done
  # every column of old's profiles equal in new's (an earlier build may name the columns
  # with their units and lack granular_temperature: read_profiles reads both as now)
  /usr/bin/python3 - "$REPO" <<'PY' &&
import sys
import numpy as np
sys.path.insert(0, sys.argv[1] + "/tools/granhydro_py")
from granhydro.readers import read_profiles
(a, _), (b, _) = read_profiles("out-old"), read_profiles("out-new")
sys.exit(0 if all(c in b and np.array_equal(a[c], b[c]) for c in a) else 1)
PY
    echo "round $r: new profiles = old profiles, bit for bit" >&2 ||
    { echo "round $r: new profiles DIFFER from old" >&2; exit 1; }
done
/usr/bin/python3 - <<'PY'
import csv, statistics as st
rows = list(csv.DictReader(open("results.csv")))
print("config  wall_s  convection_s  diffusion_s  steps  MUSTA stages/point  (medians of %d)"
      % len({r["round"] for r in rows}))
base = None
for c in ["old", "new", "new1"]:
    rr = [r for r in rows if r["config"] == c]
    m = lambda k: st.median(float(r[k]) for r in rr)
    base = base or m("convection")
    print("%-6s %7.2f %13.2f %12.2f %6d %19s   convection x%.2f" % (
        c, m("wall"), m("convection"), m("diffusion"), m("steps"),
        "%.3f" % (float(rr[0]["musta_stages"]) / float(rr[0]["flux_points"])),
        base / m("convection")))
PY
