#!/usr/bin/python3
"""Does the DEM's finite contact stiffness matter? Run the ensemble at Young's modulus E
and at FACTOR x E (the default time step follows: dt = t_c/30, t_c ~ E^(-2/5)) with the
same seeds and compare the profiles against the ensemble error.

  /usr/bin/python3 tools/dem/stiffness_check.py SCENE.prm --out DIR [--factor 10]
      [--seeds N] [--reuse] [run_ensemble.py / make_input.py options]

DIR/base and DIR/stiff are two run_ensemble.py outputs (--reuse keeps existing ones).
For every output time (or phase) and for phi, the number flux along the profile
direction and T:
  change = sum_bins |stiff - base| / sum_bins |base|
  error  = sum_bins sqrt(SE_base^2 + SE_stiff^2) / sum_bins |base|
  chi2   = mean over the bins of (stiff - base)^2 / (SE_base^2 + SE_stiff^2)
(T over the bins where both have a temperature). For pure sampling noise between
independent ensembles change/error is about sqrt(2/pi) = 0.8 and chi2 about 1 (the same
seeds are used for both, so early on the two ensembles are correlated and both are
smaller). Verdict: PASS when chi2 <= 1 + 3 sqrt(2/bins) for every time and quantity,
i.e. the stiffer run changes the profiles by no more than the ensemble error (the rms
change in units of the combined standard error is not detectably above 1); the L1
ratio change/error is reported beside it. The table and the verdict go to stdout and
DIR/stiffness_check.txt; exit code 0 (pass) or 1 (fail).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import coarse_grain  # noqa: E402
import run_ensemble  # noqa: E402
from scene import AXES  # noqa: E402


def compare_ensembles(base_csv, stiff_csv, ax):
    kc, b = coarse_grain.read_csv(base_csv)
    _, s = coarse_grain.read_csv(stiff_csv)
    fcol = "number_flux_%s" % ax  # read_csv: the names of now, also for older files
    rows = []
    for k in sorted(set(b) & set(s)):
        r = {kc: k}
        for q, name in (("packing_fraction", "phi"), (fcol, "flux"), ("temperature", "T")):
            x, y = b[k][q], s[k][q]
            ex, ey = b[k][q + "_se"], s[k][q + "_se"]
            m = np.isfinite(x) & np.isfinite(y) & np.isfinite(ex) & np.isfinite(ey)
            den = np.sum(np.abs(x[m]))
            r["change_" + name] = np.sum(np.abs(y[m] - x[m])) / den if den > 0 else np.nan
            r["error_" + name] = np.sum(np.sqrt(ex[m] ** 2 + ey[m] ** 2)) / den if den > 0 else np.nan
            sig2 = ex[m] ** 2 + ey[m] ** 2
            g = sig2 > 0
            r["chi2_" + name] = np.mean((y[m][g] - x[m][g]) ** 2 / sig2[g]) if g.any() else np.nan
            r["dof_" + name] = int(g.sum())
        rows.append(r)
    return kc, rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene")
    p.add_argument("--out", required=True)
    p.add_argument("--factor", type=float, default=10.0)
    p.add_argument("--reuse", action="store_true")
    p.add_argument("--skip-first", action="store_true",
                   help="leave out the first time (t = 0: the same initial state in both, change 0)")
    run_ensemble.add_options(p)
    a = p.parse_args()
    if a.dt:
        raise SystemExit("stiffness_check: leave --dt to the default (t_c/30) so that it follows the stiffness")
    E0 = a.youngs
    for sub, E in (("base", E0), ("stiff", E0 * a.factor)):
        out = os.path.join(a.out, sub)
        if a.reuse and os.path.exists(os.path.join(out, "dem_profiles.csv")):
            continue
        b = argparse.Namespace(**vars(a))
        b.youngs, b.out = E, out
        print("== %s: E = %g Pa" % (sub, E))
        run_ensemble.run_ensemble(b)
    from scene import Scene
    ax = AXES[Scene(a.scene).profile_direction]
    kc, rows = compare_ensembles(os.path.join(a.out, "base", "dem_profiles.csv"),
                                 os.path.join(a.out, "stiff", "dem_profiles.csv"), ax)
    if a.skip_first and rows:
        rows = rows[1:]
    L = ["stiffness check of %s: E = %g Pa vs %g Pa (x %g), %d seeds each" % (a.scene, E0, E0 * a.factor, a.factor, a.seeds),
         "%-8s %22s %22s %22s" % (kc, "phi chg/err chi2", "flux chg/err chi2", "T chg/err chi2")]
    worst, worst_l1, ok = 0.0, 0.0, True
    for r in rows:
        L.append("%-8.4g " % r[kc] + " ".join("%7.4f/%-7.4f %5.2f" % (r["change_" + q], r["error_" + q], r["chi2_" + q])
                                             for q in ("phi", "flux", "T")))
        for q in ("phi", "flux", "T"):
            if r["dof_" + q] > 0 and np.isfinite(r["chi2_" + q]):
                lim = 1 + 3 * np.sqrt(2.0 / r["dof_" + q])
                worst = max(worst, r["chi2_" + q] / lim)
                ok &= r["chi2_" + q] <= lim
                worst_l1 = max(worst_l1, r["change_" + q] / r["error_" + q])
    L.append("largest chi2 / (1 + 3 sqrt(2/bins)) = %.3f, largest L1 change/error = %.3f: %s"
             % (worst, worst_l1, "PASS (the stiffer run changes the profiles by no more than the ensemble error)"
                if ok else "FAIL (the stiffness changes the profiles beyond the ensemble error)"))
    text = "\n".join(L)
    print(text)
    with open(os.path.join(a.out, "stiffness_check.txt"), "w") as f:
        f.write(text + "\n")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
