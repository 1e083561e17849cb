#!/usr/bin/python3
"""Mutation fuzzer for granhydro scene files (deal.II ParameterHandler *.prm).

Every committed scene (parameters/*.prm, parameters/hard/*.prm) is mutated
deterministically (seeded) into many broken or unusual variants.  Each variant
is validated with `granhydro --check` in its own empty working directory and
classified:

  refused             exit 2, stderr names a parameter ('Section/Name', or deal.II's
                      "entry named X") or a line ("Line <N>"), no crash text, working
                      directory left empty
  refused-unclear     exit 2 but the message names neither a parameter nor a line
  refused-misleading  exit 2 naming a line that is not the offending one (or a line
                      beyond the end of the file, or the main file for an error that
                      sits in an included file)
  refused-dirty       exit 2 but files were left in the working directory
  accepted            exit 0 (a *silent acceptance* defect when the mutation made the
                      scene clearly invalid)
  accepted-dirty      exit 0 but --check wrote files
  crash               signal, exit 1/other, or crash text on stderr ("internal error",
                      "Stacktrace", "Aborted", "terminate called", "MPI_ABORT", ...)
  hang                --check exceeded its timeout (30 s)

Variants accepted by --check are then run for real with 'Time/Maximum steps' forced to
a few steps and 'Output/Directory' inside the temporary working directory, and
classified run-ok / run-fail (exit 3, message recorded) / run-refused (exit 2: --check
and the run disagree) / run-crash / run-hang.  Scenes whose unmutated base run is
slower than --slow-base seconds are not run (the check phase still covers them).

  /usr/bin/python3 tools/fuzz_scenes.py --exe build/granhydro --per-scene 40 --jobs 2 --out fuzz-out
  /usr/bin/python3 tools/fuzz_scenes.py --list --per-scene 5          # print the cases only
  /usr/bin/python3 tools/fuzz_scenes.py --dump DIR                    # write the cases as files

Report: <out>/report.json (counts; every defect with its reproducer diff and stderr),
<out>/cases.csv (one row per case) and <out>/repro/<case>/ (reproducer scene trees of
the defects).  Mutation classes: see CLASSES below and tests/input/fuzz/README.md.
tests/input/fuzz/fuzz_corpus.py reuses the generator (corpus_cases()) for the ctest corpus.
"""
from __future__ import annotations

import argparse
import csv
import difflib
import json
import math
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
ENC = 'utf-8'
ERRS = 'surrogateescape'

# =====================================================================================
# Parameter table: key, kind, default, pattern lo, pattern hi (from `--print-parameters`
# and the deal.II patterns the binary reports).  Kinds: int, real, bool, sel:<a|b>,
# reals, ints (comma lists, granhydro-parsed), expr, exprs (';' list), consts, file,
# dir, name.
# =====================================================================================
INF = float('inf')
_TABLE = r"""
Dimension|int|2|1|3
Adaptivity/Buffer|int|2|0|8
Adaptivity/Coarsen threshold|real|0.01|0|inf
Adaptivity/Indicator|sel:jumps|second differences|jumps||
Adaptivity/Interval|int|5|1|2147483647
Adaptivity/Maximum level|int|0|0|7
Adaptivity/Refine threshold|real|0.05|0|inf
Dense closure/Coefficient|real|0.05|0|inf
Dense closure/Exponent r|real|2|1|10
Dense closure/Exponent s|real|5|1.5|20
Dense closure/Friction angle|real|28.5|0|90
Dense closure/Minimum packing fraction|real|0.62|0|1
Dense closure/Model|sel:none|johnson-jackson|none||
Dense closure/Viscosity time|real|0.5|0|inf
Diffusion step/Integrator|sel:gauss-legendre|implicit midpoint|sdirk2|rkl2|cost-based|automatic|explicit euler|cost-based||
Diffusion step/Jacobian|sel:lagged|full|lagged||
Diffusion step/Linear forcing|sel:eisenstat-walker|fixed|eisenstat-walker||
Diffusion step/Linear solver tolerance|real|1e-12|0|1
Diffusion step/Newton maximum iterations|int|25|1|200
Diffusion step/Newton tolerance|real|1e-10|0|1
Diffusion step/Preconditioner|sel:block ilu|ilu|amg|block ilu||
Diffusion step/Reuse Newton matrix|bool|true||
Domain/Boundary x+|sel:periodic|slip wall|no-slip wall|outflow|slip wall||
Domain/Boundary x-|sel:periodic|slip wall|no-slip wall|outflow|slip wall||
Domain/Boundary y+|sel:periodic|slip wall|no-slip wall|outflow|slip wall||
Domain/Boundary y-|sel:periodic|slip wall|no-slip wall|outflow|slip wall||
Domain/Boundary z+|sel:periodic|slip wall|no-slip wall|outflow|slip wall||
Domain/Boundary z-|sel:periodic|slip wall|no-slip wall|outflow|slip wall||
Domain/Cells|ints|100, 100, 1||
Domain/Lower corner|reals|0, 0, 0||
Domain/Mesh file|file|||
Domain/Mesh refinements|int|0|0|8
Domain/Upper corner|reals|0.1, 0.1, 0.1||
Domain/Wall restitution x+|real|1|0|1
Domain/Wall restitution x-|real|1|0|1
Domain/Wall restitution y+|real|1|0|1
Domain/Wall restitution y-|real|1|0|1
Domain/Wall restitution z+|real|1|0|1
Domain/Wall restitution z-|real|1|0|1
Domain/Wall velocity x+|reals|0, 0, 0||
Domain/Wall velocity x-|reals|0, 0, 0||
Domain/Wall velocity y+|reals|0, 0, 0||
Domain/Wall velocity y-|reals|0, 0, 0||
Domain/Wall velocity z+|reals|0, 0, 0||
Domain/Wall velocity z-|reals|0, 0, 0||
Effects/Convection|bool|true||
Effects/Cooling|bool|true||
Effects/Diffusive flux|sel:full|diagonal|full||
Effects/Gravity|reals|0, 0, 0||
Effects/Heat conduction|bool|true||
Effects/Vibration amplitude|real|0|0|inf
Effects/Vibration direction|sel:x|y|z|y||
Effects/Vibration frequency|real|0|0|inf
Effects/Viscosity|bool|true||
Initial state/Checkpoint|file|||
Initial state/Constants|consts|||
Initial state/Packing fraction|expr|0.01||
Initial state/Quadrature points|int|3|1|8
Initial state/Temperature|expr|1e-8||
Initial state/Velocity|exprs|0; 0; 0||
Material/Adiabatic index|real|1.6666666666666667|1|3
Material/Close packing fraction|real|0.64|0|1
Material/Close packing guard|real|1e-3|0|0.1
Material/Freezing packing fraction|real|0.49|0|1
Material/Grain diameter|real|1e-3|0|inf
Material/Material density|real|2600|0|inf
Material/Maximum mean free path|real|0|0|inf
Material/Model|sel:ideal gas|granular|ideal gas||
Material/Restitution coefficient|real|1|0|1
Numerics/CFL number|real|0.4|0|1
Numerics/Face quadrature|sel:gauss|midpoint|gauss||
Numerics/Fixed time step|real|0|0|inf
Numerics/Flux|sel:musta|rusanov|hll|musta||
Numerics/MUSTA local CFL|real|0.9|0|1
Numerics/MUSTA maximum stages|int|4|1|20
Numerics/MUSTA tolerance|real|0.01|0|1
Numerics/Maximum step retries|int|6|0|30
Numerics/No-slip wall flux|sel:mirror|pressure|mirror||
Numerics/Reconstruction|sel:first order|muscl|weno3|weno5|weno5||
Numerics/Reference velocity|real|0|0|inf
Output/Base name|name|solution||
Output/Cross-section direction|sel:none|x|y|z|none||
Output/Directory|dir|output||
Output/Interval|real|0|0|inf
Output/Profile direction|sel:auto|x|y|z|auto||
Output/Progress interval|real|5|0|inf
Output/Verbose|bool|true||
Output/Write VTU|bool|true||
Output/Write checkpoint|bool|true||
Output/Write profiles|bool|true||
Output/Write summary|bool|true||
Time/End time|real|0.2|0|inf
Time/Maximum steps|int|0|0|2147483647
Time/Maximum wall time|real|0|0|inf
Time/Steady state tolerance|real|0|0|1
"""


@dataclass
class Spec:
    key: str
    kind: str
    default: str
    lo: float | None = None
    hi: float | None = None
    options: tuple = ()


def _load_table():
    specs = {}
    for line in _TABLE.strip().split('\n'):
        if line.startswith('Diffusion step/Integrator') or '|sel:' in line:
            key, rest = line.split('|sel:', 1)
            parts = rest.split('|')
            # options..., default, '', ''
            opts = tuple(parts[:-3])
            specs[key] = Spec(key, 'sel', parts[-3], options=opts)
            continue
        parts = line.split('|')
        key, kind, default = parts[0], parts[1], parts[2]
        lo = float(parts[3]) if len(parts) > 3 and parts[3] != '' else None
        hi = float(parts[4]) if len(parts) > 4 and parts[4] != '' else None
        specs[key] = Spec(key, kind, default, lo, hi)
    return specs


PARAMS = _load_table()
SECTIONS = sorted({k.rsplit('/', 1)[0] for k in PARAMS if '/' in k})
NUMERIC_KINDS = ('int', 'real', 'reals', 'ints')
AXES = 'xyz'
SIDES = [a + s for a in AXES for s in '-+']
DBL_MIN = 2.2250738585072014e-308
DECIMAL_RE = re.compile(r'^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$')
INT_RE = re.compile(r'^[+-]?\d+$')
BASE_NAME_RE = re.compile(r'^[A-Za-z0-9_\-][A-Za-z0-9_.\-]{0,99}$')
MEM_KIB_PER_CELL = {1: 2.3, 2: 6.3, 3: 13.1}
MACHINE_MEM_BYTES = 20e9

CLASSES = ['numeric', 'list', 'selection', 'valid-alt', 'unknown-param', 'unknown-subsection',
           'structure', 'truncate', 'garbage', 'long-line', 'include', 'expression', 'boundary',
           'mesh', 'path', 'admission']
# share of the per-scene budget of each class
WEIGHTS = {'numeric': 14, 'list': 4, 'selection': 3, 'valid-alt': 4, 'unknown-param': 3,
           'unknown-subsection': 2, 'structure': 3, 'truncate': 2, 'garbage': 3, 'long-line': 2,
           'include': 3, 'expression': 6, 'boundary': 2, 'mesh': 2, 'path': 2}

CRASH_MARKERS = ['internal error', 'Stacktrace', 'Aborted', 'terminate called', 'MPI_ABORT',
                 'Segmentation fault', 'core dumped', 'An error occurred in line <',
                 'Floating point exception', 'std::bad_alloc']


def split_key(key):
    if '/' in key:
        sec, name = key.rsplit('/', 1)
        return tuple(sec.split('/')), name
    return (), key


def norm_ws(s):
    return ' '.join(s.split())


# =====================================================================================
# Scene text model
# =====================================================================================
class Scene:
    """A parsed scene text: entries, subsection blocks, structural problems."""

    def __init__(self, text: str, relpath: str = ''):
        self.text = text
        self.relpath = relpath
        self.lines = text.split('\n')
        self.entries = []        # (idx, path, name, value)
        self.blocks = []         # [path, open idx, end idx]
        self.includes = []       # (idx, file name)
        self.problems = []       # structural problems (strings) that deal.II must refuse
        stack = []
        open_blocks = []
        joined = {}
        cont = None
        for i, raw in enumerate(self.lines):
            # deal.II joins a line ending in a backslash (trailing blanks ignored) with the next
            r = raw.replace('\r', '').rstrip(' \t')
            if cont is not None:
                joined[cont] += r.lstrip()
                joined[i] = ''
            else:
                joined[i] = r
            if r.endswith('\\'):
                if cont is None:
                    cont = i
                joined[cont] = joined[cont][:-1]
            else:
                cont = None
        for i, raw in enumerate(self.lines):
            line = joined[i].split('#', 1)[0].strip()
            if not line:
                continue
            word = line.split()[0]
            if word in ('SET', 'SUBSECTION', 'INCLUDE'):
                word = word.lower()          # deal.II accepts all-lower or all-upper keywords
            if line == 'END':
                line = 'end'
            if word == 'subsection':
                name = norm_ws(line[len('subsection'):])
                if not name:
                    self.problems.append(f'line {i + 1}: subsection without name')
                stack.append(name)
                blk = [tuple(stack), i, None]
                self.blocks.append(blk)
                open_blocks.append(blk)
                if tuple(stack) not in KNOWN_PATHS:
                    self.problems.append(f'line {i + 1}: unknown subsection {"/".join(stack)!r}')
            elif line == 'end':
                if not stack:
                    self.problems.append(f'line {i + 1}: end without subsection')
                    continue
                open_blocks.pop()[2] = i
                stack.pop()
            elif word == 'set':
                body = line[3:]
                if '=' not in body:
                    self.problems.append(f'line {i + 1}: set without =')
                    continue
                n, v = body.split('=', 1)
                n = norm_ws(n)
                self.entries.append((i, tuple(stack), n, v.strip()))
                key = '/'.join(stack + [n])
                if key not in PARAMS:
                    self.problems.append(f'line {i + 1}: unknown parameter {key!r}')
            elif word == 'include':
                self.includes.append((i, line[len('include'):].strip()))
            else:
                self.problems.append(f'line {i + 1}: not a set/subsection/end/include line')
        if stack:
            self.problems.append(f'unclosed subsection {"/".join(stack)!r}')
        if not self.entries and not self.includes:
            self.problems.append('sets no parameter')

    @property
    def balanced(self):
        return not any(p.startswith('unclosed') or 'end without' in p for p in self.problems)

    def raw(self, key):
        path, name = split_key(key)
        val = None
        for (_, p, n, v) in self.entries:
            if p == path and n == name:
                val = v
        return val

    def get(self, key):
        v = self.raw(key)
        if v is None:
            spec = PARAMS.get(key)
            return spec.default if spec else None
        return v

    def first_content_line(self):
        for i, raw in enumerate(self.lines):
            s = raw.strip()
            if s and not s.startswith('#'):
                return i
        return len(self.lines)

    def with_value(self, key, value):
        """Text with 'key' set to 'value' (replaced in place, or inserted); (text, line idx)."""
        path, name = split_key(key)
        lines = list(self.lines)
        idxs = [i for (i, p, n, _) in self.entries if p == path and n == name]
        newline = f'set {name} = {value}' if value != '' else f'set {name} ='
        if idxs:
            for i in idxs:
                indent = re.match(r'\s*', lines[i]).group(0)
                lines[i] = indent + newline
            return '\n'.join(lines), idxs[-1]
        if not path:
            i0 = self.first_content_line()
            lines.insert(i0, newline)
            return '\n'.join(lines), i0
        blocks = [b for b in self.blocks if b[0] == path and b[2] is not None]
        if blocks:
            e = blocks[-1][2]
            lines.insert(e, '  ' * len(path) + newline)
            return '\n'.join(lines), e
        block = [f'{"  " * k}subsection {p}' for k, p in enumerate(path)]
        block.append('  ' * len(path) + newline)
        block += [f'{"  " * k}end' for k in reversed(range(len(path)))]
        pos = len(lines)
        while pos > 0 and lines[pos - 1].strip() == '':
            pos -= 1
        lines[pos:pos] = block
        return '\n'.join(lines), pos + len(path)

    def with_values(self, kv):
        sc = self
        idx = None
        for k, v in kv:
            t, idx = sc.with_value(k, v)
            sc = Scene(t, self.relpath)
        return sc.text, idx

    def insert_lines(self, idx, new):
        lines = list(self.lines)
        lines[idx:idx] = new
        return '\n'.join(lines)

    def top_level_positions(self):
        """Line indices at which a line can be inserted at nesting depth 0."""
        pos = [self.first_content_line()]
        for b in self.blocks:
            if len(b[0]) == 1 and b[2] is not None:
                pos.append(b[2] + 1)
        return sorted(set(pos))

    def dim(self):
        try:
            return int(self.get('Dimension'))
        except (TypeError, ValueError):
            return None


KNOWN_PATHS = {tuple(s.split('/')) for s in SECTIONS}


