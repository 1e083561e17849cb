#!/usr/bin/env python3
"""ctest input.fuzz_corpus: a fixed corpus of broken scenes that granhydro must refuse.

The corpus is regenerated deterministically by the mutation fuzzer
(tools/fuzz_scenes.py, corpus_cases(): fixed seed, only cases whose mutation makes the
scene invalid, spread over the mutation classes and the committed scenes).  Each case
is checked like tests/input/bad_input/check_bad_input.cmake does, but with `--check`:

  - exit code exactly 2 (bad input), no signal, no timeout (30 s),
  - stderr names the parameter ('Section/Name', "entry named X") or the offending line
    ("Line <N>", the right one), or a whole-file condition as such (empty scene,
    include cycle, missing include),
  - no crash text ("internal error", "Stacktrace", "Aborted", "terminate called",
    "MPI_ABORT", ...),
  - the (empty) working directory stays empty.

  /usr/bin/python3 tests/input/fuzz/fuzz_corpus.py --exe build/granhydro [--jobs 2]
  /usr/bin/python3 tests/input/fuzz/fuzz_corpus.py --list                 # the cases
  /usr/bin/python3 tests/input/fuzz/fuzz_corpus.py --exe X --only sod_1d:numeric:003 --write /tmp/repro

Exit status 0 when every case passes, 1 otherwise (every failing case is listed with
its mutation, the diff from its base scene and granhydro's stderr).
"""
import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent.parent
sys.path.insert(0, str(REPO / 'tools'))
import fuzz_scenes as fz  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--exe', help='the granhydro executable')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--workdir', help='folder for the scratch folder (default: the system temporary folder)')
    ap.add_argument('--timeout', type=float, default=30)
    ap.add_argument('--only', help='comma-separated substrings of case ids to run')
    ap.add_argument('--list', action='store_true', help='list the cases and exit')
    ap.add_argument('--write', help='write the scene trees of the failing (or --only) cases here')
    a = ap.parse_args()

    cases = fz.corpus_cases()
    # admission: scenes inside the documented limits that --check may accept, but then the
    # run must take its first steps (no exit 3)
    run_cases = fz.admission_run_cases()
    if a.only:
        keys = a.only.split(',')
        cases = [c for c in cases if any(k in c.cid for k in keys)]
        run_cases = [c for c in run_cases if any(k in c.cid for k in keys)]
    if a.list:
        for c in cases:
            print(f'{c.cid:45s} {c.desc}')
        for c in run_cases:
            print(f'{c.cid:45s} (check, then run) {c.desc}')
        print(f'{len(cases)} cases to refuse, {len(run_cases)} to refuse or run', file=sys.stderr)
        return 0
    if not a.exe or not Path(a.exe).exists():
        ap.error(f'--exe: executable {a.exe!r} does not exist')

    t0 = time.time()
    if a.workdir:
        Path(a.workdir).mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix='granhydro-fuzz-corpus-', dir=a.workdir))
    # 2 GiB of address space: plenty for --check, and a scene that makes granhydro allocate
    # without bound fails fast (std::bad_alloc) instead of exhausting the machine
    runner = fz.Runner(a.exe, scratch, jobs=a.jobs, check_timeout=a.timeout, mem_gib=2)
    print(f'fuzz corpus: {len(cases)} scenes that must be refused, {len(run_cases)} that must be refused '
          f'or run, {a.jobs} in parallel, exe {runner.exe}', flush=True)
    runner.prepare(cases + run_cases)  # the checkpoints of another mesh
    results = runner.map(runner.check, cases, 'corpus')
    failing = []
    for c, r in zip(cases, results):
        problems = []
        o = r['outcome']
        if o == 'hang':
            problems.append(f'no answer within {a.timeout:g} s')
        elif o == 'crash':
            problems.append(f"crash: exit code {r['rc']}" + (f", stderr contains '{r['marker']}'" if r.get('marker') else ''))
        elif o.startswith('accepted'):
            problems.append('accepted (exit code 0): the scene is invalid (' + c.invalid + ')')
        elif o == 'refused-unclear':
            problems.append('exit 2, but the message names neither the parameter nor the line')
        elif o == 'refused-misleading':
            problems.append('exit 2, but the message points elsewhere: ' + r.get('misleading', ''))
        elif o == 'harness-error':
            problems.append('harness error: ' + r['stderr'])
        if r.get('leftovers'):
            problems.append('left files in the working directory: ' + ', '.join(r['leftovers']))
        if r.get('seconds', 0) > a.timeout:
            problems.append(f"took {r['seconds']} s")
        if problems:
            failing.append((c, r, problems))
    # the run phase: refused cleanly by --check, or accepted and then 3 steps with exit 0
    run_checks = runner.map(runner.check, run_cases, 'admission check')
    accepted = [c for c, r in zip(run_cases, run_checks) if r['outcome'] == 'accepted']
    run_results = dict(zip([c.cid for c in accepted], runner.map(runner.run, accepted, 'admission run')))
    n_ran = 0
    for c, r in zip(run_cases, run_checks):
        problems = []
        o = r['outcome']
        if o == 'accepted':
            n_ran += 1
            rr = run_results[c.cid]
            if rr['outcome'] != 'run-ok':
                problems.append(f"--check accepted it, the run ended {rr['outcome']} (exit {rr['rc']}): "
                                + rr['stderr'].strip()[-500:])
        elif o != 'refused':
            problems.append(f"--check: {o} (exit {r['rc']})")
        if problems:
            failing.append((c, r, problems))
    print(f'admission: {len(run_cases)} extreme scenes inside the documented limits, '
          f'{len(run_cases) - n_ran} refused by --check, {n_ran} run')
    cases = cases + run_cases
    results = results + run_checks
    base = {}
    for c, r, problems in failing:
        if c.scene not in base:
            base[c.scene] = (REPO / c.scene).read_text(encoding=fz.ENC, errors=fz.ERRS)
        print(f'\nFAIL {c.cid}: {c.desc}')
        for p in problems:
            print(f'  - {p}')
        print(f'  base scene: {c.scene}; change:')
        print('    ' + fz.diff_text(base[c.scene], c.text, 200).replace('\n', '\n    '))
        for k, v in c.files.items():
            print(f'    (+ file {k}: {fz.shorten(v or "", 80)})')
        err = r['stderr'].strip()
        print('  stderr: ' + (err[:600].replace('\n', '\n          ') if err else '(empty)'))
    if a.write:
        for c in ([f[0] for f in failing] if not a.only else cases):
            fz.write_repro(c, Path(a.write) / c.cid.replace(':', '_').replace('/', '_'), REPO)
        print(f'\nscene trees written to {a.write}')
    shutil.rmtree(scratch, ignore_errors=True)
    dt = time.time() - t0
    print(f'\nfuzz corpus: {len(cases) - len(failing)} of {len(cases)} passed (refused properly, or run), '
          f'{len(failing)} failing, {dt:.0f} s')
    slow = sorted(zip(results, cases), key=lambda rc: -rc[0].get('seconds', 0))[:3]
    print('slowest: ' + ', '.join(f"{c.cid} {r.get('seconds', 0):.1f} s" for r, c in slow))
    if failing:
        print('failing cases: ' + ' '.join(c.cid for c, _, _ in failing))
    return 1 if failing else 0


if __name__ == '__main__':
    sys.exit(main())
