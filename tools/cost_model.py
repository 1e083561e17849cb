#!/usr/bin/python3
"""A measured cost model of a granhydro run on P MPI ranks (doc/user-guide.md "Running on a cluster").

  wall(P) = c_cell * cell_steps / P                       (compute, owned cells)
          + n_exchanges * msgs(P) * t_msg(halo_bytes(P) / msgs(P))   (halo)
          + n_reductions * ceil(log2 P) * latency          (time step, norms)
          + t_adapt(1) * (a / P + 1 - a)                  (adaptation; a: the part that
                                                             scales, --adapt-parallel-fraction)

Inputs, measured on this machine:
  c_cell       = (wall - adaptation) / cell_steps of a 1-rank run (median of --repeat runs):
                 seconds per cell and time step, everything that is not adaptation (both
                 operators, outputs) counted as per-cell work; measured twice: the run
                 alone, and P 1-rank runs at once (P processes sharing the node's cores
                 and memory bandwidth, as P ranks do; two predictions are printed);
  cell_steps   = cells x steps (uniform mesh); adaptive meshes: the mean of the initial
                 and the final number of leaves x steps;
  message time: tools/cluster/pingpong.c between 2 ranks (median of 7 bursts), the
                 one-way time per message size 8 B .. 8 MiB, interpolated log-log at the
                 halo message size (latency = 8..128 B, bandwidth = 8 MiB are printed);
  n_exchanges  = halo exchanges of the run from the 1-rank log: per SSP-RK3 stage one of
                 the state and one per reconstruction stage (dim of them with WENO5: the
                 owners send the stage values of the halo's cells, which no rank
                 recomputes; charged as large as the state's), so 3 (1 + dim) per step; one
                 per RKL2 stage and per GMRES iteration of the diffusion step;
  n_reductions = one per time step (the global time step) plus one per GMRES iteration.
Computed from the mesh geometry, not measured:
  halo_bytes(P) = ghost cells of the most loaded rank x (dim + 2) x 8 bytes. p4est orders
                 the coarse cells (trees) of 'Domain/Cells' lexicographically (x fastest)
                 and gives each rank an equal share of the leaves in that order, so rank r
                 owns trees [r N/P, (r+1) N/P); its ghost cells are the cells of other ranks
                 within Chebyshev distance 2 (the WENO5 boxes of the owned cells and the
                 face neighbours' gradient stencils; the halo's transverse stages come
                 from their owners; periodic directions wrap). Adaptive meshes: the ghost fraction of the tree
                 lattice times the mean leaves per tree (uniform leaf density assumed);
  msgs(P)      = neighbouring ranks of the most loaded rank.
Assumptions (where it is wrong, the measurement says by how much): the work per cell is
the same on every rank (no load imbalance beyond the leaf count), messages to different
neighbours do not overlap, ghost cells cost no compute (the convection's stages of the
halo come from their owners; virtual cells next to level changes are not charged), the part a of the adaptation
scales as 1/P and the rest is replicated on every rank (a = 1 unless told), the setup before the time loop is not
counted (the run summary's wall time starts with the time loop).

  tools/cost_model.py --build build --scene S.prm [-p "Sec/Name=value" ...]
                      [--ranks 2] [--repeat 3] [--measure]
prints the inputs, the prediction for --ranks, and with --measure the median measured
wall time of --repeat runs on --ranks ranks (mpirun --oversubscribe).
"""
import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

import numpy as np

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
HERE = os.path.dirname(os.path.abspath(__file__))


