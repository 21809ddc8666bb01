#!/usr/bin/python3
"""Angle of the cracks that leave notch tips, from a LAMMPS custom dump
(columns x y and a damage column; see plot_damage.py).

usage: crack_angle.py DUMP [--tip X,Y ...] [--threshold 0.35]
                      [--rmin MM] [--rmax MM] [--side +1|-1 ...]

For each notch tip (mm; default the Kalthoff-Winkler tips 50,25 and
50,-25), the crack points (damage >= threshold) at distances rmin..rmax
from the tip, ahead of it (x > x_tip) and on the side given (default: the
upper tip's crack runs to +y, the lower one's to -y), are fitted by a line
through the tip (the principal direction of their second moment about the
tip).  The angle is measured from the notch direction (+x), in degrees.
Also printed: the angle of the chord from the tip to the farthest crack
point within rmax, and the crack length.  Positions are current ones
(small strain), converted from metres to mm."""
import argparse
import sys

import numpy as np

sys.path.insert(0, __import__("os").path.dirname(__file__))
from crack_tip import read_dump  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dump")
    ap.add_argument("--tip", action="append", default=None, help="x,y in mm")
    ap.add_argument("--side", action="append", type=int, default=None)
    ap.add_argument("--threshold", type=float, default=0.35)
    ap.add_argument("--rmin", type=float, default=6.0)
    ap.add_argument("--rmax", type=float, default=30.0)
    a = ap.parse_args()
    tips = [tuple(float(v) for v in t.split(",")) for t in (a.tip or ["50,25", "50,-25"])]
    sides = a.side or [1 if ty >= 0 else -1 for _, ty in tips]
    step, x, y, d = read_dump(a.dump)
    x, y = x * 1e3, y * 1e3
    crack = d >= a.threshold
    print(f"{a.dump}: step {step}, {crack.sum()} crack points (damage >= {a.threshold})")
    angles = []
    for (tx, ty), sd in zip(tips, sides):
        dx, dy = x[crack] - tx, y[crack] - ty
        r = np.hypot(dx, dy)
        sel = (r >= a.rmin) & (r <= a.rmax) & (dx > -1e-9) & (sd * dy > 0)
        if sel.sum() < 3:
            print(f"tip ({tx:g}, {ty:g}): no crack between {a.rmin} and {a.rmax} mm")
            angles.append(np.nan)
            continue
        P = np.column_stack([dx[sel], sd * dy[sel]])
        M = P.T @ P
        w, v = np.linalg.eigh(M)
        e = v[:, np.argmax(w)]
        if e[1] < 0:
            e = -e
        ang = np.degrees(np.arctan2(e[1], e[0]))
        far = np.argmax(r[sel])
        chord = np.degrees(np.arctan2(P[far, 1], P[far, 0]))
        length = r[(dx > -1e-9) & (sd * dy > 0)].max()
        print(f"tip ({tx:g}, {ty:g}): crack angle {ang:.1f} deg from the notch direction "
              f"(fit of {sel.sum()} points at r = {a.rmin}-{a.rmax} mm); chord to r = "
              f"{r[sel][far]:.1f} mm: {chord:.1f} deg; crack length {length:.1f} mm")
        angles.append(ang)
    if np.all(np.isfinite(angles)):
        print(f"mean crack angle {np.mean(angles):.1f} deg")
    return 0


if __name__ == "__main__":
    sys.exit(main())
