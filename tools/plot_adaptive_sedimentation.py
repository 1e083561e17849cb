#!/usr/bin/python3
"""Packing fraction of the sedimentation column, uniform vs adaptive mesh, against the DEM.

  /usr/bin/python3 tools/plot_adaptive_sedimentation.py UNIFORM_OUT ADAPTIVE_OUT DEM_PROFILES_CSV OUT.png

UNIFORM_OUT, ADAPTIVE_OUT: granhydro output folders of parameters/sedimentation.prm as a
column (profiles along y); DEM_PROFILES_CSV: doc/validation/sedimentation_column/dem/
dem_profiles.csv (the same scene, binned along x). Plots phi against height at 50, 100
and 150 ms (doc/performance.md, 'Adaptive sedimentation').
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def granhydro(folder):
    prof = {}
    with open(folder + "/solution_profiles.csv") as f:
        for r in csv.DictReader(f):
            prof.setdefault(round(float(r["time"]), 4), []).append((float(r["y"]), float(r["packing_fraction"])))
    return prof


def dem(path):
    prof = {}
    with open(path) as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        for r in rows:
            prof.setdefault(round(float(r["time_s"]), 4), []).append((float(r["x_m"]), float(r["packing_fraction"])))
    return prof


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("uniform", help="granhydro output folder of the uniform column")
    ap.add_argument("adaptive", help="granhydro output folder of the adaptive column")
    ap.add_argument("dem", help="the DEM ensemble's dem_profiles.csv")
    ap.add_argument("png", help="the figure to write")
    a = ap.parse_args()
    uni, ada, ref = granhydro(a.uniform), granhydro(a.adaptive), dem(a.dem)
    fig, axes = plt.subplots(1, 3, figsize=(11, 4), sharey=True)
    for ax, t in zip(axes, (0.05, 0.1, 0.15)):
        for data, style, label in ((ref, "k.", "DEM (8 seeds)"), (uni, "b-", "uniform 4 x 100 x 4"),
                                   (ada, "r--", "adaptive, 1 level")):
            pts = sorted(data[t])
            ax.plot([p[1] for p in pts], [1e3 * p[0] for p in pts], style, label=label, ms=3)
        ax.set_title("t = %g ms" % (1e3 * t))
        ax.set_xlabel("packing fraction")
    axes[0].set_ylabel("height [mm]")
    axes[0].legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
