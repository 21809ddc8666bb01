#!/usr/bin/python3
"""Picture of the granular-coupling example.  Top rows: side view (x-z) of
the grains (circles to scale) and of the plate's top layer of points at
three times.  Bottom: top view of the plate's top layer coloured by von
Mises stress (compute nospd/atom) at the time of the most contacts, grains
drawn as outlines.  usage: picture.py [dump.top] [out.png]"""
import os
import sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle

path = sys.argv[1] if len(sys.argv) > 1 else "dump.top"
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(sys.argv[0]) or ".",
                                                         "granular.png")
dt, dg = 2e-8, 1.2407e-3
frames = {}
with open(path) as f:
    lines = f.read().splitlines()
i = 0
while i < len(lines):
    if lines[i].startswith("ITEM: TIMESTEP"):
        step, n = int(lines[i + 1]), int(lines[i + 3])
        cols = lines[i + 8].split()[2:]
        data = np.array([[float(v) for v in l.split()] for l in lines[i + 9:i + 9 + n]])
        frames[step] = dict(zip(cols, data.T))
        i += 9 + n
    else:
        i += 1
steps = sorted(frames)
side = [steps[0], steps[len(steps) // 2], steps[-1]]
hot = max(steps, key=lambda s: np.max(frames[s]["c_S[1]"]))


def grains(ax, d, a, b):
    g = d["type"] == 2
    ax.add_collection(PatchCollection([Circle((1e3 * u, 1e3 * v), 0.5e3 * dg)
                                       for u, v in zip(d[a][g], d[b][g])],
                                      facecolor="0.65" if b == "z" else "none",
                                      edgecolor="0.3" if b == "z" else "c",
                                      lw=0.6 if b == "z" else 1.0))


fig = plt.figure(figsize=(7, 10))
gs = fig.add_gridspec(4, 1, height_ratios=[1, 1, 1, 2.6])
for k, s in enumerate(side):
    ax = fig.add_subplot(gs[k])
    d = frames[s]
    p = d["type"] == 1
    ax.scatter(1e3 * d["x"][p], 1e3 * d["z"][p], c="k", s=6, marker="s")
    grains(ax, d, "x", "z")
    ax.set_aspect("equal")
    ax.set_xlim(-1.5, 31.5)
    ax.set_ylim(0.5, 7.5)
    ax.set_ylabel("z (mm)")
    ax.set_title(f"side view, t = {1e6 * s * dt:.0f} us", fontsize=9, loc="left")
ax = fig.add_subplot(gs[3])
d = frames[hot]
p = d["type"] == 1
sc = ax.scatter(1e3 * d["x"][p], 1e3 * d["y"][p], c=1e-6 * d["c_S[1]"][p], cmap="inferno",
                norm=matplotlib.colors.PowerNorm(0.5, vmin=0), s=28, marker="s")
grains(ax, d, "x", "y")
ax.set_aspect("equal")
ax.set_xlabel("x (mm)")
ax.set_ylabel("y (mm)")
ax.set_title(f"top layer of the plate, t = {1e6 * hot * dt:.0f} us (grains as outlines)",
             fontsize=9, loc="left")
fig.colorbar(sc, ax=ax, label="von Mises stress (MPa, square-root scale)", shrink=0.8)
fig.suptitle("Granite grains (pair granular) on a free aluminium plate (peri/nospd)", fontsize=10)
fig.savefig(out, dpi=100)
print("picture:", out)
