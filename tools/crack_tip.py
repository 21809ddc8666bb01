#!/usr/bin/python3
"""Crack-tip position, speed and branching of a 2D crack from a series of
LAMMPS custom dumps (columns x y and a damage column; see plot_damage.py).

usage: crack_tip.py 'dump.crack_branching.*' --timestep SECONDS
          [--threshold 0.35] [--xstart MM] [--xmin MM --xmax MM]
          [--cr M/S] [--E PA --nu NU --rho KG/M3 --plane stress|strain]
          [--spacing MM] [--out tip.txt] [--plot tip.png] [--check LO,HI[,branch]]

Crack points are the points with damage >= threshold.  The tip at each
dump is the crack point of largest x (the leading branch); its speed is the
slope of a least-squares line through the tip positions (x, and the arc
length along the path for a curved crack) in a window, reported as the mean
over the propagation (from the first move beyond --xstart, the pre-crack
tip, to the last dump before the tip reaches --xmax) and as the largest
speed over windows of 5 dumps.  Branching: along vertical lines x = const
(every spacing), the crack points are split into clusters separated by
gaps wider than 4 spacings in y; a line crossing two or more clusters is
branched, and the first such x (beyond --xstart) is the branching point.
The Rayleigh speed comes from --cr or from E, nu, rho and the plane
assumption (plane stress: nu' = nu/(1+nu)), by solving the Rayleigh
equation.  All lengths in the dumps are in metres."""
import argparse
import glob
import re
import sys

import numpy as np

from lammps_dump import damage_column
from lammps_dump import read_dump as read_dump_columns


def read_dump(path):
    """(timestep, x, y, damage) of a dump"""
    step, d = read_dump_columns(path)
    return step, d["x"], d["y"], damage_column(d)


def rayleigh_speed(E, nu, rho, plane):
    """Root of the Rayleigh equation (2 - k^2)^2 = 4 sqrt(1 - k^2 a^2) sqrt(1 - k^2),
    k = c_R / c_S, a = c_S / c_P, for the 2D problem (plane stress: nu' = nu/(1+nu))."""
    nup = nu / (1.0 + nu) if plane == "stress" else nu
    mu = E / (2.0 * (1.0 + nu))
    cs = np.sqrt(mu / rho)
    a2 = (1.0 - 2.0 * nup) / (2.0 * (1.0 - nup))
    f = lambda k: (2.0 - k * k) ** 2 - 4.0 * np.sqrt(1.0 - k * k * a2) * np.sqrt(1.0 - k * k)
    lo, hi = 0.5, 0.999999
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(lo) * f(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi) * cs


