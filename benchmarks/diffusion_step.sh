#!/bin/bash
# Cost and accuracy of the diffusion step V, before/after, on three stiff granular scenes.
#
#   benchmarks/diffusion_step.sh OLD_DIR [ROUNDS]
#
# OLD_DIR holds an earlier build (its granhydro and libgranhydro_core.so, run with
# LD_LIBRARY_PATH=OLD_DIR); the new one is build/granhydro. Each round runs every scene
# with the old binary (its defaults) and with the new one under each integrator, one
# process at a time, interleaved, so that a noisy shared machine hits all of them alike.
# Writes bench-diffusion/results.csv (one row per run, from its <Base name>_summary.csv,
# summary.csv for a build before the base name prefix) and prints the
# medians; then runs a reference per scene (Gauss-Legendre, fixed GMRES tolerance, time
# step capped ~10x below the CFL step) and prints the largest difference of the
# cross-section profiles of phi and T at the end time to it (relative to max|ref|; this
# is a max-norm over the last output block).
set -e
OLD=$(cd "$1" && pwd); ROUNDS=${2:-3}
REPO=$(cd "$(dirname "$0")/.." && pwd); NEW=$REPO/build/granhydro
OUT=$PWD/bench-diffusion; mkdir -p $OUT; cd $OUT
mk() { # scene-file tag diffusion-step-lines
  # the scene included, the changes after it (a scene file sets each parameter once; it may
  # override what it includes)
  printf "include %s\n" "$1" > $2.prm
  printf "subsection Output\n  set Directory = $OUT/out-$2\n  set Write VTU = false\nend\nsubsection Diffusion step\n$3\nend\n" >> $2.prm
}
summary_csv() { # the summary of the run in directory $1: <Base name>_summary.csv, or summary.csv (older builds)
  local f; for f in "$1"/*_summary.csv; do [ -f "$f" ] && { echo "$f"; return; }; done; echo "$1/summary.csv"
}
SCENES="bb:$REPO/parameters/bouncing_bed-ci.prm:1e-4 bed1d:$REPO/parameters/vibrated_bed_1d.prm:4e-5 hv:$REPO/parameters/hard/harsh_vibration-ci.prm:4e-5"
CONFIGS="old gl sdirk2 rkl2 cost"
for sc in $SCENES; do
  IFS=: read name f dt <<< "$sc"
  mk $f $name-old ""
  mk $f $name-gl ""
  mk $f $name-sdirk2 "set Integrator = sdirk2"
  mk $f $name-rkl2 "set Integrator = rkl2"
  mk $f $name-cost "set Integrator = cost-based"
  mk $f $name-ref "set Linear forcing = fixed\nset Reuse Newton matrix = false"
  printf "subsection Numerics\n  set Fixed time step = $dt\nend\n" >> $name-ref.prm
done
echo "scene,config,round,wall,convection,diffusion,steps,newton,gmres,rkl2_steps,rkl2_stages" > results.csv
for r in $(seq $ROUNDS); do
  for sc in $SCENES; do
    name=${sc%%:*}
    for c in $CONFIGS; do
      if [ $c = old ]; then LD_LIBRARY_PATH=$OLD $OLD/granhydro $name-$c.prm > $name-$c.log 2>&1
      else $NEW $name-$c.prm > $name-$c.log 2>&1; fi
      s=$(summary_csv out-$name-$c)
      g() { grep "^$1," $s | cut -d, -f2; }
      echo "$name,$c,$r,$(g wall_seconds),$(g convection_seconds),$(g diffusion_seconds),$(g steps),$(g newton_iterations),$(g gmres_iterations),$(g rkl2_steps),$(g rkl2_stages)" >> results.csv
      echo "round $r: $name $c done" >&2
    done
  done
done
for sc in $SCENES; do name=${sc%%:*}; $NEW $name-ref.prm > $name-ref.log 2>&1; done
/usr/bin/python3 - "$CONFIGS" "$REPO" <<'PY'
import csv, os, statistics as st, sys
import numpy as np
sys.path.insert(0, os.path.join(sys.argv[2], "tools"))
from granhydro_output import find_output_file  # <Base name>_profiles.csv, or profiles.csv (older builds)
rows = list(csv.DictReader(open("results.csv")))
def last_block(f, col):
    lines = [l.strip().split(",") for l in open(f) if not l.startswith("#")]
    hdr, data = lines[0], [r for r in lines[1:] if r and r[0] != lines[0][0]]
    a = np.array([[float(x) for x in r] for r in data])
    j = [i for i, h in enumerate(hdr) if h.startswith(col)][0]
    return a[a[:, 0] == a[-1, 0], j]
print("scene  config  diffusion_s convection_s diffusion/convection  steps newton gmres rkl2_stages  err_phi  err_T  (medians of %d)" % len({r['round'] for r in rows}))
for sc in ["bb", "bed1d", "hv"]:
    for c in sys.argv[1].split():
        rr = [r for r in rows if r["scene"] == sc and r["config"] == c]
        d = st.median(float(r["diffusion"]) for r in rr); cv = st.median(float(r["convection"]) for r in rr)
        e = []
        for col in ["packing_fraction", "temperature"]:  # a prefix: older runs' temperature_J too
            ref = last_block(find_output_file("out-%s-ref" % sc, "profiles"), col)
            x = last_block(find_output_file("out-%s-%s" % (sc, c), "profiles"), col)
            e.append(np.abs(x - ref).max() / np.abs(ref).max())
        print("%-6s %-7s %10.3f %11.3f %12.2f %13s %6s %6s %6s %9.2e %8.2e" % (sc, c, d, cv, d / cv, rr[0]["steps"], rr[0]["newton"], rr[0]["gmres"], rr[0]["rkl2_stages"] or "-", e[0], e[1]))
PY
