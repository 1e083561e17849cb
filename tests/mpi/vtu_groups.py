#!/usr/bin/env python3
"""VTU files grouped by 'Output/VTU files per output' (ctest mpi.vtu_groups_4ranks).

  vtu_groups.py <granhydro> <scene.prm> <work dir> <files per output> <launcher...>

Runs the scene with the launcher (e.g. mpirun -n 4) and the given bound, then restarts
it from its final checkpoint with a later end time (the series must continue), and
checks every output time:
  - exactly min(bound, ranks) .vtu files were written, named <base>_NNNN.<k>.vtu;
  - the .pvtu lists exactly these files (no piece missing, none extra);
  - the <Piece> elements of the files hold one piece per rank and their cells add up
    to the cells of the mesh (the 'cells' line of the run's summary.csv): no cell lost
    or written twice by the grouped (MPI-IO) write;
  - the .pvd lists every output time once, in order, each with its .pvtu;
  - the grouped files hold byte for byte the pieces a run with one file per rank writes.
Exit 0 when all hold, 1 with the reason otherwise.
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

exe, scene, work = (os.path.abspath(p) for p in sys.argv[1:4])
bound = int(sys.argv[4])
launcher = sys.argv[5:]
ranks = int(launcher[launcher.index('-n') + 1]) if '-n' in launcher else 1
expected_files = ranks if bound == 0 or bound >= ranks else bound

shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
os.chdir(work)


def fail(msg):
    print('FAIL:', msg)
    sys.exit(1)


def run(name, extra, directory='out', files=bound):
    # the scene included and overridden (a value set twice in one file is refused)
    text = 'include %s\n' % os.path.abspath(scene)
    with open(name + '.prm', 'w') as f:
        f.write(text + extra +
                'subsection Output\n  set Directory = %s\n'
                '  set VTU files per output = %d\nend\n' % (directory, files))
    r = subprocess.run(launcher + [exe, name + '.prm'], capture_output=True, text=True)
    with open(name + '.log', 'w') as f:
        f.write(r.stdout + r.stderr)
    if r.returncode != 0:
        fail('%s run exited with %d:\n%s' % (name, r.returncode, (r.stdout + r.stderr)[-3000:]))


def mesh_cells():
    for line in open('out/solution_summary.csv'):
        k, _, v = line.strip().partition(',')
        if k == 'cells':
            return int(float(v))
    fail('no cells line in out/solution_summary.csv')


def check_outputs(n_outputs, cells):
    for c in range(n_outputs):
        stem = 'solution_%04d' % c
        written = sorted(os.path.basename(f) for f in glob.glob('out/%s.*.vtu' % stem))
        if len(written) != expected_files:
            fail('%s: %d .vtu files %s, expected %d (%d ranks, bound %d)'
                 % (stem, len(written), written, expected_files, ranks, bound))
        digits = len(str(max(expected_files - 1, 0)))
        names = sorted('%s.%s.vtu' % (stem, str(k).zfill(digits)) for k in range(expected_files))
        if written != names:
            fail('%s: files %s, expected %s' % (stem, written, names))
        pvtu = ET.parse('out/%s.pvtu' % stem).getroot()
        listed = sorted(p.get('Source') for p in pvtu.iter('Piece'))
        if listed != written:
            fail('%s.pvtu lists %s, written %s' % (stem, listed, written))
        pieces, total = 0, 0
        for f in written:
            ET.parse('out/' + f)  # one well-formed XML file, however many ranks wrote it
            for m in re.finditer(r'<Piece\s+NumberOfPoints="(\d+)"\s+NumberOfCells="(\d+)"',
                                 open('out/' + f).read()):
                pieces += 1
                total += int(m.group(2))
        if pieces != ranks:
            fail('%s: %d <Piece> elements in its files, expected one per rank (%d)'
                 % (stem, pieces, ranks))
        if total != cells:
            fail('%s: the pieces hold %d cells, the mesh has %d' % (stem, total, cells))
    pvd = ET.parse('out/solution.pvd').getroot()
    files = [d.get('file') for d in pvd.iter('DataSet')]
    times = [float(d.get('timestep')) for d in pvd.iter('DataSet')]
    if files != ['solution_%04d.pvtu' % c for c in range(n_outputs)]:
        fail('solution.pvd lists %s, expected %d outputs in order' % (files, n_outputs))
    if times != sorted(times) or len(set(times)) != len(times):
        fail('solution.pvd times %s are not increasing' % times)


def pieces(directory, stem):
    """the <Piece> elements of an output time's .vtu files, as text, sorted"""
    return sorted(p for f in glob.glob('%s/%s.*.vtu' % (directory, stem))
                  for p in re.findall(r'<Piece .*?</Piece>', open(f).read(), re.S))


run('first', '')
cells = mesh_cells()
n_first = len(glob.glob('out/solution_*.pvtu'))
check_outputs(n_first, cells)
# the same run with one file per rank: the grouped files hold the same pieces, byte for
# byte (each rank's piece is the text it writes alone; only the files differ)
run('per_rank', '', 'out_per_rank', 0)
for c in range(n_first):
    if pieces('out', 'solution_%04d' % c) != pieces('out_per_rank', 'solution_%04d' % c):
        fail('output %d: the grouped files do not hold the pieces of the per-rank files' % c)
# the restart continues the numbering and the .pvd series
run('restart', 'subsection Initial state\n  set Checkpoint = out/solution.checkpoint\nend\n'
    'subsection Time\n  set End time = 0.04\nend\n')
n_all = len(glob.glob('out/solution_*.pvtu'))
if n_all <= n_first:
    fail('the restart wrote no output (%d .pvtu before, %d after)' % (n_first, n_all))
check_outputs(n_all, cells)
print('OK: %d outputs, %d .vtu files each (%d ranks, bound %d), %d cells in the pieces'
      % (n_all, expected_files, ranks, bound, cells))
