#!/usr/bin/python3
"""Energy balance of the crack-branching run: the loss of etotal (kinetic +
elastic + the traction's potential; energy densities summed over points,
times the point volume) against G0 times the crack area (per metre of
thickness), the crack being the leading tip's path up to the branch point
plus two symmetric branches.  Exit 1 outside the band.

usage: check_fracture_energy.py LOG TIP.txt --volume V --g0 G0 [--band 0.8,1.25]"""
import argparse
import sys

import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("log")
ap.add_argument("tip")
ap.add_argument("--volume", type=float, required=True)
ap.add_argument("--g0", type=float, required=True)
ap.add_argument("--band", default="0.8,1.25")
a = ap.parse_args()

lines = open(a.log).read().splitlines()
head = next(i for i, l in enumerate(lines) if l.split()[:1] == ["Step"])
col = lines[head].split().index("TotEng")
etot = []
for l in lines[head + 1:]:
    if l.startswith("Loop"):
        break
    etot.append(float(l.split()[col]))
etot = np.array(etot)
# velocity Verlet's etotal wobbles from step to step (with thermo 1 the
# example's rises reach 1.7e5 in pe units, 12 % of what the run dissipates;
# sampled every 100 steps the dissipation between samples hides them, but
# not over the run's last, 2-step interval): a rise beyond 1 % of the
# dissipated energy is creation, which accumulates where wobbles do not
lost = etot[0] - etot.min()
if lost <= 0.0 or np.any(np.diff(etot) > 0.01 * lost):
    sys.exit(f"etotal increased during the run (largest rise {np.diff(etot).max():.4g}, "
             f"dissipated {lost:.4g})")
dissipated = (etot[0] - etot[-1]) * a.volume

t, x, y, s = np.loadtxt(a.tip, unpack=True)
ok = np.isfinite(s)
t, y, s = t[ok], y[ok], s[ok]
off = np.where(np.abs(y - y[0]) > 0.4)[0]    # the tip leaves the axis: branch point
if len(off) == 0:
    sys.exit("no branch point in the tip path")
sb = s[off[0] - 1]
length = (sb + 2.0 * (s[-1] - sb)) * 1e-3    # m
griffith = a.g0 * length
ratio = dissipated / griffith
lo, hi = (float(v) for v in a.band.split(","))
print(f"dissipated {dissipated:.4g} J/m, G0 x crack length {griffith:.4g} J/m "
      f"(crack {length*1e3:.1f} mm), ratio {ratio:.3f}, band {lo}-{hi}: "
      f"{'pass' if lo <= ratio <= hi else 'FAIL'}")
sys.exit(0 if lo <= ratio <= hi else 1)
