#!/usr/bin/python3
"""Stress concentration of the plate_hole example against CalculiX and
Heywood's formula, and a picture.

usage: measure.py [plate_hole.dump]
Reads the dump written by in.plate_hole (id x y sxx syy sxy of compute
nospd/atom), takes sigma_yy at the two points of the row y = 0 next to the
hole, and compares it with
  - the FEM solution of the same plate by CalculiX at the same points
    (bench/chart/plate_fem.py writes the mesh and the deck and runs ccx;
    skipped when ccx is not installed: apt-get install calculix-ccx),
  - the FEM stress at the hole edge itself and Heywood's finite-width
    formula for a long strip, K_tg = (2 + (1 - d/W)^3)/(1 - d/W)."""
import os
import shutil
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bench", "chart"))
import plate_fem  # noqa: E402

S = plate_fem.S
path = sys.argv[1] if len(sys.argv) > 1 else "plate_hole.dump"
lines = open(path).readlines()
start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
d = np.array([[float(v) for v in l.split()] for l in lines[start:]])
ref = open("ref.dump").readlines()
r0 = next(i for i, l in enumerate(ref) if l.startswith("ITEM: ATOMS")) + 1
X = np.array([[float(v) for v in l.split()[1:3]] for l in ref[r0:]])
syy = d[:, 4]
dx = np.min(np.abs(np.diff(np.unique(np.round(X[:, 0], 12)))))
row = np.abs(X[:, 1]) < 0.25 * dx
xr, sr = X[row, 0], syy[row]
right = np.argmin(np.where(xr > 0, xr, np.inf))
left = np.argmax(np.where(xr < 0, xr, -np.inf))
xe = 0.5 * (xr[right] - xr[left])
kt_pd = 0.5 * (sr[right] + sr[left]) / S
print(f"n = {round(plate_fem.W / dx)}, dx = {dx * 1e3:.4f} mm, point next to the hole at x = {xe * 1e3:.4f} mm "
      f"(edge at {plate_fem.A * 1e3:g} mm)")
print(f"peri/nospd: sigma_yy/S there = {kt_pd:.4f}")
print(f"Heywood (long strip, d/W = {2 * plate_fem.A / plate_fem.W:g}): Kt = {plate_fem.heywood_kt():.4f}; Kirsch: 3")
fem = None
if shutil.which("ccx"):
    plate_fem.run("fem", "stress", 0.3, 48, 80)
    fem = plate_fem.FemField(os.path.join("fem", "fem.npz"))
    _, s = fem.at(np.array([xe]), np.array([0.0]))
    kt_pt = s[0, 1] / S
    print(f"CalculiX (quarter plate, 7680 CPS8): Kt at the hole edge = {fem.S[0, 0, 1] / S:.4f}, "
          f"sigma_yy/S at x = {xe * 1e3:.4f} mm = {kt_pt:.4f}")
    print(f"peri/nospd against CalculiX at the same point: {100 * (kt_pd / kt_pt - 1):+.2f} %")
else:
    print("ccx (CalculiX) not installed: no FEM comparison (apt-get install calculix-ccx)")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    sc = ax[0].scatter(X[:, 0] * 1e3, X[:, 1] * 1e3, c=syy / S, s=4, cmap="viridis", vmin=0, vmax=3.4)
    ax[0].set_aspect("equal")
    ax[0].set_xlabel("x (mm)")
    ax[0].set_ylabel("y (mm)")
    ax[0].set_title("peri/nospd: sigma_yy / S")
    fig.colorbar(sc, ax=ax[0])
    keep = xr > 0
    o = np.argsort(xr[keep])
    ax[1].plot(xr[keep][o] * 1e3, sr[keep][o] / S, "o", ms=4, label="peri/nospd (row y = 0)")
    if fem is not None:
        xf = np.linspace(plate_fem.A, plate_fem.W / 2, 400)
        _, sf = fem.at(xf, 0 * xf)
        ax[1].plot(xf * 1e3, sf[:, 1] / S, "k-", lw=1, label="CalculiX")
    ax[1].axhline(plate_fem.heywood_kt(), color="gray", ls=":", label="Heywood Kt (long strip)")
    ax[1].set_xlabel("x (mm)")
    ax[1].set_ylabel("sigma_yy / S on the ligament")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig("plate_hole.png", dpi=110)
    print("wrote plate_hole.png")
except ImportError:
    print("matplotlib not available: no picture")
