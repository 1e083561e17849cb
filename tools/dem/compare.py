#!/usr/bin/python3
"""Compare a granhydro output directory against a DEM ensemble of the same scene.

  /usr/bin/python3 tools/dem/compare.py --scene SCENE.prm --model GRANHYDRO_OUTPUT_DIR
      --dem DEM_DIR --out DIR [--base NAME] [--phase-bins K --skip-time T0]
      [--front-threshold 0.05] [--pile-threshold 0.5] [--gap-threshold 0.05]
      [--t-min-phi 1e-3] [--t-min-grains 2]

GRANHYDRO_OUTPUT_DIR holds the run's <Base name>_profiles.csv (and <Base name>_summary.csv
for the wall time; profiles.csv and summary.csv in older output folders); it may also be
the profiles CSV file itself. When several runs share the directory, --base NAME picks
one (default: the only one there, else the scene's Output/Base name). DEM_DIR
is run_ensemble.py's --out (dem_profiles.csv, ensemble.json). The profile bins must
be the same (the DEM takes them from the scene). Time mode (default): each
granhydro output time is matched with the DEM snapshot time (same Output/Interval
by default). Phase mode (--phase-bins K, DEM run with the same option): granhydro's
output blocks from --skip-time on are averaged per phase bin like the DEM snapshots.

Per time or phase, over the bins:
  D_phi  = sum |phi_model - phi_DEM| / sum phi_DEM
  D_flux = sum |nu_model - nu_DEM| / sum |nu_DEM|   (number flux along the profile direction)
  D_T    = sum |T_model - T_DEM| / sum T_DEM         (bins where the DEM has T, phi_DEM >= --t-min-phi
                                                     and >= --t-min-grains grains per snapshot)
and each D's DEM noise floor, sum SE_DEM / sum |DEM| (what the ensemble error alone contributes).
Features, for both: front height (the highest point where phi crosses --front-threshold
coming down from the top, linear between bin centres), floor phi (the bin at the floor, the
end gravity points to), pile height (contiguous bins from the floor with phi > --pile-threshold,
times the bin height), gap (contiguous bins from the floor with phi < --gap-threshold).

Writes DIR/compare.csv (one row per time or phase), DIR/compare.png (phi, flux, T against
height: granhydro solid, DEM dashed with a +-2 SE band) and DIR/report.txt.
"""

import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "granhydro_py"))  # tools/granhydro_py: import granhydro
import coarse_grain  # noqa: E402
from granhydro.output import (OutputFileError, SeveralRunsError, add_base_option, base_of,  # noqa: E402
                              find_output_file)
from granhydro.readers import blocks, read_profiles, read_summary  # noqa: E402
from scene import AXES, Scene  # noqa: E402


def model_files(model, base, scene_base):
    """(profiles CSV, summary CSV or None) of the granhydro run in MODEL (an output
    directory or the profiles CSV itself). Without BASE, several runs in the directory
    are resolved by the scene's Output/Base name SCENE_BASE when it is one of them."""
    try:
        try:
            prof = find_output_file(model, "profiles", base)
        except SeveralRunsError:
            if base is not None or not os.path.isfile(os.path.join(model, scene_base + "_profiles.csv")):
                raise
            prof = find_output_file(model, "profiles", scene_base)
    except OutputFileError as e:
        raise SystemExit("compare: %s" % e)
    try:  # the summary of the same run (the same base name, or summary.csv of an older run)
        summ = find_output_file(os.path.dirname(prof) or ".", "summary", base_of(prof), required=False)
    except OutputFileError:
        summ = None
    return prof, summ


def features(h, phi, floor, dh, front_thr, pile_thr, gap_thr):
    order = np.argsort(h)
    h, phi = h[order], phi[order]
    # front: from the top (away from the floor) down to the first phi >= thr
    hh, pp = (h[::-1], phi[::-1]) if floor < 0 else (h, phi)
    front = np.nan
    for i in range(len(pp)):
        if pp[i] >= front_thr:
            if i == 0:
                front = hh[0]
            else:
                s = (front_thr - pp[i - 1]) / (pp[i] - pp[i - 1])
                front = hh[i - 1] + s * (hh[i] - hh[i - 1])
            break
    fp = phi if floor < 0 else phi[::-1]
    base = h[0] - 0.5 * dh if floor < 0 else h[-1] + 0.5 * dh
    front_height = abs(front - base) if np.isfinite(front) else np.nan

    def run(mask):
        k = 0
        while k < len(mask) and mask[k]:
            k += 1
        return k * dh

    return {"front_height_m": front_height, "floor_phi": fp[0], "pile_height_m": run(fp > pile_thr),
            "gap_m": run(fp < gap_thr)}


