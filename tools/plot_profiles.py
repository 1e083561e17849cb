#!/usr/bin/python3
"""Plot output/profiles.csv of a granhydro run: packing fraction, temperature,
vertical mass flux and energy density against the profile coordinate, one curve
per output time.  Debian: apt-get install python3-matplotlib python3-numpy

    /usr/bin/python3 tools/plot_profiles.py OUTPUT_DIR [--out profiles.png]
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = [r for r in f if not r.startswith("#")]
    reader = csv.reader(rows)
    header = next(reader)
    blocks = {}
    for r in reader:
        if not r:
            continue
        blocks.setdefault(float(r[0]), []).append([float(v) for v in r])
    return header, blocks


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("directory", help="the scene's Output/Directory")
    p.add_argument("--out", default=None, help="PNG file (default DIRECTORY/profiles.png)")
    a = p.parse_args()
    path = os.path.join(a.directory, "profiles.csv")
    if not os.path.exists(path):
        sys.exit(f"plot_profiles: no {path} (run with 'Output/Write profiles = true')")
    header, blocks = read(path)
    col = {h: i for i, h in enumerate(header)}
    coord = header[1]
    # the mass flux along the profile direction (coordinate column "y_m" -> "n*u_y...")
    along = [h for h in header if h.startswith("n*u_" + coord[0])]
    flux = along[0] if along else [h for h in header if h.startswith("n*u_")][-1]
    panels = [("packing_fraction", "packing fraction"), ("temperature_J", "T [J]"),
              (flux, flux), ("n*E_J/m3", "nE [J/m^3]")]
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.5), sharey=True)
    for t, rows in sorted(blocks.items()):
        y = [r[1] for r in rows]
        for ax, (name, label) in zip(axes, panels):
            ax.plot([r[col[name]] for r in rows], y, label=f"t = {t:g} s")
            ax.set_xlabel(label)
    axes[1].set_xscale("log")
    axes[0].set_ylabel(coord)
    axes[0].legend(fontsize=7)
    fig.suptitle(os.path.abspath(a.directory))
    fig.tight_layout()
    out = a.out or os.path.join(a.directory, "profiles.png")
    fig.savefig(out, dpi=110)
    print(f"plot_profiles: wrote {out}")


if __name__ == "__main__":
    main()
