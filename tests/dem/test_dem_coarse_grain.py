#!/usr/bin/python3
"""dem.coarse_grain: tools/dem/coarse_grain.py on synthetic grains with known profiles.

Every reference below is a closed form (sphere and cap volumes, means and variances of
two or three velocities), so the tolerances are round-off:
  * RTOL_SUM = 1e-14: a grain's bin volumes add up to its volume through a difference of
    F(u) = pi (R^2 u - u^3/3) at the bin edges; each F carries a few ulps of |F| <= 2/3 pi R^3
    and the telescoping sum adds at most ~2 (bins cut) + 2 such errors, i.e. ~1e-15 of the
    volume; 1e-14 leaves one decimal for the summation order of many grains.
  * RTOL_BIN = 1e-14 for per-bin values: a cap of height R/2 has 5/32 of the sphere's
    volume, so the cancellation in F(b) - F(a) amplifies the ulps of F by at most ~7.
  * velocities are dyadic numbers, masses the same for all grains: n u and T are a few
    multiplications and one division away from the reference (RTOL_BIN).
"""

import json
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "dem"))
import coarse_grain as cg  # noqa: E402

RTOL_SUM = 1e-14
RTOL_BIN = 1e-14
failures = []


def check(name, got, ref, rtol, atol_scale=None):
    got, ref = np.asarray(got, float), np.asarray(ref, float)
    scale = np.abs(ref) if atol_scale is None else atol_scale
    err = np.max(np.abs(got - ref) / np.maximum(scale, 1e-300)) if got.size else 0.0
    ok = err <= rtol
    print("%-62s rel. error %.2e (tolerance %.0e) %s" % (name, err, rtol, "ok" if ok else "FAIL"))
    if not ok:
        failures.append(name)
        print("   got", got, "\n   ref", ref)


h = 1e-3
edges = np.arange(5) * h  # 4 bins of 1 mm, walls at 0 and 4 mm
Vs = lambda R: 4.0 / 3.0 * math.pi * R ** 3
cap = lambda R, c: math.pi * c * c * (3 * R - c) / 3  # cap of height c

# ---- 1. single grains: known sphere-slab volumes -----------------------------------------
R = 0.3e-3
cases = [
    ("whole grain inside bin 1", 1.5 * h, R, [0, Vs(R), 0, 0]),
    ("grain centred on the edge 2 mm: halves", 2 * h, R, [0, Vs(R) / 2, Vs(R) / 2, 0]),
    ("cap of height R/2 below edge 1 mm", h + R / 2, R, [cap(R, R / 2), Vs(R) - cap(R, R / 2), 0, 0]),
    ("grain pressed 0.1 R into the floor: all in bin 0", -0.1 * R + R, R, [Vs(R), 0, 0, 0]),
    ("grain protruding through the top wall", 4 * h - 0.5 * R, R, [0, 0, 0, Vs(R)]),
]
Rb = 1.5 * h  # a grain larger than a bin, centred on the edge 2 mm: spans bins 0..3
cases.append(("R = 1.5 h on edge 2 mm: caps + slabs", 2 * h, Rb,
              [cap(Rb, 0.5 * h), math.pi * (Rb ** 2 * h - h ** 3 / 3), math.pi * (Rb ** 2 * h - h ** 3 / 3), cap(Rb, 0.5 * h)]))
for name, c, r, ref in cases:
    V = cg.slab_volumes(np.array([c]), np.array([r]), edges)[0]
    check("volume: " + name, V, ref, RTOL_BIN, atol_scale=Vs(r))
    check("volume sum: " + name, [V.sum()], [Vs(r)], RTOL_SUM)

# periodic profile direction: a grain on the lower end is folded half into the last bin
V = cg.slab_volumes(np.array([0.0]), np.array([R]), edges, period=4 * h)[0]
check("periodic: grain on the seam, half in bin 0, half in bin 3", V, [Vs(R) / 2, 0, 0, Vs(R) / 2], RTOL_BIN, atol_scale=Vs(R))

