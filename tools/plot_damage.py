#!/usr/bin/python3
"""Draw the damage of a 2D peridynamic body from a LAMMPS custom dump.

usage: plot_damage.py DUMP OUT.png [--title TEXT] [--vmax 0.6] [--column NAME --label TEXT]
                      [--plane xy|xz|zy] [--slab=LO,HI] [--spacing MM]
                      [--xlim=LO,HI] [--ylim=LO,HI]

The dump needs the columns x y (z for other planes) and a damage column
(c_<id> of compute damage/atom, or any column whose name contains 'dmg' or
'damage').  Points are drawn at their current positions, coloured by
damage (0 blue to vmax red), lengths in mm.  3D: --plane picks the two
axes drawn and --slab (mm) keeps the points whose third coordinate lies in
LO..HI (a cut through the body)."""
import argparse
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

from lammps_dump import damage_column, read_dump


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dump")
    ap.add_argument("out")
    ap.add_argument("--title", default="")
    ap.add_argument("--vmax", type=float, default=0.6)
    ap.add_argument("--column", default="",
                    help="colour by this dump column instead of the damage (e.g. c_s[1])")
    ap.add_argument("--label", default="damage", help="colour-bar label")
    ap.add_argument("--plane", default="xy")
    ap.add_argument("--slab", default="")
    ap.add_argument("--xlim", default="")
    ap.add_argument("--ylim", default="")
    ap.add_argument("--spacing", type=float, default=0.0,
                    help="point spacing (mm) for the marker size; default from the area per point")
    a = ap.parse_args()
    step, d = read_dump(a.dump)
    h_, v_ = a.plane[0], a.plane[1]
    x, y, dm = d[h_] * 1e3, d[v_] * 1e3, (d[a.column] if a.column else damage_column(d))
    if a.slab:
        third = ({"x", "y", "z"} - {h_, v_}).pop()
        lo, hi = (float(t) for t in a.slab.split(","))
        keep = (d[third] * 1e3 >= lo) & (d[third] * 1e3 <= hi)
        x, y, dm = x[keep], y[keep], dm[keep]
    for lim, v in ((a.xlim, 0), (a.ylim, 1)):
        if lim:
            lo, hi = (float(t) for t in lim.split(","))
            keep = ((x if v == 0 else y) >= lo) & ((x if v == 0 else y) <= hi)
            x, y, dm = x[keep], y[keep], dm[keep]
    w = max(x.max() - x.min(), 1e-9)
    h = max(y.max() - y.min(), 1e-9)
    figw = 10.0 if w >= h else max(4.0, 8.0 * w / h)
    figh = figw * h / w + 0.8
    fig, ax = plt.subplots(figsize=(figw, figh))
    spacing = a.spacing or np.sqrt(w * h / len(x))
    order = np.argsort(dm)
    s = ax.scatter(x[order], y[order], c=dm[order], s=1.0, cmap="jet", vmin=0.0,
                   vmax=a.vmax, marker="s", linewidths=0)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{h_} (mm)")
    ax.set_ylabel(f"{v_} (mm)")
    ax.set_title(a.title or f"{a.dump}: damage, step {step}")
    fig.colorbar(s, ax=ax, label=a.label, shrink=0.8)
    ax.set_xlim(x.min() - spacing, x.max() + spacing)
    ax.set_ylim(y.min() - spacing, y.max() + spacing)
    fig.tight_layout()
    # marker side: one spacing in data units, measured in points on the drawn axes
    fig.canvas.draw()
    p0 = ax.transData.transform((0.0, 0.0))
    p1 = ax.transData.transform((spacing, 0.0))
    side = abs(p1[0] - p0[0]) * 72.0 / fig.dpi
    s.set_sizes([(1.2 * side) ** 2])    # a little overlap: no gaps from rounding
    fig.savefig(a.out, dpi=110)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
