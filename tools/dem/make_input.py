#!/usr/bin/python3
"""granhydro scene -> LIGGGHTS (3.8) run directory.

  /usr/bin/python3 tools/dem/make_input.py SCENE.prm RUN_DIR [--seed S] [--friction MU]
      [--youngs E] [--poisson NU] [--dt DT] [--v-ref V] [--width W] [--lateral L]
      [--end-time T] [--dump-interval DT_OUT] [--rsa-max PHI]

writes RUN_DIR/in.liggghts, RUN_DIR/particles.data (initial grains), wall meshes
(vibrated scenes) and RUN_DIR/meta.json (scene, geometry, contact stiffness, time step,
packing report). Run it with `cd RUN_DIR && liggghts -in in.liggghts`.

Geometry: LIGGGHTS axes are the scene's axes. Resolved directions keep the scene's
extent (or --lateral L for the resolved directions other than the profile direction)
and boundaries: periodic, or a flat wall (slip and no-slip walls alike: with the
default friction 0 a DEM wall exerts no tangential force; with --friction MU every
wall is frictional). Unresolved directions (1D/2D scenes) are periodic with extent
--width (default 10 grain diameters). A vibrated scene moves every wall as
s(t) = A sin(2 pi f t) along the vibration direction (LIGGGHTS move/mesh wiggle on
STL wall meshes); a static scene uses primitive planes.

Contacts: Hertz normal force with tangential history (LIGGGHTS `gran model hertz
tangential history`), restitution of the scene (grain-grain: Material/Restitution
coefficient; grain-wall: Domain/Wall restitution of the side), Coulomb friction
--friction (default 0: smooth spheres like the continuum model), Young's modulus
--youngs (default 1e7 Pa), Poisson ratio --poisson (0.3). The default time step is
t_c/30, t_c the Hertz contact time of a head-on collision at --v-ref (default 1 m/s),
shortened so that the dump interval is a whole number of steps.
"""

import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scene import AXES, SIDES, Scene, SceneError  # noqa: E402
import packing  # noqa: E402


def hertz_contact(E, nu, d, m, v):
    """Head-on collision of two equal grains at relative speed v (elastic Hertz):
    contact time and largest overlap."""
    Estar = E / (2 * (1 - nu * nu))
    Reff = d / 4
    meff = m / 2
    tc = 2.868 * (meff * meff / (Reff * Estar * Estar * v)) ** 0.2
    delta = (15 * meff * v * v / (16 * Estar * math.sqrt(Reff))) ** 0.4
    return tc, delta


def rayleigh_time(E, nu, d, rho):
    G = E / (2 * (1 + nu))
    return math.pi * (d / 2) * math.sqrt(rho / G) / (0.1631 * nu + 0.8766)


def geometry(sc, width, lateral):
    lo, hi, per = np.zeros(3), np.zeros(3), [True] * 3
    for k in range(3):
        if k < sc.dim:
            lo[k], hi[k] = sc.lower[k], sc.upper[k]
            if lateral and k != sc.profile_direction:
                hi[k] = lo[k] + lateral
            per[k] = sc.periodic(k)
        else:
            lo[k], hi[k] = 0.0, width
    return packing.Box(lo, hi, per)


def wall_tile(box):
    """Largest tile edge of a wall mesh: the smallest periodic extent of the box.
    LIGGGHTS 3.8 builds a mesh's topology with the periodic ghost copies of its
    triangles; a triangle much wider than a periodic extent (a 0.1 m wall of a 3D bed
    with a 0.01 m periodic depth) has images beyond the bins of that search and the run
    stops at setup ("assertion failed (./src/region_neighbor_list_I.h:165)")."""
    ext = [box.hi[k] - box.lo[k] for k in range(3) if box.periodic[k]]
    return min(ext) if ext else math.inf