# ---- 2. many random grains: every grain's volume conserved ---------------------------------
rng = np.random.default_rng(7)
n = 20000
c = rng.uniform(-0.2 * h, 4.2 * h, n)
r = rng.uniform(0.1 * h, 1.2 * h, n)
V = cg.slab_volumes(c, r, edges)
check("random grains: per-grain sum of bin volumes = 4/3 pi R^3", V.sum(axis=1), Vs(r), RTOL_SUM)
check("random grains: total volume", [V.sum()], [Vs(r).sum()], RTOL_SUM)
Vp = cg.slab_volumes(c, r, edges, period=4 * h)
check("random grains, periodic: per-grain volume", Vp.sum(axis=1), Vs(r), RTOL_SUM)

# ---- 3. bin sums -> phi, n, n u, u, T ----------------------------------------------------------
m = 2.0 ** -20  # kg, the same for all grains
area = 2.0 ** -10  # m^2 lateral area
Vb = area * h
# bin 1: two whole grains with v = (0.5, -0.25, 1) and (-0.25, 0.25, 0.5)
# bin 2/3: one grain centred on the edge 3 mm with v = (1, 0, 0): weight 1/2 in each
# bin 3: one whole grain with v = (0, 0, 2)
pos = np.array([1.5 * h, 1.4 * h, 3 * h, 3.5 * h])
vel = np.array([[0.5, -0.25, 1.0], [-0.25, 0.25, 0.5], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0]])
S = cg.Sums(4)
S.add(pos, vel, R, m, edges)
P = S.profiles(Vb)
check("phi per bin", P["phi"], [0, 2 * Vs(R) / Vb, 0.5 * Vs(R) / Vb, 1.5 * Vs(R) / Vb], RTOL_BIN, atol_scale=Vs(R) / Vb)
check("n per bin", P["n"], [0, 2 / Vb, 0.5 / Vb, 1.5 / Vb], RTOL_BIN, atol_scale=1 / Vb)
check("n u per bin (x, y, z)", P["nu"][1:], [[0.25 / Vb, 0, 1.5 / Vb], [0.5 / Vb, 0, 0], [0.5 / Vb, 0, 2 / Vb]],
      RTOL_BIN, atol_scale=1 / Vb)
# bin 1: u = mean of the two, T_d = m (v1 - v2)^2 / 4
check("bin 1: T_x, T_y, T_z = m (v1 - v2)^2 / 4", P["Td"][1], m * np.array([0.75, 0.5, 0.5]) ** 2 / 4, RTOL_BIN)
# bin 3: weights 1/2 (v_a = (1,0,0)) and 1 (v_b = (0,0,2)): u = (v_a/2 + v_b)/1.5,
# T_d = m (0.5 (v_a - u)^2 + (v_b - u)^2) / 1.5
va, vb = np.array([1.0, 0, 0]), np.array([0, 0, 2.0])
u3 = (0.5 * va + vb) / 1.5
check("bin 3 (weights 1/2 and 1): mass-weighted u", P["u"][3], u3, RTOL_BIN, atol_scale=1.0)
T3 = m * (0.5 * (va - u3) ** 2 + (vb - u3) ** 2) / 1.5
check("bin 3: T per direction", P["Td"][3], T3, RTOL_BIN, atol_scale=m)
check("bin 3: T = (T_x + T_y + T_z)/3", [P["T"][3]], [T3.mean()], RTOL_BIN)
check("bin 2 (one half grain): T = 0", P["Td"][2], [0, 0, 0], RTOL_BIN, atol_scale=m)
if not np.all(np.isnan(P["T"][0])):
    failures.append("empty bin must have no temperature")
    print("empty bin T:", P["T"][0], "FAIL")

