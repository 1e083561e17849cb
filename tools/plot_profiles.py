#!/usr/bin/python3
"""Plot the profiles CSV of a granhydro run (OUTPUT_DIR/<Base name>_profiles.csv,
profiles.csv in older output folders): packing fraction, temperature,
vertical mass flux and the energy density split into its thermal (3/2 n T, solid),
contact (n w of the dense closure, dashed) and kinetic (n m |u|^2/2, dotted) parts
against the profile coordinate, one colour per output time.  Files written before
the split (one n*E_J/m3 column, read as total_energy_density) get the total energy
density in that panel. Older runs' column names (units in the names) are read as the
names of now (granhydro.readers.column_name).
Debian: apt-get install python3-matplotlib python3-numpy

    /usr/bin/python3 tools/plot_profiles.py OUTPUT_DIR [--base NAME] [--out profiles.png] [--spacetime] [--title T]

OUTPUT_DIR may also be the CSV file itself; --base picks a run when several share the
directory. The figure goes to OUTPUT_DIR/<Base name>_profiles.png (profiles.png for an
older folder) unless --out is given.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import OutputFileError, SeveralRunsError, add_base_option, find_output_file  # noqa: E402
from granhydro.readers import read_profiles  # noqa: E402


def read(path):
    """(header, {time: [row (list of floats) per layer]}) of a profiles CSV"""
    columns, _ = read_profiles(path)
    header = list(columns)
    blocks = {}
    for r in zip(*(columns[h].tolist() for h in header)):
        blocks.setdefault(r[0], []).append(list(r))
    return header, blocks


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("directory", help="the scene's Output/Directory (or its profiles CSV file)")
    add_base_option(p)
    p.add_argument("--out", default=None,
                   help="PNG file (default: the CSV's name with .png, DIRECTORY/<Base name>_profiles.png)")
    p.add_argument("--spacetime", action="store_true",
                   help="draw packing fraction and temperature as maps over (time, coordinate) "
                        "instead of one curve per output time (many outputs, e.g. a vibrated bed)")
    p.add_argument("--title", default=None, help="figure title (default: the directory)")
    a = p.parse_args()
    try:
        path = find_output_file(a.directory, "profiles", a.base)
    except OutputFileError as e:
        sys.exit(f"plot_profiles: {e}" + ("" if isinstance(e, SeveralRunsError) else " (run with 'Output/Write profiles = true')"))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    default_out = os.path.splitext(path)[0] + ".png"
    header, blocks = read(path)
    col = {h: i for i, h in enumerate(header)}
    coord = header[1]
    # the number flux along the profile direction (coordinate column "y" -> "number_flux_y")
    along = [h for h in header if h == "number_flux_" + coord]
    flux = along[0] if along else [h for h in header if h.startswith("number_flux_")][-1]
    panels = [("packing_fraction", "packing fraction"), ("temperature", "T [J]"),
              (flux, "n u_%s [1/(m^2 s)]" % flux[-1])]
    # the energy panel: (column, legend label, line style)
    energy = [(c, label, style) for c, label, style in (
        ("thermal_energy_density", "thermal 3/2 n T", "-"),
        ("contact_energy_density", "contact n w", "--"),
        ("kinetic_energy_density", "kinetic n m |u|^2/2", ":")) if c in col]
    if not energy:  # the profiles of an older run: only the total
        energy = [("total_energy_density", "total nE", "-")]
    if a.spacetime:
        import numpy as np
        times = sorted(t for t, rows in blocks.items() if len(rows) == len(blocks[min(blocks)]))
        y = [r[1] for r in blocks[times[0]]]
        fig, axes = plt.subplots(2, 1, figsize=(12, 7), sharex=True)
        for ax, (name, label), log in zip(axes, panels[:2], (False, True)):
            z = np.array([[r[col[name]] for r in blocks[t]] for t in times]).T
            if log:
                z = np.log10(np.maximum(z, 1e-30))
                label = "log10 " + label
            m = ax.pcolormesh(times, y, z, shading="nearest", cmap="viridis")
            fig.colorbar(m, ax=ax, label=label)
            ax.set_ylabel(coord + " [m]")
        axes[1].set_xlabel("time [s]")
        fig.suptitle(a.title or os.path.abspath(a.directory))
        fig.tight_layout()
        out = a.out or default_out
        fig.savefig(out, dpi=110)
        print(f"plot_profiles: wrote {out}")
        return
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.5), sharey=True)
    # one colour per output time in every panel; beyond 12 times a colour scale over
    # time (with a colour bar) instead of a legend that would not fit
    n_times = len(blocks)
    many = n_times > 12
    t_lo, t_hi = min(blocks), max(blocks)
    for i, (t, rows) in enumerate(sorted(blocks.items())):
        y = [r[1] for r in rows]
        colour = plt.cm.viridis((t - t_lo) / max(t_hi - t_lo, 1e-300)) if many else f"C{i % 10}"
        for ax, (name, label) in zip(axes, panels):
            ax.plot([r[col[name]] for r in rows], y, color=colour, label=f"t = {t:g} s")
            ax.set_xlabel(label)
        for name, label, style in energy:
            axes[3].plot([r[col[name]] for r in rows], y, color=colour, linestyle=style)
    axes[1].set_xscale("log")
    # the parts span decades (and the contact energy is 0 away from the pile: not drawn);
    # six decades below the largest value are enough to see which part dominates where
    axes[3].set_xscale("log")
    top = max((r[col[name]] for rows in blocks.values() for r in rows for name, _, _ in energy), default=0)
    if top > 0:
        axes[3].set_xlim(left=1e-6 * top)
    axes[3].set_xlabel("energy density [J/m^3]")
    axes[3].legend(handles=[plt.Line2D([], [], color="k", linestyle=style, label=label)
                            for _, label, style in energy], fontsize=7)
    axes[0].set_ylabel(coord + " [m]")
    fig.suptitle(a.title or os.path.abspath(a.directory))
    fig.tight_layout()
    if many:
        sm = plt.cm.ScalarMappable(cmap="viridis", norm=plt.Normalize(t_lo, t_hi))
        fig.colorbar(sm, ax=list(axes), label="time [s]", fraction=0.02, pad=0.01)
    else:
        axes[0].legend(fontsize=7)
    out = a.out or default_out
    fig.savefig(out, dpi=110, bbox_inches="tight")  # the colour bar's label inside the picture
    print(f"plot_profiles: wrote {out}")


if __name__ == "__main__":
    main()
