#!/usr/bin/python3
"""dem.e2e: scene -> packing -> LIGGGHTS -> coarse-graining -> comparison with granhydro.

  test_dem_e2e.py GRANHYDRO LIGGGHTS WORKDIR

Scene tests/dem/dem_column.prm (1D column, 30 x 1 mm bins, phi = 0.1 + 0.05 tanh((15 mm - x)/5 mm),
T = 1e-8 J, settling for 60 ms), DEM box 30 x 8 x 8 mm, 3 seeds. Asserted:
  1. grain count = round(A int phi dx / v_grain) with the integral in closed form (exact integer),
     and the grain centres per bin = the cumulatively rounded closed-form bin integrals (exact);
  2. coarse-grained grain volume = N v_grain in every snapshot of every seed (round-off, 1e-13:
     a sum of ~N x 3 sphere-slab volumes each exact to a few ulps);
  3. initial velocities: m var(v) over all grains and components = T0 within 4 standard errors
     of a variance estimate, sqrt(2/(3N - 1)) (a Maxwellian with the scene's T);
  4. largest grain-grain and grain-wall overlap <= the Hertz overlap of a head-on collision at
     the largest relative speed the column allows, 2 sqrt(2 g H) (two grains falling from the
     top, one reflected): the contact stiffness keeps the grains hard (0.05 d);
  5. model vs DEM (regression bounds, not exact: the continuum model is not the DEM): at every
     output time D_phi <= 0.15 and, after t = 0, D_flux <= 0.40; front height (phi = 0.05)
     within 2.5 mm (2.5 bins) of the model's. Measured with these seeds (see the output):
     D_phi <= 0.110, D_flux <= 0.315, fronts within 2.2 mm. Negative control (measured): the DEM
     with gravity reversed gives D_flux = 1.82 at 0.01 s and D_phi = 0.40 at 0.02 s, 1.86 at 0.06 s.
"""

import glob
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.join(HERE, "..", "..", "tools", "dem")
sys.path.insert(0, TOOLS)
import coarse_grain as cg  # noqa: E402
import make_input  # noqa: E402

granhydro, liggghts, work = sys.argv[1], sys.argv[2], sys.argv[3]
scene = os.path.join(HERE, "dem_column.prm")
SEEDS, WIDTH = 3, 0.008
failures = []


def check(name, ok, detail):
    print("%-70s %s  %s" % (name, "ok" if ok else "FAIL", detail))
    if not ok:
        failures.append(name)


shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
t0 = time.time()
subprocess.run([granhydro, scene], cwd=work, check=True, stdout=subprocess.DEVNULL)
t_model = time.time() - t0
t0 = time.time()
py = sys.executable
subprocess.run([py, os.path.join(TOOLS, "run_ensemble.py"), scene, "--seeds", str(SEEDS), "--out", "dem",
                "--width", str(WIDTH), "--liggghts", liggghts, "--progress-interval", "1000"], cwd=work, check=True)
t_dem = time.time() - t0
t0 = time.time()
subprocess.run([py, os.path.join(TOOLS, "compare.py"), "--scene", scene, "--model", "output-dem-column", "--dem", "dem",
                "--out", "compare"], cwd=work, check=True)
t_cmp = time.time() - t0
print("wall: granhydro %.2f s, DEM ensemble (packing + LIGGGHTS + coarse-graining) %.2f s, compare %.2f s" % (t_model, t_dem, t_cmp))