def clusters(values, gap):
    v = np.sort(values)
    if len(v) == 0:
        return []
    out, start = [], v[0]
    for a, b in zip(v[:-1], v[1:]):
        if b - a > gap:
            out.append((start, a))
            start = b
    out.append((start, v[-1]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pattern")
    ap.add_argument("--timestep", type=float, required=True, help="MD time step (s)")
    ap.add_argument("--threshold", type=float, default=0.35)
    ap.add_argument("--xstart", type=float, default=50.0, help="pre-crack tip x (mm)")
    ap.add_argument("--xmax", type=float, default=95.0, help="stop before the tip passes this x (mm)")
    ap.add_argument("--spacing", type=float, default=0.5, help="point spacing (mm)")
    ap.add_argument("--cr", type=float, default=0.0)
    ap.add_argument("--E", type=float, default=72e9)
    ap.add_argument("--nu", type=float, default=0.22)
    ap.add_argument("--rho", type=float, default=2440.0)
    ap.add_argument("--plane", default="stress")
    ap.add_argument("--out", default="")
    ap.add_argument("--plot", default="", help="draw the tip path length against time")
    ap.add_argument("--check", default="", metavar="LO,HI[,branch]",
                    help="exit 1 unless the mean tip speed lies in LO..HI c_R (and, with "
                         "',branch', the crack branches)")
    a = ap.parse_args()

    files = sorted(glob.glob(a.pattern), key=lambda p: int(re.findall(r"\d+", p)[-1]))
    if not files:
        sys.exit(f"no files match {a.pattern}")
    cr = a.cr or rayleigh_speed(a.E, a.nu, a.rho, a.plane)
    steps, tips, branch_x = [], [], None
    last = None
    for p in files:
        step, x, y, d = read_dump(p)
        x, y = x * 1e3, y * 1e3
        crack = d >= a.threshold
        xc, yc = x[crack], y[crack]
        # no crack point yet (a notch made by deleting points): the tip
        # is still at the notch end, x = xstart
        tip = (xc.max(), yc[np.argmax(xc)]) if crack.any() else (a.xstart, np.nan)
        steps.append(step)
        tips.append(tip)
        last = (x, y, d)
    # branching on the last dump
    x, y, d = last
    crack = d >= a.threshold
    nbranch_max = 0
    for xl in np.arange(a.xstart + 2 * a.spacing, x.max(), a.spacing):
        sel = crack & (np.abs(x - xl) < 0.5 * a.spacing)
        nb = len(clusters(y[sel], 4 * a.spacing))
        nbranch_max = max(nbranch_max, nb)
        if nb >= 2 and branch_x is None:
            branch_x = xl

    t = np.array(steps, dtype=float) * a.timestep
    tx = np.array([p[0] for p in tips])
    ty = np.array([p[1] for p in tips])
    if np.isfinite(ty).any():    # no crack yet: the tip's y is the first crack point's
        ty[~np.isfinite(ty)] = ty[np.isfinite(ty)][0]
    moving = np.where(tx > a.xstart + 2 * a.spacing)[0]
    if len(moving) == 0:
        print(f"crack did not grow beyond x = {a.xstart} mm (Rayleigh speed {cr:.0f} m/s)")
        return 1
    i0 = max(moving[0] - 1, 0)
    stop = np.where(tx >= a.xmax)[0]
    i1 = stop[0] if len(stop) else len(tx) - 1
    # path length of the tip (mm): follows a curved or branching leading tip
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(tx), np.diff(ty)))])
    seg = slice(i0, i1 + 1)
    vmean = np.polyfit(t[seg], s[seg] * 1e-3, 1)[0] if i1 - i0 >= 2 else np.nan
    vmax = 0.0
    for k in range(i0, i1 - 3):
        w = slice(k, k + 5)
        vmax = max(vmax, np.polyfit(t[w], s[w] * 1e-3, 1)[0])
    print(f"Rayleigh speed c_R = {cr:.0f} m/s")
    print(f"tip leaves the pre-crack (x = {a.xstart} mm) at t = {t[i0]*1e6:.1f} us; "
          f"at t = {t[i1]*1e6:.1f} us it is at x = {tx[i1]:.1f} mm")
    print(f"mean tip speed {vmean:.0f} m/s = {vmean/cr:.2f} c_R; "
          f"largest over 5 dumps {vmax:.0f} m/s = {vmax/cr:.2f} c_R")
    if branch_x is not None:
        print(f"branching: yes, first at x = {branch_x:.1f} mm (up to {nbranch_max} crack branches "
              f"across a vertical line)")
    else:
        print("branching: no (one crack across every vertical line)")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.5, 4.2))
        ax.plot(t * 1e6, s + a.xstart, "o-", ms=3, label="tip (path length from the pre-crack tip)")
        tt = np.array([t[i0], t[i1]])
        for frac, ls in ((1.0, "--"), (0.4, ":")):
            ax.plot(tt * 1e6, a.xstart + s[i0] + frac * cr * (tt - t[i0]) * 1e3, "k" + ls,
                    label=f"{frac:g} c_R = {frac*cr:.0f} m/s")
        ax.set_xlabel("t (us)")
        ax.set_ylabel("x (mm)")
        ax.set_title(f"mean tip speed {vmean:.0f} m/s = {vmean/cr:.2f} c_R")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)
    if a.out:
        np.savetxt(a.out, np.column_stack([t * 1e6, tx, ty, s]), fmt="%.6g",
                   header="t_us tip_x_mm tip_y_mm path_mm")
    if a.check:
        parts = a.check.split(",")
        lo, hi = float(parts[0]), float(parts[1])
        ok = lo <= vmean / cr <= hi
        if "branch" in parts[2:]:
            ok = ok and branch_x is not None
        print(f"check {a.check}: {'pass' if ok else 'FAIL'}")
        return 0 if ok else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
