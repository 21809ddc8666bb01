#!/usr/bin/env python3
"""Damage of the quenched plates (examples/quench), one panel per dump,
each titled with its initial temperature and the cracks measure.py finds.
usage: plot_quench.py PNG DX DUMP[=LABEL] ...
(a dump named quench_<T0>... is titled by its T0, or by LABEL if given)"""
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import measure  # noqa: E402


def main():
    png, dx, dumps = sys.argv[1], float(sys.argv[2]), sys.argv[3:]
    fig, axes = plt.subplots(len(dumps), 1, figsize=(10, 1.9 * len(dumps)), squeeze=False)
    for ax, arg in zip(axes[:, 0], dumps):
        path, _, label = arg.partition("=")
        d = measure.read_dump(path)
        s = measure.summary(measure.measure(d, dx)[0])
        m = re.search(r"quench_(\d+)", path)
        t0 = label or (f"T0 = {int(m.group(1)) - 273} C" if m else path)
        ax.scatter(1e3 * d["x"], 1e3 * d["y"], c=d["c_dmg"], s=(13e3 * dx) ** 2,
                   cmap="inferno_r", vmin=0.0, vmax=0.6, marker="s", linewidths=0)
        ax.set_aspect("equal")
        ax.set_title(f"{t0}: {s['n']} edge cracks, spacing {1e3 * s['spacing']:.2f} mm, "
                     f"mean length {1e3 * s['mean']:.2f} mm (long/medium/short "
                     f"{s['long']}/{s['medium']}/{s['short']})", fontsize=9)
        ax.set_ylabel("y (mm)")
    axes[-1, 0].set_xlabel("x (mm)")
    fig.tight_layout()
    fig.savefig(png, dpi=150)


if __name__ == "__main__":
    main()
