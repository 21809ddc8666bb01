#!/usr/bin/python3
"""Compare damage dumps (X0 Y0 Z0 x y z fx fy fz damage), matched by reference position.

usage: compare_damage.py TOLX TOLF REF OTHER [OTHER...]
Positions must agree with REF to TOLX relative to the body's size, forces to
TOLF relative to REF's largest force; damage (compute damage/atom) must agree
to 1e-12 absolute, and REF must hold damage beyond the pre-crack (some atom
above 0.3).  Different decompositions sum families in different orders (atom
IDs from create_atoms depend on the decomposition), so positions differ by
round-off that a fracture run amplifies in the forces: near a crack tip a
position change dx changes the force by about (dx / spacing) / strain
relative to the largest force.  Damage must agree exactly."""
import sys
import numpy as np


def load(path):
    with open(path) as f:
        lines = f.readlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    d = np.array([[float(v) for v in l.split()] for l in lines[start:]])
    key = np.round(d[:, :3] * 1e9).astype(np.int64)
    order = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
    return key[order], d[order][:, 3:]


tolx, tolf = float(sys.argv[1]), float(sys.argv[2])
rkey, ref = load(sys.argv[3])
ndamaged = int(np.sum(ref[:, 6] > 0.0))
print(f"{sys.argv[3]}: {len(ref)} atoms, {ndamaged} damaged, max damage {ref[:, 6].max():.3f}")
passed = failed = 0
for other in sys.argv[4:]:
    key, d = load(other)
    ok = d.shape == ref.shape and np.array_equal(key, rkey)
    worst = {}
    if ok:
        xs = np.max(np.abs(ref[:, 0:3] - ref[:, 0:3].mean(axis=0)))
        fs = np.max(np.abs(ref[:, 3:6]))
        worst["x"] = np.max(np.abs(d[:, 0:3] - ref[:, 0:3])) / xs
        worst["f"] = np.max(np.abs(d[:, 3:6] - ref[:, 3:6])) / fs
        worst["damage"] = np.max(np.abs(d[:, 6] - ref[:, 6]))
        ok = worst["x"] <= tolx and worst["f"] <= tolf and worst["damage"] <= 1e-12
        ok = ok and ref[:, 6].max() > 0.3
    print(f"{other}: {'ok' if ok else 'MISMATCH'} max diff {worst}")
    passed += ok
    failed += not ok
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
