#!/usr/bin/python3
"""Final shape of a Taylor bar from a LAMMPS custom dump (id x y z ...).

usage: taylor_bar.py DUMP [--spacing DX] [--check L_REF,D_REF,TOL_L,TOL_D]
                     [--l0 L0 --d0 D0] [--plot OUT.png] [--reference NAME]

Prints the length (max z - min z) and the footprint diameter: twice the
largest distance from the bar axis (the mean x, y of the rear quarter) of
the points within one spacing of the impact face, plus one spacing (each
point stands for a cell of width DX).  With --check the run fails (exit 1)
unless the length and diameter are within TOL_L and TOL_D (relative) of the
reference values; the closing line is 'N passed, N failed'.  --plot draws
the cut |y - y_axis| < DX/2 in the x-z plane coloured by the dump's column
c_s[1] (equivalent plastic strain), with the initial outline dashed and,
with --check, the reference length and footprint marked (labelled NAME,
default 'experiment')."""
import argparse
import sys

import numpy as np

from lammps_dump import read_dump


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dump")
    ap.add_argument("--spacing", type=float, default=0.381e-3)
    ap.add_argument("--check", default=None)
    ap.add_argument("--l0", type=float, default=25.4e-3)
    ap.add_argument("--d0", type=float, default=7.62e-3)
    ap.add_argument("--plot", default=None)
    ap.add_argument("--reference", default="experiment")
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
    if a.plot:
        plot(a, d, cx, cy, zmin, length, diameter)
    if a.check:
        lref, dref, tl, td = (float(v) for v in a.check.split(","))
        el = abs(length - lref) / lref
        ed = abs(diameter - dref) / dref
        passed = int(el <= tl) + int(ed <= td)
        print(f"length {length * 1e3:.3f} vs {lref * 1e3:.3f} mm: {el * 100:.1f} % (tolerance {tl * 100:.0f} %)")
        print(f"diameter {diameter * 1e3:.3f} vs {dref * 1e3:.3f} mm: {ed * 100:.1f} % (tolerance {td * 100:.0f} %)")
        print(f"{passed} passed, {2 - passed} failed")
        sys.exit(0 if passed == 2 else 1)


def plot(a, d, cx, cy, zmin, length, diameter):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    x, y, z = d["x"], d["y"], d["z"]
    cut = np.abs(y - cy) < 0.5 * a.spacing
    col = d.get("c_s[1]", np.zeros_like(x))
    fig, ax = plt.subplots(figsize=(4.2, 6.5))
    sc = ax.scatter((x[cut] - cx) * 1e3, (z[cut] - zmin + 0.5 * a.spacing) * 1e3, c=col[cut],
                    s=9, cmap="viridis", marker="s", linewidths=0)
    fig.colorbar(sc, ax=ax, label="equivalent plastic strain")
    r0, l0 = 0.5 * a.d0 * 1e3, a.l0 * 1e3
    ax.plot([-r0, -r0, r0, r0], [0, l0, l0, 0], "k--", lw=0.8, label="initial")
    if a.check:
        lref, dref = (float(v) for v in a.check.split(",")[:2])
        ax.axhline(lref * 1e3, color="r", lw=0.8, label=f"{a.reference}: length")
        ax.plot([-0.5 * dref * 1e3, 0.5 * dref * 1e3], [0, 0], "r", lw=3,
                label=f"{a.reference}: footprint")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title(f"L = {length * 1e3:.2f} mm, D = {diameter * 1e3:.2f} mm", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(a.plot, dpi=130)
    print(f"wrote {a.plot}")


if __name__ == "__main__":
    main()
