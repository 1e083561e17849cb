#!/usr/bin/python3
"""Sensitivity of the 1D sedimentation column to the dense (Johnson-Jackson) closure.

Runs the 1D sedimentation column (parameters/sedimentation_column_1d.prm) with
the paper's sedimentation temperature T0 = 3.4e-7 J to t = 0.2 s, varying one
parameter of 'Dense closure' at a time around the reference point

    F = 0.05 Pa, phi_min = 0.62, r = 2, s = 5, t_f = 0.5 s, theta_f = 28.5 deg

(all six are always set explicitly, so built-in defaults of the binary do not
matter), plus the closure switched off (Model = none, the paper's model), which
stops at close packing. With --paper-runs it also runs the paper's model with
the paper's fixed time step (Numerics/Fixed time step = 1e-6 s).

Each variant is the base scene with override blocks appended (a later 'set'
wins) and runs in its own directory under --workdir. From the profiles CSV
(out/<Base name>_profiles.csv, the base scene's Output/Base name) it reports,
at t = 0.1, 0.15, 0.2 s:

  floor phi    packing fraction of the lowest cell
  pile height  top of the highest cell with phi >= 0.5 (0 if there is none)
  front height top of the highest cell with phi > 0.05 (upper edge of the gas)
  T pile       mean temperature of the cells with phi >= 0.5 [J]

and from out/<Base name>_summary.csv the steps, rejected steps, temperature repairs and
wall seconds. The Markdown tables are printed on stdout (and written with
--markdown); --plot writes a figure.

Example:
    python3 tools/closure_sensitivity.py --granhydro build/granhydro \
        --jobs 2 --paper-runs --markdown closure.md --plot closure.png
"""

import argparse
import concurrent.futures
import dataclasses
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import find_output_file  # noqa: E402
from granhydro.readers import blocks, read_profiles, read_summary  # noqa: E402

REFERENCE = {
    "Coefficient": 0.05,
    "Minimum packing fraction": 0.62,
    "Exponent r": 2,
    "Exponent s": 5,
    "Viscosity time": 0.5,
    "Friction angle": 28.5,
}

# (parameter entry, short label, unit, values)
FAMILIES = [
    ("Coefficient", "F", "Pa", [0.005, 0.05, 0.5]),
    ("Minimum packing fraction", "phi_min", "", [0.5, 0.6, 0.61, 0.62, 0.63]),
    ("Exponent r", "r", "", [1, 2, 3]),
    ("Exponent s", "s", "", [3, 5, 8]),
    ("Viscosity time", "t_f", "s", [0, 0.5, 5]),
    ("Friction angle", "angle", "deg", [15, 28.5, 40]),
]

TEMPERATURE = 3.4e-7  # J, the paper's sedimentation conditions
END_TIME = 0.2
OUTPUT_INTERVAL = 0.05
REPORT_TIMES = (0.1, 0.15, 0.2)
PILE_PHI = 0.5
FRONT_PHI = 0.05
PAPER_FIXED_DT = 1e-6


@dataclasses.dataclass
class Run:
    """One variant of the scene and, after running, what it produced."""

    name: str
    model: str = "johnson-jackson"
    closure: dict = dataclasses.field(default_factory=lambda: dict(REFERENCE))
    fixed_dt: float = 0.0
    returncode: int = None
    timed_out: bool = False
    summary: dict = dataclasses.field(default_factory=dict)
    profiles: dict = dataclasses.field(default_factory=dict)  # time -> array
    stop: dict = dataclasses.field(default_factory=dict)
    stop_message: str = ""
    last_progress: str = ""
    elapsed: float = 0.0


def scene_text(base, run):
    """The base scene followed by the override blocks of this run."""
    lines = [base.rstrip("\n"), "", "# --- overrides (closure_sensitivity.py) ---",
             "subsection Dense closure", f"  set Model = {run.model}"]
    lines += [f"  set {key} = {value:g}" for key, value in run.closure.items()]
    lines += ["end",
              "subsection Initial state", f"  set Temperature = {TEMPERATURE:g}", "end",
              "subsection Time", f"  set End time = {END_TIME:g}", "end",
              "subsection Output", "  set Directory = out",
              f"  set Interval = {OUTPUT_INTERVAL:g}", "end"]
    if run.fixed_dt > 0:
        lines += ["subsection Numerics", f"  set Fixed time step = {run.fixed_dt:g}", "end"]
    return "\n".join(lines) + "\n"


def profile_blocks(path):
    """profiles CSV of a 1D run -> {time: array with columns x, n, nu, nE, phi, T, ...}
    (the columns after time)."""
    columns, times = read_profiles(path)
    names = list(columns)[1:]
    return {t: np.column_stack([b[n] for n in names]) for t, b in blocks(columns, times).items()}