# =====================================================================================
# Validator: what granhydro must refuse ('invalid') and what is merely odd ('dubious').
# Derived from the parameter documentation, the deal.II patterns and tests/input/bad_input.
# =====================================================================================
def _num(s):
    s = s.strip()
    if not DECIMAL_RE.match(s):
        return None, f'{s[:40]!r} is not a decimal number'
    v = float(s)
    if not math.isfinite(v):
        return None, f'{s[:40]!r} overflows a double'
    if v != 0 and abs(v) < DBL_MIN:
        return None, f'{s[:40]!r} is below the smallest normal double'
    return v, ''


def _int(s):
    s = s.strip()
    if not INT_RE.match(s):
        return None, f'{s[:40]!r} is not a whole number'
    v = int(s)
    if abs(v) > 2147483647:
        return None, f'{s[:40]!r} does not fit a 32-bit int'
    return v, ''


def parse_value(spec, raw):
    """(ok, value, reason) at pattern level."""
    k = spec.kind
    if k in ('int', 'real'):
        v, why = (_int if k == 'int' else _num)(raw)
        if v is None:
            return False, None, why
        if spec.lo is not None and v < spec.lo:
            return False, None, f'{raw} below the pattern minimum {spec.lo:g}'
        if spec.hi is not None and v > spec.hi:
            return False, None, f'{raw} above the pattern maximum {spec.hi:g}'
        if k == 'real' and v == 0 and raw.strip().startswith('-') and spec.lo == 0:
            pass  # -0 == 0: passes a 0...MAX pattern
        return True, v, ''
    if k == 'bool':
        r = raw.strip()
        if r in ('true', 'false'):
            return True, r == 'true', ''
        if r in ('yes', 'no', '1', '0', 'True', 'False', 'TRUE', 'FALSE', 'on', 'off'):
            return None, None, f'boolean spelled {r!r}'
        return False, None, f'{r[:40]!r} is not true|false'
    if k == 'sel':
        r = raw.strip()
        if r in spec.options:
            return True, r, ''
        return False, None, f'{r[:40]!r} is not one of {"|".join(spec.options)}'
    if k in ('reals', 'ints'):
        r = raw.strip()
        if r.endswith(','):
            r = r[:-1]          # deal.II's split_string_list drops one trailing separator
        comps = [c.strip() for c in r.split(',')] if r else []
        out = []
        for c in comps:
            v, why = (_int if k == 'ints' else _num)(c)
            if v is None:
                return False, None, 'entry ' + why
            out.append(v)
        return True, out, ''
    return True, raw.strip(), ''


GRANHYDRO_PARSED = {'Domain/Cells', 'Domain/Lower corner', 'Domain/Upper corner', 'Effects/Gravity',
                    'Initial state/Constants', 'Initial state/Packing fraction',
                    'Initial state/Temperature', 'Initial state/Velocity', 'Domain/Mesh file',
                    'Initial state/Checkpoint', 'Output/Base name', 'Output/Directory'} | \
                   {f'Domain/Wall velocity {s}' for s in SIDES}


def validate(sc: Scene):
    """{key: (verdict, reason)}, verdict 'invalid' or 'dubious'."""
    res = {}

    def put(key, verdict, reason):
        if key in res and res[key][0] == 'invalid':
            return
        if key in res and verdict == 'dubious':
            return
        res[key] = (verdict, reason)

    if sc.problems:
        put('<structure>', 'invalid', sc.problems[0])
    vals = {}
    for key, spec in PARAMS.items():
        raw = sc.raw(key)
        if raw is None:
            ok, v, why = parse_value(spec, spec.default)
            vals[key] = v
            continue
        ok, v, why = parse_value(spec, raw)
        if ok:
            vals[key] = v
        elif ok is None:
            put(key, 'dubious', why)
        else:
            put(key, 'invalid' if key not in GRANHYDRO_PARSED else 'pending', why)

    dim = vals.get('Dimension')
    gran = vals.get('Material/Model') == 'granular'
    mesh = bool(vals.get('Domain/Mesh file'))
    ckpt = bool(vals.get('Initial state/Checkpoint'))

    def active(key):
        if key in ('Domain/Cells', 'Domain/Lower corner', 'Domain/Upper corner'):
            return not mesh
        if key.startswith('Initial state/') and key != 'Initial state/Checkpoint':
            return not ckpt
        return True

    # granhydro-parsed entries fail only where used
    for key, (v, why) in list(res.items()):
        if v == 'pending':
            res[key] = ('invalid', why) if active(key) else ('dubious', why + ' (unused in this scene)')

    def bad(key, why, act=True):
        if act:
            put(key, 'invalid', why)
        else:
            put(key, 'dubious', why + ' (unused in this scene)')

    def dub(key, why):
        put(key, 'dubious', why)

    if dim is None:
        return res
    end = vals.get('Time/End time')
    sigma = vals.get('Material/Grain diameter')
    rho = vals.get('Material/Material density')
    if end is not None and end <= 0:
        bad('Time/End time', 'end time must be positive')
    elif end is not None and end < 1e-100:
        dub('Time/End time', 'vanishing end time')
    if sigma is not None:
        if sigma <= 0:
            bad('Material/Grain diameter', 'grain diameter must be positive')
        elif rho is not None and rho > 0:
            m = rho * math.pi * sigma ** 3 / 6 if sigma < 1e100 else INF
            if not (DBL_MIN < m < 1e300):
                bad('Material/Grain diameter', f'grain mass {m:g} under/overflows')
    if rho is not None and rho <= 0:
        bad('Material/Material density', 'density must be positive')
    elif rho is not None and not (1e-3 <= rho <= 1e6):
        bad('Material/Material density', 'density outside 1e-3 .. 1e6 kg/m^3')
    # material (granular)
    phic = vals.get('Material/Close packing fraction')
    guard = vals.get('Material/Close packing guard')
    phif = vals.get('Material/Freezing packing fraction')
    if phic is not None:
        if phic <= 0:
            bad('Material/Close packing fraction', 'phi_c must be positive', gran)
        elif phic > 0.7405:
            bad('Material/Close packing fraction', 'phi_c above 0.7405', gran)
    if guard is not None:
        if guard <= 0:
            bad('Material/Close packing guard', 'guard must be positive', gran)
        elif phic and guard >= phic:
            bad('Material/Close packing guard', 'guard >= phi_c', gran)
        elif guard < 1e-100:
            dub('Material/Close packing guard', 'vanishing guard')
    if phif is not None:
        if phif <= 0:
            bad('Material/Freezing packing fraction', 'phi_f must be positive', gran)
        elif phic is not None and phif >= phic:
            bad('Material/Freezing packing fraction', 'phi_f >= phi_c', gran)
    eps = vals.get('Material/Restitution coefficient')
    if eps is not None and eps < 0.5:
        bad('Material/Restitution coefficient', 'eps below 0.5 (GD99 range)', gran)
    gam = vals.get('Material/Adiabatic index')
    if gam is not None and gam <= 1:
        bad('Material/Adiabatic index', 'gamma must exceed 1', not gran)
    mfp = vals.get('Material/Maximum mean free path')
    if mfp is not None and 0 < mfp < 1e-100:
        dub('Material/Maximum mean free path', 'vanishing cap')
    # dense closure
    jj = gran and vals.get('Dense closure/Model') == 'johnson-jackson'
    pmin = vals.get('Dense closure/Minimum packing fraction')
    if pmin is not None and phic is not None and pmin >= phic:
        bad('Dense closure/Minimum packing fraction', 'phi_min >= phi_c', jj)
    elif pmin is not None and pmin <= 0:
        dub('Dense closure/Minimum packing fraction', 'phi_min 0')
    for k in ('Dense closure/Coefficient', 'Dense closure/Viscosity time'):
        v = vals.get(k)
        if v is not None and v > 1e100:
            dub(k, 'absurd value')
    # diffusion step
    ew = vals.get('Diffusion step/Linear forcing') == 'eisenstat-walker'
    for k in ('Diffusion step/Linear solver tolerance', 'Diffusion step/Newton tolerance'):
        v = vals.get(k)
        if v is not None and v <= 0 and k.endswith('Linear solver tolerance') and ew:
            dub(k, 'no floor for the Eisenstat-Walker forcing')
        elif v is not None and v <= 0:
            bad(k, 'tolerance 0 can never be met', gran)
        elif v is not None and v < 1e-100:
            dub(k, 'unreachable tolerance')
        elif v is not None and v >= 1:
            dub(k, 'tolerance 1 (no accuracy)')
    # numerics
    cfl = vals.get('Numerics/CFL number')
    if cfl is not None and cfl <= 0:
        bad('Numerics/CFL number', 'CFL number must be positive')
    elif cfl is not None and cfl < 1e-100:
        bad('Numerics/CFL number', 'vanishing CFL number: no progress')
    musta = vals.get('Numerics/Flux') == 'musta'
    lcfl = vals.get('Numerics/MUSTA local CFL')
    if lcfl is not None and lcfl <= 0:
        bad('Numerics/MUSTA local CFL', 'local CFL must be positive', musta)
    elif lcfl is not None and lcfl < 1e-100:
        dub('Numerics/MUSTA local CFL', 'vanishing local CFL')
    mtol = vals.get('Numerics/MUSTA tolerance')
    if mtol is not None and mtol <= 0:
        bad('Numerics/MUSTA tolerance', 'tolerance must be positive', musta)
    dt = vals.get('Numerics/Fixed time step')
    if dt is not None and end and dt > 0 and end / dt > 1e9:
        bad('Numerics/Fixed time step', 'more than 1e9 fixed steps')
    if vals.get('Effects/Convection') is False and dt == 0:
        bad('Numerics/Fixed time step', 'convection off needs a fixed time step')
    uref = vals.get('Numerics/Reference velocity')
    if uref is not None and uref > 0 and (uref < 1e-100 or uref > 1e100):
        dub('Numerics/Reference velocity', 'absurd reference velocity')
    # output
    iv = vals.get('Output/Interval')
    if iv is not None and iv > 0 and end and end / iv > 1e5:
        bad('Output/Interval', 'more than 1e5 outputs')
    csd = vals.get('Output/Cross-section direction')
    if csd and csd != 'none' and dim < 3:
        bad('Output/Cross-section direction', 'cross sections need 3D')
    pd = vals.get('Output/Profile direction')
    if pd and pd != 'auto' and AXES.index(pd) >= dim:
        bad('Output/Profile direction', 'profile direction not resolved')
    bn = sc.raw('Output/Base name')
    if bn is not None and not BASE_NAME_RE.match(bn.strip()):
        bad('Output/Base name', 'base name must be 1..100 plain characters')
    dd = sc.raw('Output/Directory')
    if dd is not None:
        d = dd.strip()
        if '\x00' in d or any(len(c.encode(ENC, ERRS)) > 255 for c in d.split('/')) \
                or d.startswith('/proc/') or d.startswith('/dev/null/') or d.startswith('/etc/passwd'):
            bad('Output/Directory', 'directory cannot be created')
        elif d == '':
            dub('Output/Directory', 'empty output directory')
    # adaptivity
    lvl = vals.get('Adaptivity/Maximum level')
    amr = bool(lvl)
    if amr and dim == 1:
        bad('Adaptivity/Maximum level', 'adaptivity needs 2D/3D')
    if amr and mesh:
        bad('Adaptivity/Maximum level', 'adaptivity needs a box domain')
    ct, rt = vals.get('Adaptivity/Coarsen threshold'), vals.get('Adaptivity/Refine threshold')
    if ct is not None and rt is not None and ct >= rt:
        bad('Adaptivity/Coarsen threshold', 'coarsen threshold >= refine threshold', amr)
    if rt == 0:
        dub('Adaptivity/Refine threshold', 'refine threshold 0')
    # domain
    if mesh and dim == 1:
        bad('Domain/Mesh file', 'mesh files need 2D/3D')
    bc = {s: vals.get(f'Domain/Boundary {s}') for s in SIDES}
    for ax in range(3):
        a, b = bc[AXES[ax] + '-'], bc[AXES[ax] + '+']
        if ax < dim and (a == 'periodic') != (b == 'periodic') and a and b:
            bad(f'Domain/Boundary {AXES[ax]}-', 'periodic on one side only')
        if ax < dim and mesh and 'periodic' in (a, b):
            bad('Domain/Mesh file', 'periodic boundaries with a mesh file')
    for s in SIDES:
        ax = AXES.index(s[0])
        wr = vals.get(f'Domain/Wall restitution {s}')
        if wr is not None and wr != 1 and sc.raw(f'Domain/Wall restitution {s}') is not None:
            if ax >= dim:
                dub(f'Domain/Wall restitution {s}', 'unresolved direction')
            elif bc[s] == 'periodic':
                bad(f'Domain/Wall restitution {s}', 'periodic boundary cannot dissipate')
            elif bc[s] == 'outflow':
                dub(f'Domain/Wall restitution {s}', 'restitution of an outflow boundary')
            elif wr == 0:
                dub(f'Domain/Wall restitution {s}', 'wall restitution 0')
        wv = vals.get(f'Domain/Wall velocity {s}')
        if wv is not None and sc.raw(f'Domain/Wall velocity {s}') is not None:
            key = f'Domain/Wall velocity {s}'
            if len(wv) > 3:
                bad(key, 'more than 3 entries')
            elif len(wv) < min(dim, 3) and bc[s] == 'no-slip wall' and ax < dim:
                bad(key, 'fewer entries than dimensions')
            nz = any(v != 0 for v in wv)
            if nz:
                if ax >= dim:
                    dub(key, 'unresolved direction')
                elif bc[s] == 'slip wall':
                    bad(key, 'only no-slip walls move')
                elif bc[s] != 'no-slip wall':
                    dub(key, f'velocity of a {bc[s]} boundary')
                elif not mesh and ax < len(wv) and wv[ax] != 0:
                    bad(key, 'wall velocity normal to the wall')
                if any(abs(v) > 1e100 for v in wv):
                    dub(key, 'absurd wall velocity')
    if not mesh:
        cells = vals.get('Domain/Cells')
        lo, up = vals.get('Domain/Lower corner'), vals.get('Domain/Upper corner')
        if cells is not None:
            if len(cells) not in (dim, 3):
                bad('Domain/Cells', f'{len(cells)} entries, need {dim} or 3')
            elif any(c < 1 for c in cells):
                bad('Domain/Cells', 'cells must be >= 1')
            else:
                prod = 1
                for c in cells[:dim]:
                    prod *= c
                if prod > 5e7:
                    bad('Domain/Cells', 'more than 5e7 cells')
                elif prod * MEM_KIB_PER_CELL[dim] * 1024 > MACHINE_MEM_BYTES:
                    bad('Domain/Cells', 'beyond the memory of this machine')
                rec = vals.get('Numerics/Reconstruction')
                for ax in range(dim):
                    if bc[AXES[ax] + '-'] != 'periodic':
                        if rec == 'weno5' and cells[ax] < 3:
                            bad('Domain/Cells', 'weno5 needs 3 cells between walls')
        for key, v in (('Domain/Lower corner', lo), ('Domain/Upper corner', up)):
            if v is None:
                continue
            if len(v) < dim:
                bad(key, f'{len(v)} entries for {dim} dimensions')
            elif len(v) > 3:
                dub(key, 'more than 3 entries')
            if any(abs(x) > 1e6 for x in v):
                bad(key, 'corner beyond 1e6 m')
        if lo is not None and up is not None and len(lo) >= dim and len(up) >= dim \
                and not any(abs(x) > 1e6 for x in lo + up):
            for ax in range(dim):
                if up[ax] <= lo[ax]:
                    bad('Domain/Upper corner', 'upper corner not above the lower corner')
                elif cells and len(cells) in (dim, 3) and sigma and sigma > 0 and cells[ax] >= 1 \
                        and (up[ax] - lo[ax]) / cells[ax] < 1e-3 * sigma:
                    bad('Domain/Cells', 'cells smaller than 1e-3 grain diameters')
    if mesh and dim in (2, 3) and sc.relpath:
        ncoarse = mesh_cell_count(str(Path(sc.relpath).parent / vals['Domain/Mesh file']), dim)
        r = vals.get('Domain/Mesh refinements')
        if ncoarse and r is not None:
            prod = ncoarse * 2 ** (dim * r)
            if prod > 5e7 or prod * MEM_KIB_PER_CELL[dim] * 1024 > MACHINE_MEM_BYTES:
                bad('Domain/Mesh refinements', f'{prod:.3g} cells')
    g = vals.get('Effects/Gravity')
    if g is not None:
        if len(g) > 3:
            bad('Effects/Gravity', 'more than 3 entries')
        elif len(g) < dim:
            bad('Effects/Gravity', 'fewer entries than dimensions')
        if not gran and any(x != 0 for x in g):
            bad('Effects/Gravity', 'ideal gas has no body force')
        if math.sqrt(sum(x * x for x in g if math.isfinite(x)) or 0) > 1e5:
            bad('Effects/Gravity', '|g| above 1e5 m/s^2')
    amp, freq = vals.get('Effects/Vibration amplitude'), vals.get('Effects/Vibration frequency')
    vdir = vals.get('Effects/Vibration direction')
    if amp is not None and amp > 0:
        if freq == 0:
            bad('Effects/Vibration frequency', 'vibration without frequency')
        if vdir and AXES.index(vdir) >= dim:
            bad('Effects/Vibration direction', 'vibration direction not resolved')
        if freq is not None:
            acc = amp * (2 * math.pi * freq) ** 2 if freq < 1e150 else INF
            if not math.isfinite(acc) or acc > 1e100:
                bad('Effects/Vibration frequency', 'vibration acceleration overflows')
        if amp > 1e100:
            dub('Effects/Vibration amplitude', 'absurd amplitude')
        if not gran:
            dub('Effects/Vibration amplitude', 'vibration of an ideal gas')
    elif freq is not None and freq > 1e100:
        dub('Effects/Vibration frequency', 'absurd frequency (no amplitude)')
    vel = sc.raw('Initial state/Velocity')
    if vel is not None and not ckpt:
        v = vel.strip()
        n = len((v[:-1] if v.endswith(';') else v).split(';'))
        if n not in (dim, 3):
            bad('Initial state/Velocity', f'{n} components for {dim} dimensions')
    return res


