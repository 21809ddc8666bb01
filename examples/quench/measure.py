#!/usr/bin/env python3
"""Edge cracks of a quenched plate (examples/quench): count, spacing and
lengths, from the damage in a dump of in.quench (columns id x y c_dmg ...).

Each lattice column (one x) has, from each long edge, a damaged depth: how
far the points from that edge inward keep damage >= DMIN without a gap.
The skin that the first cooling damages all along the edge is that depth's
median; a crack is a run of neighbouring columns whose depth exceeds the
skin by more than three spacings, at the run's depth-weighted centre, as
long as its deepest column (measured from the edge).  Classes as in the
experiment's description: long (at least half the longest crack), medium
(a quarter to a half), short.

usage: measure.py DUMP [DX] [--plot PNG] [--title TEXT]
Prints one line per crack and a summary line:
  CRACKS n=.. per_edge=.. mean_spacing_mm=.. mean_length_mm=.. long=.. medium=.. short=.. skin_mm=..
"""
import sys

import numpy as np

DMIN = 0.3


def read_dump(path):
    with open(path) as f:
        lines = f.read().splitlines()
    n = int(lines[lines.index("ITEM: NUMBER OF ATOMS") + 1])
    head = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[head].split()[2:]
    data = np.array([[float(v) for v in l.split()] for l in lines[head + 1:head + 1 + n]])
    return {c: data[:, k] for k, c in enumerate(cols)}


def depth_profiles(d, dx):
    """per column (sorted x): damaged depth from the bottom and the top edge"""
    x, y, dmg = d["x"], d["y"], d["c_dmg"]
    col = np.rint((x - x.min()) / dx).astype(int)
    row = np.rint((y - y.min()) / dx).astype(int)
    ncol, nrow = col.max() + 1, row.max() + 1
    grid = np.zeros((ncol, nrow))
    grid[col, row] = dmg
    xs = np.zeros(ncol)
    xs[col] = x
    hit = grid >= DMIN
    bottom = np.argmin(np.hstack([hit, np.zeros((ncol, 1), bool)]), axis=1) * dx
    top = np.argmin(np.hstack([hit[:, ::-1], np.zeros((ncol, 1), bool)]), axis=1) * dx
    return xs, {"bottom": bottom, "top": top}


def measure(d, dx):
    xs, depth = depth_profiles(d, dx)
    skin = float(np.median(np.concatenate(list(depth.values()))))
    cracks = []
    for edge, dep in depth.items():
        deep = dep > skin + 3.0 * dx
        k = 0
        while k < len(dep):
            if not deep[k]:
                k += 1
                continue
            j = k
            while j < len(dep) and deep[j]:
                j += 1
            w = dep[k:j]
            cracks.append((edge, float(np.sum(xs[k:j] * w) / np.sum(w)), float(w.max())))
            k = j
    return cracks, skin


def summary(cracks):
    if not cracks:
        return dict(n=0, per_edge=0.0, spacing=float("nan"), mean=0.0, long=0, medium=0, short=0)
    lengths = np.array([c[2] for c in cracks])
    top = lengths.max()
    spacing = []
    for edge in ("bottom", "top"):
        xs = sorted(c[1] for c in cracks if c[0] == edge)
        spacing += list(np.diff(xs))
    return dict(n=len(cracks), per_edge=len(cracks) / 2.0,
                spacing=float(np.mean(spacing)) if spacing else float("nan"),
                mean=float(lengths.mean()),
                long=int(np.sum(lengths >= 0.5 * top)),
                medium=int(np.sum((lengths >= 0.25 * top) & (lengths < 0.5 * top))),
                short=int(np.sum(lengths < 0.25 * top)))


def main():
    args = sys.argv[1:]
    png = title = None
    if "--plot" in args:
        k = args.index("--plot")
        png = args[k + 1]
        del args[k:k + 2]
    if "--title" in args:
        k = args.index("--title")
        title = args[k + 1]
        del args[k:k + 2]
    d = read_dump(args[0])
    x = d["x"]
    dx = float(args[1]) if len(args) > 1 else float(np.median(np.diff(np.unique(np.round(x, 9)))))
    cracks, skin = measure(d, dx)
    for edge, xc, length in sorted(cracks):
        print(f"crack {edge:6s} x {1e3 * xc:7.2f} mm length {1e3 * length:6.2f} mm")
    s = summary(cracks)
    print(f"CRACKS n={s['n']} per_edge={s['per_edge']:.1f} mean_spacing_mm={1e3 * s['spacing']:.2f} "
          f"mean_length_mm={1e3 * s['mean']:.2f} long={s['long']} medium={s['medium']} "
          f"short={s['short']} skin_mm={1e3 * skin:.2f}")
    if png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(10, 2.4))
        sc = ax.scatter(1e3 * d["x"], 1e3 * d["y"], c=d["c_dmg"], s=(13e3 * dx) ** 2,
                        cmap="inferno_r", vmin=0.0, vmax=0.6, marker="s", linewidths=0)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        if title:
            ax.set_title(title)
        fig.colorbar(sc, ax=ax, label="damage", fraction=0.02, pad=0.01)
        fig.tight_layout()
        fig.savefig(png, dpi=150)


if __name__ == "__main__":
    main()