def parse_log(text):
    """The over-packing diagnostic, the stop message (without the advice) and
    the last progress line of a run log."""
    stop = {}
    m = re.search(r"over-packing at t = ([0-9.eE+-]+) s.*?phi = ([0-9.eE+-]+) "
                  r"at x = \(([^)]*)\) m, and (\d+) cell\(s\) at phi >= ([0-9.eE+-]+) "
                  r"hold ([0-9.eE+-]+) %", text, re.S)
    if m:
        stop = {"time": float(m.group(1)), "phi": float(m.group(2)),
                "x": m.group(3), "cells": int(m.group(4)),
                "cells_phi": float(m.group(5)), "mass_percent": float(m.group(6))}
    m = re.search(r"run stopped: (.*)$", text, re.M)
    message = m.group(1).split(" Lower '")[0].split(" Kinetic theory")[0] if m else ""
    progress = re.findall(r"^\s*t = .*step \d+.*$", text, re.M)
    return stop, message, (progress[-1].strip() if progress else "")


def execute(run, args, base):
    """Write the scene, run granhydro in the run's directory, collect results."""
    directory = Path(args.workdir) / run.name
    if directory.exists():
        shutil.rmtree(directory)
    directory.mkdir(parents=True)
    (directory / "scene.prm").write_text(scene_text(base, run))
    env = dict(os.environ)
    if args.library_path:
        env["LD_LIBRARY_PATH"] = os.pathsep.join(
            p for p in (args.library_path, env.get("LD_LIBRARY_PATH", "")) if p)
    start = time.monotonic()
    with open(directory / "log.txt", "w") as log:
        proc = subprocess.Popen([args.granhydro, "scene.prm"], cwd=directory,
                                stdout=log, stderr=subprocess.STDOUT, env=env)
        try:
            run.returncode = proc.wait(timeout=args.timeout or None)
        except subprocess.TimeoutExpired:
            proc.kill()
            run.returncode = proc.wait()
            run.timed_out = True
    run.elapsed = time.monotonic() - start
    text = (directory / "log.txt").read_text(errors="replace")
    run.stop, run.stop_message, run.last_progress = parse_log(text)
    (directory / "exit_code.txt").write_text(f"{run.returncode}\n")
    # the run's own out/ holds one run: its *_profiles.csv, *_summary.csv (or the
    # un-prefixed names of an older granhydro)
    profiles = find_output_file(str(directory / "out"), "profiles", required=False)
    if profiles:
        run.profiles = profile_blocks(profiles)
    summary = find_output_file(str(directory / "out"), "summary", required=False)
    if summary:
        run.summary = read_summary(summary)
    return run


def profile_at(run, t):
    for time_s, block in run.profiles.items():
        if abs(time_s - t) < 1e-9:
            return block
    return None


def metrics(block):
    """Figures of one profile (x ascending from the floor).

    floor_phi, pile [m], front [m], T_pile [J] as in the module docstring, and
    level [m]: the phi = 0.5 level interpolated linearly between the highest
    pile cell and the cell above it; pile_grains [%]: share of the grains in
    the pile cells; T_layer [J]: mean T of the cells with 0.05 < phi < 0.5
    (the settling layer between the pile and the front); T_top [J]: T of the
    highest cell (the dilute gas left behind by the falling column).
    """
    x, phi, temperature = block[:, 0], block[:, 4], block[:, 5]
    half = 0.5 * (x[1] - x[0])
    pile = phi >= PILE_PHI
    gas = phi > FRONT_PHI
    layer = gas & ~pile
    nan = float("nan")
    level = 0.0
    if pile.any():
        i = np.nonzero(pile)[0].max()
        level = x[i] + half if i + 1 == len(x) else \
            x[i] + (phi[i] - PILE_PHI) / (phi[i] - phi[i + 1]) * (x[i + 1] - x[i])
    return {"floor_phi": phi[np.argmin(x)],
            "pile": x[pile].max() + half if pile.any() else 0.0,
            "front": x[gas].max() + half if gas.any() else 0.0,
            "T_pile": temperature[pile].mean() if pile.any() else nan,
            "level": level,
            "pile_grains": 100 * phi[pile].sum() / phi.sum(),
            "T_layer": temperature[layer].mean() if layer.any() else nan,
            "T_top": temperature[np.argmax(x)]}


def fmt_series(run, key, fmt):
    out = []
    for t in REPORT_TIMES:
        block = profile_at(run, t)
        if block is None:
            out.append("—")
            continue
        value = metrics(block)[key]
        out.append("—" if np.isnan(value) else fmt(value))
    return " / ".join(out)


