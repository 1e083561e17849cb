#!/usr/bin/python3
"""Run an ensemble of DEM (LIGGGHTS) runs of a granhydro scene, one process at a time,
and coarse-grain it.

  /usr/bin/python3 tools/dem/run_ensemble.py SCENE.prm --seeds N --out DIR
      [--first-seed 1] [--liggghts EXE] [--nice 10] [--phase-bins K --skip-time T0]
      [make_input.py options: --friction --youngs --poisson --dt --v-ref --width
       --lateral --end-time --dump-interval --rsa-max]

writes DIR/seed_NNN/ (one LIGGGHTS run each, see make_input.py), DIR/ensemble.json
(per-seed wall time, steps, grains, steps/s) and DIR/dem_profiles.csv (ensemble
mean and standard error, see coarse_grain.py). Prints a progress line every few
seconds: seed i/N, simulated time, wall time, ETA of the ensemble.
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import coarse_grain  # noqa: E402
import make_input  # noqa: E402
from scene import SceneError  # noqa: E402

THERMO = re.compile(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s*$")


def find_liggghts(exe=None):
    for c in ([exe] if exe else []) + ["liggghts", "lmp_auto", "lmp"]:
        p = shutil.which(c) if c else None
        if p:
            return p
    raise SystemExit("run_ensemble: no LIGGGHTS executable found (apt-get install liggghts, or --liggghts EXE)")


def run_one(exe, run_dir, nice, progress):
    """Run LIGGGHTS in run_dir; progress(step) is called on each thermo line.
    Returns the wall time [s]."""
    cmd = ([] if nice is None else ["nice", "-n", str(nice)]) + [exe, "-in", "in.liggghts", "-log", "log.liggghts", "-nocite"]
    t0 = time.time()
    tail = []
    with open(os.path.join(run_dir, "screen.txt"), "w") as screen:
        proc = subprocess.Popen(cmd, cwd=run_dir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        for line in proc.stdout:
            screen.write(line)
            tail = (tail + [line])[-20:]
            m = THERMO.match(line)
            if m:
                progress(int(m.group(1)))
        rc = proc.wait()
    wall = time.time() - t0
    if rc != 0 or any("ERROR" in l for l in tail):
        raise RuntimeError("LIGGGHTS failed in %s (exit %d):\n%s" % (run_dir, rc, "".join(tail)))
    return wall


def run_ensemble(args, log=print):
    exe = find_liggghts(args.liggghts)
    os.makedirs(args.out, exist_ok=True)
    seeds = list(range(args.first_seed, args.first_seed + args.seeds))
    runs, info = [], []
    t_start = time.time()
    steps_done_total = 0
    last = [0.0]
    for i, seed in enumerate(seeds):
        rd = os.path.join(args.out, "seed_%03d" % seed)
        a = argparse.Namespace(**vars(args))
        a.seed, a.run_dir = seed, rd
        tp = time.time()
        meta = make_input.build(a, log=log)
        t_pack = time.time() - tp
        nsteps, dt = meta["steps"], meta["dt_s"]
        total_steps = nsteps * len(seeds)

        def progress(step, final=False):
            now = time.time()
            if not final and now - last[0] < args.progress_interval:
                return
            last[0] = now
            done = steps_done_total + step
            el = now - t_start
            eta = "%.0f s" % (el / done * (total_steps - done)) if done > 0 else "?"
            log("seed %d/%d  t = %.4g / %.4g s  wall %.1f s  ETA %s" % (i + 1, len(seeds), step * dt, nsteps * dt, el, eta))
            sys.stdout.flush()

        wall = run_one(exe, rd, args.nice, progress)
        progress(nsteps, final=True)
        steps_done_total += nsteps
        runs.append(rd)
        info.append({"seed": seed, "run_dir": os.path.basename(rd), "grains": meta["grains"], "steps": nsteps,
                     "packing_wall_s": t_pack, "liggghts_wall_s": wall, "steps_per_s": nsteps / wall,
                     "grain_steps_per_s": nsteps * meta["grains"] / wall})
    summary = {"liggghts": exe, "seeds": info, "total_liggghts_wall_s": sum(x["liggghts_wall_s"] for x in info),
               "total_wall_s": time.time() - t_start, "options": {k: v for k, v in vars(args).items() if k not in ("out",)}}
    with open(os.path.join(args.out, "ensemble.json"), "w") as f:
        json.dump(summary, f, indent=1)
    tc = time.time()
    meta, metas, res, diags = coarse_grain.ensemble(runs, args.phase_bins, args.skip_time)
    csv = os.path.join(args.out, "dem_profiles.csv")
    coarse_grain.write_csv(csv, meta, metas, res, diags, args.phase_bins, args.skip_time, extra_comments=[
        "DEM wall time: %.2f s in LIGGGHTS over %d seeds (%.0f grain-steps/s), %.2f s in total with packing"
        % (summary["total_liggghts_wall_s"], len(info),
           sum(x["steps"] * x["grains"] for x in info) / max(summary["total_liggghts_wall_s"], 1e-9),
           summary["total_wall_s"])])
    summary["coarse_grain_wall_s"] = time.time() - tc
    with open(os.path.join(args.out, "ensemble.json"), "w") as f:
        json.dump(summary, f, indent=1)
    log("wrote %s (%d seeds, %d grains, LIGGGHTS %.1f s)" % (csv, len(info), meta["grains"], summary["total_liggghts_wall_s"]))
    return summary


def add_options(p):
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--first-seed", type=int, default=1)
    p.add_argument("--liggghts", default=None, help="LIGGGHTS executable (default: liggghts on PATH)")
    p.add_argument("--nice", type=int, default=10, help="run LIGGGHTS under nice -n NICE (default 10)")
    p.add_argument("--phase-bins", type=int, default=0, help="phase-average a vibrated scene into K bins")
    p.add_argument("--skip-time", type=float, default=0.0, help="phase averaging starts here [s]")
    p.add_argument("--progress-interval", type=float, default=5.0, help="seconds between progress lines")
    make_input.add_options(p)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene")
    p.add_argument("--out", required=True)
    add_options(p)
    args = p.parse_args()
    try:
        run_ensemble(args)
    except (SceneError, ValueError, RuntimeError) as e:
        print("run_ensemble: %s" % e, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
