#!/usr/bin/python3
"""Final shape of a Taylor bar from a LAMMPS custom dump (id x y z ...).

usage: taylor_bar.py DUMP [--spacing DX] [--check L_REF,D_REF,TOL_L,TOL_D]
                     [--l0 L0 --d0 D0]

Prints the length (max z - min z) and the footprint diameter: twice the
largest distance from the bar axis (the mean x, y of the rear quarter) of
the points within one spacing of the impact face, plus one spacing (each
point stands for a cell of width DX).  With --check the run fails (exit 1)
unless the length and diameter are within TOL_L and TOL_D (relative) of the
reference values; the closing line is 'N passed, N failed'."""
import argparse
import sys

import numpy as np

from lammps_dump import read_dump


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dump")
    ap.add_argument("--spacing", type=float, default=0.381e-3)
    ap.add_argument("--check", default=None)
    ap.add_argument("--l0", type=float, default=25.4e-3)
    ap.add_argument("--d0", type=float, default=7.62e-3)
    a = ap.parse_args()
    step, d = read_dump(a.dump)
    x, y, z = d["x"], d["y"], d["z"]
    dx = a.spacing
    zmin, zmax = z.min(), z.max()
    # lengths and diameters of the body: cell faces, not point centres
    length = zmax - zmin + dx
    rear = z > zmin + 0.75 * (zmax - zmin)
    cx, cy = x[rear].mean(), y[rear].mean()
    face = z < zmin + dx
    r = np.hypot(x[face] - cx, y[face] - cy)
    diameter = 2.0 * r.max() + dx
    print(f"step {step}: length {length * 1e3:.3f} mm (L/L0 = {length / a.l0:.4f}), "
          f"footprint diameter {diameter * 1e3:.3f} mm (D/D0 = {diameter / a.d0:.4f}), "
          f"{face.sum()} points in the impact face")
    if a.check:
        lref, dref, tl, td = (float(v) for v in a.check.split(","))
        el = abs(length - lref) / lref
        ed = abs(diameter - dref) / dref
        passed = (el <= tl) + (ed <= td)
        print(f"length {length * 1e3:.3f} vs {lref * 1e3:.3f} mm: {el * 100:.1f} % (tolerance {tl * 100:.0f} %)")
        print(f"diameter {diameter * 1e3:.3f} vs {dref * 1e3:.3f} mm: {ed * 100:.1f} % (tolerance {td * 100:.0f} %)")
        print(f"{passed} passed, {2 - passed} failed")
        sys.exit(0 if passed == 2 else 1)


if __name__ == "__main__":
    main()
