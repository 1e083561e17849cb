#!/bin/bash
# The Newton matrix and its preconditioner, Trilinos (Epetra + Ifpack ILU(0)) against
# granhydro's block-sparse matrix with block ILU(0) (Diffusion step/Preconditioner =
# ilu | block ilu), side by side in one binary:
#
#   benchmarks/linear_algebra.sh [ROUNDS] [MEMORY_STEPS]
#
# 1. time: three stiff granular scenes (bouncing_bed-ci, vibrated_bed_1d,
#    harsh_vibration-ci) under Gauss-Legendre and SDIRK2 with either preconditioner,
#    ROUNDS rounds (default 3), one process at a time, interleaved; medians of the
#    diffusion step's wall time and of its parts (<Base name>_summary.csv), and the largest
#    difference of the final profiles between the two preconditioners (both stop GMRES
#    at the same tolerance, so they agree to the Newton tolerance, not bit for bit);
# 2. memory: the paper's sedimentation (50 x 100 x 50 cells) for MEMORY_STEPS steps
#    (default 2) per configuration: peak resident memory per cell (<Base name>_summary.csv;
#    summary.csv of a build before the base name prefix).
# Writes bench-linear-algebra/results.csv and prints the tables.
set -e
ROUNDS=${1:-3}; MSTEPS=${2:-2}
REPO=$(cd "$(dirname "$0")/.." && pwd); BIN=$REPO/build/granhydro
OUT=$PWD/bench-linear-algebra; mkdir -p $OUT; cd $OUT
mk() { # scene-file tag integrator preconditioner [extra lines]
  # the scene included, the changes after it (a scene file sets each parameter once; it may
  # override what it includes)
  printf "include %s\n" "$1" > $2.prm
  printf "subsection Output\n  set Directory = $OUT/out-$2\n  set Write VTU = false\nend\n" >> $2.prm
  printf "subsection Diffusion step\n  set Integrator = $3\n  set Preconditioner = $4\nend\n$5" >> $2.prm
}
summary_csv() { # the summary of the run in directory $1: <Base name>_summary.csv, or summary.csv (older builds)
  local f; for f in "$1"/*_summary.csv; do [ -f "$f" ] && { echo "$f"; return; }; done; echo "$1/summary.csv"
}
SCENES="bb:$REPO/parameters/bouncing_bed-ci.prm bed1d:$REPO/parameters/vibrated_bed_1d.prm hv:$REPO/parameters/hard/harsh_vibration-ci.prm"
CONFIGS="gl:gauss-legendre:ilu gl-block:gauss-legendre:block%ilu sdirk2:sdirk2:ilu sdirk2-block:sdirk2:block%ilu"
for sc in $SCENES; do
  IFS=: read name f <<< "$sc"
  for c in $CONFIGS; do
    IFS=: read tag integ pc <<< "$c"
    mk $f $name-$tag $integ "${pc/\%/ }"
  done
done
g() { grep "^$2," $1 | cut -d, -f2; }
echo "scene,config,round,diffusion,jacobian,preconditioner,gmres,newton,gmres_its,peak_bytes,cells" > results.csv
for r in $(seq $ROUNDS); do
  for sc in $SCENES; do
    name=${sc%%:*}
    for c in $CONFIGS; do
      tag=${c%%:*}
      $BIN $name-$tag.prm > $name-$tag.log 2>&1
      s=$(summary_csv out-$name-$tag)
      echo "$name,$tag,$r,$(g $s diffusion_seconds),$(g $s jacobian_seconds),$(g $s preconditioner_seconds),$(g $s gmres_seconds),$(g $s newton_iterations),$(g $s gmres_iterations),$(g $s peak_memory_bytes_all_ranks),$(g $s cells)" >> results.csv
      echo "round $r: $name $tag done" >&2
    done
  done
done
echo "config,peak_bytes,cells,diffusion" > memory.csv
for c in $CONFIGS; do
  IFS=: read tag integ pc <<< "$c"
  mk $REPO/parameters/sedimentation.prm sed-$tag $integ "${pc/\%/ }" "subsection Time\n  set Maximum steps = $MSTEPS\nend\n"
  $BIN sed-$tag.prm > sed-$tag.log 2>&1
  s=$(summary_csv out-sed-$tag)
  echo "$tag,$(g $s peak_memory_bytes_all_ranks),$(g $s cells),$(g $s diffusion_seconds)" >> memory.csv
  echo "memory: $tag done" >&2
done
/usr/bin/python3 - "$CONFIGS" "$REPO" <<'PY'
import csv, os, statistics as st, sys
import numpy as np
sys.path.insert(0, os.path.join(sys.argv[2], "tools"))
from granhydro_output import find_output_file  # <Base name>_profiles.csv, or profiles.csv (older builds)
rows = list(csv.DictReader(open("results.csv")))
tags = [c.split(":")[0] for c in sys.argv[1].split()]
def last_block(f, col):
    lines = [l.strip().split(",") for l in open(f) if not l.startswith("#")]
    hdr, data = lines[0], [r for r in lines[1:] if r and r[0] != lines[0][0]]
    a = np.array([[float(x) for x in r] for r in data])
    j = [i for i, h in enumerate(hdr) if h.startswith(col)][0]
    return a[a[:, 0] == a[-1, 0], j]
print("time (medians of %d rounds, seconds of the diffusion step and its parts, rank 0)" % len({r['round'] for r in rows}))
print("scene  config        diffusion  jacobian  precond   gmres  newton gmres_its  KiB/cell  ratio   max|dphi|/max  max|dT|/max")
for sc in ["bb", "bed1d", "hv"]:
    for t in tags:
        rr = [r for r in rows if r["scene"] == sc and r["config"] == t]
        m = lambda k: st.median(float(r[k]) for r in rr)
        ratio, dphi, dT = "", "", ""
        if t.endswith("-block"):
            base = [r for r in rows if r["scene"] == sc and r["config"] == t[:-6]]
            ratio = "%.2f" % (st.median(float(r["diffusion"]) for r in base) / m("diffusion"))
            e = []
            for col in ["packing_fraction", "temperature"]:  # a prefix: older runs' temperature_J too
                a = last_block(find_output_file("out-%s-%s" % (sc, t), "profiles"), col)
                b = last_block(find_output_file("out-%s-%s" % (sc, t[:-6]), "profiles"), col)
                e.append(np.abs(a - b).max() / np.abs(b).max())
            dphi, dT = "%.1e" % e[0], "%.1e" % e[1]
        print("%-6s %-13s %9.3f %9.3f %8.3f %7.3f %7s %9s %9.2f %6s %14s %12s" % (sc, t, m("diffusion"), m("jacobian"), m("preconditioner"), m("gmres"), rr[0]["newton"], rr[0]["gmres_its"], m("peak_bytes") / 1024 / float(rr[0]["cells"]), ratio, dphi, dT))
print("\nmemory: the paper sedimentation (%s cells), peak resident memory per cell" % next(csv.DictReader(open("memory.csv")))["cells"])
for r in csv.DictReader(open("memory.csv")):
    print("%-13s %8.2f KiB/cell  (diffusion step %.1f s)" % (r["config"], float(r["peak_bytes"]) / 1024 / float(r["cells"]), float(r["diffusion"])))
PY