def write_stl(path, k, pos, box, tile=math.inf):
    """A rectangle normal to axis k at coordinate pos spanning the box in the other axes,
    as tiles of two triangles with edges no longer than tile (one tile if it fits)."""
    a, b = [j for j in range(3) if j != k]
    na = max(1, math.ceil((box.hi[a] - box.lo[a]) / tile - 1e-9))
    nb = max(1, math.ceil((box.hi[b] - box.lo[b]) / tile - 1e-9))
    ea = np.linspace(box.lo[a], box.hi[a], na + 1)
    eb = np.linspace(box.lo[b], box.hi[b], nb + 1)
    with open(path, "w") as f:
        f.write("solid wall\n")
        for i in range(na):
            for j in range(nb):
                corners = []
                for ua, ub in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]:
                    p = [0.0] * 3
                    p[k] = pos
                    p[a] = float(ea[ua])
                    p[b] = float(eb[ub])
                    corners.append(p)
                for tri in [(0, 1, 2), (0, 2, 3)]:
                    n = [0.0] * 3
                    n[k] = 1.0
                    f.write(" facet normal %r %r %r\n  outer loop\n" % tuple(n))
                    for q in tri:
                        f.write("   vertex %r %r %r\n" % tuple(corners[q]))
                    f.write("  endloop\n endfacet\n")
        f.write("endsolid wall\n")


