#!/usr/bin/python3
"""The explicit-diffusion baseline on the hard cases: each scene runs twice,
with its own implicit diffusion step and with 'Diffusion step/Integrator = explicit
euler' (forward Euler sub-cycled at the explicit diffusive limit 0.9 / max sum_d 2D/dx_d^2,
at most 1e6 sub-steps per step, then the run stops and says where the limit collapsed),
each under a wall-clock cap. Reads the summary CSV of every run (<Base name>_summary.csv
in its output directory) and writes a Markdown table:
the smallest step of our run, the smallest explicit limit it met (and when), and how far
the explicit baseline got in the same wall time.

    /usr/bin/python3 tools/explicit_baseline.py --granhydro build/granhydro \\
        [--cap 120] [--out doc/explicit_baseline.md] [scene.prm ...]

Without scene files: parameters/hard/*-ci.prm (except overpacking-ci.prm) and
parameters/inclined_chute-ci.prm.
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import find_output_file  # noqa: E402
from granhydro.readers import read_summary  # noqa: E402


def summary(directory):
    # each run has its own directory: the one *_summary.csv there, whatever the scene's base name
    path = find_output_file(directory, "summary", required=False)
    if path is None:
        return None
    return read_summary(path)


def run(granhydro, scene, extra, directory, cap):
    text = open(scene).read() + "\n" + extra + (
        "\nsubsection Output\n  set Directory = %s\n  set Write VTU = false\n"
        "  set Write checkpoint = false\n  set Verbose = false\nend\n"
        "subsection Time\n  set Maximum wall time = %g\nend\n" % (directory, cap))
    prm = os.path.join(directory + ".prm")
    with open(prm, "w") as f:
        f.write(text)
    p = subprocess.run([granhydro, prm], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    s = summary(directory)
    if s is None:
        sys.exit("explicit_baseline: %s wrote no *_summary.csv (exit %d): %s" % (scene, p.returncode, p.stderr[-500:]))
    s["message"] = p.stderr.strip().splitlines()[-1] if p.returncode != 0 and p.stderr.strip() else ""
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--granhydro", default="build/granhydro")
    ap.add_argument("--cap", type=float, default=120, help="wall-clock cap per run [s] (default 120)")
    ap.add_argument("--out", default=None, help="Markdown file (default: stdout)")
    a = ap.parse_args()
    if not os.access(a.granhydro, os.X_OK):
        sys.exit("explicit_baseline: --granhydro %s is not an executable" % a.granhydro)
    if a.cap <= 0:
        sys.exit("explicit_baseline: --cap must be > 0 seconds")
    scenes = a.scenes or sorted(s for s in glob.glob("parameters/hard/*-ci.prm") if "overpacking" not in s) + [
        "parameters/inclined_chute-ci.prm"]
    for s in scenes:
        if not os.path.exists(s):
            sys.exit("explicit_baseline: no scene file %s" % s)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, scene in enumerate(scenes):
            name = os.path.basename(scene)[:-4]
            imp = run(a.granhydro, scene, "", os.path.join(tmp, "imp%d" % i), a.cap)
            exp = run(a.granhydro, scene, "subsection Diffusion step\n  set Integrator = explicit euler\nend\n",
                      os.path.join(tmp, "exp%d" % i), a.cap)
            rows.append((name, imp, exp))
            print("%s: ours min dt %s s (%s), explicit limit %s s; baseline %s at t = %s s" % (
                name, imp["min_dt"], imp["status"], imp["min_explicit_dt"], exp["status"], exp["time"]),
                file=sys.stderr)
    out = ["| hard case | our smallest dt [s] | steps, rejected | wall [s] | smallest explicit limit met [s] (at t [s]) | ratio | explicit baseline: reached t [s] of | its sub-steps | its smallest sub-step [s] | its wall [s] | how it ended |",
           "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name, imp, exp in rows:
        lim = float(imp["min_explicit_dt"])
        ratio = float(imp["min_dt"]) / lim if lim > 0 else float("nan")
        how = exp["status"]
        if exp["message"]:
            how += ": " + exp["message"].replace("|", "/")[:160]
        out.append("| %s | %.3g | %s, %s | %.1f | %.3g (%.3g) | %.3g | %.3g of %s | %s | %.3g | %.1f | %s |" % (
            name, float(imp["min_dt"]), imp["steps"], imp["rejected_steps"], float(imp["wall_seconds"]), lim,
            float(imp["min_explicit_dt_time"]), ratio, float(exp["time"]), imp["time"], exp["explicit_substeps"],
            float(exp["min_explicit_dt"]), float(exp["wall_seconds"]), how))
    text = "\n".join(out) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
