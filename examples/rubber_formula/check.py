#!/usr/bin/python3
"""Hold the rubber strip's middle against the homogeneous uniaxial-stress
solution of the same Mooney-Rivlin W, and plot the curve.

usage: check.py rubber_formula.out [--tol 0.01] [--plot rubber_formula.png]

For each measured axial stretch l (the middle's mean F11), the lateral
stretch t solves P22(l, t, t) = 0, and sigma_xx = P11 l / J with J = l t^2;
P = dW/dF of diag(l, t, t) from W's closed-form partial derivatives.
Fails (exit 1) if the measured sigma_xx or lateral stretch differ by more
than tol (relative) at any step.
"""
import argparse
import sys

C10, C01, K = 0.4e6, 0.1e6, 10.0e6


def stress(l, t):
    """Principal Piola stresses P11, P22 of F = diag(l, t, t)."""
    J = l * t * t
    I1 = l * l + 2 * t * t
    I2 = 2 * l * l * t * t + t ** 4
    j23 = J ** (-2.0 / 3.0)
    # dW/dl_a through I1b, I2b, J (l_a = l or t)
    def dW(la):
        dI1 = 2 * la
        dI2 = 2 * la * (I1 - la * la)
        dJ = J / la
        dI1b = j23 * dI1 - 2.0 / 3.0 * j23 * I1 / la
        dI2b = j23 * j23 * dI2 - 4.0 / 3.0 * j23 * j23 * I2 / la
        return C10 * dI1b + C01 * dI2b + K * (J - 1) * dJ
    return dW(l), dW(t)


def lateral(l):
    lo, hi = 0.3, 1.2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if stress(l, mid)[1] > 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--tol", type=float, default=0.01)
    ap.add_argument("--plot")
    a = ap.parse_args()
    rows = [list(map(float, ln.split())) for ln in open(a.out) if ln.strip() and ln[0] != "#"]
    worst = 0.0
    print("  F11      F22 (model, analytic)    sigma_xx MPa (model, analytic)")
    curve = []
    for f11, f22, f33, sxx in rows:
        t = lateral(f11)
        P11, _ = stress(f11, t)
        s_an = P11 * f11 / (f11 * t * t)
        e_s = abs(sxx - s_an) / abs(s_an)
        e_t = abs(0.5 * (f22 + f33) - t) / t
        worst = max(worst, e_s, e_t)
        curve.append((f11, sxx, s_an))
        print(f"  {f11:.4f}   {0.5*(f22+f33):.5f} {t:.5f}          {sxx/1e6:.5f} {s_an/1e6:.5f}"
              f"   ({100*e_s:.2f} %, {100*e_t:.2f} %)")
    print(f"largest relative difference: {100*worst:.3f} % (tolerance {100*a.tol:.1f} %)")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 3.6))
        ls = [1 + 0.01 * k for k in range(int(100 * (max(r[0] for r in curve) - 1)) + 2)]
        ax.plot(ls, [stress(l, lateral(l))[0] / (lateral(l) ** 2) / 1e6 for l in ls], "k-",
                label="homogeneous solution of W")
        ax.plot([r[0] for r in curve], [r[1] / 1e6 for r in curve], "o", label="peri/nospd strain formula")
        ax.set_xlabel("axial stretch (middle third)")
        ax.set_ylabel("Cauchy stress sigma_xx (MPa)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)
    return 0 if worst <= a.tol else 1


if __name__ == "__main__":
    sys.exit(main())
