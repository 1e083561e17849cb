#!/usr/bin/python3
"""Plot the inclined-chute cross section (OUTPUT_DIR/<Base name>_cross_section.csv,
cross_section.csv in older output folders; averages along the flow
direction x) at the last output time: the down-slope velocity u_x(y, z) across the
channel (paper fig. 8) and the packing fraction phi(y) across the channel at a few
heights (paper fig. 7), plus phi(z) and u_x(z) on the centreline.
Debian: apt-get install python3-matplotlib python3-numpy

    /usr/bin/python3 tools/plot_chute.py OUTPUT_DIR [--base NAME] [--out chute.png]

OUTPUT_DIR may also be the CSV file itself; --base picks a run when several share the
directory. The figure goes to OUTPUT_DIR/<Base name>_chute.png (chute.png for an older
folder) unless --out is given.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import OutputFileError, SeveralRunsError, add_base_option, find_output_file  # noqa: E402
from granhydro.readers import read_cross_section, select_time  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("directory", help="the scene's Output/Directory (or its cross-section CSV file)")
    add_base_option(p)
    p.add_argument("--out", default=None, help="PNG file (default: DIRECTORY/<Base name>_chute.png)")
    a = p.parse_args()
    try:
        path = find_output_file(a.directory, "cross_section", a.base)
    except OutputFileError as e:
        sys.exit(f"plot_chute: {e}" + ("" if isinstance(e, SeveralRunsError) else " (set 'Output/Cross-section direction = x')"))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    columns, times = read_cross_section(path)
    t_last = times[-1]
    d = select_time(columns, t_last)
    across = list(columns)[1:3]  # the two coordinates of the section, the first fastest
    y, z = np.unique(d[across[0]]), np.unique(d[across[1]])
    grid = lambda name: d[name].reshape(len(z), len(y))
    ux, phi = grid("velocity_x"), grid("packing_fraction")
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    c = ax[0].contourf(y * 1e3, z * 1e3, ux, 20, cmap="viridis")
    fig.colorbar(c, ax=ax[0], label="u_x [m/s]")
    ax[0].set_xlabel("y [mm] (across)")
    ax[0].set_ylabel("z [mm] (normal to the base)")
    ax[0].set_title(f"down-slope velocity, t = {t_last:g} s")
    for k in np.linspace(0, len(z) - 1, 4).astype(int):
        ax[1].plot(y * 1e3, phi[k], label=f"z = {z[k] * 1e3:.1f} mm")
    ax[1].set_xlabel("y [mm]")
    ax[1].set_ylabel("packing fraction")
    ax[1].legend(fontsize=7)
    mid = len(y) // 2
    ax[2].plot(phi[:, mid], z * 1e3, label="phi")
    ax2 = ax[2].twiny()
    ax2.plot(ux[:, mid], z * 1e3, "r--", label="u_x")
    ax[2].set_xlabel("packing fraction (centreline)")
    ax2.set_xlabel("u_x [m/s] (dashed)")
    ax[2].set_ylabel("z [mm]")
    fig.tight_layout()
    # <Base name>_cross_section.csv -> <Base name>_chute.png (cross_section.csv -> chute.png)
    stem = path[:-len("cross_section.csv")] if path.endswith("cross_section.csv") else os.path.splitext(path)[0] + "_"
    out = a.out or stem + "chute.png"
    fig.savefig(out, dpi=110)
    print(f"plot_chute: wrote {out}")


if __name__ == "__main__":
    main()
