#!/usr/bin/python3
"""Energy balance of a Taylor bar run (examples/taylor_bar) from its log.

usage: check_taylor_energy.py LOG --tol TOL [--l0 L0] [--band LO,HI]

Reads the thermo table (step time ke pe f_NOSPD_BONDS[4] v_length ...) and
checks that ke + pe + plastic work stays within TOL (relative) of its start
at every printed step, that the bar has come to rest (ke below 2 % of the
start) with nearly all of the impact energy in plastic work (over 90 %),
and that it has shortened to L/L0 within the band (default 0.6 - 0.7, for
the copper bar: the experiment's 0.638).  Prints 'N passed, N failed' and exits 1 on a failure."""
import argparse
import sys


def thermo_rows(path):
    rows, on = [], False
    with open(path) as f:
        for line in f:
            w = line.split()
            if w[:3] == ["Step", "Time", "KinEng"]:
                on, rows = True, []
                continue
            if on and w and w[0] == "Loop":
                on = False
                continue
            if on and len(w) >= 6:
                try:
                    rows.append([float(v) for v in w])
                except ValueError:
                    pass
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("log")
    ap.add_argument("--tol", type=float, default=1e-4)
    ap.add_argument("--l0", type=float, default=25.4e-3)
    ap.add_argument("--band", default="0.6,0.7")
    a = ap.parse_args()
    rows = thermo_rows(a.log)
    if len(rows) < 3:
        print(f"no thermo table in {a.log}\n0 passed, 1 failed")
        sys.exit(1)
    total = [r[2] + r[3] + r[4] for r in rows]
    drift = max(abs(t - total[0]) for t in total) / abs(total[0])
    ke0, ke1, wp1 = rows[0][2], rows[-1][2], rows[-1][4]
    # the length column is max z - min z of the point centres
    ratio = rows[-1][5] / a.l0
    lo, hi = (float(v) for v in a.band.split(","))
    checks = [
        (f"energy: max |ke + pe + W_p - start| / start = {drift:.3e} (tol {a.tol:g})",
         drift <= a.tol),
        (f"at rest: ke / ke0 = {ke1 / ke0:.4f} (< 0.02)", ke1 < 0.02 * ke0),
        (f"dissipated: W_p / ke0 = {wp1 / ke0:.4f} (> 0.9)", wp1 > 0.9 * ke0),
        (f"shortened: L/L0 = {ratio:.4f} ({lo:g} - {hi:g})", lo < ratio < hi),
    ]
    for text, ok in checks:
        print(("PASS " if ok else "FAIL ") + text)
    nf = sum(not ok for _, ok in checks)
    print(f"{len(checks) - nf} passed, {nf} failed")
    sys.exit(1 if nf else 0)


if __name__ == "__main__":
    main()
