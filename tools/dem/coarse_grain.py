#!/usr/bin/python3
"""Coarse-grain LIGGGHTS dumps into granhydro's profile bins.

  /usr/bin/python3 tools/dem/coarse_grain.py RUN_DIR [RUN_DIR ...] -o dem_profiles.csv
      [--phase-bins K] [--skip-time T0]

Each RUN_DIR is a seed written by make_input.py and run by LIGGGHTS (meta.json +
dump.liggghts). Bins: the scene's cells along the profile direction (granhydro's
profile layers), in the container frame for a vibrated scene (h = h_lab - s(t) when
the profile direction is the vibration direction). A grain of radius R at height c
contributes to bin [a, b] its exact sphere-slab volume

    V(a, b) = F(clip(b - c)) - F(clip(a - c)),  F(u) = pi (R^2 u - u^3 / 3),
    clip(u) = min(max(u, -R), R),

and the weight w = V / (4/3 pi R^3) to the number-based sums. The two outer edges of
a wall-bounded direction are taken as -inf / +inf (a grain pressed into a wall by its
contact overlap keeps its whole volume in the end bin), so the bin volumes of every
grain add up to its volume: total grain volume is conserved to round-off. A periodic
profile direction folds the parts beyond an end into the bins at the other end.

Per bin (volume V_b = lateral area x bin height):
  phi     = sum V / V_b
  n       = sum w / V_b
  n u_d   = sum w v_d / V_b               (number flux, lab frame like granhydro's)
  u_d     = sum w m v_d / sum w m          (mass-weighted mean velocity)
  T_d     = sum w m (v_d - u_d)^2 / sum w  (J; granhydro's T = m <c^2>/3)
  T       = (T_x + T_y + T_z) / 3
Sums are pooled over the snapshots of one key (an output time, or a phase bin of a
vibrated scene with --phase-bins: phase bin j collects the snapshots with
t f mod 1 in [(j - 1/2)/K, (j + 1/2)/K), after --skip-time), then per seed the
profiles are formed, and the ensemble mean and standard error (std/sqrt(N), ddof 1)
are taken over the seeds (a bin without grains in a seed has no T there; its T
statistics use the seeds that have one).

Columns (SI units, named like granhydro's profiles; doc/user-guide.md): time (or phase),
the coordinate (x, y or z), seeds, snapshots, grains_in_bin, packing_fraction,
number_density, number_flux_x/_y/_z, temperature [J], temperature_x/_y/_z [J], each
quantity followed by its standard error <name>_se. read_csv also reads the files of
older versions (units in the names: time_s, y_m, n_1/m3, n*u_x_1/(m2 s), temperature_J)
under these names.
"""

import argparse
import json
import math
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "granhydro_py"))  # tools/granhydro_py: import granhydro
from scene import AXES  # noqa: E402
import packing  # noqa: E402
from granhydro.readers import column_name  # noqa: E402


def slab_volumes(c, R, edges, period=None):
    """(N, nb) exact volumes of spheres (centres c, radii R) inside the slabs between
    consecutive edges. period=None: outer edges at -inf/+inf; else the direction is
    periodic with that length (edges[-1] - edges[0]) and parts are folded."""
    c = np.asarray(c, float)
    R = np.broadcast_to(np.asarray(R, float), c.shape)
    e = np.array(edges, float)
    if period is None:
        e_lo = e.copy()
        e_lo[0] = -np.inf
        e_lo[-1] = np.inf
        u = np.clip(e_lo[None, :] - c[:, None], -R[:, None], R[:, None])
        F = np.pi * (R[:, None] ** 2 * u - u ** 3 / 3)
        return np.diff(F, axis=1)
    out = np.zeros((len(c), len(e) - 1))
    cc = e[0] + np.mod(c - e[0], period)
    for shift in (-period, 0.0, period):
        u = np.clip(e[None, :] - (cc + shift)[:, None], -R[:, None], R[:, None])
        F = np.pi * (R[:, None] ** 2 * u - u ** 3 / 3)
        out += np.diff(F, axis=1)
    return out