# 1. grain counts, closed form: int_a^b tanh((c - x)/w) dx = w [ln cosh((c - a)/w) - ln cosh((c - b)/w)]
c0, w0, d, H = 0.015, 0.005, 1e-3, 0.03
area, vg = WIDTH * WIDTH, math.pi / 6 * d ** 3
I = lambda a, b: 0.1 * (b - a) + 0.05 * w0 * (math.log(math.cosh((c0 - a) / w0)) - math.log(math.cosh((c0 - b) / w0)))
edges = np.linspace(0, H, 31)
cum = np.rint(np.concatenate([[0], np.cumsum([I(edges[i], edges[i + 1]) * area / vg for i in range(30)])])).astype(int)
ens = json.load(open(os.path.join(work, "dem", "ensemble.json")))
runs = sorted(glob.glob(os.path.join(work, "dem", "seed_*")))
N = int(round(I(0, H) * area / vg))
for rd in runs:
    meta = json.load(open(os.path.join(rd, "meta.json")))
    lines = open(os.path.join(rd, "particles.data")).read().split("Atoms")[1].split("Velocities")
    atoms = np.array([l.split() for l in lines[0].strip().splitlines()], float)
    percount = np.histogram(atoms[:, 4], bins=edges)[0]
    check("seed %d: grains = round(A int phi / v_grain) = %d" % (meta["seed"], N), len(atoms) == N, "(%d)" % len(atoms))
    check("seed %d: grain centres per bin = rounded closed-form bin integrals" % meta["seed"],
          np.array_equal(percount, np.diff(cum)), "")

# 2. volume conservation of the coarse-graining in every snapshot
worst, gg, gw = 0.0, 0.0, 0.0
for rd in runs:
    meta, sums, diag = cg.coarse_grain_run(rd, overlaps=True)
    gg = max(gg, diag["max_grain_overlap_m"] / d)
    gw = max(gw, diag["max_wall_overlap_m"] / d)
    for k, s in sums.items():
        worst = max(worst, abs(s.vol.sum() / s.snapshots - N * vg) / (N * vg))
check("coarse-grained grain volume = N v_grain, every snapshot (1e-13)", worst <= 1e-13, "(%.2e)" % worst)

# 3. Maxwellian initial velocities
m = 2600 * vg
v = []
for rd in runs:
    lines = open(os.path.join(rd, "particles.data")).read().split("Velocities")[1]
    v.append(np.array([l.split() for l in lines.strip().splitlines()], float)[:, 1:4])
v = np.concatenate(v).ravel()
T = m * np.mean(v * v)
se = 1e-8 * math.sqrt(2.0 / (len(v) - 1))
check("initial m <v^2> = T0 = 1e-8 J within 4 SE", abs(T - 1e-8) <= 4 * se, "(%.4g J, SE %.2g)" % (T, se))

# 4. overlaps against the Hertz overlap at 2 sqrt(2 g H)
vmax = 2 * math.sqrt(2 * 9.81 * H)
_, delta = make_input.hertz_contact(meta["youngs_modulus_Pa"], meta["poisson_ratio"], d, m, vmax)
check("largest overlaps %.3g d (grains), %.3g d (wall) <= Hertz at %.2f m/s (%.3g d)" % (gg, gw, vmax, delta / d),
      gg <= delta / d and gw <= delta / d, "")

# 5. model vs DEM
rows = [l.strip().split(",") for l in open(os.path.join(work, "compare", "compare.csv"))]
cols, rows = rows[0], [dict(zip(rows[0], map(float, r))) for r in rows[1:]]
check("compared at the 7 output times 0, 0.01, ..., 0.06 s", len(rows) == 7, "(%d)" % len(rows))
for r in rows:
    t = r["time"]
    check("t = %.2f s: D_phi <= 0.15" % t, r["D_phi"] <= 0.15, "(%.3f)" % r["D_phi"])
    if t > 0:
        check("t = %.2f s: D_flux <= 0.40" % t, r["D_flux"] <= 0.40, "(%.3f)" % r["D_flux"])
    df = abs(r["model_front_height_m"] - r["dem_front_height_m"])
    check("t = %.2f s: front height within 2.5 mm" % t, df <= 2.5e-3, "(model %.2f mm, DEM %.2f mm)"
          % (1e3 * r["model_front_height_m"], 1e3 * r["dem_front_height_m"]))
g = ens["seeds"]
print("DEM cost: %d grains x %d steps per seed, LIGGGHTS %.2f s per seed (%.0f steps/s, %.3g grain-steps/s)"
      % (g[0]["grains"], g[0]["steps"], ens["total_liggghts_wall_s"] / len(g), np.mean([x["steps_per_s"] for x in g]),
         np.mean([x["grain_steps_per_s"] for x in g])))
print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
