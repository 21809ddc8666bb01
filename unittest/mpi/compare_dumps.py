#!/usr/bin/python3
"""Compare LAMMPS custom dumps (X0 Y0 Z0 x y z fx fy fz), matched by reference position.

usage: compare_dumps.py TOL REF OTHER [OTHER...]
Fails (exit 1) if any position or force differs from REF by more than TOL
relative to the largest magnitude of that quantity in REF.  Prints the
closing line 'N passed, N failed'."""
import sys
import numpy as np


def load(path):
    with open(path) as f:
        lines = f.readlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    d = np.array([[float(v) for v in l.split()] for l in lines[start:]])
    # order rows by reference position (rounded to a nanometre)
    key = np.round(d[:, :3] * 1e9).astype(np.int64)
    order = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
    d = d[order]
    d[:, 0] = key[order, 0] * 1e6 + key[order, 1] * 1e3 + key[order, 2]
    return d[:, [0, 3, 4, 5, 6, 7, 8]]


tol = float(sys.argv[1])
ref = load(sys.argv[2])
passed = failed = 0
for other in sys.argv[3:]:
    d = load(other)
    ok = d.shape == ref.shape and np.array_equal(d[:, 0], ref[:, 0])
    worst = {}
    if ok:
        for name, cols in (("x", slice(1, 4)), ("f", slice(4, 7))):
            scale = np.max(np.abs(ref[:, cols]))
            if name == "x":
                scale = np.max(np.abs(ref[:, cols] - ref[:, cols].mean(axis=0)))
            err = np.max(np.abs(d[:, cols] - ref[:, cols])) / scale
            worst[name] = err
            ok = ok and err <= tol
        ok = ok and np.max(np.abs(ref[:, 4:7])) > 0.0
    print(f"{other}: {'ok' if ok else 'MISMATCH'} relative max diff {worst}")
    passed += ok
    failed += not ok
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