def run(build, scene, overrides, ranks, work, bind=True):
    """one run; returns the parsed log figures. bind=False: no core binding (Open MPI binds
    the ranks of each mpirun to cores from core 0 on, so separate 1-rank runs started
    together would all share core 0)"""
    os.makedirs(work, exist_ok=True)
    cmd = ['mpirun', '--oversubscribe', '-n', str(ranks)] + ([] if bind else ['--bind-to', 'none'])
    cmd += [os.path.join(build, 'granhydro')]
    for o in overrides + ['Output/Directory=' + os.path.join(work, 'out'), 'Output/Write VTU=false',
                          'Output/Write checkpoint=false', 'Output/Write profiles=false']:
        cmd += ['-p', o]
    r = subprocess.run(cmd + [scene], capture_output=True, text=True, env=ENV)
    if r.returncode != 0:
        sys.exit('run failed (%d): %s\n%s' % (r.returncode, ' '.join(cmd), r.stdout[-2000:] + r.stderr[-2000:]))
    log = r.stdout
    f = {}
    f['wall'] = float(re.search(r'wall ([-+0-9.e]+) s', log).group(1))
    m = re.search(r'adaptation ([-+0-9.e]+) s', log)
    f['adapt'] = float(m.group(1)) if m else 0.
    f['steps'] = int(re.search(r'run summary: (\d+) steps', log).group(1))
    m = re.search(r'(\d+) SSP-RK3 steps', log)
    f['rk_steps'] = int(m.group(1)) if m else f['steps']
    m = re.search(r'RKL2: \d+ steps, (\d+) stages', log)
    f['rkl2_stages'] = int(m.group(1)) if m else 0
    m = re.search(r'(\d+) GMRES iterations', log)
    f['gmres'] = int(m.group(1)) if m else 0
    m = re.search(r'(\d+)D, (\d+) cells \(([\d x]+)\)', log)
    f['dim'] = int(m.group(1))
    f['trees'] = [int(v) for v in m.group(3).split(' x ')]
    m = re.search(r'initial refinement: (\d+) cells', log)
    first = int(m.group(1)) if m else int(re.search(r'D, (\d+) cells', log).group(1))
    m = re.search(r'(\d+) cells at the end', log)
    last = int(m.group(1)) if m else first
    f['cells'] = 0.5 * (first + last)
    f['periodic'] = [re.search(r'%s-/\+ = periodic' % a, log) is not None for a in 'xyz'[:f['dim']]]
    return f


def run_concurrently(build, scene, overrides, copies, work):
    """`copies` 1-rank runs at the same time: the compute rate when P processes share the
    node's cores and memory bandwidth, as P ranks do (no communication)"""
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(copies) as pool:
        return list(pool.map(lambda k: run(build, scene, overrides, 1, '%s-%d' % (work, k), bind=False),
                             range(copies)))


def network(build_dir):
    """latency [s] and bandwidth [B/s] from the ping-pong between 2 ranks"""
    exe = os.path.join(build_dir, 'pingpong')
    subprocess.run(['mpicc', '-O2', '-o', exe, os.path.join(HERE, 'cluster', 'pingpong.c')], check=True)
    out = subprocess.run(['mpirun', '--oversubscribe', '-n', '2', exe], capture_output=True, text=True,
                         env=ENV, check=True).stdout
    rows = [tuple(float(v) for v in line.split()) for line in out.split('\n') if line.strip()]
    latency = statistics.median(t for b, t in rows if b <= 128)
    big = [r for r in rows if r[0] == 8 << 20][0]
    return latency, big[0] / big[1], rows


def message_time(rows, nbytes):
    """one-way time of a message of nbytes: the measured ping-pong table, interpolated
    log-log (protocol switches such as eager -> rendezvous are in the table, not in a fit)"""
    b = np.log([r[0] for r in rows])
    t = np.log([r[1] for r in rows])
    return float(np.exp(np.interp(np.log(max(nbytes, rows[0][0])), b, t)))


