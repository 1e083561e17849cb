#!/usr/bin/python3
"""Compare the profiles of two runs (e.g. adaptive vs uniform at the same finest
resolution) at their common output times: max and mean |difference| of the packing
fraction and the relative difference of the temperature and the mass per layer.

  /usr/bin/python3 tools/compare_profiles.py RUN_A RUN_B [--time T] [--base-a NAME] [--base-b NAME]

RUN_A and RUN_B are output directories (their <Base name>_profiles.csv, or profiles.csv
in older folders) or the profiles CSV files themselves; --base-a / --base-b (or --base
for both) pick a run when several share a directory, e.g. two runs with different base
names in one folder: compare_profiles.py out out --base-a adaptive --base-b uniform.
Debian: apt-get install python3-numpy
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import OutputFileError, find_output_file  # noqa: E402
from granhydro.readers import read_profiles  # noqa: E402


def read(path):
    """{time rounded to 1e-9 s: [(coordinate, packing fraction, temperature) per layer]}"""
    columns, _ = read_profiles(path)
    coordinate = list(columns)[1]
    blocks = {}
    for t, x, phi, T in zip(*(columns[c].tolist() for c in ('time', coordinate, 'packing_fraction', 'temperature'))):
        blocks.setdefault(round(t, 9), []).append((x, phi, T))
    return blocks


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('a', help='output directory (or profiles CSV file) of run A')
    ap.add_argument('b', help='output directory (or profiles CSV file) of run B')
    ap.add_argument('--time', type=float, default=None, help='compare at this output time only')
    ap.add_argument('--base', metavar='NAME', default=None,
                    help="Output/Base name of both runs, when several runs share a directory")
    ap.add_argument('--base-a', metavar='NAME', default=None, help='Output/Base name of run A (default --base)')
    ap.add_argument('--base-b', metavar='NAME', default=None, help='Output/Base name of run B (default --base)')
    args = ap.parse_args()
    try:
        A = read(find_output_file(args.a, 'profiles', args.base_a or args.base))
        B = read(find_output_file(args.b, 'profiles', args.base_b or args.base))
    except OutputFileError as e:
        sys.exit('compare_profiles: %s' % e)
    times = sorted(set(A) & set(B))
    if args.time is not None:
        times = [t for t in times if abs(t - args.time) < 1e-9]
    if not times:
        sys.exit('no common output time')
    print('time_s, layers, max|dphi|, mean|dphi|, max phi A, max phi B, mean |dT|/T (phi > 0.01)')
    for t in times:
        a, b = A[t], B[t]
        if len(a) != len(b):
            print(f'{t}: different number of layers ({len(a)} vs {len(b)})')
            continue
        dphi = [abs(x[1] - y[1]) for x, y in zip(a, b)]
        dT = [abs(x[2] - y[2]) / max(abs(y[2]), 1e-300) for x, y in zip(a, b) if y[1] > 0.01]
        print(f'{t:.6g}, {len(a)}, {max(dphi):.4g}, {sum(dphi) / len(dphi):.4g}, '
              f'{max(x[1] for x in a):.4g}, {max(y[1] for y in b):.4g}, '
              f'{(sum(dT) / len(dT) if dT else float("nan")):.4g}')


if __name__ == '__main__':
    main()