def t_mask(d, a):
    """Bins where the DEM temperature is used: defined, phi >= --t-min-phi and at least
    --t-min-grains grains per snapshot (a bin holding k grains underestimates T by
    about (k - 1)/k: the fluctuation is taken about the bin's own mean velocity)."""
    return np.isfinite(d["temperature"]) & (d["packing_fraction"] >= a.t_min_phi) & (d["grains_in_bin"] >= a.t_min_grains)


def rel_l1(model, dem, absval=False):
    den = np.sum(np.abs(dem)) if absval else np.sum(dem)
    return float(np.sum(np.abs(model - dem)) / den) if den > 0 else np.nan


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", required=True)
    p.add_argument("--model", required=True, help="granhydro output directory (or its profiles CSV file)")
    add_base_option(p)
    p.add_argument("--dem", required=True, help="run_ensemble.py output directory")
    p.add_argument("--out", required=True)
    p.add_argument("--phase-bins", type=int, default=0)
    p.add_argument("--skip-time", type=float, default=0.0)
    p.add_argument("--front-threshold", type=float, default=0.05)
    p.add_argument("--pile-threshold", type=float, default=0.5)
    p.add_argument("--gap-threshold", type=float, default=0.05)
    p.add_argument("--t-min-phi", type=float, default=1e-3)
    p.add_argument("--t-min-grains", type=float, default=2.0)
    p.add_argument("--max-plot-keys", type=int, default=6)
    a = p.parse_args()
    rows, text = compare(a)
    print(text)
    return 0


