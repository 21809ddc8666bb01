#!/usr/bin/python3
"""Measure the pulse speed in the wave_bar example and draw an x-t picture.

usage: measure.py [vx_profile.txt] [E] [rho]
The front is where the slab-averaged axial velocity first reaches half of
the largest value it takes at that station (the initial velocity splits
into two half pulses, so the station's own peak is the reference); its
arrival times at stations 40 mm and 100 mm give the speed,
compared with the bar velocity c0 = sqrt(E/rho)."""
import sys
import numpy as np

path = sys.argv[1] if len(sys.argv) > 1 else "vx_profile.txt"
E = float(sys.argv[2]) if len(sys.argv) > 2 else 210e9
rho = float(sys.argv[3]) if len(sys.argv) > 3 else 7850.0
dt = 2e-8

steps, frames = [], []
with open(path) as f:
    lines = [l for l in f if not l.startswith("#")]
i = 0
while i < len(lines):
    step, nrows = (int(v) for v in lines[i].split()[:2])
    rows = np.array([[float(v) for v in l.split()] for l in lines[i + 1:i + 1 + nrows]])
    steps.append(step)
    frames.append(rows)
    i += 1 + nrows
t = np.array(steps) * dt
x = frames[0][:, 1]
vx = np.array([fr[:, 3] for fr in frames])
peak = vx[0].max()


def arrival(xs):
    k = int(np.argmin(np.abs(x - xs)))
    v = vx[:, k]
    # first passage only: stop before the reflection from the far end returns
    late = t > (2 * x.max() - xs) / np.sqrt(E / rho) * 0.95
    half = 0.5 * v[~late].max()
    n = int(np.argmax(v >= half))
    # linear interpolation between the frames around the half-peak crossing
    return t[n - 1] + (half - v[n - 1]) / (v[n] - v[n - 1]) * (t[n] - t[n - 1])


x1, x2 = 0.040, 0.100
t1 = arrival(x1)
c = (x2 - x1) / (arrival(x2) - t1)
c0 = np.sqrt(E / rho)
err = (c - c0) / c0
print(f"pulse speed {c:.1f} m/s, bar velocity c0 = {c0:.1f} m/s, error {100 * err:+.2f} %")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    m = ax.pcolormesh(x * 1e3, t * 1e6, vx, shading="auto", cmap="RdBu_r", vmin=-peak, vmax=peak)
    tt = np.linspace(0, t[-1], 50)
    ax.plot((x1 + c0 * (tt - t1)) * 1e3, tt * 1e6, "k--", lw=1, label=f"c0 = {c0:.0f} m/s")
    ax.set_xlim(0, x.max() * 1e3)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("t (us)")
    ax.set_title(f"peri/nospd: pulse speed {c:.0f} m/s ({100 * err:+.1f} % vs c0)")
    ax.legend(loc="lower right")
    fig.colorbar(m, label="slab-averaged vx (m/s)")
    fig.tight_layout()
    fig.savefig("wave_bar.png", dpi=120)
    print("wrote wave_bar.png")
except ImportError:
    print("matplotlib not available: no picture")
sys.exit(0 if abs(err) < 0.05 else 1)
