#!/usr/bin/python3
"""Plate with a hole (bench/chart/in.plate, 2D plane stress) against
CalculiX: the displacement of every point within one hole radius of the
edge (r < 2a), rigid motion of the difference removed, relative to the
FEM displacement there (the plate scene of bench/scenes/run_suite.py).

usage:
  check_plate.py reference N FILE     CalculiX (ccx) at the points of the
                                      N-across plate: x y ux uy per line
  check_plate.py check REF.dump DEF.dump FILE [--tol T]
                                      the run's error against FILE

The reference file is written once by `reference` (CalculiX, 7680 CPS8
elements, bench/chart/plate_fem.py) and kept in the source tree, so that
the check needs no FE code."""
import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', '..', 'bench', 'chart'))
import plate_fem    # noqa: E402


def near(x, y):
    return np.hypot(x, y) < 2 * plate_fem.A


def points(n):
    """the lattice points of in.plate (sq lattice dx = W/n, box -n/2..n/2
    spacings, hole cut by r > a) within r < 2a"""
    dx = plate_fem.W / n
    k = np.arange(-n, n + 1)
    X, Y = np.meshgrid(k * dx, k * dx, indexing='ij')
    X, Y = X.ravel(), Y.ravel()
    keep = (np.hypot(X, Y) > plate_fem.A) & near(X, Y)
    return X[keep], Y[keep]


def read_dump(path):
    lines = open(path).read().splitlines()
    i = next(k for k, l in enumerate(lines) if l.startswith('ITEM: ATOMS'))
    d = np.array([[float(v) for v in l.split()] for l in lines[i + 1:]])
    return d[np.argsort(d[:, 0])]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('cmd', choices=['reference', 'check'])
    ap.add_argument('args', nargs='+')
    ap.add_argument('--tol', type=float, default=0.03)
    a = ap.parse_args()
    if a.cmd == 'reference':
        n, path = int(a.args[0]), a.args[1]
        work = path + '.fem'
        plate_fem.run(work, 'stress', 0.3, 48, 80)
        fem = plate_fem.FemField(os.path.join(work, 'fem.npz'))
        x, y = points(n)
        u, _ = fem.at(x, y)
        with open(path, 'w') as f:
            f.write('# CalculiX (7680 CPS8, bench/chart/plate_fem.py) at the %d-across plate\'s '
                    'points with r < 2a: x y ux uy (m)\n' % n)
            for k in range(len(x)):
                f.write('%.10e %.10e %.10e %.10e\n' % (x[k], y[k], u[k, 0], u[k, 1]))
        print('%d points -> %s' % (len(x), path))
        return 0
    ref, dfm = read_dump(a.args[0]), read_dump(a.args[1])
    fem = np.loadtxt(a.args[2])
    assert (ref[:, 0] == dfm[:, 0]).all()
    X, U = ref[:, 1:3], dfm[:, 1:3] - ref[:, 1:3]
    # match the reference's points by position (to a tenth of a spacing)
    dx = np.min(np.diff(np.unique(np.round(fem[:, 0], 9))))
    key = {(int(round(x / dx)), int(round(y / dx))): k for k, (x, y) in enumerate(X)}
    idx = [key.get((int(round(x / dx)), int(round(y / dx)))) for x, y in fem[:, :2]]
    if any(k is None for k in idx):
        print('FAIL: %d reference points missing from the run' % sum(k is None for k in idx))
        return 1
    up, uf = U[idx], fem[:, 2:4]
    px, py = fem[:, 0], fem[:, 1]
    G = np.zeros((2 * len(px), 3))
    G[0::2, 0], G[1::2, 1], G[0::2, 2], G[1::2, 2] = 1, 1, -py, px
    diff = (up - uf).reshape(-1)
    coef, *_ = np.linalg.lstsq(G, diff, rcond=None)
    err = np.linalg.norm(diff - G @ coef) / np.linalg.norm(uf.reshape(-1))
    print('%d points within one hole radius of the edge: displacement error %.2f %% '
          '(tolerance %.1f %%)' % (len(px), 100 * err, 100 * a.tol))
    ok = err <= a.tol
    print('1 passed, 0 failed' if ok else '0 passed, 1 failed')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
