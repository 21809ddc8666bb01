#!/usr/bin/python3
"""Thick-walled cylinder under internal pressure, plane strain, elastic-
perfectly plastic (von Mises): the deck's data file and the check against
the classical solution (Hill, The Mathematical Theory of Plasticity, 1950,
ch. V.3).

usage:
  cylinder.py data  NR FILE           write the ring body: NR rings across the wall
  cylinder.py check NR DUMP [--tol T] compare the final state with the solution
  cylinder.py converge NR1 DUMP1 NR2 DUMP2 [--tol T]
                                      two resolutions (NR2 = 2 NR1): errors shrink,
                                      the extrapolated displacement within T
  cylinder.py solution                print p, u(a), c

Geometry and material (SI): bore a = 10 mm, outer radius b = 20 mm;
E = 200 GPa, nu = 0.3, yield stress 250 MPa, no hardening; the pressure
brings the elastic-plastic boundary to c = 1.5 a.

The solution, with k = sigma_y / sqrt(3) and sigma_z taken as the mean of
the in-plane stresses in the plastic zone (Hill's approximation, exact for
an incompressible solid):
  plastic zone a <= r <= c:  sigma_r = -p + 2k ln(r/a), sigma_t = sigma_r + 2k
  elastic zone c <= r <= b:  sigma_r,t = k c^2/b^2 (1 -/+ b^2/r^2) (Lame)
  pressure:                  p = k (1 - c^2/b^2 + 2 ln(c/a))
  displacement:  elastic zone  u = (1+nu)/E k c^2 ((1-2nu) r/b^2 + 1/r);
                 plastic zone  (1/r) d(r u)/dr = 3 (1-2nu)/E (sigma_r + k)
                 (plastic flow is isochoric, eps_z = 0), integrated from c.
The points sit on rings r_k = a + (k + 1/2) dr with about 2 pi r_k / dr
points each, volume r_k dr dtheta, so that the bore and the outer surface
lie where the continuum's do.
"""
import math
import sys

A, B = 0.010, 0.020
E, NU, SY = 200e9, 0.3, 250e6
K = SY / math.sqrt(3.0)
C = 1.5 * A


def pressure(c=C):
    return K * (1.0 - c * c / (B * B) + 2.0 * math.log(c / A))


def bore_displacement(c=C):
    p = pressure(c)
    uc = (1 + NU) / E * K * c * c * ((1 - 2 * NU) * c / (B * B) + 1.0 / c)
    # r u = c u(c) - int_r^c 3(1-2nu)/E (sigma_r(s) + k) s ds
    def G(s):
        return (K - p) * s * s / 2 + K * s * s * math.log(s / A) - K * s * s / 2
    return (c * uc - 3 * (1 - 2 * NU) / E * (G(c) - G(A))) / A


def write_data(nr, path):
    dr = (B - A) / nr
    atoms = []
    for k in range(nr):
        r = A + (k + 0.5) * dr
        n = max(6, int(round(2 * math.pi * r / dr)))
        dth = 2 * math.pi / n
        shift = 0.5 * dth * (k % 2)
        for m in range(n):
            t = m * dth + shift
            atoms.append((r * math.cos(t), r * math.sin(t), r * dr * dth, k))
    with open(path, "w") as f:
        f.write("thick-walled cylinder, %d rings (cylinder.py)\n\n" % nr)
        f.write("%d atoms\n1 atom types\n\n" % len(atoms))
        L = 1.2 * B
        f.write("%.6g %.6g xlo xhi\n%.6g %.6g ylo yhi\n-0.5 0.5 zlo zhi\n\n" % (-L, L, -L, L))
        f.write("Atoms # peri\n\n")
        for i, (x, y, v, k) in enumerate(atoms):
            f.write("%d 1 %.17g 7850 %.17g %.17g 0\n" % (i + 1, v, x, y))
    print("%d points, dr = %.6g m" % (len(atoms), dr))