def summary_int(run, key):
    return run.summary.get(key, "—")


def summary_float(run, key, fmt="{:.1f}"):
    return fmt.format(float(run.summary[key])) if key in run.summary else "—"


MM = lambda v: f"{1e3 * v:.1f}"  # noqa: E731
PHI = lambda v: f"{v:.4f}"  # noqa: E731
TEMP = lambda v: f"{v:.2e}"  # noqa: E731


def sensitivity_table(runs, families):
    head = ("| parameter | value | exit | floor phi | pile height [mm] | front height [mm] "
            "| T pile [J] | steps | rejected | T repairs | wall [s] |")
    lines = [f"Values at t = {' / '.join(f'{t:g}' for t in REPORT_TIMES)} s; "
             "reference values in bold.", "", head,
             "|" + "|".join(["---"] * 11) + "|"]
    for entry, label, unit, values in families:
        for value in values:
            run = runs[run_name(label, value)]
            shown = f"**{value:g}**" if value == REFERENCE[entry] else f"{value:g}"
            lines.append(
                f"| {label}{' [' + unit + ']' if unit else ''} | {shown} | {run.returncode} "
                f"| {fmt_series(run, 'floor_phi', PHI)} | {fmt_series(run, 'pile', MM)} "
                f"| {fmt_series(run, 'front', MM)} | {fmt_series(run, 'T_pile', TEMP)} "
                f"| {summary_int(run, 'steps')} | {summary_int(run, 'rejected_steps')} "
                f"| {summary_int(run, 'temperature_repairs')} "
                f"| {summary_float(run, 'wall_seconds')} |")
    off = runs["closure_off"]
    lines.append(
        f"| Model | none | {off.returncode} | {fmt_series(off, 'floor_phi', PHI)} "
        f"| {fmt_series(off, 'pile', MM)} | {fmt_series(off, 'front', MM)} "
        f"| {fmt_series(off, 'T_pile', TEMP)} | {summary_int(off, 'steps')} "
        f"| {summary_int(off, 'rejected_steps')} | {summary_int(off, 'temperature_repairs')} "
        f"| {summary_float(off, 'wall_seconds')} |")
    lines += [""]
    shown = [run_name(label, value) for _, label, _, values in families for value in values]
    lines += [last_state_text(runs[name]) + "\n"
              for name in dict.fromkeys(shown + ["closure_off"]) if runs[name].returncode != 0]
    return "\n".join(lines)


def extra_table(runs, families, t=END_TIME):
    """Finer figures at one time: the cell-resolution pile height hides the
    closure's effect on the pile, the interpolated phi = 0.5 level shows it."""
    head = ("| parameter | value | floor phi | phi = 0.5 level [mm] | grains in pile [%] "
            "| T pile [J] | T layer 0.05<phi<0.5 [J] | T top cell [J] |")
    lines = [f"At t = {t:g} s (runs that stopped earlier are left out).", "", head,
             "|" + "|".join(["---"] * 8) + "|"]
    for entry, label, unit, values in families:
        for value in values:
            block = profile_at(runs[run_name(label, value)], t)
            if block is None:
                continue
            m = metrics(block)
            shown = f"**{value:g}**" if value == REFERENCE[entry] else f"{value:g}"
            lines.append(
                f"| {label}{' [' + unit + ']' if unit else ''} | {shown} | {m['floor_phi']:.4f} "
                f"| {1e3 * m['level']:.2f} | {m['pile_grains']:.1f} | {m['T_pile']:.2e} "
                f"| {m['T_layer']:.2e} | {m['T_top']:.2e} |")
    return "\n".join(lines)


def last_state_text(run):
    """One sentence on where and when a run stopped, with its last profile."""
    if not run.profiles:
        return f"`{run.name}`: no profiles written."
    t_last = max(run.profiles)
    m = metrics(run.profiles[t_last])
    text = f"`{run.name}` (exit {run.returncode}, status {run.summary.get('status', '?')})"
    if run.timed_out:
        text += f": killed at the time limit; last progress line '{run.last_progress}'"
    elif run.stop:
        s = run.stop
        text += (f": over-packing at t = {s['time']:g} s, phi = {s['phi']:g} in the cell "
                 f"at x = {s['x']} m; {s['cells']} cell(s) at phi >= {s['cells_phi']:g} "
                 f"hold {s['mass_percent']:g} % of the grains")
    elif run.stop_message:
        text += f": {run.stop_message.rstrip('.')}"
    text += (f". Last profile written at t = {t_last:.6g} s: floor phi {m['floor_phi']:.4f}, "
             f"pile height {1e3 * m['pile']:.1f} mm, front {1e3 * m['front']:.1f} mm, "
             f"T pile {m['T_pile']:.2e} J.")
    return text


