#!/usr/bin/python3
"""FEM reference for the plate-with-hole scene, computed by CalculiX (ccx,
Debian package calculix-ccx), an open-source FE code nobody here wrote.

Quarter model (symmetry u_y = 0 on y = 0, u_x = 0 on x = 0) of a W x W plate
with a central hole of radius a, uniform traction S along y on the edge
y = W/2.  Structured mesh of 8-node quadrilaterals (CPS8 plane stress, or
CPE8 plane strain), built here: rays from the hole centre, 2*nt elements
around the quarter, ns elements radially, graded towards the hole.  The
traction is applied as consistent nodal loads (1/6, 4/6, 1/6 of an edge's
force on its three nodes).

usage:
  plate_fem.py run OUTDIR [plane=stress|strain] [nu=0.3] [nt=24] [ns=40]
      writes OUTDIR/plate.inp, runs ccx, writes OUTDIR/fem.npz (node grid,
      displacements, stresses) and prints Kt at the hole edge.
As a module: FemField(npz).at(x, y) interpolates u and sigma at points of
the full plate (by symmetry) from the node grid.
"""
import os
import subprocess
import sys

import numpy as np

W, A, S, E = 0.05, 0.005, 10.0e6, 191.0e9
GRADE = 1.08      # ratio of successive radial element sizes (hole outwards)


def _g(s, ns):
    """radial mapping: fraction of the ray length at parameter s in [0, 1]"""
    q = GRADE
    return (q ** (s * ns) - 1.0) / (q ** ns - 1.0)


def _ginv(f, ns):
    q = GRADE
    return np.log(1.0 + f * (q ** ns - 1.0)) / (ns * np.log(q))


def _outer(theta):
    h = W / 2
    return np.where(theta <= np.pi / 4,
                    h / np.maximum(np.cos(theta), 1e-300), h / np.maximum(np.sin(theta), 1e-300))


def grid(nt, ns):
    """node positions on the doubled index grid (2ns+1) x (4nt+1):
    index (p, k): radial p (0 at the hole), angular k (0 on y = 0)"""
    s = np.arange(2 * ns + 1) / (2 * ns)
    th = np.arange(4 * nt + 1) / (4 * nt) * np.pi / 2
    f = _g(s, ns)[:, None]
    r = A + f * (_outer(th)[None, :] - A)
    return r * np.cos(th)[None, :], r * np.sin(th)[None, :]


def write_inp(path, plane, nu, nt, ns):
    X, Y = grid(nt, ns)
    P, K = X.shape
    X[:, -1] = 0.0                 # exactly on the symmetry line x = 0
    nid = -np.ones((P, K), dtype=int)
    lines = ["*HEADING", "plate with a hole, quarter model (bench/chart/plate_fem.py)", "*NODE"]
    n = 0
    for p in range(P):
        for k in range(K):
            if p % 2 == 1 and k % 2 == 1:
                continue            # no centre node in an 8-node quad
            n += 1
            nid[p, k] = n
            # the deck is in mm, N and MPa (ccx rejects metre-sized 2D elements
            # expanded to a unit thickness)
            lines.append(f"{n}, {1e3 * X[p, k]:.12e}, {1e3 * Y[p, k]:.12e}")
    etype = "CPS8" if plane == "stress" else "CPE8"
    lines.append(f"*ELEMENT, TYPE={etype}, ELSET=EALL")
    e = 0
    for p in range(0, P - 1, 2):
        for k in range(0, K - 1, 2):
            e += 1
            # counter-clockwise in (x, y): radial outwards then angular
            c = [nid[p, k], nid[p + 2, k], nid[p + 2, k + 2], nid[p, k + 2]]
            mid = [nid[p + 1, k], nid[p + 2, k + 1], nid[p + 1, k + 2], nid[p, k + 1]]
            lines.append(f"{e}, " + ", ".join(str(v) for v in c + mid))
    lines += ["*NSET, NSET=YSYM"] + [f"{nid[p, 0]}," for p in range(P)]
    lines += ["*NSET, NSET=XSYM"] + [f"{nid[p, K - 1]}," for p in range(P)]
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E * 1e-6:.6e}, {nu}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "1.0",
              "*BOUNDARY", "YSYM, 2, 2", "XSYM, 1, 1",
              "*STEP", "*STATIC", "*CLOAD"]
    # top edge: outer row (p = P-1), angular k from K//2 (45 deg) to K-1
    loads = {}
    k0 = (K - 1) // 2
    for k in range(k0, K - 1, 2):
        x1, x3 = X[P - 1, k], X[P - 1, k + 2]
        fedge = S * 1e-6 * abs(x1 - x3) * 1e3      # N, thickness 1 mm
        for kk, w in ((k, 1 / 6), (k + 1, 4 / 6), (k + 2, 1 / 6)):
            loads[nid[P - 1, kk]] = loads.get(nid[P - 1, kk], 0.0) + w * fedge
    lines += [f"{i}, 2, {f:.12e}" for i, f in sorted(loads.items())]
    lines += ["*NODE FILE", "U", "*EL FILE", "S", "*END STEP"]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    return nid