class Sums:
    """Bin sums of one key of one seed."""

    def __init__(self, nb):
        self.vol = np.zeros(nb)
        self.w = np.zeros(nb)
        self.wm = np.zeros(nb)
        self.wv = np.zeros((nb, 3))
        self.wmv = np.zeros((nb, 3))
        self.wmv2 = np.zeros((nb, 3))
        self.snapshots = 0

    def add(self, h, v, R, m, edges, period=None):
        V = slab_volumes(h, R, edges, period)
        vp = 4.0 / 3.0 * np.pi * np.broadcast_to(np.asarray(R, float), np.shape(h)) ** 3
        w = V / vp[:, None]
        m = np.broadcast_to(np.asarray(m, float), np.shape(h))
        self.vol += V.sum(axis=0)
        self.w += w.sum(axis=0)
        self.wm += w.T @ m
        self.wv += w.T @ v
        self.wmv += w.T @ (m[:, None] * v)
        self.wmv2 += w.T @ (m[:, None] * v * v)
        self.snapshots += 1

    def profiles(self, bin_volume):
        """phi, n, n u (nb, 3), u (nb, 3), T_d (nb, 3), T (nb) averaged over the snapshots."""
        k = max(self.snapshots, 1)
        Vb = np.broadcast_to(np.asarray(bin_volume, float) * k, self.vol.shape)
        with np.errstate(invalid="ignore", divide="ignore"):
            u = self.wmv / self.wm[:, None]
            Td = (self.wmv2 - self.wmv * u) / self.w[:, None]
        empty = self.w <= 0
        u[empty] = np.nan
        Td[empty] = np.nan
        return {"phi": self.vol / Vb, "n": self.w / Vb, "nu": self.wv / np.asarray(Vb)[:, None],
                "u": u, "Td": Td, "T": Td.mean(axis=1), "count": self.w / k}


def read_dump(path):
    """Yield (step, array (N, 8): id x y z vx vy vz radius) from a LIGGGHTS custom dump."""
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            if not line.startswith("ITEM: TIMESTEP"):
                continue
            step = int(next(lines))
            next(lines)
            n = int(next(lines))
            for _ in range(4):
                next(lines)
            header = next(lines).split()[2:]
            rows = [next(lines) for _ in range(n)]
            a = np.array(" ".join(rows).split(), float).reshape(n, len(header))
            cols = [header.index(c) for c in ("id", "x", "y", "z", "vx", "vy", "vz", "radius")]
            yield step, a[:, cols]


def max_overlaps(pos, R, box_lo, box_hi, periodic, walls):
    """Largest grain-grain overlap and grain-wall overlap [m] of one snapshot.
    walls: list of (axis, position, +1 for a floor-like lower wall / -1 upper)."""
    d = 2 * R.max()
    I, J, dx, r = packing.find_pairs(pos, box_lo, box_hi, periodic, d)
    gg = float(((R[I] + R[J]) - r).max()) if len(r) else 0.0
    gw = 0.0
    for (k, p, s) in walls:
        gw = max(gw, float((R - s * (pos[:, k] - p)).max()))
    return max(gg, 0.0), max(gw, 0.0)