def paper_table(runs):
    head = ("| run | time step | exit | stopped at t [s] | over-packed cell x [m] "
            "| floor phi at 0.05 / 0.1 s | floor phi at last output | steps | rejected "
            "| dt min .. max [s] | wall [s] |")
    lines = [head, "|" + "|".join(["---"] * 11) + "|"]
    for name, step in (("closure_off", "CFL 0.4"),
                       ("paper_fixed_dt", f"fixed {PAPER_FIXED_DT:g} s")):
        if name not in runs:
            continue
        run = runs[name]
        floor = []
        for t in (0.05, 0.1):
            block = profile_at(run, t)
            floor.append("—" if block is None else f"{metrics(block)['floor_phi']:.4f}")
        last = max(run.profiles) if run.profiles else None
        last_text = "—" if last is None else \
            f"{metrics(run.profiles[last])['floor_phi']:.4f} (t = {last:.6g})"
        stop_t = f"{run.stop['time']:.6g}" if run.stop else \
            (f"killed after {run.elapsed:.0f} s wall ({run.last_progress})" if run.timed_out
             else "—")
        dt = (f"{float(run.summary['min_dt']):.3g} .. {float(run.summary['max_dt']):.3g}"
              if "min_dt" in run.summary else "—")
        lines.append(
            f"| {name} | {step} | {run.returncode} | {stop_t} "
            f"| {run.stop.get('x', '—')} | {' / '.join(floor)} | {last_text} "
            f"| {summary_int(run, 'steps')} | {summary_int(run, 'rejected_steps')} | {dt} "
            f"| {summary_float(run, 'wall_seconds')} |")
    return "\n".join(lines)


def run_name(label, value):
    return f"{label}_{value:g}"


def build_runs(paper_runs):
    """One run per table row (the reference point recurs; see deduplicate)."""
    runs = {}
    for entry, label, _, values in FAMILIES:
        for value in values:
            closure = dict(REFERENCE)
            closure[entry] = value
            runs[run_name(label, value)] = Run(run_name(label, value), closure=closure)
    runs["closure_off"] = Run("closure_off", model="none")
    if paper_runs:
        runs["paper_fixed_dt"] = Run("paper_fixed_dt", model="none", fixed_dt=PAPER_FIXED_DT)
    return runs


def deduplicate(runs):
    """Map each run to the first run with the same scene (the reference point
    appears in every family)."""
    canonical, alias = {}, {}
    for name, run in runs.items():
        key = (run.model, tuple(sorted(run.closure.items())), run.fixed_dt)
        alias[name] = canonical.setdefault(key, name)
    return alias