_MESH_CELLS = {}


def mesh_cell_count(rel, dim):
    """Number of cells of a committed gmsh file (relative to the repository), or None."""
    key = (os.path.normpath(rel), dim)
    if key not in _MESH_CELLS:
        n = None
        try:
            lines = (REPO / key[0]).read_text().split('\n')
            e0 = lines.index('$Elements')
            cell_type = '5' if dim == 3 else '3'
            n = sum(1 for ln in lines[e0 + 2:e0 + 2 + int(lines[e0 + 1])] if ln.split()[1] == cell_type)
        except (OSError, ValueError, IndexError):
            pass
        _MESH_CELLS[key] = n
    return _MESH_CELLS[key]


def new_findings(base_res, mut_res):
    inv = {k: r for k, (v, r) in mut_res.items() if v == 'invalid' and base_res.get(k, ('',))[0] != 'invalid'}
    dub = {k: r for k, (v, r) in mut_res.items() if v == 'dubious' and base_res.get(k, ('',))[0] != 'dubious'}
    return inv, dub


# =====================================================================================
# Cases and generators
# =====================================================================================
@dataclass
class Case:
    cid: str
    scene: str                   # relpath of the base scene (e.g. parameters/hard/x.prm)
    cls: str
    desc: str
    text: str
    files: dict = field(default_factory=dict)   # extra files relative to the scene dir
    invalid: str = ''            # why refusal is required ('' = acceptance allowed)
    dubious: str = ''
    key: str = ''                # mutated parameter, if any
    bad_line: int | None = None  # 1-based line of the offence in the scene file, if known
    bad_include: str = ''        # the offence sits in this included file
    runnable: bool = True        # may be run for real if --check accepts it
    note: str = ''

    @property
    def must_refuse(self):
        return bool(self.invalid)


NUM_VALUES = ['0', '-1', '1e-310', 'nan', '1e300', '', '-0', 'inf', '1e-300', 'abc', '1e308', '99999999999',
              '4294967296', '-inf', '1e309', '0x10', '1e', '1,5', '--1', '1.5', '-2147483649', '1e-3x']


def numeric_values(spec):
    vals = list(NUM_VALUES)
    if spec.kind in ('int', 'real'):
        lo, hi = spec.lo, spec.hi
        if spec.kind == 'int':
            vals += [str(int(lo)), str(int(hi)), str(int(lo) - 1)]
            if hi < 2147483647:
                vals.append(str(int(hi) + 1))
        else:
            vals += ['%.17g' % lo, '-1e-300']
            if math.isfinite(hi):
                vals += ['%.17g' % hi, '%.17g' % (hi * 1.000001)]
    return vals


class Gen:
    """Per-scene generation context."""

    def __init__(self, relpath, text, sidx, nscenes, seed):
        self.rel = relpath
        self.base = Scene(text, relpath)
        self.base_res = validate(self.base)
        self.sidx, self.nsc, self.seed = sidx, nscenes, seed
        self.dim = self.base.dim() or 2
        self.name = Path(relpath).name
        self.stem = relpath[len('parameters/'):-4] if relpath.startswith('parameters/') else relpath
        self.count = {}

    def rng(self, cls):
        return random.Random(f'{self.seed}/{self.rel}/{cls}')

    def mk(self, cls, desc, text, **kw):
        n = self.count.get(cls, 0)
        self.count[cls] = n + 1
        return Case(f'{self.stem}:{cls}:{n:03d}', self.rel, cls, desc, text, **kw)

    def judged(self, cls, desc, text, key='', bad_line=None, invalid='', dubious='', **kw):
        """A case whose validity the validator decides (plus an explicit reason)."""
        mut = Scene(text, self.rel)
        inv, dub = new_findings(self.base_res, validate(mut))
        if not invalid and inv:
            invalid = '; '.join(f'{k}: {r}' for k, r in sorted(inv.items()))
        if not dubious and dub and not invalid:
            dubious = '; '.join(f'{k}: {r}' for k, r in sorted(dub.items()))
        return self.mk(cls, desc, text, key=key, bad_line=bad_line, invalid=invalid, dubious=dubious, **kw)

    def value_case(self, cls, key, value, desc=None, invalid='', dubious='', **kw):
        text, idx = self.base.with_value(key, value)
        return self.judged(cls, desc or f'{key} = {shorten(value)}', text, key=key,
                           bad_line=idx + 1, invalid=invalid, dubious=dubious, **kw)

    def pick(self, recipes, quota, applicable=lambda r: True):
        """Spread a global recipe list over the scenes: scene i takes recipes i, i+S, i+2S, ..."""
        out = []
        if not recipes:
            return out
        n = len(recipes)
        used = set()
        k = 0
        while len(out) < quota and len(used) < n:
            idx = (self.sidx + k * self.nsc) % n
            k += 1
            while idx in used:
                idx = (idx + 1) % n
            used.add(idx)
            if applicable(recipes[idx]):
                out.append(recipes[idx])
        return out


def shorten(s, n=60):
    s = s if isinstance(s, str) else str(s)
    r = repr(s)[1:-1] if any(ord(c) < 32 or ord(c) > 126 for c in s) else s
    return r if len(r) <= n else f'{r[:n]}...({len(s)} chars)'


def latin_order(items_per_key, seed, tag):
    """[(key, item)] so that the first len(keys) entries give every key a different item."""
    keys = sorted(items_per_key)
    random.Random(f'{seed}/{tag}').shuffle(keys)
    out = []
    width = max(len(v) for v in items_per_key.values())
    for j in range(width):
        for i, k in enumerate(keys):
            items = items_per_key[k]
            if j < len(items):
                out.append((k, items[(j + i) % len(items)]))
    return out


# ---- numeric ---------------------------------------------------------------------------
def gen_numeric(g: Gen, quota):
    per = {k: numeric_values(s) for k, s in PARAMS.items() if s.kind in NUMERIC_KINDS}
    recipes = latin_order(per, g.seed, 'numeric')
    rng = g.rng('numeric')
    out = []
    for key, val in g.pick(recipes, quota):
        spec = PARAMS[key]
        if spec.kind in ('reals', 'ints'):
            comps = [c.strip() for c in g.base.get(key).split(',')]
            c = rng.randrange(len(comps))
            comps[c] = val
            out.append(g.value_case('numeric', key, ', '.join(comps), f'{key} entry {c} = {shorten(val)}'))
        else:
            out.append(g.value_case('numeric', key, val))
    return out


# ---- list: wrong counts, duplicates, separators ---------------------------------------
def gen_list(g: Gen, quota):
    recipes = []
    for key in ('Domain/Cells', 'Domain/Lower corner', 'Domain/Upper corner', 'Effects/Gravity',
                'Domain/Wall velocity x-', 'Domain/Wall velocity y+', 'Initial state/Velocity',
                'Initial state/Packing fraction', 'Initial state/Temperature', 'Material/Grain diameter',
                'Time/End time', 'Numerics/CFL number', 'Dimension'):
        for how in ('fewer', 'more', 'four', 'five', 'empty-entry', 'trailing-sep', 'leading-sep',
                    'semicolon', 'space', 'duplicate'):
            recipes.append((key, how))
    random.Random(f'{g.seed}/list').shuffle(recipes)
    out = []
    for key, how in g.pick(recipes, quota):
        spec = PARAMS[key]
        cur = g.base.get(key)
        sep = ';' if spec.kind == 'exprs' else ','
        comps = [c.strip() for c in cur.split(sep)]
        if spec.kind in ('reals', 'ints', 'exprs'):
            if key == 'Domain/Cells':
                comps = comps[:max(g.dim, 1)]
            if how == 'fewer':
                new = comps[:-1] if len(comps) > 1 else []
            elif how == 'more':
                new = comps + comps[-1:] if len(comps) != 2 else comps + comps[-1:] * 2 + comps[-1:]
            elif how == 'four':
                new = (comps * 4)[:4]
            elif how == 'five':
                new = (comps * 5)[:5]
            elif how == 'empty-entry':
                new = comps[:1] + [''] + comps[1:]
            elif how == 'trailing-sep':
                new = comps + ['']
            elif how == 'leading-sep':
                new = [''] + comps
            elif how == 'semicolon':
                val = (';' if sep == ',' else ',').join(comps + comps[:1] if len(comps) == 1 else comps)
                out.append(g.value_case('list', key, val, f'{key} with the wrong separator: {shorten(val)}'))
                continue
            elif how == 'space':
                val = ' '.join(comps + comps[:1] if len(comps) == 1 else comps)
                out.append(g.value_case('list', key, val, f'{key} separated by spaces: {shorten(val)}'))
                continue
            else:  # duplicate
                new = comps + comps
            val = (sep + ' ').join(new)
            out.append(g.value_case('list', key, val, f'{key} ({how}): {shorten(val)}'))
        else:
            # scalar parameter given a list (the brief's 'Packing fraction = 0.01, 0.02')
            v = cur.strip()
            variants = {'fewer': '', 'more': f'{v}, {v}', 'four': f'{v}, {v}, {v}, {v}',
                        'five': f'{v}; {v}', 'empty-entry': f'{v},', 'trailing-sep': f'{v};',
                        'leading-sep': f', {v}', 'semicolon': f'{v}; {v}; {v}', 'space': f'{v} {v}',
                        'duplicate': f'{v}, {v}'}
            val = variants[how]
            inv = ''
            if spec.kind == 'expr':
                inv = f'{key}: one expression expected, got {shorten(val)}' if val else f'{key}: empty expression'
            out.append(g.value_case('list', key, val, f'scalar {key} given {shorten(val) or "nothing"}',
                                    invalid=inv))
    return out


# ---- selection: unknown names and booleans --------------------------------------------
def sel_bad_values(spec, cur):
    if spec.kind == 'bool':
        return ['maybe', '', 'yes', '1', 'True', 'true false', 'tru', 'false ,']
    o = cur.strip()
    other = [x for x in spec.options if x != o][0]
    return ['bogus', o.upper(), o.title(), o + 'x', o[:-1], '', f'{o}|{other}', o.replace(' ', '  ') if ' ' in o
            else o + ' ' + o, f'"{o}"', f'{o},{other}', 'none' if 'none' not in spec.options else 'None']


def gen_selection(g: Gen, quota):
    per = {k: list(range(11)) for k, s in PARAMS.items() if s.kind in ('sel', 'bool')}
    recipes = latin_order(per, g.seed, 'selection')
    out = []
    for key, j in g.pick(recipes, quota):
        spec = PARAMS[key]
        vals = sel_bad_values(spec, g.base.get(key))
        out.append(g.value_case('selection', key, vals[j % len(vals)]))
    return out


# ---- valid alternatives (acceptance allowed; exercises the run) --------------------------
def gen_valid_alt(g: Gen, quota):
    recipes = []
    for key, spec in sorted(PARAMS.items()):
        if spec.kind == 'sel':
            for o in spec.options:
                recipes.append((key, o))
        elif spec.kind == 'bool':
            recipes += [(key, 'true'), (key, 'false')]
        elif key == 'Dimension':
            recipes += [(key, '1'), (key, '2'), (key, '3')]
    random.Random(f'{g.seed}/valid-alt').shuffle(recipes)
    out = []
    for key, v in g.pick(recipes, quota, lambda r: g.base.get(r[0]).strip() != r[1]):
        out.append(g.value_case('valid-alt', key, v, f'{key} = {v} (a valid choice)'))
    return out


# ---- unknown parameter names ------------------------------------------------------------
def typos(name):
    out = [name[:-1], name.lower() if name.lower() != name else name.upper(), name.replace(' ', '_')
           if ' ' in name else name + '_', name + 's', name + ' 2', name.replace(' ', '')
           if ' ' in name else '_' + name, name[0] + name[2:] if len(name) > 2 else name + 'x']
    return [t for t in out if t and t != name]