def coarse_grain_run(run_dir, phase_bins=0, skip_time=0.0, overlaps=True):
    """{key: Sums} for one seed, plus diagnostics. key = output time index
    (time mode) or phase bin."""
    with open(os.path.join(run_dir, "meta.json")) as f:
        meta = json.load(f)
    pd = meta["profile_direction"]
    edges = np.array(meta["bin_edges_m"])
    lo, hi = np.array(meta["box_lo_m"]), np.array(meta["box_hi_m"])
    per = meta["periodic"]
    vib = meta["vibration"]
    A, f, vd = vib["amplitude_m"], vib["frequency_Hz"], vib["direction"]
    dt, m0, d0 = meta["dt_s"], meta["grain_mass_kg"], meta["grain_diameter_m"]
    period = (hi[pd] - lo[pd]) if per[pd] else None
    out = {}
    diag = {"max_grain_overlap_m": 0.0, "max_wall_overlap_m": 0.0, "snapshots": 0}
    for step, a in read_dump(os.path.join(run_dir, "dump.liggghts")):
        t = step * dt
        if phase_bins:
            if t < skip_time - 1e-12:
                continue
            ph = (t * f) % 1.0
            key = int(math.floor(ph * phase_bins + 0.5)) % phase_bins
        else:
            key = int(round(t / meta["dump_interval_s"]))
        s = A * math.sin(2 * math.pi * f * t) if A > 0 else 0.0
        pos = a[:, 1:4].copy()
        pos[:, vd] -= s  # container frame
        R = a[:, 7]
        m = m0 * (2 * R / d0) ** 3
        out.setdefault(key, Sums(len(edges) - 1)).add(pos[:, pd], a[:, 4:7], R, m, edges, period)
        if overlaps:
            walls = []
            for k in range(3):
                if not per[k]:
                    walls += [(k, lo[k], 1), (k, hi[k], -1)]
            gg, gw = max_overlaps(pos, R, lo, hi, per, walls)
            diag["max_grain_overlap_m"] = max(diag["max_grain_overlap_m"], gg)
            diag["max_wall_overlap_m"] = max(diag["max_wall_overlap_m"], gw)
        diag["snapshots"] += 1
    return meta, out, diag


def ensemble(run_dirs, phase_bins=0, skip_time=0.0, log=None):
    metas, per_seed, diags = [], [], []
    for rd in run_dirs:
        meta, sums, diag = coarse_grain_run(rd, phase_bins, skip_time)
        metas.append(meta)
        per_seed.append(sums)
        diags.append(diag)
    meta = metas[0]
    for other in metas[1:]:
        for k in ("bin_edges_m", "box_lo_m", "box_hi_m", "profile_direction", "vibration", "dump_interval_s"):
            if other.get(k) != meta.get(k):
                raise ValueError("coarse_grain: the runs differ in '%s' (not one ensemble)" % k)
    edges = np.array(meta["bin_edges_m"])
    pd = meta["profile_direction"]
    lo, hi = np.array(meta["box_lo_m"]), np.array(meta["box_hi_m"])
    area = np.prod([hi[k] - lo[k] for k in range(3) if k != pd])
    Vb = area * np.diff(edges)
    keys = sorted(set.intersection(*[set(s.keys()) for s in per_seed]))
    res = {}
    for key in keys:
        profs = [s[key].profiles(Vb) for s in per_seed]
        r = {}
        for q in ("phi", "n", "nu", "Td", "T", "count"):
            a = np.stack([p[q] for p in profs])
            with np.errstate(invalid="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", category=RuntimeWarning)
                k = np.sum(np.isfinite(a), axis=0)
                mean = np.nanmean(a, axis=0)
                sd = np.nanstd(a, axis=0, ddof=1) if len(profs) > 1 else np.full(mean.shape, np.nan)
                se = sd / np.sqrt(np.maximum(k, 1))
            r[q], r[q + "_se"] = mean, se
        r["seeds"] = len(profs)
        r["snapshots"] = per_seed[0][key].snapshots
        res[key] = r
    return meta, metas, res, diags


def key_value(meta, key, phase_bins):
    return key / phase_bins if phase_bins else key * meta["dump_interval_s"]


def csv_columns(ax, phase_bins=0):
    """the header of the profiles CSV along axis AX ('x', 'y' or 'z'): see the docstring"""
    cols = ["phase" if phase_bins else "time", ax, "seeds", "snapshots", "grains_in_bin",
            "packing_fraction", "packing_fraction_se", "number_density", "number_density_se"]
    for a in AXES:
        cols += ["number_flux_%s" % a, "number_flux_%s_se" % a]
    cols += ["temperature", "temperature_se"]
    for a in AXES:
        cols += ["temperature_%s" % a, "temperature_%s_se" % a]
    return cols


