"""1D transient conduction against the semi-infinite solution: the largest
error over the bar's points (relative to the 100 K step) at each resolution,
below 1 % at the finest, converging at an order of at least 0.8.
usage: check_heat_bar.py t N1 N2 N3 (dumps bar_N.txt in the working folder)"""
import math
import sys

import numpy as np

K, RHO, C, L = 400.0, 8960.0, 385.0, 0.02
ALPHA = K / (RHO * C)


def max_error(n, t):
    d = np.loadtxt("bar_%d.txt" % n, skiprows=9)
    dx = L / n
    x, T = d[:, 1], d[:, 2]
    free = x > 0.5 * dx    # the held end layer is x = 0
    s = x[free]
    exact = np.array([300.0 + 100.0 * math.erfc(v / (2.0 * math.sqrt(ALPHA * t))) for v in s])
    return float(np.max(np.abs(T[free] - exact)) / 100.0)


def main():
    t = float(sys.argv[1])
    ns = [int(v) for v in sys.argv[2:]]
    errs = [max_error(n, t) for n in ns]
    ok = True
    print("points  dx (mm)  max error (% of the step)  order")
    for k, (n, e) in enumerate(zip(ns, errs)):
        order = math.log(errs[k - 1] / e) / math.log(n / ns[k - 1]) if k else float("nan")
        print("%6d  %7.4f  %8.3f  %6.2f" % (n, 1e3 * L / n, 100 * e, order))
        if k and not order >= 0.8:
            ok = False
    if not errs[-1] < 0.01:
        ok = False
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