def read_frd(path):
    """nodal DISP and STRESS blocks of an ASCII .frd file"""
    out, cur = {}, None
    with open(path) as fh:
        for line in fh:
            if line.startswith(" -4"):
                name = line.split()[1]
                cur = out.setdefault(name, {})
            elif line.startswith(" -3"):
                cur = None
            elif line.startswith(" -1") and cur is not None:
                node = int(line[3:13])
                vals = [float(line[13 + 12 * i:25 + 12 * i]) for i in range((len(line.rstrip()) - 13) // 12)]
                cur[node] = vals
    return out


def run(outdir, plane="stress", nu=0.3, nt=24, ns=40):
    os.makedirs(outdir, exist_ok=True)
    inp = os.path.join(outdir, "plate.inp")
    nid = write_inp(inp, plane, nu, nt, ns)
    r = subprocess.run(["ccx", "-i", "plate"], cwd=outdir, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    with open(os.path.join(outdir, "ccx.log"), "w") as fh:
        fh.write(r.stdout)
    if r.returncode != 0 or "Job finished" not in r.stdout:
        raise SystemExit(f"ccx failed, see {outdir}/ccx.log")
    res = read_frd(os.path.join(outdir, "plate.frd"))
    X, Y = grid(nt, ns)
    X[:, -1] = 0.0
    P, K = X.shape
    U = np.full((P, K, 2), np.nan)
    Sg = np.full((P, K, 3), np.nan)        # sxx, syy, sxy
    for p in range(P):
        for k in range(K):
            i = nid[p, k]
            if i < 0:
                continue
            d, s = res["DISP"][i], res["STRESS"][i]
            U[p, k] = 1e-3 * d[0], 1e-3 * d[1]          # mm -> m
            Sg[p, k] = 1e6 * s[0], 1e6 * s[1], 1e6 * s[3]  # MPa -> Pa
    # centre nodes of the 8-node quads: serendipity value at the centre
    for p in range(1, P, 2):
        for k in range(1, K, 2):
            for arr in (U, Sg):
                corners = arr[p - 1, k - 1] + arr[p + 1, k - 1] + arr[p + 1, k + 1] + arr[p - 1, k + 1]
                mids = arr[p - 1, k] + arr[p + 1, k] + arr[p, k - 1] + arr[p, k + 1]
                arr[p, k] = -0.25 * corners + 0.5 * mids
    np.savez(os.path.join(outdir, "fem.npz"), X=X, Y=Y, U=U, S=Sg, nt=nt, ns=ns,
             plane=plane, nu=nu)
    kt = Sg[0, 0, 1] / S
    return kt


class FemField:
    """u and sigma of the FEM solution anywhere in the full plate (|x|, |y| by
    symmetry), by bilinear interpolation on the node grid in the mapping's
    own coordinates (radial parameter, angle)."""

    def __init__(self, npz):
        d = np.load(npz)
        self.U, self.S = d["U"], d["S"]
        self.nt, self.ns = int(d["nt"]), int(d["ns"])

    def at(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        sx, sy = np.sign(x) + (x == 0), np.sign(y) + (y == 0)
        ax, ay = np.abs(x), np.abs(y)
        th = np.arctan2(ay, ax)
        r = np.hypot(ax, ay)
        f = np.clip((r - A) / (_outer(th) - A), 0.0, 1.0)
        ps = _ginv(f, self.ns) * 2 * self.ns
        ks = th / (np.pi / 2) * 4 * self.nt
        P, K = self.U.shape[:2]
        p0 = np.clip(np.floor(ps).astype(int), 0, P - 2)
        k0 = np.clip(np.floor(ks).astype(int), 0, K - 2)
        tp, tk = ps - p0, ks - k0

        def interp(arr):
            return ((1 - tp)[:, None] * (1 - tk)[:, None] * arr[p0, k0]
                    + tp[:, None] * (1 - tk)[:, None] * arr[p0 + 1, k0]
                    + tp[:, None] * tk[:, None] * arr[p0 + 1, k0 + 1]
                    + (1 - tp)[:, None] * tk[:, None] * arr[p0, k0 + 1])
        u = interp(self.U)
        s = interp(self.S)
        u[:, 0] *= sx
        u[:, 1] *= sy
        s[:, 2] *= sx * sy
        return u, s


def heywood_kt():
    """Heywood's finite-width formula for a central hole: the net-section
    factor K_tn = 2 + (1 - d/W)^3, gross factor K_tg = K_tn / (1 - d/W)
    (R. B. Heywood, Designing by Photoelasticity, Chapman & Hall, 1952; as
    quoted in Pilkey & Pilkey, Peterson's Stress Concentration Factors, 3rd
    ed., Wiley 2008, chart 4.1).  Infinite plate (Kirsch 1898): 3."""
    dw = 2 * A / W
    ktn = 2.0 + (1.0 - dw) ** 3
    return ktn / (1.0 - dw)


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] != "run":
        print(__doc__)
        sys.exit(2)
    args = dict(a.split("=") for a in sys.argv[3:])
    kt = run(sys.argv[2], args.get("plane", "stress"), float(args.get("nu", 0.3)),
             int(args.get("nt", 24)), int(args.get("ns", 40)))
    print(f"FEM (ccx) Kt = sigma_yy(a, 0)/S = {kt:.4f}; Heywood {heywood_kt():.4f}; Kirsch 3")