def write_csv(path, meta, metas, res, diags, phase_bins=0, skip_time=0.0, extra_comments=()):
    pd = meta["profile_direction"]
    edges = np.array(meta["bin_edges_m"])
    centres = 0.5 * (edges[:-1] + edges[1:])
    ax = AXES[pd]
    d = meta["grain_diameter_m"]
    with open(path, "w") as f:
        f.write("# DEM (LIGGGHTS) profiles of %s coarse-grained into granhydro's %d bins along %s; "
                "ensemble of %d seeds: mean and standard error (_se)\n" % (os.path.basename(meta["scene"]), len(centres), ax, len(metas)))
        f.write("# grains %d, Hertz E = %g Pa, nu = %g, friction %g, restitution %g, dt = %.6g s "
                "(t_c = %.4g s at %g m/s, dt/t_c = %.4f, dt/Rayleigh time = %.4f)\n"
                % (meta["grains"], meta["youngs_modulus_Pa"], meta["poisson_ratio"], meta["friction"],
                   meta["restitution"], meta["dt_s"], meta["contact_time_at_v_ref_s"], meta["v_ref_m_s"],
                   meta["dt_s"] / meta["contact_time_at_v_ref_s"], meta["dt_s"] / meta["rayleigh_time_s"]))
        f.write("# largest overlap seen in the snapshots: grain-grain %.3g d, grain-wall %.3g d\n"
                % (max(x["max_grain_overlap_m"] for x in diags) / d, max(x["max_wall_overlap_m"] for x in diags) / d))
        if phase_bins:
            f.write("# phase-averaged: %d phase bins (phase = t f mod 1), snapshots from t = %g s; "
                    "heights in the container frame, velocities in the lab frame\n" % (phase_bins, skip_time))
        elif meta["vibration"]["amplitude_m"] > 0:
            f.write("# heights in the container frame, velocities in the lab frame\n")
        for c in extra_comments:
            f.write("# %s\n" % c)
        f.write(",".join(csv_columns(ax, phase_bins)) + "\n")
        for key in sorted(res):
            r = res[key]
            for i in range(len(centres)):
                row = [key_value(meta, key, phase_bins), centres[i], r["seeds"], r["snapshots"], r["count"][i],
                       r["phi"][i], r["phi_se"][i], r["n"][i], r["n_se"][i]]
                for a in range(3):
                    row += [r["nu"][i, a], r["nu_se"][i, a]]
                row += [r["T"][i], r["T_se"][i]]
                for a in range(3):
                    row += [r["Td"][i, a], r["Td_se"][i, a]]
                f.write(",".join("%.10g" % x for x in row) + "\n")


def read_csv(path):
    """DEM profiles CSV -> (key column name, {key: {column: array}}); the columns of an
    older file under the names of now (granhydro.readers.column_name: time_s -> time,
    temperature_J_se -> temperature_se, ...)."""
    with open(path) as f:
        lines = [l for l in f if not l.startswith("#")]
    cols = [column_name(c) for c in lines[0].strip().split(",")]
    a = np.array([[float(x) for x in l.split(",")] for l in lines[1:] if l.strip()])
    blocks = {}
    for k in np.unique(a[:, 0]):
        sel = a[a[:, 0] == k]
        blocks[float(k)] = {c: sel[:, i] for i, c in enumerate(cols)}
    return cols[0], blocks


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run_dirs", nargs="+")
    p.add_argument("-o", "--output", default="dem_profiles.csv")
    p.add_argument("--phase-bins", type=int, default=0)
    p.add_argument("--skip-time", type=float, default=0.0)
    a = p.parse_args()
    meta, metas, res, diags = ensemble(a.run_dirs, a.phase_bins, a.skip_time)
    write_csv(a.output, meta, metas, res, diags, a.phase_bins, a.skip_time)
    print("wrote %s (%d keys, %d seeds)" % (a.output, len(res), len(metas)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