def build(args, log=print):
    sc = Scene(args.scene)
    d, m, rho = sc.diameter, sc.grain_mass, sc.density
    width = args.width if args.width else 10 * d
    box = geometry(sc, width, args.lateral)
    pd = sc.profile_direction
    edges = sc.bin_edges()
    # layered initial state: evaluated at the lateral centre; refuse lateral dependence
    lat_pts = [0.5 * (box.lo + box.hi), box.lo + 0.17 * (box.hi - box.lo), box.lo + 0.71 * (box.hi - box.lo)]
    phi_f = lambda h: sc.layered(sc.phi_expr, "Packing fraction", h, lat_pts)
    hq = np.linspace(edges[0], edges[-1], 257)
    sc.layered(sc.temp_expr, "Temperature", hq, lat_pts)
    for e in sc.vel_expr:
        sc.layered(e, "Velocity", hq, lat_pts)
    phi_bin = packing.gauss_bin_average(phi_f, edges)
    if np.any(phi_bin < 0) or np.any(phi_bin > 0.64):
        raise SceneError("initial packing fraction outside [0, 0.64]")
    area = np.prod([box.hi[k] - box.lo[k] for k in range(3) if k != pd])
    vgrain = math.pi / 6 * d ** 3
    counts = packing.bin_counts(phi_bin, area * np.diff(edges), vgrain)
    rng = np.random.default_rng(args.seed)
    pos, pinfo = packing.place(rng, box, pd, edges, counts, d, args.rsa_max, phi_bin, log=log)
    vel = packing.maxwellian(rng, sc, pos, float(sc.container_velocity(0.0)))

    # time step and output
    end = args.end_time if args.end_time else sc.end_time
    dump_dt = args.dump_interval if args.dump_interval else (sc.output_interval if sc.output_interval > 0 else end / 10)
    tc, delta = hertz_contact(args.youngs, args.poisson, d, m, args.v_ref)
    dt0 = args.dt if args.dt else tc / 30
    nd = max(1, math.ceil(dump_dt / dt0 - 1e-9))
    dt = dump_dt / nd
    nsteps = int(round(end / dt))
    tR = rayleigh_time(args.youngs, args.poisson, d, rho)

    os.makedirs(args.run_dir, exist_ok=True)
    # wall material types by restitution
    walls = []  # (axis, side 0/1, position, restitution)
    for k in range(3):
        if not box.periodic[k]:
            for s in (0, 1):
                e = sc.wall_restitution[SIDES[2 * k + s]] if k < sc.dim else 1.0
                walls.append((k, s, box.lo[k] if s == 0 else box.hi[k], e))
    wall_e = sorted(set(w[3] for w in walls))
    ntypes = 1 + len(wall_e)
    rest = np.ones((ntypes, ntypes))
    rest[0, 0] = sc.restitution
    for i, e in enumerate(wall_e):
        rest[0, 1 + i] = rest[1 + i, 0] = e
    A = sc.vib_amplitude
    blo, bhi = box.lo.copy(), box.hi.copy()
    for k in range(3):
        if not box.periodic[k]:
            extra = d + (A if k == sc.vib_direction else 0.0)
            blo[k] -= extra
            bhi[k] += extra
    # particles.data
    with open(os.path.join(args.run_dir, "particles.data"), "w") as f:
        f.write("granhydro DEM initial state from %s, seed %d\n\n" % (os.path.basename(args.scene), args.seed))
        f.write("%d atoms\n%d atom types\n\n" % (len(pos), ntypes))
        for k in range(3):
            f.write("%.17g %.17g %slo %shi\n" % (blo[k], bhi[k], AXES[k], AXES[k]))
        f.write("\nAtoms\n\n")
        for i, p in enumerate(pos):
            f.write("%d 1 %.17g %.17g %.17g %.17g %.17g\n" % (i + 1, d, rho, p[0], p[1], p[2]))
        f.write("\nVelocities\n\n")
        for i, v in enumerate(vel):
            f.write("%d %.17g %.17g %.17g 0 0 0\n" % (i + 1, v[0], v[1], v[2]))
    # in.liggghts
    L = []
    w = L.append
    w("# LIGGGHTS 3.8 input written by tools/dem/make_input.py from %s (seed %d)" % (os.path.basename(args.scene), args.seed))
    w("# Hertz contacts E = %g Pa, nu = %g, friction %g; dt = %.6g s = t_c/%.1f (t_c = %.4g s at %g m/s), %.3f of the Rayleigh time"
      % (args.youngs, args.poisson, args.friction, dt, tc / dt, tc, args.v_ref, dt / tR))
    w("atom_style granular")
    w("atom_modify map array")
    w("boundary %s" % " ".join("p" if box.periodic[k] else "f" for k in range(3)))
    w("newton off")
    w("communicate single vel yes")
    w("units si")
    w("read_data particles.data")
    w("neighbor %.6g bin" % (0.2 * d))
    w("neigh_modify delay 0")
    w("fix m1 all property/global youngsModulus peratomtype " + " ".join(["%.9g" % args.youngs] * ntypes))
    w("fix m2 all property/global poissonsRatio peratomtype " + " ".join(["%.9g" % args.poisson] * ntypes))
    w("fix m3 all property/global coefficientRestitution peratomtypepair %d " % ntypes
      + " ".join("%.9g" % x for x in rest.ravel()))
    w("fix m4 all property/global coefficientFriction peratomtypepair %d " % ntypes
      + " ".join(["%.9g" % args.friction] * (ntypes * ntypes)))
    w("pair_style gran model hertz tangential history")
    w("pair_coeff * *")
    w("timestep %.17g" % dt)
    g = np.array(sc.gravity, float)
    gn = float(np.linalg.norm(g))
    if gn > 0:
        w("fix gravi all gravity %.17g vector %.17g %.17g %.17g" % (gn, *(g / gn)))
    if walls:
        if A > 0:
            ids = []
            for (k, s, p, e) in walls:
                name = "wall_%s%s" % (AXES[k], ("lo", "hi")[s])
                write_stl(os.path.join(args.run_dir, name + ".stl"), k, p, box, wall_tile(box))
                w("fix %s all mesh/surface file %s.stl type %d" % (name, name, 2 + wall_e.index(e)))
                ids.append(name)
            w("fix walls all wall/gran model hertz tangential history mesh n_meshes %d meshes %s" % (len(ids), " ".join(ids)))
            amp = [0.0] * 3
            amp[sc.vib_direction] = A
            for name in ids:
                w("fix move_%s all move/mesh mesh %s wiggle amplitude %.17g %.17g %.17g period %.17g"
                  % (name, name, amp[0], amp[1], amp[2], 1.0 / sc.vib_frequency))
        else:
            for (k, s, p, e) in walls:
                w("fix wall_%s%s all wall/gran model hertz tangential history primitive type %d %splane %.17g"
                  % (AXES[k], ("lo", "hi")[s], 2 + wall_e.index(e), AXES[k], p))
    w("fix integr all nve/sphere")
    thermo = max(1, nsteps // 200)
    w("thermo_style custom step atoms ke")
    w("thermo %d" % thermo)
    w("thermo_modify lost error norm no")
    w("dump d all custom %d dump.liggghts id x y z vx vy vz radius" % nd)
    w("dump_modify d sort id")
    w("run %d" % nsteps)
    with open(os.path.join(args.run_dir, "in.liggghts"), "w") as f:
        f.write("\n".join(L) + "\n")
    meta = {
        "scene": os.path.abspath(args.scene), "seed": args.seed, "grains": int(len(pos)),
        "grain_diameter_m": d, "grain_mass_kg": m, "restitution": sc.restitution,
        "wall_restitution": {SIDES[2 * k + s]: e for (k, s, p, e) in walls},
        "friction": args.friction, "youngs_modulus_Pa": args.youngs, "poisson_ratio": args.poisson,
        "v_ref_m_s": args.v_ref, "contact_time_at_v_ref_s": tc, "max_overlap_at_v_ref_m": delta,
        "max_overlap_at_v_ref_over_d": delta / d, "rayleigh_time_s": tR,
        "dt_s": dt, "steps": nsteps, "end_time_s": nsteps * dt, "dump_every_steps": nd,
        "dump_interval_s": nd * dt, "box_lo_m": box.lo.tolist(), "box_hi_m": box.hi.tolist(),
        "periodic": box.periodic, "profile_direction": pd, "bin_edges_m": edges.tolist(),
        "vibration": {"amplitude_m": A, "frequency_Hz": sc.vib_frequency, "direction": sc.vib_direction},
        "target_phi_bin": phi_bin.tolist(), "grains_per_bin": counts.tolist(), "packing": pinfo,
        "rsa_max": args.rsa_max,
    }
    with open(os.path.join(args.run_dir, "meta.json"), "w") as f:
        json.dump(meta, f, indent=1)
    return meta


def add_options(p):
    p.add_argument("--friction", type=float, default=0.0, help="Coulomb friction coefficient (default 0)")
    p.add_argument("--youngs", type=float, default=1e7, help="Young's modulus [Pa] (default 1e7)")
    p.add_argument("--poisson", type=float, default=0.3, help="Poisson ratio (default 0.3)")
    p.add_argument("--dt", type=float, default=0.0, help="time step [s] (default t_c(v_ref)/30)")
    p.add_argument("--v-ref", type=float, default=1.0, help="collision speed for the default dt [m/s]")
    p.add_argument("--width", type=float, default=0.0, help="extent of unresolved directions [m] (default 10 d)")
    p.add_argument("--lateral", type=float, default=0.0, help="extent of the resolved non-profile directions [m] (default: the scene's)")
    p.add_argument("--end-time", type=float, default=0.0, help="end time [s] (default: the scene's)")
    p.add_argument("--dump-interval", type=float, default=0.0, help="snapshot interval [s] (default: Output/Interval)")
    p.add_argument("--rsa-max", type=float, default=0.30, help="densest bin packed by RSA (default 0.30)")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene")
    p.add_argument("run_dir")
    p.add_argument("--seed", type=int, default=1)
    add_options(p)
    args = p.parse_args()
    try:
        meta = build(args)
    except (SceneError, ValueError, RuntimeError) as e:
        print("make_input: %s" % e, file=sys.stderr)
        return 2
    print("%s: %d grains, dt = %.4g s, %d steps, E = %g Pa (t_c = %.3g s, overlap %.2g d at %g m/s)"
          % (args.run_dir, meta["grains"], meta["dt_s"], meta["steps"], meta["youngs_modulus_Pa"],
             meta["contact_time_at_v_ref_s"], meta["max_overlap_at_v_ref_over_d"], meta["v_ref_m_s"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