def measure(nr, dump):
    """Signed relative errors of the bore-ring displacement and of the
    plastic radius against the solution, and a report."""
    dr = (B - A) / nr
    with open(dump) as f:
        lines = f.read().splitlines()
    i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[i].split()[2:]
    rows = [dict(zip(cols, map(float, l.split()))) for l in lines[i + 1:]]
    # mean radial displacement of the innermost ring, against the
    # solution at that ring's radius a + dr/2
    r0 = A + 0.5 * dr
    def radius(v):
        return math.hypot(v["f_ref[1]"], v["f_ref[2]"])
    inner = [v for v in rows if radius(v) < A + dr]
    u_inner = sum((v["x"] * v["f_ref[1]"] + v["y"] * v["f_ref[2]"]) / radius(v) - radius(v)
                  for v in inner) / len(inner)
    u_sol = u_at(r0)
    # plastic zone: rings where most points yielded; the boundary is taken
    # half a ring past the last such ring's centre
    rings = {}
    for v in rows:
        rings.setdefault(int((radius(v) - A) / dr), []).append(v["c_s[1]"])
    yielded = [k for k in sorted(rings) if sum(1 for e in rings[k] if e > 0) > 0.5 * len(rings[k])]
    kmax = max(yielded) if yielded else -1
    c_model = A + (kmax + 1) * dr
    eu = (u_inner - u_sol) / u_sol
    ec = (c_model - C) / C
    report = ("rings %d (dr %.4g mm, %d points): displacement at r = %.4f mm %.4f um vs %.4f um "
              "(%+.2f %%); plastic radius %.4f mm vs %.4f mm (%+.2f %%)"
              % (nr, dr * 1e3, len(rows), r0 * 1e3, u_inner * 1e6, u_sol * 1e6, 100 * eu,
                 c_model * 1e3, C * 1e3, 100 * ec))
    return eu, ec, report


def check(nr, dump, tol):
    eu, ec, report = measure(nr, dump)
    print("pressure %.6g MPa (elastic limit %.6g MPa)" % (pressure() / 1e6, K * (1 - A * A / (B * B)) / 1e6))
    print(report)
    ok = abs(eu) <= tol and abs(ec) <= tol
    print("PASS" if ok else "FAIL", "(tolerance %.1f %%)" % (100 * tol))
    return 0 if ok else 1


def converge(nr1, dump1, nr2, dump2, tol):
    """Two resolutions, nr2 = 2 nr1: the errors must shrink as the spacing
    (and the horizon with it) halves, and the first-order (Richardson)
    extrapolation of the displacement, 2 e2 - e1, and the finer plastic
    radius must lie within tol of the solution."""
    eu1, ec1, r1 = measure(nr1, dump1)
    eu2, ec2, r2 = measure(nr2, dump2)
    print("pressure %.6g MPa (elastic limit %.6g MPa)" % (pressure() / 1e6, K * (1 - A * A / (B * B)) / 1e6))
    print(r1)
    print(r2)
    eux = 2 * eu2 - eu1
    print("displacement error ratio e2/e1 = %.3f (first order: 0.5); extrapolated error %+.2f %%"
          % (eu2 / eu1 if eu1 else 0.0, 100 * eux))
    ok = abs(eu2) < 0.7 * abs(eu1) and abs(eux) <= tol and abs(ec2) <= tol and abs(ec2) <= abs(ec1)
    print("PASS" if ok else "FAIL", "(tolerance %.1f %%)" % (100 * tol))
    return 0 if ok else 1


def u_at(r):
    """The solution's radial displacement at radius r (plastic or elastic zone)."""
    p = pressure()
    uc = (1 + NU) / E * K * C * C * ((1 - 2 * NU) * C / (B * B) + 1.0 / C)
    if r >= C:
        return (1 + NU) / E * K * C * C * ((1 - 2 * NU) * r / (B * B) + 1.0 / r)
    def G(s):
        return (K - p) * s * s / 2 + K * s * s * math.log(s / A) - K * s * s / 2
    return (C * uc - 3 * (1 - 2 * NU) / E * (G(C) - G(r))) / r


if __name__ == "__main__":
    if sys.argv[1] == "data":
        write_data(int(sys.argv[2]), sys.argv[3])
    elif sys.argv[1] == "check":
        tol = float(sys.argv[sys.argv.index("--tol") + 1]) if "--tol" in sys.argv else 0.03
        sys.exit(check(int(sys.argv[2]), sys.argv[3], tol))
    elif sys.argv[1] == "converge":
        tol = float(sys.argv[sys.argv.index("--tol") + 1]) if "--tol" in sys.argv else 0.03
        sys.exit(converge(int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), sys.argv[5], tol))
    elif sys.argv[1] == "solution":
        print("p = %.6g MPa, u(a) = %.6g um, c = %.4g mm" % (pressure() / 1e6, bore_displacement() * 1e6, C * 1e3))
