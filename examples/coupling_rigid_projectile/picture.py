#!/usr/bin/python3
"""Picture of the rigid-projectile example: the mid-plane slice (y = 15 mm)
at four times, plate points coloured by von Mises stress (compute
nospd/atom) and drawn with their displacement relative to the plate's mean
motion magnified 20 times; ball points in grey, at their true positions.
usage: picture.py [dump.slice] [out.png]"""
import sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

path = sys.argv[1] if len(sys.argv) > 1 else "dump.slice"
out = sys.argv[2] if len(sys.argv) > 2 else sys.argv[0].replace("picture.py", "") + "projectile.png"
dt = 2e-8
frames = {}
with open(path) as f:
    lines = f.read().splitlines()
i = 0
while i < len(lines):
    if lines[i].startswith("ITEM: TIMESTEP"):
        step = int(lines[i + 1])
        n = int(lines[i + 3])
        cols = lines[i + 8].split()[2:]
        data = np.array([[float(v) for v in l.split()] for l in lines[i + 9:i + 9 + n]])
        frames[step] = dict(zip(cols, data.T))
        i += 9 + n
    else:
        i += 1
show = [s for s in (600, 750, 900, 1500) if s in frames] or sorted(frames)[:4]
mag = 20.0
ref = frames[min(frames)]
fig, axes = plt.subplots(len(show), 1, figsize=(7, 1.9 * len(show)), sharex=True)
for ax, s in zip(np.atleast_1d(axes), show):
    d = frames[s]
    plate = d["type"] == 1
    order = np.argsort(ref["id"])
    pos = np.searchsorted(ref["id"][order], d["id"])
    x0, z0 = ref["x"][order][pos], ref["z"][order][pos]
    ux, uz = d["x"] - x0, d["z"] - z0
    ux -= ux[plate].mean()
    uz -= uz[plate].mean()
    sc = ax.scatter(1e3 * (x0 + mag * ux)[plate], 1e3 * (z0 + mag * uz)[plate],
                    c=1e-6 * d["c_S[1]"][plate], cmap="inferno", vmin=0, vmax=1000, s=14,
                    marker="s")
    ax.scatter(1e3 * d["x"][~plate], 1e3 * (d["z"][~plate] - (d["z"] - z0)[plate].mean()),
               c="0.6", s=14)
    ax.set_aspect("equal")
    ax.set_ylim(-2.5, 12.5)
    ax.set_ylabel("z (mm)")
    ax.set_title(f"t = {1e6 * s * dt:.0f} us", fontsize=9, loc="left")
np.atleast_1d(axes)[-1].set_xlabel("x (mm)")
fig.colorbar(sc, ax=axes, label="von Mises stress (MPa)", shrink=0.8)
fig.suptitle("Rigid steel ball (fix rigid) on a free aluminium plate (peri/nospd)\n"
             "slice y = 15 mm, in the plate's frame, plate displacement x 20", fontsize=10)
fig.savefig(out, dpi=100)
print("picture:", out)