def gen_unknown_param(g: Gen, quota):
    recipes = []
    for key in sorted(PARAMS):
        path, name = split_key(key)
        for t in typos(name)[:4]:
            recipes.append((path, t))
    for sec in SECTIONS:
        recipes.append(((sec,), 'Bogus key'))
        other = [split_key(k)[1] for k in PARAMS if not k.startswith(sec + '/')]
        names_here = {split_key(k)[1] for k in PARAMS if k.startswith(sec + '/')}
        for n in other[:: max(1, len(other) // 3)][:3]:
            if n not in names_here:
                recipes.append(((sec,), n))          # a parameter of another section
    recipes += [(('Domain',), 'Boundary w-'), (('Domain',), 'Boundary x'), (('Domain',), 'Boundary x0'),
                (('Domain',), 'Wall restitution q+'), (('Domain',), 'Wall velocity x'), ((), 'Dimensions'),
                ((), 'Cells'), ((), 'Grain diameter'), (('Domain',), 'Boundary id 6'), (('Domain',), 'Boundary 7')]
    random.Random(f'{g.seed}/unknown-param').shuffle(recipes)
    out = []
    for path, name in g.pick(recipes, quota):
        key = '/'.join(path + (name,))
        spec = None
        value = '1'
        # a plausible value: the value of the parameter it resembles
        for k, s in PARAMS.items():
            if split_key(k)[1].lower().replace('_', ' ').rstrip('s2 ') == name.lower().replace('_', ' ').rstrip('s2 '):
                spec = s
        if spec:
            value = g.base.get(spec.key) or spec.default or '1'
        text, idx = g.base.with_value(key, value)
        out.append(g.mk('unknown-param', f'unknown parameter {key!r}', text, key=key, bad_line=idx + 1,
                        invalid=f'{key!r} is not a declared parameter'))
    return out


# ---- unknown subsections ------------------------------------------------------------------
def gen_unknown_subsection(g: Gen, quota):
    recipes = []
    for sec in SECTIONS:
        for t in typos(sec)[:4]:
            recipes.append(('typo', sec, t))
        recipes.append(('nested', sec, None))
    recipes += [('typo', 'Time', 'Bogus'), ('typo', 'Time', 'Domain/Cells'), ('typo', 'Time', 'Time Time'),
                ('empty', 'Numerics', 'Numerix'), ('noname', 'Time', ''), ('typo', 'Time', '\tTime x')]
    random.Random(f'{g.seed}/unknown-subsection').shuffle(recipes)
    rng = g.rng('unknown-subsection')
    out = []
    for kind, sec, name in g.pick(recipes, quota):
        pkeys = [k for k in PARAMS if k.startswith(sec + '/')]
        pk = pkeys[rng.randrange(len(pkeys))]
        pname = split_key(pk)[1]
        pval = g.base.get(pk)
        if kind == 'nested':
            host = [s for s in SECTIONS if s != sec][rng.randrange(len(SECTIONS) - 1)]
            block = [f'subsection {host}', f'  subsection {sec}', f'    set {pname} = {pval}', '  end', 'end']
            desc = f'subsection {sec!r} nested in {host!r}'
            bad = 2
        else:
            nm = name if kind != 'noname' else ''
            block = [f'subsection {nm}'.rstrip()] + ([] if kind == 'empty' else [f'  set {pname} = {pval}']) + ['end']
            desc = f'unknown subsection {nm!r}'
            bad = 1
        pos = rng.choice(g.base.top_level_positions())
        text = g.base.insert_lines(pos, block)
        out.append(g.mk('unknown-subsection', desc, text, bad_line=pos + bad, invalid=desc))
    return out


# ---- structure --------------------------------------------------------------------------------
STRUCTURE_KINDS = ['missing-end', 'extra-end', 'extra-end-eof', 'unclosed-subsection', 'set-no-equals',
                   'set-empty-name', 'set-bare', 'keyword-typo', 'value-double-equals', 'end-garbage',
                   'upper-keywords', 'duplicate-set', 'duplicate-block', 'continuation', 'continuation-eof',
                   'tabs', 'comment-in-value', 'escaped-hash', 'empty-file', 'comments-only', 'whitespace-only',
                   'only-dimension', 'subsection-keyword-only', 'equals-only', 'include-keyword-only']


def gen_structure(g: Gen, quota):
    recipes = list(STRUCTURE_KINDS)
    random.Random(f'{g.seed}/structure').shuffle(recipes)
    rng = g.rng('structure')
    b = g.base
    out = []
    sets = [e for e in b.entries]
    for kind in g.pick(recipes, quota):
        lines = list(b.lines)
        bad_line = None
        inv = ''
        if kind == 'missing-end':
            ends = [blk[2] for blk in b.blocks if blk[2] is not None]
            i = rng.choice(ends)
            del lines[i]
            desc, inv = f'the end of line {i + 1} deleted', 'unbalanced subsection/end'
        elif kind == 'extra-end':
            i = rng.choice(b.top_level_positions())
            lines.insert(i, 'end')
            desc, inv, bad_line = f'an extra end at line {i + 1}', 'end without subsection', i + 1
        elif kind == 'extra-end-eof':
            lines.append('end')
            desc, inv, bad_line = 'an extra end at the end of the file', 'end without subsection', len(lines)
        elif kind == 'unclosed-subsection':
            lines.append('subsection Time')
            desc, inv = 'subsection Time opened at the end, never closed', 'unbalanced subsection/end'
        elif kind in ('set-no-equals', 'value-double-equals', 'keyword-typo', 'comment-in-value',
                      'escaped-hash', 'continuation', 'duplicate-set'):
            i, p, n, v = rng.choice(sets)
            ind = re.match(r'\s*', lines[i]).group(0)
            if kind == 'set-no-equals':
                lines[i] = f'{ind}set {n} {v}'
                desc, inv, bad_line = f'"set {n} {shorten(v, 30)}" (no =)', 'set without =', i + 1
            elif kind == 'value-double-equals':
                lines[i] = f'{ind}set {n} = = {v}'
                key = '/'.join(p + (n,))
                desc, bad_line = f'"set {n} = = ..."', i + 1
                if PARAMS[key].kind not in ('dir', 'file', 'name', 'consts'):
                    inv = f'{key}: value "= {shorten(v, 30)}"'
            elif kind == 'keyword-typo':
                kw = rng.choice(['sett', 'Set ', 'se t', 'set:'])
                lines[i] = f'{ind}{kw} {n} = {v}'
                desc, inv, bad_line = f'keyword {kw!r} instead of set', 'not a keyword', i + 1
                if kw == 'Set ':
                    inv = ''  # deal.II may accept case variants
            elif kind == 'comment-in-value':
                lines[i] = f'{ind}set {n} = {v} # trailing comment'
                desc = 'a trailing comment after a value (valid)'
            elif kind == 'escaped-hash':
                lines[i] = f'{ind}set {n} = {v}\\#x'
                desc = 'an escaped \\# inside a value'
                key = '/'.join(p + (n,))
                if PARAMS[key].kind in NUMERIC_KINDS + ('sel', 'bool'):
                    inv = f'{key}: value with "#x" appended'
            elif kind == 'continuation':
                lines[i] = f'{ind}set {n} = \\'
                lines.insert(i + 1, f'{ind}  {v}')
                desc = 'a value continued on the next line with a backslash (valid)'
            else:
                # the same parameter twice: deal.II keeps the last value; a second, different value
                lines.insert(i + 1, f'{ind}set {n} = {v}')
                desc = f'{n} set twice (same value)'
            text = '\n'.join(lines)
            out.append(g.judged('structure', desc, text, bad_line=bad_line, invalid=inv)
                       if not inv else g.mk('structure', desc, text, bad_line=bad_line, invalid=inv))
            continue
        elif kind == 'set-empty-name':
            i = rng.choice(b.top_level_positions())
            lines.insert(i, 'set = 1')
            desc, inv, bad_line = '"set = 1"', 'set with empty name', i + 1
        elif kind == 'set-bare':
            i = rng.choice(b.top_level_positions())
            lines.insert(i, 'set')
            desc, inv, bad_line = 'a bare "set" line', 'bare set', i + 1
        elif kind == 'equals-only':
            i = rng.choice(b.top_level_positions())
            lines.insert(i, '= 1')
            desc, inv, bad_line = 'a line "= 1"', 'not a keyword', i + 1
        elif kind == 'subsection-keyword-only':
            i = rng.choice(b.top_level_positions())
            lines[i:i] = ['subsection', 'end']
            desc, inv, bad_line = 'subsection without a name', 'subsection without name', i + 1
        elif kind == 'include-keyword-only':
            i = rng.choice(b.top_level_positions())
            lines.insert(i, 'include')
            desc, inv, bad_line = 'include without a file name', 'include without file', i + 1
        elif kind == 'end-garbage':
            ends = [blk[2] for blk in b.blocks if blk[2] is not None]
            i = rng.choice(ends)
            lines[i] = lines[i] + ' Domain'
            desc, bad_line = f'"end Domain" at line {i + 1}', i + 1
        elif kind == 'upper-keywords':
            lines = [re.sub(r'^(\s*)(set|subsection|end)\b', lambda m: m.group(1) + m.group(2).upper(), ln)
                     for ln in lines]
            desc = 'keywords in upper case (SET, SUBSECTION, END)'
        elif kind == 'duplicate-block':
            blk = rng.choice([x for x in b.blocks if x[2] is not None])
            lines[blk[2] + 1:blk[2] + 1] = lines[blk[1]:blk[2] + 1]
            desc = f'subsection {"/".join(blk[0])} repeated (valid)'
        elif kind == 'continuation-eof':
            while lines and lines[-1].strip() == '':
                lines.pop()
            lines[-1] = lines[-1] + ' \\'
            desc = 'the last line ends with a continuation backslash'
        elif kind == 'tabs':
            lines = [re.sub(r'^ +', lambda m: '\t' * len(m.group(0)), ln) for ln in lines]
            desc = 'tab indentation (valid)'
        elif kind == 'empty-file':
            lines = ['']
            desc, inv = 'an empty file', 'sets no parameter'
        elif kind == 'comments-only':
            lines = [ln for ln in lines if ln.strip().startswith('#')] or ['# nothing']
            desc, inv = 'only the comments of the scene', 'sets no parameter'
        elif kind == 'whitespace-only':
            lines = ['   ', '\t', '', '  \t  ', '']
            desc, inv = 'only whitespace', 'sets no parameter'
        else:  # only-dimension
            lines = [f'set Dimension = {g.dim}', '']
            desc = 'only "set Dimension" (defaults for the rest)'
        text = '\n'.join(lines)
        if inv:
            out.append(g.mk('structure', desc, text, bad_line=bad_line, invalid=inv))
        else:
            out.append(g.judged('structure', desc, text, bad_line=bad_line))
    return out


# ---- truncation ---------------------------------------------------------------------------------
def gen_truncate(g: Gen, quota):
    rng = g.rng('truncate')
    out = []
    b = g.base
    n = len(b.lines)
    for j in range(quota):
        if j % 2 == 0:
            k = rng.randrange(1, max(2, n - 1))
            text = '\n'.join(b.lines[:k]) + '\n'
            desc = f'truncated after line {k} of {n}'
        else:
            data = b.text.encode(ENC, ERRS)
            k = rng.randrange(1, len(data))
            text = data[:k].decode(ENC, ERRS)
            desc = f'truncated at byte {k} of {len(data)} (mid-line)'
        out.append(g.judged('truncate', desc, text))
    return out


# ---- garbage ------------------------------------------------------------------------------------
GARBAGE_KINDS = ['binary-line', 'binary-line', 'nul-in-value', 'ctrl-in-value', 'high-bytes-comment',
                 'utf8-bom', 'crlf', 'cr-only', 'random-file', 'printable-line', 'garbage-after-value',
                 'nul-file', 'utf16', 'unicode-digit', 'binary-value']


def gen_garbage(g: Gen, quota):
    rng = g.rng('garbage')
    recipes = list(GARBAGE_KINDS)
    random.Random(f'{g.seed}/garbage').shuffle(recipes)
    b = g.base
    out = []
    numeric_sets = [e for e in b.entries if PARAMS.get('/'.join(e[1] + (e[2],)), Spec('', '', '')).kind in ('real', 'int')]
    for kind in g.pick(recipes, quota):
        lines = list(b.lines)
        bad_line = None
        inv = ''
        if kind in ('binary-line', 'printable-line'):
            if kind == 'binary-line':
                nbytes = rng.randrange(1, 200)
                data = bytes(rng.choice([0, 1, 7, 8, 11, 12, 27, 127, 128, 159, 192, 255] + list(range(32, 127)))
                             for _ in range(nbytes))
                data = data.replace(b'\n', b'\x00').replace(b'\r', b'\x01')
                data = bytes([rng.choice([0, 1, 255, 0xc3, 0x80, 0x7f, 0x1b])]) + data  # never '#' or blank first
            else:
                data = ('qwerty ' + ''.join(rng.choice('abcdefghij =,;') for _ in range(30))).encode()
            ln = data.decode(ENC, ERRS)
            i = rng.randrange(0, len(lines))
            lines.insert(i, ln)
            desc, inv, bad_line = f'a {kind} of {len(data)} bytes inserted at line {i + 1}', 'garbage line', i + 1
        elif kind in ('nul-in-value', 'ctrl-in-value', 'garbage-after-value', 'unicode-digit', 'binary-value'):
            i, p, n, v = rng.choice(numeric_sets)
            ind = re.match(r'\s*', lines[i]).group(0)
            junk = {'nul-in-value': '\x00junk', 'ctrl-in-value': '\x1b[31m', 'garbage-after-value': ' xyz',
                    'unicode-digit': '\uff11', 'binary-value': b'\xff\xfe'.decode(ENC, ERRS)}[kind]
            lines[i] = f'{ind}set {n} = {v}{junk}'
            key = '/'.join(p + (n,))
            desc, inv, bad_line = f'{key} = {shorten(v + junk)}', f'{key}: trailing garbage in the value', i + 1
        elif kind == 'high-bytes-comment':
            i = rng.randrange(0, len(lines))
            lines.insert(i, '# ' + b'\xff\xfe\x80 caf\xc3\xa9 \x00'.decode(ENC, ERRS))
            desc = 'a comment with non-UTF-8 bytes and a NUL (valid)'
        elif kind == 'utf8-bom':
            lines[0] = '\ufeff' + lines[0]
            out.append(g.mk('garbage', 'a UTF-8 byte-order mark at the start', '\n'.join(lines)))
            continue
        elif kind == 'crlf':
            lines = [ln + '\r' if ln else ln for ln in lines]
            desc = 'CRLF line endings'
        elif kind == 'cr-only':
            text = '\r'.join(lines)
            out.append(g.mk('garbage', 'CR-only line endings (old Mac)', text))
            continue
        elif kind == 'random-file':
            data = bytes(rng.randrange(256) for _ in range(rng.randrange(64, 8192)))
            text = data.decode(ENC, ERRS)
            out.append(g.mk('garbage', f'a file of {len(data)} random bytes', text, invalid='random bytes'))
            continue
        elif kind == 'nul-file':
            out.append(g.mk('garbage', 'a file of 4096 NUL bytes', '\x00' * 4096, invalid='NUL bytes'))
            continue
        else:  # utf16
            text = b.text.encode('utf-16').decode(ENC, ERRS)
            out.append(g.mk('garbage', 'the scene encoded as UTF-16', text, invalid='UTF-16 text'))
            continue
        text = '\n'.join(lines)
        if inv:
            out.append(g.mk('garbage', desc, text, bad_line=bad_line, invalid=inv))
        else:
            out.append(g.judged('garbage', desc, text))
    return out


# ---- very long lines (1 MB) -----------------------------------------------------------------------
MB = 1 << 20
LONG_KINDS = ['comment', 'numeric-digits', 'numeric-underflow', 'trailing-spaces', 'param-name', 'subsection-name',
              'expression-sum', 'expression-parens', 'base-name', 'directory', 'mesh-file', 'constants',
              'garbage-no-newline', 'selection']


def gen_long_line(g: Gen, quota):
    recipes = list(LONG_KINDS)
    random.Random(f'{g.seed}/long-line').shuffle(recipes)
    rng = g.rng('long-line')
    b = g.base
    out = []
    for kind in g.pick(recipes, quota):
        if kind == 'comment':
            i = rng.randrange(len(b.lines))
            out.append(g.judged('long-line', 'a 1 MB comment line', b.insert_lines(i, ['#' + 'c' * MB])))
        elif kind == 'numeric-digits':
            out.append(g.value_case('long-line', 'Material/Grain diameter', '1' * MB,
                                    'Material/Grain diameter = 1111... (1 MB of digits)'))
        elif kind == 'numeric-underflow':
            out.append(g.value_case('long-line', 'Material/Grain diameter', '0.' + '0' * MB + '1',
                                    'Material/Grain diameter = 0.000...1 (1 MB, underflows to 0)'))
        elif kind == 'trailing-spaces':
            v = g.base.get('Time/End time')
            out.append(g.value_case('long-line', 'Time/End time', v + ' ' * MB + 'x',
                                    'Time/End time = <value> + 1 MB of spaces + x'))
        elif kind == 'param-name':
            text, idx = b.with_value('Time/' + 'N' * MB, '1')
            out.append(g.mk('long-line', 'a 1 MB parameter name in Time', text, bad_line=idx + 1,
                            invalid='unknown parameter'))
        elif kind == 'subsection-name':
            pos = rng.choice(b.top_level_positions())
            text = b.insert_lines(pos, ['subsection ' + 'S' * MB, 'end'])
            out.append(g.mk('long-line', 'a 1 MB subsection name', text, bad_line=pos + 1,
                            invalid='unknown subsection'))
        elif kind == 'expression-sum':
            v = '0.01' + '+0' * (MB // 2)
            out.append(g.value_case('long-line', 'Initial state/Packing fraction', v,
                                    'Packing fraction = 0.01+0+0+... (1 MB, valid)'))
        elif kind == 'expression-parens':
            depth = MB // 2
            v = '(' * depth + '0.01' + ')' * depth
            out.append(g.value_case('long-line', 'Initial state/Packing fraction', v,
                                    'Packing fraction = ((((...0.01...)))) (512 Ki nested parentheses)'))
        elif kind == 'base-name':
            out.append(g.value_case('long-line', 'Output/Base name', 'b' * MB, 'Output/Base name of 1 MB'))
        elif kind == 'directory':
            out.append(g.value_case('long-line', 'Output/Directory', 'd' * MB, 'Output/Directory of 1 MB',
                                    runnable=False))
        elif kind == 'mesh-file':
            out.append(g.value_case('long-line', 'Domain/Mesh file', 'm' * MB + '.msh', 'Domain/Mesh file of 1 MB',
                                    invalid='Domain/Mesh file: no such file'))
        elif kind == 'constants':
            v = ', '.join(f'c{i}=1' for i in range(MB // 8))
            out.append(g.value_case('long-line', 'Initial state/Constants', v, 'Constants: 131072 constants (1 MB)'))
        elif kind == 'selection':
            out.append(g.value_case('long-line', 'Numerics/Reconstruction', 'weno5' * (MB // 5),
                                    'Numerics/Reconstruction = weno5weno5... (1 MB)'))
        else:  # garbage-no-newline
            text = b.text.rstrip('\n') + '\n' + 'g' * MB
            out.append(g.mk('long-line', '1 MB of text without newline at the end', text,
                            bad_line=len(b.lines) if b.text.endswith('\n') else len(b.lines) + 1,
                            invalid='garbage line'))
    return out


# ---- include ---------------------------------------------------------------------------------------
INCLUDE_KINDS = ['missing', 'missing-absolute', 'self', 'self-dotslash', 'cycle2', 'directory', 'dev-null',
                 'empty-name', 'binary-file', 'bad-value-inside', 'unknown-inside', 'valid-then-bad-main',
                 'deep-chain', 'quoted', 'trailing-comment', 'split-subsection', 'dev-zero', 'in-subsection']


def gen_include(g: Gen, quota):
    recipes = list(INCLUDE_KINDS)
    random.Random(f'{g.seed}/include').shuffle(recipes)
    rng = g.rng('include')
    b = g.base
    out = []
    top = b.first_content_line()
    for kind in g.pick(recipes, quota):
        files = {}
        inv = ''
        bad_line = None
        bad_inc = ''
        pos = rng.choice(b.top_level_positions())
        if kind == 'missing':
            ins, desc, inv = ['include no_such_file.prm'], 'include of a missing file', 'missing include'
        elif kind == 'missing-absolute':
            ins, desc, inv = ['include /nonexistent/dir/x.prm'], 'include of a missing absolute path', 'missing include'
        elif kind == 'self':
            ins, desc, inv = [f'include {g.name}'], 'the scene includes itself', 'include cycle'
        elif kind == 'self-dotslash':
            ins, desc, inv = [f'include ./{g.name}'], 'the scene includes itself as ./name', 'include cycle'
        elif kind == 'cycle2':
            files['fuzz_b.prm'] = f'# b includes the scene back\ninclude {g.name}\n'
            ins, desc, inv = ['include fuzz_b.prm'], 'scene -> fuzz_b.prm -> scene', 'include cycle'
        elif kind == 'directory':
            ins, desc, inv = ['include .'], 'include of a directory (.)', 'include of a directory'
        elif kind == 'dev-null':
            ins, desc = ['include /dev/null'], 'include /dev/null (empty, valid)'
        elif kind == 'empty-name':
            ins, desc, inv = ['include    '], 'include with blanks only', 'include without file'
        elif kind == 'binary-file':
            files['fuzz_bin.prm'] = bytes(rng.randrange(256) for _ in range(512)).decode(ENC, ERRS)
            ins, desc, inv = ['include fuzz_bin.prm'], 'include of 512 random bytes', 'garbage in the include'
            bad_inc = 'fuzz_bin.prm'
        elif kind == 'bad-value-inside':
            files['fuzz_part.prm'] = '# a fragment\n# line 2\nsubsection Material\n  set Grain diameter = -1\nend\n'
            ins, desc, inv = ['include fuzz_part.prm'], 'include of a fragment with Grain diameter = -1 (its line 4)', \
                'negative grain diameter in the include'
            bad_inc = 'fuzz_part.prm'
        elif kind == 'unknown-inside':
            files['fuzz_part.prm'] = '# a fragment\n# line 2\nsubsection Time\n  set Bogus key = 1\nend\n'
            ins, desc, inv = ['include fuzz_part.prm'], 'include of a fragment with an unknown key (its line 4)', \
                'unknown key in the include'
            bad_inc = 'fuzz_part.prm'
        elif kind == 'valid-then-bad-main':
            # a valid 5-line fragment first, then an unknown key in the scene itself
            end = b.get('Time/End time')
            files['fuzz_part.prm'] = f'# a valid fragment\n# line 2\nsubsection Time\n  set End time = {end}\nend\n'
            sc2 = Scene(b.insert_lines(top, ['include fuzz_part.prm']), g.rel)
            text, idx = sc2.with_value('Time/Bogus key', '1')
            out.append(g.mk('include', 'valid include at the top, then an unknown key "Time/Bogus key" in the scene',
                            text, files=files, bad_line=idx + 1, invalid='unknown key'))
            continue
        elif kind == 'deep-chain':
            depth = 200
            for d in range(depth):
                files[f'fuzz_chain_{d}.prm'] = f'include fuzz_chain_{d + 1}.prm\n' if d < depth - 1 else '# end\n'
            ins, desc = ['include fuzz_chain_0.prm'], f'a chain of {depth} nested includes'
        elif kind == 'quoted':
            files['fuzz_part.prm'] = '# valid\n'
            ins, desc, inv = ['include "fuzz_part.prm"'], 'include with a quoted file name', 'missing include'
        elif kind == 'trailing-comment':
            files['fuzz_part.prm'] = '# valid\n'
            ins, desc = ['include fuzz_part.prm # a comment'], 'include followed by a comment'
        elif kind == 'split-subsection':
            files['fuzz_open.prm'] = 'subsection Time\n'
            files['fuzz_close.prm'] = 'end\n'
            ins, desc = ['include fuzz_open.prm', f'  set End time = {b.get("Time/End time")}', 'include fuzz_close.prm'], \
                'a subsection opened in one include and closed in another'
        elif kind == 'dev-zero':
            ins, desc, inv = ['include /dev/zero'], 'include /dev/zero (endless NUL bytes)', 'not a scene file'
        else:  # in-subsection
            files['fuzz_part.prm'] = f'  set End time = {b.get("Time/End time")}\n'
            blk = [x for x in b.blocks if x[0] == ('Time',) and x[2] is not None]
            if blk:
                pos = blk[0][2]
            ins, desc = (['include fuzz_part.prm'] if blk else ['subsection Time', 'include fuzz_part.prm', 'end']), \
                'include inside subsection Time'
        text = b.insert_lines(pos, ins)
        if inv and not bad_inc:
            bad_line = pos + 1
        if inv:
            out.append(g.mk('include', desc, text, files=files, invalid=inv, bad_line=bad_line, bad_include=bad_inc))
        else:
            # includes are not expanded by the validator: acceptance allowed
            out.append(g.mk('include', desc, text, files=files))
    return out


# ---- expressions and constants -------------------------------------------------------------------
def expr_recipes(dim):
    un = AXES[dim] if dim < 3 else None          # an unresolved coordinate
    P, T, V, C = ('Initial state/Packing fraction', 'Initial state/Temperature', 'Initial state/Velocity',
                  'Initial state/Constants')
    r = [
        (P, '0', 'zero packing fraction'), (P, '-0.01', 'negative packing fraction'), (P, '-0', 'zero packing fraction'),
        (P, '1/0', 'non-finite'), (P, '0/0', 'NaN'), (P, 'sqrt(-1)', 'NaN'), (P, 'log(0)', '-inf'),
        (P, '1e300', 'G:above phi_c'), (P, '1e400', 'overflows'), (P, '1', 'G:phi >= 1'), (P, '0.01 +', 'syntax'),
        (P, '(0.01', 'syntax'), (P, '0.01)', 'syntax'), (P, 'foo', 'undefined variable'), (P, '', 'empty'),
        (P, 'if(x < 0, 0.01)', 'syntax'), (P, 'x +* 2', 'syntax'), (P, '0.01 0.02', 'syntax'), (P, 't', 'zero at t = 0'),
        (P, '0.01*(x > 1e6)', 'zero everywhere'), (P, '0.01 - 0.02*(x > -1e9)', 'negative everywhere'),
        (P, 'exp(1000)', 'overflows'), (P, '1e-310', '~denormal packing fraction'), (P, 'abs(-0.01)', ''), (P, '0.01 + 0*sin(x)', ''),
        (P, 'pi/1000', ''), (P, '0.01 ? 1 : 2', 'G:phi = 1 (muParser ternary)'), (P, 'nan', 'undefined variable'), (P, 'inf', 'undefined variable'),
        (P, '0.01 + 0*t', ''), (P, '0.01*x/x', 'NaN where x = 0 only at a corner'),
        (T, '0', 'zero temperature'), (T, '-1e-8', 'negative temperature'), (T, '1/0', 'non-finite'), (T, '0/0', 'NaN'),
        (T, '1e300', '~absurd temperature'), (T, '1e-310', '~denormal temperature'), (T, '1e-8 +', 'syntax'), (T, '', 'empty'), (T, '1e-8; 1e-8', 'two components'),
        (T, 't', 'zero at t = 0'), (T, '-0', 'zero temperature'), (T, 'log(0)', '-inf'), (T, 'exp(1000)', 'overflows'),
        (T, 'sqrt(-1e-8)', 'NaN'), (T, '1e-8*(x > 1e6)', 'zero everywhere'),
        (V, '0/0', 'NaN'), (V, '1/0', 'non-finite'), (V, '', 'empty'), (V, '0; 0; 0; 0', 'four components'),
        (V, ';', 'empty components'), (V, '0,0', 'comma instead of ;'), (V, '1e300', '~absurd velocity'), (V, 'exp(1000)', 'overflows'),
        (V, 'foo', 'undefined variable'), (V, '0 0', 'syntax'), (V, 'sqrt(-1)', 'NaN'),
        (C, 'a=', 'missing value'), (C, '=1', 'missing name'), (C, '1a=2', 'bad name'), (C, 'x=1', 'reserved'),
        (C, 'pi=3', 'reserved'), (C, 'a=nan', 'not a number'), (C, 'a=inf', 'not a number'), (C, 'a=1e-310', 'denormal'),
        (C, 'a=1e400', 'overflows'), (C, 'a=1;b=2', 'bad separator'), (C, 'a b=1', 'bad name'), (C, 'sin=1', '~shadows the function sin'),
        (C, 'if=1', '~shadows if()'), (C, 'a=0x10', 'not a number'), (C, 'a=1, a=2', '~constant defined twice'), (C, 'a=1,,b=2', '~empty entry'), (C, 'a=1e-3', ''),
        (C, 't=1', 'reserved'), (C, 'y=1', 'reserved'), (C, 'z=1', 'reserved'), (C, 'a=', 'missing value'),
        ('P+C', ('phi0', 'phi0=0.01'), ''), ('P+C', ('phi0', 'phi1=0.01'), 'undefined constant'),
        ('P+C', ('phi0', 'phi0=-0.01'), 'negative packing fraction'), ('P+C', ('phi0', 'phi0=0'), 'zero'),
        ('P+C', ('phi0*x/x', 'phi0=0.01'), 'NaN where x = 0 only at a corner'),
    ]
    if un:
        r.append((P, f'0.01 + 0*{un}', f'{un} undefined in {dim}D'))
        r.append((T, f'1e-8 + 0*{un}', f'{un} undefined in {dim}D'))
    if dim == 1:
        r.append((V, '0; 0', '2 components in 1D'))
    if dim == 3:
        r.append((V, '0; 0', '2 components in 3D'))
    return r


def gen_expression(g: Gen, quota):
    recipes = expr_recipes(1)  # the global list (scene-independent ordering)
    random.Random(f'{g.seed}/expression').shuffle(recipes)
    local = expr_recipes(g.dim)
    extra = [r for r in local if r not in recipes]
    recipes = recipes + extra
    out = []
    ckpt = bool(g.base.get('Initial state/Checkpoint'))
    gran = g.base.get('Material/Model') == 'granular'
    for key, val, why in g.pick(recipes, quota, lambda r: r in local):
        if key == 'P+C':
            expr, consts = val
            text, idx = g.base.with_values([('Initial state/Constants', consts),
                                            ('Initial state/Packing fraction', expr)])
            desc = f'Constants = {consts}; Packing fraction = {expr}'
            key = 'Initial state/Packing fraction'
        else:
            text, idx = g.base.with_value(key, val)
            desc = f'{key} = {shorten(val) if val else "(empty)"}'
        if why.startswith('G:'):
            # above close packing: invalid for the granular model; the ideal gas has no phi_c
            why = why[2:] if gran else '~' + why[2:] + ' (ideal gas)'
        soft = why.startswith('~') or 'only at a corner' in why
        inv = f'{key}: {why}' if why and not soft and not ckpt else ''
        dub = f'{key}: {why.lstrip("~")}' if soft else ''
        out.append(g.judged('expression', desc, text, key=key, bad_line=idx + 1, invalid=inv, dubious=dub))
    return out


# ---- boundaries ---------------------------------------------------------------------------------------
def gen_boundary(g: Gen, quota):
    recipes = []
    for ax in range(3):
        a = AXES[ax]
        recipes += [('periodic-one', a), ('restitution-periodic', a), ('velocity-normal', a),
                    ('velocity-slip', a), ('velocity-outflow', a), ('swap', a), ('restitution-outflow', a)]
    recipes += [('mesh-periodic', 'x'), ('all-outflow', 'x'), ('all-periodic', 'x'), ('all-noslip', 'x')]
    random.Random(f'{g.seed}/boundary').shuffle(recipes)
    rng = g.rng('boundary')
    out = []
    for kind, a in g.pick(recipes, quota):
        ax = AXES.index(a)
        kv = []
        cur_m = g.base.get(f'Domain/Boundary {a}-')
        if kind == 'periodic-one':
            other = 'slip wall' if cur_m != 'slip wall' else 'outflow'
            kv = [(f'Domain/Boundary {a}-', 'periodic'), (f'Domain/Boundary {a}+', other)]
            desc = f'only {a}- periodic ({a}+ {other})'
        elif kind == 'restitution-periodic':
            kv = [(f'Domain/Boundary {a}-', 'periodic'), (f'Domain/Boundary {a}+', 'periodic'),
                  (f'Domain/Wall restitution {a}-', '0.8')]
            desc = f'periodic {a} with Wall restitution {a}- = 0.8'
        elif kind in ('velocity-normal', 'velocity-slip', 'velocity-outflow'):
            v = ['0', '0', '0'][:max(g.dim, 1)] if g.dim < 3 else ['0', '0', '0']
            if kind == 'velocity-normal':
                bc = 'no-slip wall'
                v[min(ax, len(v) - 1)] = '0.1'
            else:
                bc = 'slip wall' if kind == 'velocity-slip' else 'outflow'
                v[(ax + 1) % len(v)] = '0.1'
            kv = [(f'Domain/Boundary {a}-', bc), (f'Domain/Boundary {a}+', bc),
                  (f'Domain/Wall velocity {a}-', ', '.join(v))]
            desc = f'{bc} {a}- with Wall velocity {a}- = {", ".join(v)}'
        elif kind == 'restitution-outflow':
            kv = [(f'Domain/Boundary {a}-', 'outflow'), (f'Domain/Wall restitution {a}-', '0.5')]
            desc = f'outflow {a}- with Wall restitution 0.5'
        elif kind == 'swap':
            opts = PARAMS[f'Domain/Boundary {a}-'].options
            o = rng.choice([x for x in opts if x != cur_m])
            kv = [(f'Domain/Boundary {a}-', o), (f'Domain/Boundary {a}+', o)]
            desc = f'both {a} sides {o}'
        elif kind == 'mesh-periodic':
            kv = [('Domain/Boundary x-', 'periodic'), ('Domain/Boundary x+', 'periodic')]
            desc = 'x periodic'
        else:
            bc = {'all-outflow': 'outflow', 'all-periodic': 'periodic', 'all-noslip': 'no-slip wall'}[kind]
            kv = [(f'Domain/Boundary {s}', bc) for s in SIDES]
            desc = f'every boundary {bc}'
        text, idx = g.base.with_values(kv)
        out.append(g.judged('boundary', desc, text, key=kv[-1][0]))
    return out


# ---- mesh files --------------------------------------------------------------------------------------
def _read(p):
    try:
        return (REPO / p).read_text(encoding=ENC, errors=ERRS)
    except OSError:
        return ''


def mesh_mutations(msh, dim, rng):
    """[(name, text, why)] of broken gmsh 2.2 files derived from a valid one."""
    lines = msh.split('\n')
    try:
        e0 = lines.index('$Elements')
        n0 = lines.index('$Nodes')
    except ValueError:
        return []
    nel = int(lines[e0 + 1])
    elems = list(range(e0 + 2, e0 + 2 + nel))
    face_type = '3' if dim == 3 else '1'
    faces = [i for i in elems if lines[i].split()[1] == face_type]
    out = []
    for bid in ['6', '7', '255', '65535', '99999999999', '-1', '4' if dim == 2 else '6']:
        ls = list(lines)
        i = rng.choice(faces)
        f = ls[i].split()
        f[3] = f[4] = bid
        ls[i] = ' '.join(f)
        out.append((f'boundary id {bid}', '\n'.join(ls), f'boundary id {bid} out of range'))
    ls = list(lines)
    f = ls[n0 + 2].split()
    f[1] = 'nan'
    ls[n0 + 2] = ' '.join(f)
    out.append(('node coordinate nan', '\n'.join(ls), 'nan coordinate'))
    ls = list(lines)
    f = ls[n0 + 3].split()
    f[2] = '1e309'
    ls[n0 + 3] = ' '.join(f)
    out.append(('node coordinate 1e309', '\n'.join(ls), 'infinite coordinate'))
    out.append(('truncated in the middle', '\n'.join(lines[:len(lines) // 2]), 'truncated mesh'))
    ls = list(lines)
    ls[n0 + 1] = '999999999999'
    out.append(('node count 999999999999', '\n'.join(ls), 'bad node count'))
    ls = list(lines)
    ls[e0 + 1] = '-5'
    out.append(('element count -5', '\n'.join(ls), 'bad element count'))
    ls = list(lines)
    vol = [i for i in elems if lines[i].split()[1] == ('5' if dim == 3 else '3')]
    i = vol[len(vol) // 2]
    f = ls[i].split()
    f[-1] = '99999'
    ls[i] = ' '.join(f)
    out.append(('cell referencing node 99999', '\n'.join(ls), 'missing node'))
    ls = lines[:e0 + 1] + ['0', '$EndElements', '']
    out.append(('no elements', '\n'.join(ls), 'no cells'))
    out.append(('empty file', '', 'empty mesh'))
    out.append(('random bytes', bytes(rng.randrange(256) for _ in range(2048)).decode(ENC, ERRS), 'garbage mesh'))
    ls = list(lines)
    ls[1] = '4.1 0 8'
    out.append(('MeshFormat 4.1 header on 2.2 data', '\n'.join(ls), 'wrong format version'))
    ls = list(lines)
    if dim == 3:
        # flatten one node: cells no longer congruent boxes
        f = ls[n0 + 2].split()
        f[1] = str(float(f[1]) + 1e-4)
        ls[n0 + 2] = ' '.join(f)
        out.append(('one node moved by 0.1 mm', '\n'.join(ls), 'not an axis-aligned box'))
    return out


MESH_PATH_KINDS = [('missing', 'no_such_mesh.msh', 'missing mesh'), ('directory', '.', 'a directory'),
                   ('dev-null', '/dev/null', 'empty mesh'), ('dev-zero', '/dev/zero', 'endless NUL bytes'),
                   ('extension', 'fuzz_mesh.vtk', 'unknown extension'), ('no-extension', 'fuzz_mesh', 'no extension'),
                   ('ucd-garbage', 'fuzz_mesh.inp', 'garbage ucd'), ('empty-msh', 'fuzz_mesh.msh', 'empty mesh')]


def gen_mesh(g: Gen, quota):
    cur = g.base.get('Domain/Mesh file')
    if cur:
        src = os.path.normpath(str(Path(g.rel).parent / cur))
        dim = g.dim
    else:
        dim = g.dim
        src = 'tests/data/box_3d.msh' if dim == 3 else 'tests/data/box_2d.msh'
    muts = mesh_mutations(_read(src), max(dim, 2), random.Random(f'{g.seed}/mesh/{src}')) if dim >= 2 else []
    recipes = [('content', m) for m in muts] + [('path', p) for p in MESH_PATH_KINDS]
    if dim == 1:
        recipes = [('path', p) for p in MESH_PATH_KINDS] + [('1d', None)]
    random.Random(f'{g.seed}/mesh').shuffle(recipes)
    out = []
    for kind, m in g.pick(recipes, quota):
        files = {}
        if kind == 'content':
            name, text, why = m
            files['fuzz_mesh.msh'] = text
            value, desc = 'fuzz_mesh.msh', f'mesh ({Path(src).name}) with {name}'
        elif kind == '1d':
            files['fuzz_mesh.msh'] = _read('tests/data/box_2d.msh')
            value, desc, why = 'fuzz_mesh.msh', 'a (valid 2D) mesh file in a 1D scene', 'mesh in 1D'
        else:
            pk, value, why = m
            if pk == 'extension':
                files['fuzz_mesh.vtk'] = _read(src) if dim >= 2 else 'x'
            elif pk == 'no-extension':
                files['fuzz_mesh'] = _read(src) if dim >= 2 else 'x'
            elif pk == 'ucd-garbage':
                files['fuzz_mesh.inp'] = '1 2 3\nnot a ucd file\n'
            elif pk == 'empty-msh':
                files['fuzz_mesh.msh'] = ''
            desc = f'Domain/Mesh file = {value} ({why})'
        text, idx = g.base.with_value('Domain/Mesh file', value)
        out.append(g.mk('mesh', desc, text, files=files, key='Domain/Mesh file', bad_line=idx + 1,
                        invalid=f'Domain/Mesh file: {why}'))
    return out


# ---- paths: output directory, base name, checkpoint ---------------------------------------------------
PATH_RECIPES = [
    ('Output/Directory', '/proc/granhydro_fuzz/out', 'cannot be created'),
    ('Output/Directory', '/dev/null/out', 'cannot be created'),
    ('Output/Directory', '/etc/passwd', 'a file, not a directory'),
    ('Output/Directory', '', ''), ('Output/Directory', 'sub/dir/out', ''),
    ('Output/Directory', 'd' * 300, 'component longer than 255 bytes'),
    ('Output/Base name', '', 'empty'), ('Output/Base name', 'a/b', 'a path'), ('Output/Base name', '../x', 'a path'),
    ('Output/Base name', '.hidden', 'hidden'), ('Output/Base name', 'b' * 101, 'too long'),
    ('Output/Base name', 'a b', 'a blank'), ('Output/Base name', 'caf\u00e9', 'non-ASCII'),
    ('Output/Base name', 'x' * 100, ''), ('Output/Base name', '-', ''),
    ('Initial state/Checkpoint', 'no_such.checkpoint', 'missing checkpoint'),
    ('Initial state/Checkpoint', '.', 'a directory'), ('Initial state/Checkpoint', '/dev/null', 'empty'),
    ('Initial state/Checkpoint', 'fuzz.checkpoint', 'garbage checkpoint'),
    ('Initial state/Checkpoint', 'fuzz_empty.checkpoint', 'empty checkpoint'),
    ('Initial state/Checkpoint', '/dev/zero', 'endless NUL bytes'),
    ('Initial state/Checkpoint', '<scene>', 'a scene, not a checkpoint'),
]


def gen_path(g: Gen, quota):
    recipes = list(PATH_RECIPES)
    random.Random(f'{g.seed}/path').shuffle(recipes)
    rng = g.rng('path')
    out = []
    for key, val, why in g.pick(recipes, quota):
        files = {}
        if val == 'fuzz.checkpoint':
            files[val] = bytes(rng.randrange(256) for _ in range(4096)).decode(ENC, ERRS)
        elif val == 'fuzz_empty.checkpoint':
            files[val] = ''
        elif val == '<scene>':
            val = g.name
        inv = f'{key}: {why}' if why else ''
        safe = not (key == 'Output/Directory' and (val.startswith('/') or '..' in val))
        out.append(g.value_case('path', key, val, f'{key} = {shorten(val) or "(empty)"}', invalid=inv,
                                files=files, runnable=safe))
    return out


GENERATORS = {'numeric': gen_numeric, 'list': gen_list, 'selection': gen_selection, 'valid-alt': gen_valid_alt,
              'unknown-param': gen_unknown_param, 'unknown-subsection': gen_unknown_subsection,
              'structure': gen_structure, 'truncate': gen_truncate, 'garbage': gen_garbage,
              'long-line': gen_long_line, 'include': gen_include, 'expression': gen_expression,
              'boundary': gen_boundary, 'mesh': gen_mesh, 'path': gen_path}


def quotas(n, classes):
    w = {c: WEIGHTS[c] for c in classes}
    tot = sum(w.values())
    q = {c: n * w[c] // tot for c in classes}
    rest = sorted(classes, key=lambda c: (-(n * w[c] % tot), CLASSES.index(c)))
    for c in rest[:n - sum(q.values())]:
        q[c] += 1
    return q


def scene_files(repo=REPO):
    return sorted(str(p.relative_to(repo)) for p in list((repo / 'parameters').glob('*.prm')) +
                  list((repo / 'parameters' / 'hard').glob('*.prm')))


def generate(seed=1, per_scene=40, classes=None, scenes=None, repo=REPO):
    classes = [c for c in CLASSES if classes is None or c in classes]
    scenes = scenes or scene_files(repo)
    out = []
    spread = [c for c in classes if c != 'admission']
    for sidx, rel in enumerate(scenes):
        text = (repo / rel).read_text(encoding=ENC, errors=ERRS)
        g = Gen(rel, text, sidx, len(scenes), seed)
        for cls, q in (quotas(per_scene, spread).items() if spread else []):
            if q:
                out += GENERATORS[cls](g, q)
    if 'admission' in classes:
        out += admission_cases(repo)
    return out


# =====================================================================================
# Admission: what --check accepts, the run must run (a fixed list, class 'admission')
# =====================================================================================
def box_msh(nx, ny, lx, ly, scale=1.0):
    """A gmsh 2.2 box of nx x ny quadrilaterals over [0, lx] x [0, ly] (coordinates times
    scale), boundary ids by side as deal.II colorizes a box (0 x-, 1 x+, 2 y-, 3 y+)."""
    def node(i, j):
        return j * (nx + 1) + i + 1
    nodes = [f'{node(i, j)} {"%.17g" % (i * lx / nx * scale)} {"%.17g" % (j * ly / ny * scale)} 0'
             for j in range(ny + 1) for i in range(nx + 1)]
    els = []
    for j in range(ny):
        els.append((1, 0, [node(0, j), node(0, j + 1)]))
        els.append((1, 1, [node(nx, j), node(nx, j + 1)]))
    for i in range(nx):
        els.append((1, 2, [node(i, 0), node(i + 1, 0)]))
        els.append((1, 3, [node(i, ny), node(i + 1, ny)]))
    for j in range(ny):
        for i in range(nx):
            els.append((3, 100, [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]))
    lines = ['$MeshFormat', '2.2 0 8', '$EndMeshFormat', '$Nodes', str(len(nodes))] + nodes + \
            ['$EndNodes', '$Elements', str(len(els))]
    lines += [f'{k + 1} {t} 2 {tag} {tag} ' + ' '.join(map(str, v)) for k, (t, tag, v) in enumerate(els)]
    return '\n'.join(lines + ['$EndElements', ''])


# a checkpoint made by running the binary on a scene (Runner.prepare): (scene, -p overrides)
CHECKPOINT_CACHE = {}


def admission_cases(repo=REPO):
    """The families of the admission issue: mesh-file scale and stencil, device links, the
    memory of refinement levels, checkpoints of another mesh, duplicated subsections, the
    smaller acceptances, and extreme physics inside the documented limits (those may be
    refused or run, but a run must not stop with exit 3).  Case.note 'portable' marks the
    must-refuse cases whose answer does not depend on the machine (the ctest corpus)."""
    out = []

    def gen(rel):
        return Gen(rel, (repo / rel).read_text(encoding=ENC, errors=ERRS), 0, 1, 0)

    def add(rel, desc, text, invalid='', files=None, bad_line=None, portable=True, runnable=True, key=''):
        stem = Path(rel).stem
        out.append(Case(f'admission:{len(out) + 1:02d}:{stem}', rel, 'admission', desc, text, files=files or {},
                        invalid=invalid, bad_line=bad_line, runnable=runnable, key=key,
                        note='portable' if portable else ''))

    def value(rel, kv, desc, invalid='', files=None, portable=True, base=None, runnable=True):
        sc = base or gen(rel).base
        text = sc.text
        idx = None
        for k, v in kv:
            text, idx = Scene(text, rel).with_value(k, v)
        add(rel, desc, text, invalid, files, (idx + 1) if (invalid and len(kv) == 1) else None, portable,
            runnable=runnable, key=kv[-1][0])

    blast = 'parameters/blast_2d.prm'
    # mesh files: the box limits on coordinates and cell sizes, the stencil width
    for scale, why in [(1e-300, 'cells of 2.5e-301 m, below 1e-3 grain diameters'),
                       (1e300, 'coordinates beyond 1e6 m'), (1e7, 'coordinates beyond 1e6 m'),
                       (1e-7, 'cells of 2.5e-8 m, below 1e-3 grain diameters')]:
        value(blast, [('Domain/Mesh file', 'fuzz_mesh.msh')], f'a 4 x 3 gmsh box scaled by {scale:g}',
              f'Domain/Mesh file: {why}', {'fuzz_mesh.msh': box_msh(4, 3, 1.0, 0.75, scale)})
    value(blast, [('Domain/Mesh file', 'fuzz_mesh.msh')], 'a single-cell gmsh mesh with WENO5',
          'Domain/Mesh file: 1 cell, WENO5 needs 3 between walls', {'fuzz_mesh.msh': box_msh(1, 1, 0.1, 0.1)})
    value(blast, [('Numerics/Reconstruction', 'muscl'), ('Domain/Mesh file', 'fuzz_mesh.msh')],
          'a single-cell gmsh mesh with MUSCL', 'Domain/Mesh file: 1 cell, MUSCL needs 2 between walls',
          {'fuzz_mesh.msh': box_msh(1, 1, 0.1, 0.1)})
    value(blast, [('Domain/Mesh file', 'fuzz_mesh.msh')], 'a 4 x 3 gmsh box with WENO5 (the box 4 x 3 runs)',
          '', {'fuzz_mesh.msh': box_msh(4, 3, 0.1, 0.075)})
    # files that are not what they claim: links to devices
    for dev in ['/dev/zero', '/dev/urandom']:
        value(blast, [('Domain/Mesh file', 'fuzz_mesh.msh')], f'the mesh file a link to {dev}',
              f'Domain/Mesh file: not a regular file ({dev})', {'fuzz_mesh.msh': ('symlink', dev)})
    g = gen('parameters/sod_1d.prm')
    add(g.rel, 'an include that is a link to /dev/urandom',
        g.base.insert_lines(g.base.first_content_line(), ['include fuzz_part.prm']),
        'include: not a regular file', {'fuzz_part.prm': ('symlink', '/dev/urandom')})
    # the memory of the refinement levels (the finest lattice within 2e8 points)
    value(blast, [('Adaptivity/Maximum level', '7')], '100 x 100 cells refined up to 7 levels (1.6e8 cells)',
          'Adaptivity/Maximum level: up to 1.6e8 cells, ~370 GB', portable=False)
    value('parameters/hard/harsh_vibration-ci.prm',
          [('Domain/Cells', '200, 800'), ('Diffusion step/Integrator', 'gauss-legendre'),
           ('Adaptivity/Maximum level', '5')],
          '200 x 800 cells, 5 levels, Gauss-Legendre (1.6e8 cells, ~2 TB)',
          'Adaptivity/Maximum level: up to 1.6e8 cells at 13 KiB each, ~2 TB')
    value('parameters/amr_blast_3d.prm', [('Adaptivity/Maximum level', '3')], '8^3 cells, 3 levels (fits)', '',
          runnable=False)
    # checkpoints written for another mesh
    for rel, ck_over, why in [
            ('parameters/sod_1d.prm', ('Domain/Cells=50',), 'Domain/Cells differ'),
            ('parameters/sod_1d.prm', ('Domain/Upper corner=2',), 'the corners differ'),
            (blast, ('Domain/Cells=20, 20',), 'Domain/Cells differ')]:
        value(rel, [('Initial state/Checkpoint', 'fuzz.checkpoint')], f'a checkpoint of the scene with {ck_over[0]}',
              f'Initial state/Checkpoint: {why}', {'fuzz.checkpoint': ('checkpoint', rel, ck_over)})
    # a repeated subsection that contradicts the first, and one that repeats it
    g = gen('parameters/sod_1d.prm')
    add(g.rel, 'a second subsection Output with another Directory',
        g.base.text + '\nsubsection Output\n  set Directory = elsewhere\nend\n',
        'Output/Directory: set twice with different values')
    add(g.rel, 'a second subsection Output repeating the Directory (allowed)',
        g.base.text + f'\nsubsection Output\n  set Directory = {g.base.get("Output/Directory")}\nend\n', '')
    # the smaller acceptances
    value('parameters/sod_1d.prm', [('Time/Steady state tolerance', '0.01'), ('Output/Interval', '0')],
          'Steady state tolerance with Output/Interval = 0', 'Time/Steady state tolerance: never tested')
    value('parameters/sod_1d.prm', [('Initial state/Temperature', '1e-8 + 1e-310 * x')],
          'a subnormal literal inside an expression', 'Initial state/Temperature: 1e-310 subnormal')
    value('parameters/sod_1d.prm', [('Initial state/Constants', 'sin=1')], 'a constant named sin',
          'Initial state/Constants: sin is a function')
    # extreme physics inside the documented limits: refused by --check, or run (3 steps)
    # without exit 3
    phys = 'tests/data/restart_granular_2d.prm'
    pb = Scene(Scene(gen(phys).base.with_value('Domain/Cells', '16, 16')[0], phys).with_value(
        'Initial state/Velocity', '0; 0')[0], phys)
    for kv, desc in [
            ([('Initial state/Packing fraction', '1e-12')], 'packing fraction 1e-12 under gravity'),
            ([('Initial state/Temperature', '1e-30')], 'T = 1e-30 J under gravity'),
            ([('Initial state/Temperature', '1e-30'), ('Initial state/Velocity', '1e3; 0')],
             'T = 1e-30 J at 1e3 m/s'),
            ([('Material/Material density', '1e308')], 'material density 1e308'),
            ([('Dense closure/Model', 'johnson-jackson'), ('Dense closure/Viscosity time', '1e308')],
             'Dense closure/Viscosity time 1e308'),
            ([('Effects/Gravity', '0, -1e6')], '|g| = 1e6 m/s^2'),
            ([('Domain/Wall velocity y-', '300, 0')], 'a no-slip floor at 300 m/s'),
            ([('Initial state/Packing fraction', 'if(x < 0.02, 1e-10, 0.6)')], 'a packing-fraction jump 1e-10 / 0.6'),
    ]:
        value(phys, kv, desc, '', base=pb)
    return out


# =====================================================================================
# The ctest corpus: cases that must be refused
# =====================================================================================
CORPUS_SEED = 20240611
CORPUS_PER_SCENE = 40
CORPUS_SIZE = 300
CORPUS_CLASSES = ['numeric', 'list', 'selection', 'unknown-param', 'unknown-subsection', 'structure', 'truncate',
                  'garbage', 'long-line', 'include', 'expression', 'boundary', 'mesh', 'path', 'valid-alt']


def pinned_cases(repo=REPO):
    """Reproducers of the defects the fuzzer found, kept in the corpus as regression cases
    (all must be refused).  'open' ones were still accepted by the binary of 2026-12-02 07:45."""
    out = []

    def gen(rel):
        return Gen(rel, (repo / rel).read_text(encoding=ENC, errors=ERRS), 0, 1, 0)

    def add(rel, desc, text, bad_line=None, files=None, bad_include=''):
        stem = rel[len('parameters/'):-4]
        out.append(Case(f'pinned:{len(out) + 1:02d}:{stem}', rel, 'pinned', desc, text, files=files or {},
                        invalid=desc, bad_line=bad_line, bad_include=bad_include))

    def value(rel, key, val, desc):
        g = gen(rel)
        text, idx = g.base.with_value(key, val)
        add(rel, f'{key} = {shorten(val)}: {desc}', text, idx + 1)

    def mesh(rel, src, which, desc):
        g = gen(rel)
        m = [t for (n, t, _) in mesh_mutations(_read(src), g.dim, random.Random(f'pinned/{src}')) if n == which][0]
        text, idx = g.base.with_value('Domain/Mesh file', 'fuzz_mesh.msh')
        add(rel, f'mesh {Path(src).name} with {which}: {desc}', text, idx + 1, {'fuzz_mesh.msh': m})

    value('parameters/sod_1d.prm', 'Initial state/Packing fraction', '-5, 0.01', 'a list of expressions (was: accepted)')
    value('parameters/sod_1d.prm', 'Time/End time', '0.2' + ' ' * MB + 'x',
          'a value padded with 1 MB of spaces (was: 36 s to refuse, deal.II erased them one by one)')
    value('parameters/hard/shock_into_bed.prm', 'Initial state/Temperature', '1e-8, 1e-8',
          'a list of expressions (was: accepted)')
    value('parameters/sod_1d.prm', 'Domain/Lower corner', '1e-310', 'denormal list entry (was: accepted)')
    value('parameters/bouncing_bed-ci.prm', 'Effects/Gravity', '0, -9.81, 1e-310', 'denormal list entry (was: accepted)')
    value('parameters/silo.prm', 'Initial state/Constants', 'a=1e-310', 'denormal constant (was: accepted)')
    value('parameters/hard/dense_collapse.prm', 'Material/Grain diameter', '1e-300',
          'grain mass underflows (was: accepted, run stopped with nan)')
    value('parameters/hard/harsh_vibration.prm', 'Numerics/CFL number', '1e-300', 'no progress (was: accepted)')
    value('parameters/silo-ci.prm', 'Initial state/Packing fraction', '-0.01',
          'mesh-file scene (was: accepted by --check, refused by the run)')
    value('parameters/sedimentation-ci.prm', 'Output/Directory', '/proc/granhydro_fuzz/out',
          'uncreatable (was: accepted by --check, refused by the run)')
    value('parameters/blast_2d.prm', 'Output/Directory', 'd' * 300,
          'a 300-character folder name (was: accepted by --check, refused by the run)')
    mesh('parameters/blast_2d.prm', 'tests/data/box_2d.msh', 'boundary id -1', 'negative boundary id (was: accepted)')
    mesh('parameters/hard/cooling_3d.prm', 'tests/data/box_3d.msh', 'node count 999999999999',
         'absurd node count (was: std::bad_alloc)')
    mesh('parameters/hard/cooling_3d.prm', 'tests/data/box_3d.msh', 'MeshFormat 4.1 header on 2.2 data',
         'wrong format version (was: unbounded allocation, 24 GB and OOM kill without a limit)')
    g = gen('parameters/sod_1d.prm')
    lines = list(g.base.lines)
    last_end = max(i for i, ln in enumerate(lines) if ln.strip() == 'end')
    del lines[last_end]
    add(g.rel, 'the last end deleted: must name the unclosed subsection or its line (was: no line)', '\n'.join(lines))
    part = '# a fragment\n# line 2\nsubsection Material\n  set Grain diameter = -1\nend\n'
    text = g.base.insert_lines(g.base.first_content_line() + 1, ['include fuzz_part.prm'])
    add(g.rel, 'an included fragment with Grain diameter = -1 on its line 4: must name the fragment '
        '(was: a line of the including file)', text, files={'fuzz_part.prm': part}, bad_include='fuzz_part.prm')
    frag = f'# a valid fragment\n# line 2\nsubsection Time\n  set End time = {g.base.get("Time/End time")}\nend\n'
    sc2 = Scene(g.base.insert_lines(g.base.first_content_line(), ['include fuzz_part.prm']), g.rel)
    text, idx = sc2.with_value('Time/Bogus key', '1')
    add(g.rel, 'a valid include at the top, then an unknown key: must name its own line (was: offset by the include)',
        text, idx + 1, {'fuzz_part.prm': frag})
    # open on 2026-12-02: the slip-wall rule ignores the components along unresolved directions
    value('parameters/hard/dense_collapse.prm', 'Domain/Wall velocity x+', '0, 0.1, 0',
          'a moving slip wall in 1D (open: accepted; the same in 2D along y is refused)')
    value('parameters/blast_2d.prm', 'Domain/Wall velocity x+', '0, 0, 0.1',
          'a slip wall moving along z in 2D (open: accepted)')
    return out


def corpus_cases(size=CORPUS_SIZE):
    """Deterministic list of must-refuse cases: 300 generated ones spread over classes and scenes,
    plus the pinned reproducers of defects found earlier (pinned_cases())."""
    allc = [c for c in generate(CORPUS_SEED, CORPUS_PER_SCENE, CORPUS_CLASSES) if c.must_refuse]
    # skip the slow ones (1 MB lines, /dev/zero) and paths that depend on the machine
    allc = [c for c in allc if c.cls != 'long-line' or 'comment' in c.desc or 'parameter name' in c.desc]
    allc = [c for c in allc if '/dev/zero' not in c.desc]
    by = {}
    for c in allc:
        by.setdefault(c.cls, []).append(c)
    out = []
    i = 0
    while len(out) < size and any(i < len(v) for v in by.values()):
        for cls in CORPUS_CLASSES:
            v = by.get(cls, [])
            if i < len(v) and len(out) < size:
                out.append(v[i])
        i += 1
    return out + pinned_cases() + [c for c in admission_cases() if c.must_refuse and c.note == 'portable']


# extreme physics that --check accepts and the run still stops with exit 3 (open; none since
# the first step may halve its CFL step down to 2^-30, see source/driver/time_loop.cc)
ADMISSION_OPEN = set()


def admission_run_cases():
    """The admission cases that may be accepted: each must be refused by --check or run its
    first steps (exit 0), never stop with exit 3 (ctest input.fuzz_corpus runs them)."""
    return [c for c in admission_cases() if not c.must_refuse and c.runnable and c.desc not in ADMISSION_OPEN]


# =====================================================================================
# Running
# =====================================================================================
PARAM_MSG_RE = re.compile(r"parameter '([^']+)'|entry named ([^\n]+?) does not match|No entry with name <([^>]*)>|"
                          r"entry <([^>]*)>|subsection to be entered: ([^\n]*)")
LINE_MSG_RE = re.compile(r'\b[Ll]ine <?(\d+)>?')
# whole-file conditions, named as such (no parameter or line to name)
FILE_LEVEL_RE = re.compile(r'sets no parameter|include cycle|does not name a readable file|'
                           r'includes? .*(cannot|no such|not found|does not exist|not a regular file|directory|nest)')


def links_for(rel, text, repo=REPO):
    """Top-level repository folders the scene refers to (relative mesh/checkpoint/include paths)."""
    sc = Scene(text, rel)
    refs = [sc.raw('Domain/Mesh file'), sc.raw('Initial state/Checkpoint')] + [f for (_, f) in sc.includes]
    out = set()
    for r in refs:
        if r and not r.startswith('/'):
            p = os.path.normpath(str(Path(rel).parent / r))
            if not p.startswith('..'):
                out.add(p.split('/')[0])
    out.discard(rel.split('/')[0])
    return sorted(out)


def materialise(case, root, repo=REPO, base_links=None):
    """Write the scene tree of a case under root; returns the scene path."""
    src = Path(root)
    scene = src / case.scene
    scene.parent.mkdir(parents=True, exist_ok=True)
    scene.write_bytes(case.text.encode(ENC, ERRS))
    for name, content in case.files.items():
        p = scene.parent / name
        p.parent.mkdir(parents=True, exist_ok=True)
        if content is None:
            p.mkdir(exist_ok=True)
        elif isinstance(content, tuple) and content[0] == 'symlink':
            p.symlink_to(content[1])
        elif isinstance(content, tuple) and content[0] == 'checkpoint':
            made = CHECKPOINT_CACHE.get(content[1:])
            if made:
                shutil.copyfile(made, p)
        else:
            p.write_bytes(content.encode(ENC, ERRS))
    for top in (base_links if base_links is not None else []):
        link = src / top
        if not link.exists():
            link.symlink_to(repo / top)
    return scene


def child_env(exe, isolated=True):
    env = dict(os.environ)
    d = str(Path(exe).resolve().parent)
    if (Path(d) / 'libgranhydro_core.so').exists():
        env['LD_LIBRARY_PATH'] = d + (':' + env['LD_LIBRARY_PATH'] if env.get('LD_LIBRARY_PATH') else '')
    env.setdefault('DEAL_II_NUM_THREADS', '1')
    env.setdefault('OMP_NUM_THREADS', '1')
    if isolated:
        # Open MPI singleton without the helper daemon (orted): ~30 % less start-up time
        # (run_cmd gives every process its own session directory, see there)
        env.setdefault('OMPI_MCA_ess_singleton_isolated', '1')
    env.setdefault('OMPI_ALLOW_RUN_AS_ROOT', '1')
    env.setdefault('OMPI_ALLOW_RUN_AS_ROOT_CONFIRM', '1')
    return env


def run_cmd(cmd, cwd, timeout, env, mem_gib, mpi_tmp=None):
    """Run cmd in cwd (own process group, address space limited to mem_gib: a scene that makes
    granhydro allocate without bound fails with std::bad_alloc instead of exhausting the machine)."""
    pre = None
    if mem_gib and shutil.which('prlimit'):
        cmd = ['prlimit', f'--as={int(mem_gib * (1 << 30))}', '--'] + cmd
    elif mem_gib:
        import resource
        lim = int(mem_gib * (1 << 30))
        pre = lambda: resource.setrlimit(resource.RLIMIT_AS, (lim, lim))  # noqa: E731
    if mpi_tmp:
        # isolated Open MPI singletons share the session directory of job family 0: one per case
        env = dict(env, OMPI_MCA_orte_tmpdir_base=str(mpi_tmp))
    t0 = time.time()
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                         start_new_session=True, preexec_fn=pre)
    timed_out = False
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = p.communicate()
    return p.returncode, out.decode(ENC, 'replace'), err.decode(ENC, 'replace'), timed_out, time.time() - t0


def clip(s, n=4000):
    if len(s) <= n:
        return s
    return s[:n // 2] + f'\n...[{len(s) - n} characters cut]...\n' + s[-n // 2:]


def crash_marker(err):
    for m in CRASH_MARKERS:
        if m in err:
            return m
    return ''


FILE_PARAM_RE = re.compile(r"'(Domain/Mesh file|Initial state/Checkpoint)'")


def classify_check(case, rc, err, timed_out, leftovers, nlines, scene_name):
    info = {}
    m = crash_marker(err)
    if timed_out:
        return 'hang', info
    if rc is None or rc < 0 or rc not in (0, 2) or m:
        info['marker'] = m
        return 'crash', info
    if rc == 0:
        return ('accepted-dirty' if leftovers else 'accepted'), info
    if leftovers:
        return 'refused-dirty', info
    pm = PARAM_MSG_RE.search(err)
    lm = LINE_MSG_RE.search(err)
    info['names_param'] = bool(pm)
    info['names_line'] = int(lm.group(1)) if lm else None
    fm = FILE_LEVEL_RE.search(err)
    info['names_file_level'] = bool(fm)
    if not pm and not lm and not fm:
        return 'refused-unclear', info
    if lm:
        n = int(lm.group(1))
        if FILE_PARAM_RE.search(err):
            pass  # the line is one of the file that parameter names (a mesh, a checkpoint)
        elif n > nlines:
            info['misleading'] = f'names line {n}, the file has {nlines} lines'
        elif case.bad_include and case.bad_include not in err:
            info['misleading'] = f'the offence is in {case.bad_include}, the message names line {n} of {scene_name}'
        elif case.bad_line and n != case.bad_line and not pm:
            info['misleading'] = f'names line {n}, the offending line is {case.bad_line}'
        elif case.bad_line and n != case.bad_line and pm:
            info['misleading'] = f'names line {n}, the offending line is {case.bad_line}'
    elif case.bad_include and case.bad_include not in err and not pm:
        info['misleading'] = f'the offence is in {case.bad_include}, the message does not name it'
    if info.get('misleading'):
        return 'refused-misleading', info
    return 'refused', info


def run_overrides(case, steps):
    """The -p overrides of a real run: a few steps, output in the working directory (a
    scene sets each parameter once, so they are not appended to the scene)."""
    outdir = 'fuzz-out'
    if case.key == 'Output/Directory':
        v = Scene(case.text).get('Output/Directory').strip()
        if v and not v.startswith('/') and '..' not in v and len(v) < 4000 and '#' not in v:
            outdir = v
    return ['-p', f'Time/Maximum steps={steps}', '-p', f'Output/Directory={outdir}']


def classify_run(rc, err, timed_out):
    m = crash_marker(err)
    if timed_out:
        return 'run-hang'
    if rc is None or rc < 0 or rc not in (0, 2, 3) or m:
        return 'run-crash'
    return {0: 'run-ok', 2: 'run-refused', 3: 'run-fail'}[rc]


class Runner:
    def __init__(self, exe, workroot, jobs=2, check_timeout=30, run_timeout=60, steps=3, mem_gib=6,
                 isolated=True, keep=False, repo=REPO):
        self.exe = str(Path(exe).resolve())
        self.root = Path(workroot)
        self.root.mkdir(parents=True, exist_ok=True)
        self.jobs, self.ct, self.rt, self.steps, self.mem = jobs, check_timeout, run_timeout, steps, mem_gib
        self.env = child_env(exe, isolated)
        self.keep = keep
        self.repo = repo
        self._links = {}

    def links(self, rel):
        if rel not in self._links:
            self._links[rel] = links_for(rel, (self.repo / rel).read_text(encoding=ENC, errors=ERRS), self.repo)
        return self._links[rel]

    def prepare(self, cases):
        """Make the checkpoints the cases name (('checkpoint', scene, overrides) files): one
        step of the scene with the overrides, its final checkpoint kept in the work folder."""
        for c in cases:
            for content in c.files.values():
                if not (isinstance(content, tuple) and content[0] == 'checkpoint') or content[1:] in CHECKPOINT_CACHE:
                    continue
                rel, over = content[1], content[2]
                d = Path(tempfile.mkdtemp(prefix='ck_', dir=self.root))
                cmd = [self.exe, '-p', 'Time/Maximum steps=1', '-p', f'Output/Directory={d / "out"}',
                       '-p', 'Output/Write VTU=false', '-p', 'Output/Write checkpoint=true', '-p', 'Output/Base name=ck']
                for o in over:
                    cmd += ['-p', o]
                rc, _, err, _, _ = run_cmd(cmd + [str(self.repo / rel)], d, 120, self.env, self.mem)
                made = d / 'out' / 'ck.checkpoint'
                if rc != 0 or not made.exists():
                    raise RuntimeError(f'cannot make the checkpoint of {rel} with {over}: exit {rc}: {err[-400:]}')
                CHECKPOINT_CACHE[content[1:]] = str(made)

    @staticmethod
    def place_checkpoints(case, wd):
        """A checkpoint path is relative to the working directory (a mesh path to the scene):
        the generated checkpoints also go there; returns their names (not leftovers)."""
        given = set()
        for name, content in case.files.items():
            if isinstance(content, tuple) and content[0] == 'checkpoint' and content[1:] in CHECKPOINT_CACHE:
                shutil.copyfile(CHECKPOINT_CACHE[content[1:]], wd / name)
                given.add(name)
        return given

    def check(self, case):
        d = Path(tempfile.mkdtemp(prefix='c_', dir=self.root))
        try:
            scene = materialise(case, d / 'src', self.repo, self.links(case.scene))
            wd = d / 'wd'
            wd.mkdir()
            (d / 'mpi').mkdir()
            given = self.place_checkpoints(case, wd)
            rc, out, err, to, dt = run_cmd([self.exe, '--check', str(scene)], wd, self.ct, self.env, self.mem, d / 'mpi')
            left = sorted(set(os.listdir(wd)) - given)
            nlines = case.text.count('\n') + (0 if case.text.endswith('\n') else 1)
            outcome, info = classify_check(case, rc, err, to, left, nlines, scene.name)
            return dict(outcome=outcome, rc=rc, stderr=clip(err), stdout=clip(out, 1000), seconds=round(dt, 2),
                        leftovers=left[:10], **info)
        finally:
            if not self.keep:
                shutil.rmtree(d, ignore_errors=True)

    def run(self, case, timeout=None):
        d = Path(tempfile.mkdtemp(prefix='r_', dir=self.root))
        try:
            scene = materialise(case, d / 'src', self.repo, self.links(case.scene))
            wd = d / 'wd'
            wd.mkdir()
            (d / 'mpi').mkdir()
            self.place_checkpoints(case, wd)
            rc, out, err, to, dt = run_cmd([self.exe] + run_overrides(case, self.steps) + [str(scene)], wd,
                                           timeout or self.rt, self.env, self.mem, d / 'mpi')
            return dict(outcome=classify_run(rc, err, to), rc=rc, stderr=clip(err), stdout_tail=clip(out[-1500:], 1500),
                        seconds=round(dt, 2))
        finally:
            if not self.keep:
                shutil.rmtree(d, ignore_errors=True)

    def map(self, fn, items, label, progress=True):
        res = [None] * len(items)
        t0 = time.time()
        done = 0
        counts = {}
        lock = threading.Lock()
        tty = sys.stderr.isatty()
        with ThreadPoolExecutor(max_workers=self.jobs) as ex:
            futs = {ex.submit(fn, it): i for i, it in enumerate(items)}
            for f in as_completed(futs):
                i = futs[f]
                try:
                    res[i] = f.result()
                except Exception as e:  # a harness problem, not a granhydro one
                    res[i] = dict(outcome='harness-error', rc=None, stderr=repr(e), seconds=0)
                with lock:
                    done += 1
                    o = res[i]['outcome']
                    counts[o] = counts.get(o, 0) + 1
                    if progress and (tty or done % 25 == 0 or done == len(items)):
                        line = (f'[{label} {done}/{len(items)}] ' + ' '.join(f'{k}={v}' for k, v in sorted(counts.items()))
                                + f' {time.time() - t0:.0f}s')
                        sys.stderr.write(('\r' + line + '\x1b[K') if tty else line + '\n')
                        sys.stderr.flush()
        if progress and tty:
            sys.stderr.write('\n')
        return res


# =====================================================================================
# Report
# =====================================================================================
def diff_text(base, text, limit=300):
    bl, tl = base.split('\n'), text.split('\n')
    out = []
    for ln in difflib.unified_diff(bl, tl, 'base', 'mutated', n=0, lineterm=''):
        if ln.startswith('---') or ln.startswith('+++'):
            continue
        out.append(shorten(ln, limit) if len(ln) > limit or any(ord(c) < 32 and c != '\t' for c in ln) else ln)
        if len(out) > 40:
            out.append('... (diff cut)')
            break
    return '\n'.join(out)


DEFECT_CHECK = {'crash', 'hang', 'refused-unclear', 'refused-misleading', 'refused-dirty', 'accepted-dirty'}
# an exit 3 of a scene --check accepted is a defect: the scene could have been refused,
# or the message must name the likely cause (the admission families hold reproducers)
DEFECT_RUN = {'run-crash', 'run-hang', 'run-refused', 'run-fail'}


def defect_kind(case, chk, run):
    """'' or the defect classes of a case joined by '+' (e.g. 'silent-acceptance+run-crash')."""
    o = chk['outcome']
    kinds = []
    if o in DEFECT_CHECK:
        kinds.append(o)
    if o.startswith('accepted') and case.invalid:
        kinds.append('silent-acceptance')
    if run and run['outcome'] in DEFECT_RUN:
        kinds.append(run['outcome'])
    return '+'.join(kinds)


def write_repro(case, d, repo):
    try:
        materialise(case, d, repo, links_for(case.scene, (repo / case.scene).read_text(encoding=ENC, errors=ERRS), repo))
    except OSError:
        pass


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--exe', default=os.environ.get('GRANHYDRO_EXE', str(REPO / 'build' / 'granhydro')))
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--per-scene', type=int, default=40)
    ap.add_argument('--out', default='fuzz-out')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--classes', help='comma-separated subset of: ' + ', '.join(CLASSES))
    ap.add_argument('--scenes', help='comma-separated substrings of scene paths to keep')
    ap.add_argument('--only', help='comma-separated case ids (or substrings) to keep, e.g. from a report')
    ap.add_argument('--no-run', action='store_true', help='only --check, no real runs')
    ap.add_argument('--steps', type=int, default=3, help='Time/Maximum steps of the real runs')
    ap.add_argument('--check-timeout', type=float, default=30)
    ap.add_argument('--run-timeout', type=float, default=60)
    ap.add_argument('--slow-base', type=float, default=20, help='skip runs of scenes whose base run takes longer')
    ap.add_argument('--mem-gib', type=float, default=6, help='address-space limit per process (prlimit)')
    ap.add_argument('--no-isolated-mpi', action='store_true', help='do not set OMPI_MCA_ess_singleton_isolated=1')
    ap.add_argument('--list', action='store_true', help='print the cases and exit')
    ap.add_argument('--dump', help='write the case trees into this folder and exit')
    ap.add_argument('--keep', action='store_true', help='keep the temporary case folders')
    a = ap.parse_args(argv)

    classes = a.classes.split(',') if a.classes else None
    for c in classes or []:
        if c not in CLASSES:
            ap.error(f'unknown class {c}')
    scenes = scene_files()
    if a.scenes:
        keep = a.scenes.split(',')
        scenes = [s for s in scenes if any(k in s for k in keep)]
    t_start = time.time()
    cases = generate(a.seed, a.per_scene, classes, scenes)
    if a.only:
        keys = a.only.split(',')
        cases = [c for c in cases if any(k == c.cid or (k.endswith(':') and c.cid.startswith(k)) or
                                         (':' not in k and k in c.cid) for k in keys)]
    base_texts = {s: (REPO / s).read_text(encoding=ENC, errors=ERRS) for s in scenes}
    for c in cases:  # the admission families also start from test scenes
        if c.scene not in base_texts:
            base_texts[c.scene] = (REPO / c.scene).read_text(encoding=ENC, errors=ERRS)
    if a.list:
        for c in cases:
            print(f'{c.cid:45s} {"REFUSE" if c.invalid else "any   "} {c.desc}')
        print(f'{len(cases)} cases, {sum(c.must_refuse for c in cases)} must be refused', file=sys.stderr)
        return 0
    if a.dump:
        for c in cases:
            write_repro(c, Path(a.dump) / c.cid.replace(':', '_').replace('/', '_'), REPO)
        print(f'{len(cases)} cases written to {a.dump}')
        return 0
    exe = Path(a.exe)
    if not exe.exists():
        ap.error(f'executable {exe} does not exist')
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix='granhydro-fuzz-'))
    R = Runner(exe, work, a.jobs, a.check_timeout, a.run_timeout, a.steps, a.mem_gib, not a.no_isolated_mpi)
    # parameters the binary declares that the table does not know
    try:
        pp = subprocess.run([R.exe, '--print-parameters'], capture_output=True, text=True, env=R.env, timeout=60).stdout
        stack, unknown = [], []
        for ln in pp.split('\n'):
            s = ln.split('#')[0].strip()
            if s.startswith('subsection '):
                stack.append(s[11:].strip())
            elif s == 'end' and stack:
                stack.pop()
            elif s.startswith('set '):
                k = '/'.join(stack + [norm_ws(s[4:].split('=')[0])])
                if k not in PARAMS:
                    unknown.append(k)
        if unknown:
            print('note: parameters not in the fuzzer table (not fuzzed): ' + ', '.join(unknown), file=sys.stderr)
    except (OSError, subprocess.SubprocessError):
        pass
    # sanity: every base scene valid for the validator and for --check
    for s in scenes:
        bad = {k: r for k, (v, r) in validate(Scene(base_texts[s], s)).items() if v == 'invalid'}
        if bad:
            print(f'warning: the validator thinks base scene {s} is invalid: {bad}', file=sys.stderr)
    print(f'{len(cases)} cases from {len(scenes)} scenes (seed {a.seed}, {a.per_scene} per scene), '
          f'{sum(c.must_refuse for c in cases)} must be refused; exe {R.exe}', file=sys.stderr)
    R.prepare(cases)
    checks = R.map(R.check, cases, 'check')
    runs = [None] * len(cases)
    slow = {}
    if not a.no_run:
        acc = [i for i, c in enumerate(cases) if checks[i]['outcome'] in ('accepted', 'accepted-dirty') and c.runnable]
        need = sorted({cases[i].scene for i in acc})
        bases = [Case(f'base:{s}', s, 'base', 'unmutated', base_texts[s]) for s in need]
        rt = R.rt
        R.rt = max(a.slow_base + 10, 30)
        bres = R.map(R.run, bases, 'base run')
        R.rt = rt
        base_time = {}
        for b, r in zip(bases, bres):
            base_time[b.scene] = r['seconds']
            if r['outcome'] != 'run-ok' or r['seconds'] > a.slow_base:
                slow[b.scene] = f"{r['outcome']} in {r['seconds']} s"
        if slow:
            print('not run (slow or failing base scene): ' + ', '.join(f'{k} ({v})' for k, v in slow.items()),
                  file=sys.stderr)
        todo = [i for i in acc if cases[i].scene not in slow]
        rres = R.map(lambda c: R.run(c, max(a.run_timeout, 5 * base_time.get(c.scene, 0))),
                     [cases[i] for i in todo], 'run')
        for i, r in zip(todo, rres):
            runs[i] = r
    shutil.rmtree(work, ignore_errors=True)
    runtime = time.time() - t_start

    # ---- report
    counts_cls = {}
    counts_out = {}
    rows = []
    defects = []
    dubious = []
    run_fail = []
    repro_dir = out / 'repro'
    shutil.rmtree(repro_dir, ignore_errors=True)
    for c, chk, run in zip(cases, checks, runs):
        o = chk['outcome']
        ro = run['outcome'] if run else ('not-run' if o.startswith('accepted') else '')
        counts_cls.setdefault(c.cls, {}).setdefault(o, 0)
        counts_cls[c.cls][o] += 1
        if ro:
            counts_cls[c.cls].setdefault(ro, 0)
            counts_cls[c.cls][ro] += 1
        counts_out[o] = counts_out.get(o, 0) + 1
        if ro:
            counts_out[ro] = counts_out.get(ro, 0) + 1
        kind = defect_kind(c, chk, run)
        rows.append(dict(case=c.cid, scene=c.scene, cls=c.cls, desc=c.desc, must_refuse=int(c.must_refuse),
                         check=o, rc=chk['rc'], run=ro, run_rc=run['rc'] if run else '', defect=kind,
                         seconds=chk['seconds'], stderr=(chk['stderr'].strip().split('\n') or [''])[0][:300]))
        entry = dict(case=c.cid, scene=c.scene, cls=c.cls, desc=c.desc, why_invalid=c.invalid, dubious=c.dubious,
                     diff=diff_text(base_texts[c.scene], c.text),
                     files={k: (shorten(v, 200) if v is not None else '<dir>') for k, v in c.files.items()},
                     check=chk, run=run)
        if kind:
            entry['defect'] = kind
            defects.append(entry)
            write_repro(c, repro_dir / c.cid.replace(':', '_').replace('/', '_'), REPO)
        elif o == 'accepted' and c.dubious:
            dubious.append(dict(case=c.cid, desc=c.desc, dubious=c.dubious, run=ro))
        if run and run['outcome'] == 'run-fail':
            run_fail.append(dict(case=c.cid, desc=c.desc, invalid=c.invalid, dubious=c.dubious,
                                 stderr=run['stderr'].strip()[-600:]))
    report = dict(meta=dict(exe=R.exe, seed=a.seed, per_scene=a.per_scene, scenes=len(scenes), cases=len(cases),
                            must_refuse=sum(c.must_refuse for c in cases), runtime_s=round(runtime, 1),
                            jobs=a.jobs, steps=a.steps, not_run_scenes=slow),
                  counts_by_outcome=counts_out, counts_by_class=counts_cls, defects=defects,
                  dubious_accepted=dubious, run_failures=run_fail)
    (out / 'report.json').write_text(json.dumps(report, indent=1, ensure_ascii=True))
    with open(out / 'cases.csv', 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ['case'])
        w.writeheader()
        w.writerows(rows)

    # ---- summary on stdout
    outs = sorted(counts_out)
    print(f'\n{len(cases)} cases, {runtime:.0f} s')
    print(f'{"class":20s}' + ''.join(f'{o[:14]:>15s}' for o in outs))
    for cls in CLASSES:
        if cls in counts_cls:
            print(f'{cls:20s}' + ''.join(f'{counts_cls[cls].get(o, 0):15d}' for o in outs))
    print(f'{"total":20s}' + ''.join(f'{counts_out.get(o, 0):15d}' for o in outs))
    kinds = {}
    for d in defects:
        kinds[d['defect']] = kinds.get(d['defect'], 0) + 1
    print('\ndefects: ' + (', '.join(f'{k} {v}' for k, v in sorted(kinds.items())) or 'none'))
    for d in defects:
        msg = (d['run'] or {}).get('stderr', '') if d['defect'].startswith('run-') else d['check']['stderr']
        print(f"  [{d['defect']}] {d['case']}: {d['desc']}\n      {msg.strip().splitlines()[-1][:200] if msg.strip() else '(no stderr)'}")
    print(f'\nreport: {out / "report.json"}, {out / "cases.csv"}, reproducers in {repro_dir}')
    return 1 if defects else 0


if __name__ == '__main__':
    sys.exit(main())
