"""The Taylor bar's temperature after the impact and after 0.1 s of
conduction (in.taylor_heat): a cut through the axis (|y| < dx/2), coloured
by temperature, and the temperature along the axis.
usage: plot_heat.py IMPACT_DUMP COOL_DUMP OUT.png"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def load(path):
    with open(path) as f:
        lines = f.readlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[start].split()[2:]
    d = np.array([[float(v) for v in l.split()] for l in lines[start + 1:]])
    return {c: d[:, k] for k, c in enumerate(cols)}


def main():
    a, b, out = load(sys.argv[1]), load(sys.argv[2]), sys.argv[3]
    T = "c_s[2]"
    lo = min(a[T].min(), b[T].min())
    hi = max(a[T].max(), b[T].max())
    fig, ax = plt.subplots(1, 3, figsize=(11, 4.2), gridspec_kw={"width_ratios": [1, 1, 1.4]})
    dy = np.min(np.abs(a["y"][np.abs(a["y"]) > 1e-9])) if np.any(np.abs(a["y"]) > 1e-9) else 1e-3
    for k, (d, title) in enumerate(((a, "after the impact (80 us)"), (b, "after 0.1 s of conduction"))):
        cut = np.abs(d["y"]) < 0.5 * dy + 1e-9
        sc = ax[k].scatter(1e3 * d["x"][cut], 1e3 * d["z"][cut], c=d[T][cut], s=9, vmin=lo, vmax=hi,
                           cmap="inferno")
        ax[k].set_aspect("equal")
        ax[k].set_title(title, fontsize=10)
        ax[k].set_xlabel("x (mm)")
    ax[0].set_ylabel("z (mm)")
    bar = fig.colorbar(sc, ax=list(ax[:2]), shrink=0.8)
    bar.set_label("temperature (K)")
    for d, lab in ((a, "80 us"), (b, "0.1 s")):
        axis = (np.abs(d["x"]) < 0.5 * dy + 1e-9) & (np.abs(d["y"]) < 0.5 * dy + 1e-9)
        o = np.argsort(d["z"][axis])
        ax[2].plot(1e3 * d["z"][axis][o], d[T][axis][o], "o-", ms=3, label=lab)
    ax[2].set_xlabel("z along the axis (mm)")
    ax[2].set_ylabel("temperature (K)")
    ax[2].legend()
    ax[2].grid(alpha=0.3)
    fig.savefig(out, dpi=110, bbox_inches="tight")
    print("wrote", out)


if __name__ == "__main__":
    main()