def plot(runs, path):
    """Floor phi and the phi = 0.5 level at the end time against each closure
    parameter (common axes, so the panels compare), and profiles at the end."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 3, figsize=(15, 13), constrained_layout=True)
    for ax, (entry, label, unit, values) in zip(axes.flat, FAMILIES):
        floor, level = [], []
        for value in values:
            run = runs[run_name(label, value)]
            block = profile_at(run, END_TIME)
            m = metrics(block) if block is not None else None
            floor.append(m["floor_phi"] if m else np.nan)
            level.append(1e3 * m["level"] if m else np.nan)
            if m is None and run.profiles:
                ax.annotate(f"stopped at\nt = {max(run.profiles):.4g} s", (value, 0.5),
                            xycoords=("data", "axes fraction"), ha="center", fontsize=9)
        ax.plot(values, floor, "o-", color="C0")
        ax.set_ylim(0.57, 0.645)
        ax.set_ylabel(f"floor phi at {END_TIME:g} s", color="C0")
        ax.axhline(0.64, color="grey", ls=":", lw=1)
        ax.axvline(REFERENCE[entry], color="grey", ls="--", lw=0.8)
        twin = ax.twinx()
        twin.plot(values, level, "s--", color="C3")
        twin.set_ylim(12.5, 14.5)
        twin.ticklabel_format(useOffset=False)
        twin.set_ylabel(f"phi = 0.5 level at {END_TIME:g} s [mm]", color="C3")
        if label == "F":
            ax.set_xscale("log")
            ax.set_xlim(min(values) / 2, max(values) * 2)
        else:
            pad = 0.08 * (max(values) - min(values))
            ax.set_xlim(min(values) - pad, max(values) + pad)
        ax.set_xlabel(f"{entry} ({label}" + (f" [{unit}]" if unit else "") + ")")
    ax_phi, ax_T, ax_hist = axes.flat[6], axes.flat[7], axes.flat[8]
    values = next(f[3] for f in FAMILIES if f[1] == "phi_min")
    for i, value in enumerate(values):
        block = profile_at(runs[run_name("phi_min", value)], END_TIME)
        if block is None:
            continue
        ax_phi.plot(1e3 * block[:, 0], block[:, 4], color=f"C{i}", label=f"phi_min = {value:g}")
        ax_T.semilogy(1e3 * block[:, 0], block[:, 5], color=f"C{i}", label=f"phi_min = {value:g}")
    off = runs["closure_off"]
    if off.profiles:
        t_last = max(off.profiles)
        block = off.profiles[t_last]
        label = f"Model = none, t = {t_last:.4g} s"
        ax_phi.plot(1e3 * block[:, 0], block[:, 4], "k:", label=label)
        ax_T.semilogy(1e3 * block[:, 0], block[:, 5], "k:", label=label)
    ax_phi.set(xlabel="height x [mm]", ylabel="phi", xlim=(0, 30),
               title=f"phi(x) at t = {END_TIME:g} s, phi_min variants")
    ax_T.set(xlabel="height x [mm]", ylabel="T [J]",
             title=f"T(x) at t = {END_TIME:g} s, phi_min variants")
    ax_phi.legend(fontsize=8)
    ax_T.legend(fontsize=8)
    ref = runs[run_name("F", REFERENCE["Coefficient"])]
    for t in sorted(ref.profiles):
        block = ref.profiles[t]
        ax_hist.plot(1e3 * block[:, 0], block[:, 4], label=f"t = {t:g} s")
    ax_hist.set(xlabel="height x [mm]", ylabel="phi", title="reference closure: phi(x) over time")
    ax_hist.legend(fontsize=8)
    fig.suptitle(f"1D sedimentation column, T0 = {TEMPERATURE:g} J: dense-closure sensitivity "
                 f"(dashed vertical line = reference value)")
    fig.savefig(path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--granhydro", default=shutil.which("granhydro") or "granhydro",
                        help="granhydro binary (default: granhydro on PATH)")
    parser.add_argument("--library-path", default="",
                        help="prepended to LD_LIBRARY_PATH for the binary")
    parser.add_argument("--base-scene", default=str(
        Path(__file__).resolve().parent.parent / "parameters" / "sedimentation_column_1d.prm"),
        help="scene the overrides are appended to (default: ../parameters/ of this script)")
    parser.add_argument("--workdir", default="closure_sensitivity_runs",
                        help="one sub-directory per run is created here")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time")
    parser.add_argument("--timeout", type=float, default=0,
                        help="kill a run after this many wall seconds (0 = none)")
    parser.add_argument("--paper-runs", action="store_true",
                        help=f"also run Model = none with Fixed time step = {PAPER_FIXED_DT:g} s")
    parser.add_argument("--markdown", help="also write the tables to this file")
    parser.add_argument("--plot", help="write a figure (PNG) to this file")
    args = parser.parse_args()

    base = Path(args.base_scene).read_text()
    runs = build_runs(args.paper_runs)
    alias = deduplicate(runs)
    unique = [name for name in runs if alias[name] == name]
    # longest run first, so that it overlaps with the others
    unique.sort(key=lambda name: -runs[name].fixed_dt)
    lock = threading.Lock()
    done = [0]

    def job(name):
        run = execute(runs[name], args, base)
        with lock:
            done[0] += 1
            status = run.summary.get("status", "no summary")
            print(f"[{done[0]}/{len(unique)}] {name}: exit {run.returncode} ({status}"
                  f"{', killed at timeout' if run.timed_out else ''}), "
                  f"{run.summary.get('steps', '?')} steps, {run.elapsed:.1f} s",
                  file=sys.stderr, flush=True)
        return run

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        list(pool.map(job, unique))
    for name, canonical in alias.items():
        if name != canonical:
            result = dataclasses.replace(runs[canonical], name=name, closure=runs[name].closure)
            runs[name] = result

    text = ("## Dense-closure sensitivity\n\n" + sensitivity_table(runs, FAMILIES)
            + "\n" + extra_table(runs, FAMILIES) + "\n")
    if args.paper_runs:
        text += "\n## The paper's model (Model = none)\n\n" + paper_table(runs) + "\n"
        text += "\n" + last_state_text(runs["paper_fixed_dt"]) + "\n"
    print(text)
    if args.markdown:
        Path(args.markdown).write_text(text)
    if args.plot:
        plot(runs, args.plot)


if __name__ == "__main__":
    main()
