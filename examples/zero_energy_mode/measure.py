#!/usr/bin/python3
"""Zero-energy-mode example: amplitude bounds and oscillation periods of the
checkerboard mode for every variant, against the closed-form periods, and a
picture of A(t)/a (zero_energy_mode.png).

usage: measure.py   (in the folder holding A_<variant>.txt)

Closed form (small-strain law, periodic simple-cubic grid, uniform volumes V,
constant influence function): the checkerboard u = a s_i e_x, s_i = (-1)^(i+j+k),
gives F = I at every point, so only the stabilization acts.  With N_odd the
family members at an odd lattice offset (U = -2 a s_i e_x for them, 0 for
the others) the force density is f_i = -k a s_i e_x, a harmonic mode of
angular frequency w^2 = k / rho, with
  silling G:    k = 4 alpha V N_odd,   alpha = G c / delta
  wan:          k = 4 (3 lambda + 2 mu) / kappa V N_odd,  K = kappa I
  hourglass C:  k = 4 C c V sum_odd xi_x^2 / |xi|^3
  none:         k = 0
and c = 18 K_bulk / (pi delta^4) the bond-based micromodulus."""
import itertools
import glob
import numpy as np

E, nu, rho = 210e9, 0.3, 7850.0        # steel, materials.nospd
dx, V, a = 1e-3, 1e-9, 1e-6
delta = 3.01 * dx
lam = E * nu / ((1 + nu) * (1 - 2 * nu))
mu = E / (2 * (1 + nu))
Kb = E / (3 * (1 - 2 * nu))
c = 18 * Kb / (np.pi * delta ** 4)
offs = [np.array(n) * dx for n in itertools.product(range(-3, 4), repeat=3)
        if 0 < sum(v * v for v in n) <= 3.01 ** 2]
odd = [xi for xi in offs if round(sum(xi) / dx) % 2]
kappa = V * sum(xi[0] ** 2 for xi in offs)


def stiffness(tag):
    if tag == "none":
        return 0.0
    kind, _, val = tag.partition("_")
    if kind == "silling":
        return 4 * float(val) * c / delta * V * len(odd)
    if kind == "wan":
        return 4 * (3 * lam + 2 * mu) / kappa * V * len(odd)
    if kind == "hourglass":
        return 4 * float(val) * c * V * sum(xi[0] ** 2 / np.linalg.norm(xi) ** 3 for xi in odd)
    raise ValueError(tag)


def load(path):
    d = np.loadtxt(path)
    return d[:, 0] * 2e-8, d[:, 1] / a


def period(t, A):
    # upward zero crossings, linearly interpolated
    k = np.where((A[:-1] < 0) & (A[1:] >= 0))[0]
    tc = t[k] - A[k] * (t[k + 1] - t[k]) / (A[k + 1] - A[k])
    return (tc[-1] - tc[0]) / (len(tc) - 1) if len(tc) > 1 else float("inf")


order = ["none", "silling_0.5", "silling_0.1", "hourglass_0.05", "wan"]
runs = {tag: load(f"A_{tag}.txt") for tag in order if glob.glob(f"A_{tag}.txt")}
print(f"family: {len(offs)} bonds, {len(odd)} at odd offsets; a = {a:g} m")
print(f"{'stabilization':16s} {'min A/a':>10s} {'max A/a':>10s} {'period (us)':>12s} "
      f"{'closed form':>12s} {'error':>8s}")
for tag, (t, A) in runs.items():
    k = stiffness(tag)
    T0 = 2 * np.pi / np.sqrt(k / rho) if k > 0 else float("inf")
    T = period(t, A)
    err = f"{100 * (T - T0) / T0:+.2f} %" if np.isfinite(T0) else "-"
    Ts = f"{1e6 * T:.4f}" if np.isfinite(T) else "none"
    T0s = f"{1e6 * T0:.4f}" if np.isfinite(T0) else "none"
    print(f"{tag:16s} {A.min():10.6f} {A.max():10.6f} {Ts:>12s} {T0s:>12s} {err:>8s}")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(runs), 1, figsize=(8, 1.3 + 1.1 * len(runs)), sharex=True)
    for ax, (tag, (t, A)) in zip(axes, runs.items()):
        keep = t <= 8e-6
        ax.plot(1e6 * t[keep], A[keep], color="C3" if tag == "none" else "C0", lw=1.5)
        ax.axhline(0.0, color="0.7", lw=0.6)
        ax.set_ylim(-1.2, 1.2)
        ax.set_yticks([-1, 0, 1])
        ax.set_ylabel(tag.replace("_", " ") + "\nA / a", fontsize=9)
    axes[-1].set_xlabel("time (us)")
    axes[0].set_title("Checkerboard mode u = a(-1)^(i+j+k) e_x released at rest\n"
                      "classical (none): no restoring force, stays; stabilized: oscillates about 0",
                      fontsize=10)
    fig.tight_layout()
    fig.savefig("zero_energy_mode.png", dpi=110)
    print("picture: zero_energy_mode.png")
except ImportError:
    print("matplotlib not available: no picture")