def compare(a):
    sc = Scene(a.scene)
    pd = sc.profile_direction
    ax = AXES[pd]
    floor = sc.floor_side()
    dh = (sc.upper[pd] - sc.lower[pd]) / sc.cells[pd]
    prof_path, summ_path = model_files(a.model, getattr(a, "base", None), sc.output_base)
    model = blocks(*read_profiles(prof_path))  # {time: {column: array}}
    keycol, dem = coarse_grain.read_csv(os.path.join(a.dem, "dem_profiles.csv"))
    if (keycol == "phase") != bool(a.phase_bins):
        raise SystemExit("compare: the DEM profiles are by %s; use %s--phase-bins" % (keycol, "" if keycol == "phase" else "no "))
    hcol, fcol = ax, "number_flux_%s" % ax  # names of now also for older files (read_profiles, read_csv)
    # model blocks per key
    mk = {}
    if a.phase_bins:
        acc = {}
        for t, b in model.items():
            if t < a.skip_time - 1e-12:
                continue
            j = int(np.floor(((t * sc.vib_frequency) % 1.0) * a.phase_bins + 0.5)) % a.phase_bins
            acc.setdefault(j / a.phase_bins, []).append(b)
        for k, bl in acc.items():
            mk[k] = {c: np.mean([b[c] for b in bl], axis=0) for c in bl[0]}
            mk[k]["_blocks"] = len(bl)
    else:
        mk = model
    dkeys = np.array(sorted(dem))
    tol = 1e-9 + 1e-6 * (dkeys[1] - dkeys[0] if len(dkeys) > 1 else 1.0)
    rows = []
    pairs = []
    for k in sorted(mk):
        j = np.argmin(np.abs(dkeys - k)) if len(dkeys) else None
        if j is None or abs(dkeys[j] - k) > tol:
            continue
        m, d = mk[k], dem[float(dkeys[j])]
        if len(m[hcol]) != len(d[hcol]) or np.max(np.abs(m[hcol] - d[hcol])) > 1e-9 * dh + 1e-12:
            raise SystemExit("compare: the model's and the DEM's bins differ (same scene and cells?)")
        tm = t_mask(d, a)
        r = {keycol: k,
             "D_phi": rel_l1(m["packing_fraction"], d["packing_fraction"]),
             "D_flux": rel_l1(m[fcol], d[fcol], absval=True),
             "D_T": rel_l1(m["temperature"][tm], d["temperature"][tm]),
             "noise_phi": float(np.nansum(d["packing_fraction_se"]) / np.sum(d["packing_fraction"])),
             "noise_flux": float(np.nansum(d[fcol + "_se"]) / np.sum(np.abs(d[fcol]))) if np.sum(np.abs(d[fcol])) > 0 else np.nan,
             "noise_T": float(np.nansum(d["temperature_se"][tm]) / np.sum(d["temperature"][tm])) if tm.any() else np.nan,
             "T_bins": int(tm.sum())}
        for who, prof in (("model", m), ("dem", d)):
            for fk, fv in features(prof[hcol], prof["packing_fraction"], floor, dh, a.front_threshold,
                                   a.pile_threshold, a.gap_threshold).items():
                r["%s_%s" % (who, fk)] = fv
        rows.append(r)
        pairs.append((k, m, d))
    if not rows:
        raise SystemExit("compare: no common output time/phase between the model and the DEM")
    os.makedirs(a.out, exist_ok=True)
    cols = list(rows[0].keys())
    with open(os.path.join(a.out, "compare.csv"), "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join("%.8g" % r[c] for c in cols) + "\n")
    try:
        plot(os.path.join(a.out, "compare.png"), pairs, keycol, hcol, fcol, a, sc)
        plotted = "compare.png written"
    except ImportError:
        plotted = "compare.png not written: matplotlib is missing (apt-get install python3-matplotlib)"
    # report
    summ = read_summary(summ_path) if summ_path else {}
    ens = {}
    if os.path.exists(os.path.join(a.dem, "ensemble.json")):
        ens = json.load(open(os.path.join(a.dem, "ensemble.json")))
    dem_comments = [l[2:].rstrip() for l in open(os.path.join(a.dem, "dem_profiles.csv")) if l.startswith("#")]
    L = ["DEM cross-check of %s" % a.scene]
    L += ["  " + c for c in dem_comments]
    if summ:
        L.append("granhydro: %s cells, %s steps, wall %.2f s (status %s)" % (summ.get("cells"), summ.get("steps"),
                                                                             float(summ.get("wall_seconds", "nan")), summ.get("status")))
    if ens:
        g = ens["seeds"]
        L.append("DEM: %d seeds x %d grains x %d steps, LIGGGHTS wall %.2f s (%.2f s per seed, %.0f steps/s, %.3g grain-steps/s)"
                 % (len(g), g[0]["grains"], g[0]["steps"], ens["total_liggghts_wall_s"], ens["total_liggghts_wall_s"] / len(g),
                    np.mean([x["steps_per_s"] for x in g]), np.mean([x["grain_steps_per_s"] for x in g])))
    L.append("")
    L.append("%-8s %7s %7s %7s   %7s %7s %7s   %-23s %-23s %-21s %-21s"
             % (keycol, "D_phi", "D_flux", "D_T", "n_phi", "n_flux", "n_T", "front [mm] model/DEM",
                "floor phi model/DEM", "pile [mm] model/DEM", "gap [mm] model/DEM"))
    for r in rows:
        L.append("%-8.4g %7.3f %7.3f %7.3f   %7.3f %7.3f %7.3f   %8.2f / %-8.2f      %6.3f / %-6.3f        %6.1f / %-6.1f      %6.1f / %-6.1f"
                 % (r[keycol], r["D_phi"], r["D_flux"], r["D_T"], r["noise_phi"], r["noise_flux"], r["noise_T"],
                    1e3 * r["model_front_height_m"], 1e3 * r["dem_front_height_m"], r["model_floor_phi"], r["dem_floor_phi"],
                    1e3 * r["model_pile_height_m"], 1e3 * r["dem_pile_height_m"], 1e3 * r["model_gap_m"], 1e3 * r["dem_gap_m"]))
    L.append(plotted)
    L.append("(D = sum|model - DEM| / sum|DEM| over the bins; n_* = the DEM's noise floor sum SE / sum|DEM|;"
             " front at phi = %g, pile phi > %g, gap phi < %g)" % (a.front_threshold, a.pile_threshold, a.gap_threshold))
    text = "\n".join(L)
    with open(os.path.join(a.out, "report.txt"), "w") as f:
        f.write(text + "\n")
    return rows, text


def plot(path, pairs, keycol, hcol, fcol, a_opts, sc):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    maxk = a_opts.max_plot_keys
    idx = np.unique(np.linspace(0, len(pairs) - 1, min(maxk, len(pairs))).round().astype(int))
    fig, axs = plt.subplots(1, 3, figsize=(14, 5), sharey=True)
    cmap = plt.get_cmap("viridis")
    qs = [("packing_fraction", "packing fraction"), (fcol, "number flux n u_%s [1/(m^2 s)]" % fcol[-1]),
          ("temperature", "temperature [J]")]
    for n, i in enumerate(idx):
        k, m, d = pairs[i]
        c = cmap(n / max(1, len(idx) - 1))
        lab = ("t = %.4g s" % k) if keycol == "time" else ("phase %.3g" % k)
        for a, (q, name) in zip(axs, qs):
            h = m[hcol] * 1e3
            a.plot(m[q], h, "-", color=c, label=lab + " granhydro")
            se = np.nan_to_num(d[q + "_se"])
            y = d[q].copy()
            if q == "temperature":
                y[~t_mask(d, a_opts)] = np.nan
            a.plot(y, h, "--", color=c, label=lab + " DEM")
            a.fill_betweenx(h, y - 2 * se, y + 2 * se, color=c, alpha=0.25, lw=0)
            a.set_xlabel(name)
    axs[2].set_xscale("log")
    axs[0].set_ylabel(hcol + " [mm]")
    axs[0].legend(fontsize=6)
    fig.suptitle("%s: granhydro (solid) vs DEM ensemble (dashed, band +-2 SE)" % os.path.basename(sc.path))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