def halo(trees, periodic, ranks, width=2):
    """(ghost cells, neighbour ranks) of the rank with the most ghost cells, on the tree lattice"""
    n = int(np.prod(trees))
    # lexicographic tree index, x fastest -> numpy array indexed [z, y, x]
    owner = (np.arange(n) * ranks // n).reshape(tuple(reversed(trees)))
    worst = (0, 0)
    for r in range(ranks):
        mine = owner == r
        reach = mine.copy()
        for axis in range(owner.ndim):
            d = owner.ndim - 1 - axis  # numpy axis -> direction
            grown = reach.copy()
            for s in range(1, width + 1):
                for sign in (1, -1):
                    shifted = np.roll(reach, sign * s, axis=axis)
                    if not periodic[d]:  # no wrap across a wall
                        idx = [slice(None)] * owner.ndim
                        idx[axis] = slice(0, s) if sign > 0 else slice(-s, None)
                        shifted[tuple(idx)] = False
                    grown |= shifted
            reach = grown  # Chebyshev ball = product of the 1D dilations
        ghosts = reach & ~mine
        worst = max(worst, (int(ghosts.sum()), len(np.unique(owner[ghosts]))))
    return worst


def predict(f, ranks, latency, rows, adapt_parallel=1.):
    c_cell = (f['wall'] - f['adapt']) / (f['cells'] * f['steps'])
    ghost_trees, neighbours = halo(f['trees'], f['periodic'], ranks)
    ghost = ghost_trees * f['cells'] / np.prod(f['trees'])
    exchanges = 3 * (1 + f['dim']) * f['rk_steps'] + f['rkl2_stages'] + f['gmres']
    reductions = f['steps'] + f['gmres']
    halo_bytes = ghost * (f['dim'] + 2) * 8
    parts = {
        'compute': c_cell * f['cells'] * f['steps'] / ranks,
        # the most loaded rank sends its share of the halo to each neighbour (and receives
        # as much): one message per neighbour and exchange
        'halo': exchanges * neighbours * message_time(rows, halo_bytes / max(neighbours, 1)) if ranks > 1 else 0.,
        'reductions': reductions * math.ceil(math.log2(ranks)) * latency,
        'adaptation': f['adapt'] * (adapt_parallel / ranks + 1 - adapt_parallel),
    }
    return c_cell, ghost, neighbours, exchanges, parts


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--build', default='build')
    ap.add_argument('--scene', required=True)
    ap.add_argument('-p', action='append', default=[], help='parameter override, as granhydro -p')
    ap.add_argument('--ranks', type=int, default=2)
    ap.add_argument('--repeat', type=int, default=3)
    ap.add_argument('--measure', action='store_true', help='also run on --ranks ranks and compare')
    ap.add_argument('--adapt-parallel-fraction', type=float, default=1.,
                    help='the part of the adaptation time that scales as 1/P (the rest is '
                         'replicated on every rank); 1 = all of it')
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    work = tempfile.mkdtemp(prefix='cost_model_')
    latency, bandwidth, rows = network(work)
    print('network (2 ranks, this machine): latency %.3g s, bandwidth %.3g GB/s' % (latency, bandwidth / 1e9))
    ones, loaded, many = [], [], []
    for k in range(a.repeat):  # 1 rank and P ranks alternated, so that both see the same load
        ones.append(run(build, a.scene, a.p, 1, os.path.join(work, 'r1-%d' % k)))
        loaded += run_concurrently(build, a.scene, a.p, a.ranks, os.path.join(work, 'c-%d' % k))
        if a.measure:
            many.append(run(build, a.scene, a.p, a.ranks, os.path.join(work, 'r%d-%d' % (a.ranks, k))))
    total = {}
    for label, runs in (('alone', ones), ('%d at once' % a.ranks, loaded)):
        one = dict(runs[0])
        one['wall'] = statistics.median(f['wall'] for f in runs)
        one['adapt'] = statistics.median(f['adapt'] for f in runs)
        c_cell, ghost, neighbours, exchanges, parts = predict(one, a.ranks, latency, rows,
                                                              a.adapt_parallel_fraction)
        print('1-rank runs (%s): wall %.3f s (median of %s), adaptation %.3f s, %d steps, %.0f cells '
              '(mean), %.3g s per cell-step' % (label, one['wall'], ' '.join('%.3f' % f['wall'] for f in runs),
                                                one['adapt'], one['steps'], one['cells'], c_cell))
        total[label] = sum(parts.values())
        print('  predicted wall on %d ranks: %.3f s = ' % (a.ranks, total[label]) +
              ' + '.join('%s %.3f' % kv for kv in parts.items()))
    print('%d ranks: %.0f ghost cells on the most loaded rank (%d neighbours), %d halo exchanges'
          % (a.ranks, ghost, neighbours, exchanges))
    if a.measure:
        walls = [f['wall'] for f in many]
        m = statistics.median(walls)
        print('measured wall on %d ranks: %.3f s (median of %s; adaptation %.3f s); '
              'prediction/measurement = %s'
              % (a.ranks, m, ' '.join('%.3f' % w for w in walls), statistics.median(f['adapt'] for f in many),
                 ', '.join('%.2f (%s)' % (t / m, l) for l, t in total.items())))


if __name__ == '__main__':
    main()
