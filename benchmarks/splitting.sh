#!/bin/bash
# Cost and accuracy of the merged Strang splitting (Numerics/Strang splitting) and of
# MUSTA's first-stage test (Numerics/MUSTA minimum stages = 1, config merged1), before/after.
#
#   benchmarks/splitting.sh OLD_DIR [ROUNDS]
#
# OLD_DIR holds an earlier build (its granhydro and libgranhydro_core.so, run with
# LD_LIBRARY_PATH=OLD_DIR); the new one is build/granhydro, run with `symmetric` and
# `merged` splitting, and merged with `MUSTA minimum stages = 1` (merged1). Each round runs every scene with each configuration, one process at
# a time, interleaved, so that a noisy shared machine hits all of them alike. Writes
# bench-splitting/results.csv and prints the medians of the summary timers, and the
# largest difference of the final phi and T profiles to a reference run (symmetric,
# fixed GMRES tolerance, time step capped ~10x below the CFL step; for the sedimentation
# column, where that costs too much, to the new symmetric run), relative to max|ref|.
set -e
OLD=$(cd "$1" && pwd); ROUNDS=${2:-3}
REPO=$(cd "$(dirname "$0")/.." && pwd); NEW=$REPO/build/granhydro
OUT=$PWD/bench-splitting; mkdir -p $OUT; cd $OUT
mk() { # scene-file tag extra-lines
  # the scene included, the changes after it (a scene file sets each parameter once; it may
  # override what it includes)
  printf "include %s\n" "$1" > $2.prm
  printf "subsection Output\n  set Directory = $OUT/out-$2\n  set Write VTU = false\nend\n$3\n" >> $2.prm
}
SCENES="bb:$REPO/parameters/bouncing_bed-ci.prm:1e-4 bed1d:$REPO/parameters/vibrated_bed_1d.prm:4e-5 hv:$REPO/parameters/hard/harsh_vibration-ci.prm:4e-5 sed:$REPO/parameters/sedimentation.prm:0"
CONFIGS="old symmetric merged merged1"
for sc in $SCENES; do
  IFS=: read name f dt <<< "$sc"
  extra=""
  # the sedimentation column: laterally 2 x 2 cells (laterally uniform), to 100 ms
  [ $name = sed ] && extra="subsection Domain\n  set Upper corner = 0.004, 0.1, 0.004\n  set Cells = 2, 100, 2\nend\nsubsection Time\n  set End time = 0.1\nend"
  mk $f $name-old "$extra"
  mk $f $name-symmetric "$extra\nsubsection Numerics\n  set Strang splitting = symmetric\nend"
  mk $f $name-merged "$extra\nsubsection Numerics\n  set Strang splitting = merged\nend"
  mk $f $name-merged1 "$extra\nsubsection Numerics\n  set Strang splitting = merged\n  set MUSTA minimum stages = 1\nend"
  [ $dt != 0 ] && mk $f $name-ref "$extra\nsubsection Numerics\n  set Strang splitting = symmetric\n  set Fixed time step = $dt\nend\nsubsection Diffusion step\n  set Linear forcing = fixed\n  set Reuse Newton matrix = false\nend"
done
echo "scene,config,round,wall,convection,diffusion,steps,newton,musta_stages" > results.csv
for r in $(seq $ROUNDS); do
  for sc in $SCENES; do
    name=${sc%%:*}
    for c in $CONFIGS; do
      if [ $c = old ]; then LD_LIBRARY_PATH=$OLD $OLD/granhydro $name-$c.prm > $name-$c.log 2>&1
      else $NEW $name-$c.prm > $name-$c.log 2>&1; fi
      s=$(ls out-$name-$c/*_summary.csv)
      g() { grep "^$1," $s | cut -d, -f2; }
      echo "$name,$c,$r,$(g wall_seconds),$(g convection_seconds),$(g diffusion_seconds),$(g steps),$(g newton_iterations),$(awk -F, '/^musta_stages,/{s=$2}/^flux_points,/{p=$2}END{printf "%.3f", s/p}' $s)" >> results.csv
      echo "round $r: $name $c done" >&2
    done
  done
done
for sc in $SCENES; do name=${sc%%:*}; [ -f $name-ref.prm ] && $NEW $name-ref.prm > $name-ref.log 2>&1; done
/usr/bin/python3 - "$CONFIGS" "$REPO" <<'PY'
import csv, os, statistics as st, sys
import numpy as np
sys.path.insert(0, os.path.join(sys.argv[2], "tools"))
from granhydro_output import find_output_file
rows = list(csv.DictReader(open("results.csv")))
def last_block(f, col):
    lines = [l.strip().split(",") for l in open(f)]
    hdr, data = lines[0], [r for r in lines[1:] if r and r[0] != lines[0][0]]
    a = np.array([[float(x) for x in r] for r in data])
    j = [i for i, h in enumerate(hdr) if h.startswith(col)][0]
    return a[a[:, 0] == a[-1, 0], j]
print("scene  config     wall_s  convection_s diffusion_s diff/conv  steps  newton  musta/pt   err_phi   err_T  (medians of %d; error vs %s)"
      % (len({r['round'] for r in rows}), "reference"))
for sc in ["bb", "bed1d", "hv", "sed"]:
    refdir = "out-%s-ref" % sc if os.path.isdir("out-%s-ref" % sc) else "out-%s-symmetric" % sc
    for c in sys.argv[1].split():
        rr = [r for r in rows if r["scene"] == sc and r["config"] == c]
        med = lambda k: st.median(float(r[k]) for r in rr)
        e = []
        for col in ["packing_fraction", "temperature"]:  # a prefix: older runs' temperature_J too
            ref = last_block(find_output_file(refdir, "profiles"), col)
            x = last_block(find_output_file("out-%s-%s" % (sc, c), "profiles"), col)
            e.append(np.abs(x - ref).max() / np.abs(ref).max())
        print("%-6s %-9s %8.2f %11.2f %11.2f %9.2f %6s %7s %8s %9.2e %8.2e%s" % (sc, c, med("wall"), med("convection"), med("diffusion"),
              med("diffusion") / med("convection"), rr[0]["steps"], rr[0]["newton"], rr[0]["musta_stages"], e[0], e[1],
              "" if refdir.endswith("ref") else "  (vs symmetric)"))
PY