# ---- 4. the run reader: dumps, container frame, ensemble mean and standard error -----------
# Two 'seeds', one snapshot each at t = 1/(4 f) where the container is at s = +A: grains at
# lab heights h_c + A must land in the bins of the container-frame heights h_c.
f, A, dt = 12.5, 0.004, 1e-5
step = 2000  # t = 0.02 s = 1/(4 f): sin = 1
tmp = tempfile.mkdtemp(prefix="dem_cg_")
Lx = Ly = 2.0 ** -5
d = 2 * R
m_grain = 2600 * math.pi / 6 * d ** 3
seeds = {"a": (np.array([1.5 * h, 2.5 * h]), np.array([0.5, 0.25])),
         "b": (np.array([1.5 * h, 1.5 * h + 2 * R]), np.array([0.5, -0.25]))}
dirs = []
for name, (hc, vy) in seeds.items():
    rd = os.path.join(tmp, name)
    os.makedirs(rd)
    meta = {"scene": "synthetic", "profile_direction": 1, "bin_edges_m": edges.tolist(),
            "box_lo_m": [0, 0, 0], "box_hi_m": [Lx, 4 * h, Ly], "periodic": [True, False, True],
            "vibration": {"amplitude_m": A, "frequency_Hz": f, "direction": 1}, "dt_s": dt,
            "grain_mass_kg": m_grain, "grain_diameter_m": d, "dump_interval_s": step * dt, "grains": len(hc)}
    json.dump(meta, open(os.path.join(rd, "meta.json"), "w"))
    with open(os.path.join(rd, "dump.liggghts"), "w") as fd:
        fd.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%d\nITEM: BOX BOUNDS pp ff pp\n0 1\n0 1\n0 1\n"
                 "ITEM: ATOMS id x y z vx vy vz radius\n" % (step, len(hc)))
        for i, (y, v) in enumerate(zip(hc, vy)):
            fd.write("%d %.17g %.17g %.17g 0 %.17g 0 %.17g\n" % (i + 1, Lx * (i + 1) / 4, y + A, Ly / 2, v, R))
    dirs.append(rd)
_, _, res, _ = cg.ensemble(dirs)
r = res[1]  # key = output index 1 (t = 0.02 s)
Vb = Lx * Ly * h
# seed a: one grain in bin 1, one in bin 2; seed b: two grains in bin 1 (the second's centre
# at 1.5 h + 2R = 2.1 mm: its cap of height R - 0.1 mm below 2 mm is in bin 1)
cb = cap(R, R - 0.1 * h)
phi_a = np.array([0, Vs(R), Vs(R), 0]) / Vb
phi_b = np.array([0, Vs(R) + cb, Vs(R) - cb, 0]) / Vb
check("ensemble: mean phi of two seeds (container frame)", r["phi"], (phi_a + phi_b) / 2, RTOL_BIN, atol_scale=Vs(R) / Vb)
check("ensemble: standard error = |a - b| / 2", r["phi_se"], np.abs(phi_a - phi_b) / 2, 1e-12, atol_scale=Vs(R) / Vb)
# bin 1, seed a: one grain, T = 0; seed b: weights 1 and cb/V, v = +-0.25 around 0.5 -> known T_y
w2 = cb / Vs(R)
u_b = (0.5 + w2 * -0.25) / (1 + w2)
Ty_b = m_grain * ((0.5 - u_b) ** 2 + w2 * (-0.25 - u_b) ** 2) / (1 + w2)
check("ensemble: bin 1 mean T_y over the seeds", [r["Td"][1, 1]], [(0 + Ty_b) / 2], 1e-13)
# 1e-13 here: the grain positions went through the container shift y + A - A (one rounding
# of a 4 mm offset, 4e-19 m, on a cap of height 0.2 mm: relative 1e-15 in its volume,
# amplified by the cancellation of the variance about the mean, (0.5-u)^2 vs v^2: ~10)

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
