#!/usr/bin/python3
"""Uniform tension: in the middle third of the bar (away from the grips and
more than one horizon from the lateral surfaces) the axial strain and the
lateral contraction must match linear elasticity within 2 %, and so must
the axial stress: E eps_xx (3D, plane stress) or E/(1-nu^2) eps_xx (plane
strain).

Under uniaxial stress the lateral strain is -nu eps_xx in 3D and in plane
stress; in plane strain it is -nu/(1-nu) eps_xx.
usage: check_tension.py DUMP DIM PLANE(none|strain|stress) NU E"""
import sys
import numpy as np

path, dim, plane, nu, E = sys.argv[1], int(sys.argv[2]), sys.argv[3], float(sys.argv[4]), float(sys.argv[5])
lines = open(path).readlines()
start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
d = np.array([[float(v) for v in l.split()] for l in lines[start:]])
x = d[:, 1:4]
n_along = {3: 36, 2: 48}[dim]
n_across = {3: 10, 2: 16}[dim]
dx = 1e-3
ids = d[:, 0].astype(int) - 1
# reference positions from the id layout of create_atoms on one rank
X0 = np.zeros_like(x)
X0[:, 0] = (ids % n_along) * dx
X0[:, 1] = ((ids // n_along) % n_across) * dx
if dim == 3:
    X0[:, 2] = (ids // (n_along * n_across)) * dx
u = x - X0
mid = (X0[:, 0] > n_along / 3 * dx) & (X0[:, 0] < 2 * n_along / 3 * dx)
# axial strain: slope of u_x along x in the middle third
exx = np.polyfit(X0[mid, 0], u[mid, 0], 1)[0]
# lateral strain: slope of u_y along y in the middle third
eyy = np.polyfit(X0[mid, 1], u[mid, 1], 1)[0]
expect = -nu / (1 - nu) if plane == "strain" else -nu
ratio = eyy / exx
err = abs(ratio - expect) / abs(expect)
sxx = d[mid, 4].mean()
modulus = E / (1 - nu * nu) if plane == "strain" else E
serr = abs(sxx - modulus * exx) / (modulus * exx)
ok = err < 0.02 and serr < 0.02 and exx > 0
print(f"eps_xx = {exx:.6g}, eps_yy = {eyy:.6g}, eps_yy/eps_xx = {ratio:.5f} "
      f"(elasticity {expect:.5f}, error {100 * err:.2f} %)")
print(f"sigma_xx = {sxx:.6g} Pa, elasticity {modulus * exx:.6g} Pa, error {100 * serr:.2f} %")
print(f"{int(ok)} passed, {int(not ok)} failed")
sys.exit(0 if ok else 1)
