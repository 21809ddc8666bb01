#!/usr/bin/python3
"""Speed against accuracy, and the stability study (issue 7).

    chart.py run    [--size full|reduced|smoke] [--jobs 2] [--only SCENES]
                    [--lmp LMP] [--plugin DIR] [--results DIR] [--work DIR]
    chart.py charts [--results DIR] [--doc DIR]

`run` runs every scene with every model that this LAMMPS and plugin provide
(probed first: a style that is missing, e.g. peri/nospd/hs before it lands,
is skipped and listed in results/skipped.csv), two LAMMPS processes at a
time (one core each), and writes one CSV per scene under results/.  `charts`
draws the PNGs and writes the reStructuredText tables that the doc page
includes.  bench/chart/run_all.sh does both.

Scenes (accuracy): plate (plate with a hole, Kt against a CalculiX FEM
solution and Heywood's formula), wave (pulse speed in a bar against
c0 = sqrt(E/rho)), tension (apparent Young's modulus and Poisson ratio of a
bar in uniform tension).  Stability: zem (checkerboard restoring force and
free growth), drift (long NVE energy drift), dtmax (largest stable time step
by bisection), spin (rigid rotation: spurious energy and force), damage
(a notched bar pulled apart, when fix nospd/damage exists).
"""
import argparse
import concurrent.futures as cf
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import models as M           # noqa: E402
import plate_fem             # noqa: E402

E, NU, RHO = 191.0e9, 0.3, 7850.0
C0 = math.sqrt(E / RHO)            # bar velocity
S_PLATE = plate_fem.S

# ----------------------------------------------------------------------------
# sizes: what each scene runs.  `full` is the chart of the doc page (442
# runs, 11-19 minutes on 2 shared cores with every model); `reduced` the
# same models at smaller resolutions; `smoke` one resolution each (~2 min).
SIZES = {
    # plate: {(dim, m): [points across]}; wave: {(dim, m): [dx]};
    # tension: {(dim, m): [points across]}; dtmax: [(dim, m)]
    "full": dict(plate={(2, 3): [41, 61, 81, 101], (2, 4): [41, 61, 81, 101],
                        (3, 3): [15, 21, 31], (3, 4): [11, 15, 21]},
                 wave={(3, 3): [2.0e-3, 1.6e-3, 1.3333e-3], (3, 4): [2.0e-3, 1.6e-3, 1.3333e-3],
                       (2, 3): [2.0e-3, 1.3333e-3, 1.0e-3, 0.8e-3],
                       (2, 4): [2.0e-3, 1.3333e-3, 1.0e-3, 0.8e-3]},
                 tension={(3, 3): [5, 6, 8, 10], (3, 4): [5, 6, 8, 10],
                          (2, 3): [5, 6, 8, 10, 12], (2, 4): [5, 6, 8, 10, 12]},
                 dtmax=[(3, 3), (2, 3), (2, 4)],
                 zem_steps=2000, drift_steps=10000, dtmax_steps=500, dtmax_iter=6,
                 spin_n=8, damage=True),
    "reduced": dict(plate={(2, 3): [21, 31, 41], (2, 4): [21, 31, 41], (3, 3): [11, 15, 21],
                           (3, 4): [11, 15]},
                    wave={(3, 3): [2.0e-3, 1.6e-3, 1.3333e-3], (3, 4): [2.0e-3, 1.6e-3],
                          (2, 3): [2.0e-3, 1.6e-3, 1.3333e-3], (2, 4): [2.0e-3, 1.6e-3, 1.3333e-3]},
                    tension={(3, 3): [5, 6, 8], (3, 4): [5, 6, 8], (2, 3): [5, 6, 8], (2, 4): [5, 6, 8]},
                    dtmax=[(3, 3), (2, 3), (2, 4)],
                    zem_steps=1000, drift_steps=4000, dtmax_steps=400, dtmax_iter=5,
                    spin_n=8, damage=True),
    "smoke": dict(plate={(2, 3): [21], (3, 3): [11]}, wave={(3, 3): [2.0e-3], (2, 3): [2.0e-3]},
                  tension={(3, 3): [5], (2, 3): [5]}, dtmax=[(3, 3), (2, 3)],
                  zem_steps=200, drift_steps=400, dtmax_steps=200, dtmax_iter=2,
                  spin_n=8, damage=False),
}
SCENES = ["plate", "wave", "tension", "zem", "drift", "dtmax", "spin", "damage"]


def delta_of(m, dx):
    """horizon slightly above a multiple of the spacing (no ties in families)"""
    return (m + 0.01) * dx


# ----------------------------------------------------------------------------
# running LAMMPS and reading its log

class Runner:
    def __init__(self, lmp, plugin, work):
        self.lmp, self.work = lmp, os.path.abspath(work)
        self.env = dict(os.environ, OMP_NUM_THREADS="1",
                        LAMMPS_PLUGIN_PATH=os.path.abspath(plugin),
                        LAMMPS_POTENTIALS=os.path.join(ROOT, "potentials"))

    def run(self, tag, infile, var, timeout=3000):
        d = os.path.join(self.work, tag)
        os.makedirs(d, exist_ok=True)
        args = [self.lmp, "-in", os.path.join(HERE, infile), "-log", os.path.join(d, "log.lammps"),
                "-screen", "none", "-var", "out", d]
        for k, v in var.items():
            args += ["-var", k, str(v)]
        with open(os.path.join(d, "cmd.txt"), "w") as fh:
            fh.write(" ".join(f"'{a}'" if " " in a else a for a in args) + "\n")
        t0 = time.time()
        try:
            r = subprocess.run(args, env=self.env, cwd=d, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=timeout)
            rc = r.returncode
        except subprocess.TimeoutExpired:
            rc = -9
        wall = time.time() - t0
        log = Log(os.path.join(d, "log.lammps"))
        log.rc, log.wall, log.dir = rc, wall, d
        return log


class Log:
    def __init__(self, path):
        self.text = open(path).read() if os.path.exists(path) else ""
        err = re.findall(r"^ERROR.*$", self.text, re.M)
        self.error = err[0] if err else ""
        loops = re.findall(r"Loop time of ([\d.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms",
                           self.text)
        self.loops = [(float(a), int(b), int(c)) for a, b, c in loops]
        mem = re.findall(r"Per MPI rank memory allocation \(min/avg/max\) = [\d.]+ \| ([\d.]+) \|",
                         self.text)
        self.mem_mb = float(mem[-1]) if mem else float("nan")
        # the bonds fix (and the hs style) print "<what> = N bytes/point"
        # lines: the sum of the last value of each
        bpp = dict(re.findall(r"^\s*(\S.*?) = ([\d.]+) bytes/point", self.text, re.M))
        self.bytes_per_point = sum(float(v) for v in bpp.values()) if bpp else float("nan")
        fe = re.findall(r"Iterations, force evaluations = (\d+) (\d+)", self.text)
        self.iters, self.fevals = (int(fe[-1][0]), int(fe[-1][1])) if fe else (0, 0)
        st = re.findall(r"Stopping criterion = (.*)", self.text)
        self.stop = st[-1].strip() if st else ""

    @property
    def ok(self):
        return self.rc == 0 and not self.error

    def thermo(self, index=-1):
        """the rows of one thermo block (header -> column arrays)"""
        blocks = re.findall(r"^\s*(Step\s.*?)\n(.*?)^Loop time", self.text, re.M | re.S)
        if not blocks:
            return {}
        head, body = blocks[index]
        cols = head.split()
        rows = []
        for line in body.splitlines():
            p = line.split()
            if len(p) != len(cols):
                continue
            try:
                rows.append([float(v) for v in p])
            except ValueError:
                continue
        a = np.array(rows) if rows else np.zeros((0, len(cols)))
        return {c: a[:, i] for i, c in enumerate(cols)}


def read_dump(path):
    with open(path) as fh:
        lines = fh.readlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    d = np.array([[float(v) for v in l.split()] for l in lines[start:]])
    return d[:, 0].astype(int), d[:, 1:4]


def cost_fields(log, steps=None):
    """time per force evaluation (a step), point-steps/s, memory"""
    loop, nsteps, natoms = log.loops[-1] if log.loops else (float("nan"), 0, 0)
    nev = log.fevals if log.fevals else (nsteps if nsteps else (steps or 0))
    nev = max(nev, 1)
    return dict(natoms=natoms, steps=nev, loop_s=round(loop, 4), wall_s=round(log.wall, 3),
                s_per_step=loop / nev, point_steps_per_s=natoms * nev / loop if loop > 0 else float("nan"),
                mem_mb=log.mem_mb, bytes_per_point=log.bytes_per_point)


# ----------------------------------------------------------------------------
# scene: plate with a hole

FEM_CASES = {("stress", 0.3): "ps_nu0.30", ("strain", 0.3): "pe_nu0.30",
             ("strain", 0.25): "pe_nu0.25"}


def fem_setup(results, work):
    """CalculiX solutions (plane stress; plane strain for the 3D slab with
    nu = 0.3 and 0.25) and a mesh-convergence table"""
    rows, fields = [], {}
    if shutil.which("ccx") is None:
        print("plate: ccx (CalculiX) not found: the plate scene uses Heywood's formula only")
        return None
    for (plane, nu), name in FEM_CASES.items():
        for nt in (12, 24, 48):
            d = os.path.join(work, "fem", f"{name}_nt{nt}")
            kt = plate_fem.run(d, plane, nu, nt, nt * 5 // 3)
            rows.append(dict(plane=plane, nu=nu, nt=nt, ns=nt * 5 // 3, elements=2 * nt * (nt * 5 // 3),
                             kt_fem=round(kt, 5), kt_heywood=round(plate_fem.heywood_kt(), 5),
                             kt_kirsch=3.0))
        fields[(plane, nu)] = plate_fem.FemField(os.path.join(d, "fem.npz"))
    write_csv(os.path.join(results, "plate_fem.csv"), rows)
    return fields


def recover_stress(X, U, dx, dim, nu):
    """in-plane strain from the displacement field by a least-squares fit of
    u over each point's 8 nearest in-plane neighbours (the same operator for
    every model), then Hooke's law: plane stress in 2D, plane strain in the
    3D slab.  X, U: (N, 3) reference positions and displacements."""
    ij = np.rint(X[:, :2] / dx).astype(int)
    lo = ij.min(axis=0)
    ij -= lo
    ni, nj = ij.max(axis=0) + 1
    # average over the z layers of the slab
    Ug = np.zeros((ni, nj, 2))
    cnt = np.zeros((ni, nj))
    np.add.at(Ug, (ij[:, 0], ij[:, 1]), U[:, :2])
    np.add.at(cnt, (ij[:, 0], ij[:, 1]), 1)
    valid = cnt > 0
    Ug[valid] /= cnt[valid][:, None]
    A = np.zeros((ni, nj, 2, 2))
    B = np.zeros((ni, nj, 2, 2))
    pad = np.zeros((ni + 2, nj + 2, 2))
    pv = np.zeros((ni + 2, nj + 2), bool)
    pad[1:-1, 1:-1] = Ug
    pv[1:-1, 1:-1] = valid
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            if di == 0 and dj == 0:
                continue
            xi = np.array([di * dx, dj * dx])
            nb = pv[1 + di:1 + di + ni, 1 + dj:1 + dj + nj] & valid
            du = pad[1 + di:1 + di + ni, 1 + dj:1 + dj + nj] - Ug
            A[nb] += np.outer(xi, xi)
            B[nb] += du[nb][:, :, None] * xi[None, None, :]
    H = np.full((ni, nj, 2, 2), np.nan)
    good = valid & (np.linalg.det(A) > 0)
    H[good] = B[good] @ np.linalg.inv(A[good])
    exx, eyy, exy = H[..., 0, 0], H[..., 1, 1], 0.5 * (H[..., 0, 1] + H[..., 1, 0])
    if dim == 2:
        f = E / (1 - NU ** 2)
        syy = f * (eyy + NU * exx)
        sxx = f * (exx + NU * eyy)
    else:
        f = E / ((1 + nu) * (1 - 2 * nu))
        syy = f * ((1 - nu) * eyy + nu * exx)
        sxx = f * ((1 - nu) * exx + nu * eyy)
    sxy = E / (1 + nu) * exy
    return dict(lo=lo, ni=ni, nj=nj, U=Ug, valid=valid, sxx=sxx, syy=syy, sxy=sxy)


def plate_job(R, model, dim, n, m, fem, sz):
    dx = plate_fem.W / n
    delta = delta_of(m, dx)
    pstyle, pcoeff = M.pair_lines(model, E, NU, delta, dim, dx)
    solver = M.SOLVER[model]
    fscale = S_PLATE / dx * math.sqrt(2 * n * (1 if dim == 2 else 2 * m + 1))
    var = dict(n=n, m=m, dim=dim, pstyle=pstyle, pcoeff=pcoeff, solver=solver,
               ftol=f"{1e-6 * fscale:.6g}", maxiter=200 * n, dt=f"{0.3 * dx / C0:.6g}")
    tag = f"plate/{dim}d_{model}_m{m}_n{n}"
    log = R.run(tag, "in.plate", var)
    row = dict(scene="plate", dim=dim, model=model, label=M.LABEL[model], m=m, n=n,
               dx_mm=round(dx * 1e3, 5), a_over_dx=round(plate_fem.A / dx, 3), solver=solver,
               converged=log.stop)
    row.update(cost_fields(log))
    if not log.ok:
        row.update(status="failed", note=log.error[:120])
        return [row]
    ids0, X = read_dump(os.path.join(log.dir, "ref.dump"))
    ids1, Y = read_dump(os.path.join(log.dir, "def.dump"))
    assert (ids0 == ids1).all()
    mnu = M.model_nu(model, NU)
    rec = recover_stress(X, Y - X, dx, dim, mnu)
    # ligament row y = 0: the points next to the hole edge on both sides
    j0 = -rec["lo"][1]
    rowv = rec["valid"][:, j0]
    ii = np.arange(rec["ni"])
    xs = (ii + rec["lo"][0]) * dx
    right = ii[rowv & (xs > 0)].min()
    left = ii[rowv & (xs < 0)].max()
    s_pd = 0.5 * (rec["syy"][right, j0] + rec["syy"][left, j0])
    xe = 0.5 * (xs[right] - xs[left])
    row.update(x_edge_mm=round(xe * 1e3, 4), kt_pd=round(s_pd / S_PLATE, 5))
    if fem is not None:
        plane = "stress" if dim == 2 else "strain"
        F = fem[(plane, 0.3 if dim == 2 else mnu)]
        _, s_fem = F.at(np.array([xe]), np.array([0.0]))
        kt_fem_pt = s_fem[0, 1] / S_PLATE
        # the FEM displacement at the same points, through the same recovery:
        # the recovery's own discretization error (one-sided fits at the
        # staircase hole boundary, ~10 % at n = 41) then cancels, and the
        # difference is the model's error
        u_fx, _ = F.at(X[:, 0], X[:, 1])
        Uf = np.zeros_like(X)
        Uf[:, :2] = u_fx
        recf = recover_stress(X, Uf, dx, dim, mnu)
        sf_edge = 0.5 * (recf["syy"][right, j0] + recf["syy"][left, j0])
        pts = rec["valid"] & np.isfinite(rec["syy"]) & np.isfinite(recf["syy"])
        gi, gj = np.nonzero(pts)
        px, py = (gi + rec["lo"][0]) * dx, (gj + rec["lo"][1]) * dx
        # the error measure of the chart: sigma_yy near the hole (every point
        # with r < 2a, i.e. within one radius of the edge): RMS of the
        # difference to FEM over the RMS of FEM there
        near = np.hypot(px, py) < 2 * plate_fem.A
        d_s = rec["syy"][gi, gj][near] - recf["syy"][gi, gj][near]
        err_near = math.sqrt(np.mean(d_s ** 2) / np.mean(recf["syy"][gi, gj][near] ** 2))
        # displacement field against FEM, rigid motion of the difference removed
        u_f = recf["U"][gi, gj]
        u_p = rec["U"][gi, gj]
        diff = u_p - u_f
        G = np.zeros((2 * len(px), 3))
        G[0::2, 0] = 1
        G[1::2, 1] = 1
        G[0::2, 2] = -py
        G[1::2, 2] = px
        coef, *_ = np.linalg.lstsq(G, diff.reshape(-1), rcond=None)
        res = diff.reshape(-1) - G @ coef
        err_u = np.linalg.norm(res) / np.linalg.norm(u_f.reshape(-1))
        row.update(kt_fem_point=round(kt_fem_pt, 5), kt_fem_edge=round(F.S[0, 0, 1] / S_PLATE, 5),
                   kt_fem_recovered=round(sf_edge / S_PLATE, 5),
                   err=round(err_near, 6), near_points=int(near.sum()),
                   err_point=round(s_pd / sf_edge - 1.0, 6),
                   err_kt_edge=round(s_pd / S_PLATE / (F.S[0, 0, 1] / S_PLATE) - 1.0, 6),
                   err_u=round(err_u, 6))
    row["status"] = "ok"
    return [row]


# ----------------------------------------------------------------------------
# scene: wave speed in a bar

def arrival(t, x, vx, xs):
    """time at which the slab-averaged vx at station xs first reaches half of
    its first-passage peak (the rule of examples/wave_bar/measure.py)"""
    k = int(np.argmin(np.abs(x - xs)))
    v = vx[:, k]
    late = t > (2 * x.max() - xs) / C0 * 0.95
    half = 0.5 * v[~late].max()
    nn = int(np.argmax(v >= half))
    return t[nn - 1] + (half - v[nn - 1]) / (v[nn] - v[nn - 1]) * (t[nn] - t[nn - 1])


def read_profile(path, dt):
    steps, frames = [], []
    with open(path) as f:
        lines = [l for l in f if not l.startswith("#")]
    i = 0
    while i < len(lines):
        step, nrows = (int(v) for v in lines[i].split()[:2])
        frames.append(np.array([[float(v) for v in l.split()] for l in lines[i + 1:i + 1 + nrows]]))
        steps.append(step)
        i += 1 + nrows
    t = np.array(steps) * dt
    return t, frames[0][:, 1], np.array([fr[:, 3] for fr in frames])


def wave_job(R, model, dim, dx, m, sz):
    delta = delta_of(m, dx)
    pstyle, pcoeff = M.pair_lines(model, E, NU, delta, dim, dx)
    dt = 0.1 * dx / C0
    steps = int(round(24e-6 / dt))
    every = max(1, steps // 150)
    var = dict(dx=dx, dim=dim, pstyle=pstyle, pcoeff=pcoeff, dt=f"{dt:.6g}", steps=steps, every=every)
    tag = f"wave/{dim}d_{model}_m{m}_dx{dx * 1e3:.4f}"
    log = R.run(tag, "in.wave", var)
    row = dict(scene="wave", dim=dim, model=model, label=M.LABEL[model], m=m,
               n=int(round(0.008 / dx)), dx_mm=round(dx * 1e3, 5))
    row.update(cost_fields(log, steps))
    if not log.ok:
        row.update(status="failed", note=log.error[:120])
        return [row]
    t, x, vx = read_profile(os.path.join(log.dir, "vx_profile.txt"), dt)
    x1, x2 = 0.040, 0.100
    c = (x2 - x1) / (arrival(t, x, vx, x2) - arrival(t, x, vx, x1))
    th = log.thermo()
    drift = abs(th["TotEng"][-1] - th["TotEng"][0]) / th["TotEng"][0] if len(th.get("TotEng", [])) else float("nan")
    row.update(c=round(c, 2), c0=round(C0, 2), err=round(abs(c / C0 - 1), 6),
               err_signed=round(c / C0 - 1, 6), energy_drift=drift, status="ok")
    return [row]


# ----------------------------------------------------------------------------
# scene: uniform tension

def tension_job(R, model, dim, n, m, sz):
    dx = 0.010 / n
    delta = delta_of(m, dx)
    pstyle, pcoeff = M.pair_lines(model, E, NU, delta, dim, dx)
    solver = M.SOLVER[model]
    fscale = E * 1e-3 / dx * math.sqrt(n ** (dim - 1) * 6)
    var = dict(n=n, dim=dim, pstyle=pstyle, pcoeff=pcoeff, solver=solver,
               ftol=f"{1e-7 * fscale:.6g}", maxiter=1000 * n, dt=f"{0.3 * dx / C0:.6g}")
    tag = f"tension/{dim}d_{model}_m{m}_n{n}"
    log = R.run(tag, "in.tension", var)
    row = dict(scene="tension", dim=dim, model=model, label=M.LABEL[model], m=m, n=n,
               dx_mm=round(dx * 1e3, 5), solver=solver, converged=log.stop)
    row.update(cost_fields(log))
    if not log.ok:
        row.update(status="failed", note=log.error[:120])
        return [row]
    _, X = read_dump(os.path.join(log.dir, "ref.dump"))
    _, Y = read_dump(os.path.join(log.dir, "def.dump"))
    U = Y - X
    L = X[:, 0].max() - X[:, 0].min()
    x0 = X[:, 0].min()
    mid = (X[:, 0] > x0 + L / 3) & (X[:, 0] < x0 + 2 * L / 3)
    exx = np.polyfit(X[mid, 0], U[mid, 0], 1)[0]
    eyy = np.polyfit(X[mid, 1], U[mid, 1], 1)[0]
    fr = float(re.findall(r"^REACTION (\S+)", log.text, re.M)[-1])
    area = n * n * dx * dx if dim == 3 else n * dx * dx      # 2D: thickness dx
    sxx = -fr * dx ** 3 / area        # force on the right grip from the bar pulls it back (-x)
    Eapp = sxx / exx
    nuapp = -eyy / exx
    eE, enu = Eapp / E - 1, nuapp / NU - 1
    row.update(E_app=round(Eapp / 1e9, 4), nu_app=round(nuapp, 5), err_E=round(eE, 6),
               err_nu=round(enu, 6), err=round(max(abs(eE), abs(enu)), 6), status="ok")
    return [row]


# ----------------------------------------------------------------------------
# stability scenes on a periodic cube

CUBE_N = {(3, 3): 8, (3, 4): 10, (2, 3): 16, (2, 4): 16}


def cube_var(model, dim, m, dt, steps, every, mode, seed=12345):
    dx = 1e-3
    n = CUBE_N[(dim, m)]
    delta = delta_of(m, dx)
    pstyle, pcoeff = M.pair_lines(model, E, NU, delta, dim, dx)
    return dict(n=n, m=m, dim=dim, pstyle=pstyle, pcoeff=pcoeff, dt=f"{dt:.8g}", steps=steps,
                every=every, mode=mode, seed=seed), n


def zem_job(R, model, dim, sz):
    m = 3
    dt = 0.2 * 1e-3 / C0
    steps = sz["zem_steps"]
    var, n = cube_var(model, dim, m, dt, steps, 10, "zem")
    log = R.run(f"zem/{dim}d_{model}", "in.cube", var)
    row = dict(scene="zem", dim=dim, model=model, label=M.LABEL[model], m=m, n=n)
    row.update(cost_fields(log, steps))
    if not log.ok:
        row.update(status="failed", note=log.error[:120])
        return [row], None
    mt = re.findall(r"^ZEM_FORCE amplitude (\S+) fdotmode (\S+) frms (\S+) pe (\S+)", log.text, re.M)[-1]
    a, fdot, frms, pe = (float(v) for v in mt)
    delta = delta_of(m, 1e-3)
    fref = E * (2 * a / 1e-3) / delta
    th = log.thermo()
    t, A = th["Time"], th["v_A"]
    v0 = 0.1
    growth = np.abs(A).max() / (v0 * t[-1])
    # the mode's angular frequency from the zero crossings (restrained modes)
    sgn = np.sign(A[1:])
    cross = np.nonzero(sgn[1:] * sgn[:-1] < 0)[0]
    omega = math.pi * (len(cross) - 1) / (t[1:][cross[-1]] - t[1:][cross[0]]) if len(cross) >= 2 else 0.0
    row.update(a=a, restoring=-fdot / fref, frms_over_ref=frms / fref, mode_energy=pe,
               growth=round(growth, 6), omega_dx_over_c0=omega * 1e-3 / C0, status="ok")
    np.savetxt(os.path.join(log.dir, "amplitude.txt"), np.c_[t, A])
    return [row], (t, A)


def noise_run(R, model, dim, m, dt, steps, every, tag):
    var, n = cube_var(model, dim, m, dt, steps, every, "noise")
    log = R.run(tag, "in.cube", var, timeout=1200)
    th = log.thermo() if log.ok else {}
    return log, n, th


def drift_job(R, model, dim, sz):
    m = 3
    dt = 0.2 * 1e-3 / C0
    steps = sz["drift_steps"]
    log, n, th = noise_run(R, model, dim, m, dt, steps, max(1, steps // 200), f"drift/{dim}d_{model}")
    row = dict(scene="drift", dim=dim, model=model, label=M.LABEL[model], m=m, n=n,
               dt_c0_over_dx=0.2)
    row.update(cost_fields(log, steps))
    if not log.ok or not len(th.get("TotEng", [])):
        row.update(status="failed", note=log.error[:120])
        return [row]
    e = th["TotEng"]
    rel = (e - e[0]) / e[0]
    # velocity Verlet's energy error jumps to its bounded level within the
    # first steps; past the first 5 % of the run: drift = the linear trend
    # over the rest of the run (slope times its length), fluctuation = the
    # standard deviation about that trend
    st = th["Step"]
    keep = st >= st[0] + 0.05 * (st[-1] - st[0])
    slope, icpt = np.polyfit(st[keep], rel[keep], 1)
    row.update(energy_ok=M.ENERGY_OK[model], drift=slope * (st[keep][-1] - st[keep][0]),
               fluctuation=float(np.std(rel[keep] - (slope * st[keep] + icpt))),
               max_error=np.abs(rel).max(), status="ok")
    np.savetxt(os.path.join(log.dir, "energy.txt"), np.c_[th["Step"], rel])
    return [row]


def stable(log, th, energy):
    """bounded: the run ends, energies stay finite and the kinetic energy
    stays below 100 times the initial total energy (an instability grows
    exponentially; a bounded run never comes near);
    energy: bounded and the total energy within 1 % of its initial value"""
    if not log.ok or not len(th.get("TotEng", [])) or "Fix halt condition" in log.text:
        return False
    e, ke = th["TotEng"], th["KinEng"]
    if not (np.all(np.isfinite(e)) and np.all(np.isfinite(ke))):
        return False
    if ke.max() > 100.0 * abs(e[0]):
        return False
    if energy and np.abs(e - e[0]).max() / abs(e[0]) > 0.01:
        return False
    return True


def dtmax_job(R, model, dim, m, sz):
    """largest stable time step, by bisection on dt c0/dx (geometric means)
    from random initial velocities (every mode excited), N steps a trial:
    dt_bounded: the largest step that stays bounded (all models);
    dt_energy1: the largest step whose total energy stays within 1 % (models
    whose reported energy is the potential of their forces)"""
    steps = sz["dtmax_steps"]
    nrun, t_run = 0, 0.0
    n = CUBE_N[(dim, m)]
    base = dict(scene="dtmax", dim=dim, model=model, label=M.LABEL[model], m=m, n=n)

    def trial(c, energy):
        nonlocal nrun, t_run
        log, _, th = noise_run(R, model, dim, m, c * 1e-3 / C0, steps, max(1, steps // 100),
                               f"dtmax/{dim}d_{model}_m{m}/c{c:.4f}")
        nrun += 1
        t_run += log.wall
        return stable(log, th, energy)

    out = {}
    for crit in ("bounded", "energy1"):
        energy = crit == "energy1"
        if energy and not M.ENERGY_OK[model]:
            out[crit] = (float("nan"), float("nan"), "energy not a potential of the forces")
            continue
        lo, hi = 0.05, 8.0
        if not trial(lo, energy):
            out[crit] = (0.0, lo, "unstable at the smallest step tried")
            continue
        if trial(hi, energy):
            out[crit] = (hi, hi, "stable at the largest step tried")
            continue
        for _ in range(sz["dtmax_iter"]):
            mid = math.sqrt(lo * hi)
            if trial(mid, energy):
                lo = mid
            else:
                hi = mid
        out[crit] = (lo, hi, "")
    # the classical bond-based estimate (Silling & Askari 2005) for the PMB
    # model, as a yardstick: dt < sqrt(2 rho / sum_j V_j c / |xi|)
    dx = 1e-3
    delta = delta_of(m, dx)
    K = 2 * E / 3
    c = 18 * K / (math.pi * delta ** 4) if dim == 3 else 9 * E / (math.pi * dx * delta ** 3)
    r = int(math.ceil(delta / dx))
    acc = 0.0
    rng = range(-r, r + 1)
    for i in rng:
        for j in rng:
            for k in (rng if dim == 3 else [0]):
                d = math.sqrt(i * i + j * j + k * k) * dx
                if 0 < d <= delta:
                    acc += dx ** 3 * c / d
    dt_sa = math.sqrt(2 * RHO / acc)
    (b_lo, b_hi, b_note), (e_lo, e_hi, e_note) = out["bounded"], out["energy1"]
    return [dict(base, dt_bounded=round(b_lo, 4), dt_bounded_hi=round(b_hi, 4),
                 dt_energy1=round(e_lo, 4), dt_energy1_hi=round(e_hi, 4),
                 dt_pmb_estimate=round(dt_sa * C0 / dx, 4), runs=nrun,
                 steps_per_run=steps, wall_s=round(t_run, 2), status="ok",
                 note="; ".join(v for v in (b_note and "bounded: " + b_note,
                                            e_note and "energy: " + e_note) if v))]


def spin_job(R, model, dim, sz):
    n = sz["spin_n"] if dim == 3 else 2 * sz["spin_n"]
    dx = 1e-3
    pstyle, pcoeff = M.pair_lines(model, E, NU, delta_of(3, dx), dim, dx)
    log = R.run(f"spin/{dim}d_{model}", "in.spin", dict(n=n, dim=dim, pstyle=pstyle, pcoeff=pcoeff))
    rows = []
    if not log.ok:
        return [dict(scene="spin", dim=dim, model=model, label=M.LABEL[model], status="failed",
                     note=log.error[:120])]
    delta = delta_of(3, dx)
    for th, pe, frms, nat in re.findall(r"^SPIN (\S+) pe (\S+) frms (\S+) natoms (\S+)", log.text, re.M):
        th, pe, frms, nat = float(th), float(pe), float(frms), int(float(nat))
        rows.append(dict(scene="spin", dim=dim, model=model, label=M.LABEL[model], n=n,
                         angle_deg=th, energy_density_over_E=pe / nat / E,
                         frms_delta_over_E=frms * delta / E,
                         small_strain_estimate=(1 - math.cos(math.radians(th))), status="ok"))
    return rows


# ----------------------------------------------------------------------------
# scene: damage (needs fix nospd/damage)

def damage_job(R, model, dim, sz, have_damage):
    dx = 1e-3
    m = 3
    delta = delta_of(m, dx)
    pstyle, pcoeff = M.pair_lines(model, E, NU, delta, dim, dx)
    s_c = 0.002
    if model in ("pmb", "lps"):
        pcoeff = pcoeff.replace(f" {M.S00} ", f" {s_c} ")
        dmg = "none"
    else:
        if not have_damage:
            return []
        dmg = f"nospd/damage stretch {s_c}"
    dt = 0.2 * dx / C0
    var = dict(dim=dim, pstyle=pstyle, pcoeff=pcoeff, dmg=dmg, usedmg=int(dmg != "none"),
               dt=f"{dt:.6g}", steps=3000,
               vpull=2.0, nsing="0" if model in ("pmb", "lps") else "f_NOSPD_BONDS[3]")
    log = R.run(f"damage/{dim}d_{model}", "in.damage", var)
    row = dict(scene="damage", dim=dim, model=model, label=M.LABEL[model], m=m, criterion=f"stretch {s_c}")
    row.update(cost_fields(log, 3000))
    th = log.thermo()
    if not log.ok or not len(th.get("Step", [])):
        row.update(status="failed", note=(log.error or "no thermo")[:120])
        return [row]
    finite = all(np.all(np.isfinite(v)) for v in th.values())
    halted = "Fix halt condition" in log.text
    row.update(completed=int(th["Step"][-1]), finite=finite, blew_up=halted,
               max_speed=float(np.nanmax(th["v_vmax"])) if "v_vmax" in th else float("nan"),
               max_speed_over_pull=float(np.nanmax(th["v_vmax"])) / 2.0 if "v_vmax" in th else float("nan"),
               broken_fraction=float(th["v_broken"][-1]) if "v_broken" in th else float("nan"),
               singular_max=float(np.nanmax(th["v_ns"])) if "v_ns" in th else float("nan"),
               status="ok")
    np.savetxt(os.path.join(log.dir, "history.txt"),
               np.c_[[th[k] for k in th]].T, header=" ".join(th.keys()))
    return [row]


# ----------------------------------------------------------------------------

def write_csv(path, rows):
    keys = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def probe_models(R, dims):
    """which models this LAMMPS + plugin provide, per dimension"""
    avail, skipped = {}, []
    for key in M.KEYS:
        for dim in dims:
            if M.ONLY3D[key] and dim == 2:
                continue
            pstyle, pcoeff = M.pair_lines(key, E, NU, 0.00301, dim, 1e-3)
            log = R.run(f"probe/{key}_{dim}d", "in.probe", dict(dim=dim, pstyle=pstyle, pcoeff=pcoeff))
            if log.ok:
                avail.setdefault(key, []).append(dim)
            else:
                skipped.append(dict(model=key, label=M.LABEL[key], dim=dim, reason=log.error[:160]))
    return avail, skipped


def have_damage_fix(R):
    log = R.run("probe/fix_nospd_damage", "in.probe",
                dict(dim=3, pstyle="peri/nospd", pcoeff="* * 1e9 0.3 0.00301",
                     extra="fix d all nospd/damage stretch 0.01"))
    return log.ok


def cmd_run(args):
    sz = SIZES[args.size]
    os.makedirs(args.results, exist_ok=True)
    scenes = args.only.split(",") if args.only else SCENES
    # --only reruns some scenes and keeps the others' work files and CSVs
    for d in ([args.work] if not args.only else [os.path.join(args.work, s) for s in scenes + ["probe"]]):
        if os.path.isdir(d):
            shutil.rmtree(d)
    os.makedirs(args.work, exist_ok=True)
    R = Runner(args.lmp, args.plugin, args.work)
    t_start = time.time()
    avail, skipped = probe_models(R, (3, 2))
    write_csv(os.path.join(args.results, "skipped.csv"),
              skipped or [dict(model="", label="", dim="", reason="")])
    print("models:", ", ".join(f"{k}({'/'.join(str(d) + 'D' for d in v)})" for k, v in avail.items()))
    for s in skipped:
        print(f"  skipped {s['label']} {s['dim']}D: {s['reason']}")
    has = lambda k, d: d in avail.get(k, [])     # noqa: E731
    # relative cost of a model per point-step (sorting only: longest jobs first)
    w = dict(pmb=2.0, lps=4.0, hs1=10.0, hs2=10.0)
    jobs = []          # (scene, estimated cost, callable)
    fem = None
    if "plate" in scenes:
        fem = fem_setup(args.results, args.work)
        for (dim, m), ns in sz["plate"].items():
            for n in ns:
                for k in M.KEYS:
                    if has(k, dim):
                        cost = n * n * (1 if dim == 2 else 4.4 * (2 * m + 1)) * n * (m / 3) ** 2
                        jobs.append(("plate", cost * w.get(k, 1), lambda k=k, dim=dim, n=n, m=m:
                                     plate_job(R, k, dim, n, m, fem, sz)))
    if "wave" in scenes:
        for (dim, m), dxs in sz["wave"].items():
            for dx in dxs:
                for k in M.KEYS:
                    if has(k, dim):
                        cost = (0.008 / dx) ** (dim - 1) * (0.12 / dx) ** 2 * (4.4 if dim == 3 else 1) * (m / 3) ** 2
                        jobs.append(("wave", cost * w.get(k, 1), lambda k=k, dim=dim, dx=dx, m=m:
                                     wave_job(R, k, dim, dx, m, sz)))
    if "tension" in scenes:
        for (dim, m), ns in sz["tension"].items():
            for n in ns:
                for k in M.KEYS:
                    if has(k, dim):
                        cost = n ** (dim + 1) * 4 * (4.4 if dim == 3 else 1) * (m / 3) ** 2
                        jobs.append(("tension", cost * w.get(k, 1), lambda k=k, dim=dim, n=n, m=m:
                                     tension_job(R, k, dim, n, m, sz)))
    zem_traces = {}
    if "zem" in scenes:
        for dim in (3, 2):
            for k in M.KEYS:
                if has(k, dim):
                    def zj(k=k, dim=dim):
                        rows, tr = zem_job(R, k, dim, sz)
                        if tr is not None:
                            zem_traces[f"{dim}d_{k}"] = tr
                        return rows
                    jobs.append(("zem", 512 * sz["zem_steps"] / 30 * w.get(k, 1), zj))
    if "drift" in scenes:
        for dim in (3, 2):
            for k in M.KEYS:
                if has(k, dim):
                    jobs.append(("drift", 512 * sz["drift_steps"] / 30 * w.get(k, 1),
                                 lambda k=k, dim=dim: drift_job(R, k, dim, sz)))
    if "dtmax" in scenes:
        for dim, m in sz["dtmax"]:
            for k in M.KEYS:
                if has(k, dim):
                    jobs.append(("dtmax", 512 * sz["dtmax_steps"] * 2 * (sz["dtmax_iter"] + 2) / 30
                                 * (m / 3) ** 2 * w.get(k, 1),
                                 lambda k=k, dim=dim, m=m: dtmax_job(R, k, dim, m, sz)))
    if "spin" in scenes:
        for dim in (3, 2):
            for k in M.KEYS:
                if has(k, dim):
                    jobs.append(("spin", 1, lambda k=k, dim=dim: spin_job(R, k, dim, sz)))
    if "damage" in scenes and sz["damage"]:
        have_damage = have_damage_fix(R)
        if not have_damage:
            print("damage: this plugin has no fix nospd/damage: only peri/pmb and peri/lps run")
        for k in M.KEYS:
            if has(k, 3):
                jobs.append(("damage", 2000, lambda k=k: damage_job(R, k, 3, sz, have_damage)))
    # longest first over the workers
    jobs.sort(key=lambda j: -j[1])
    print(f"{len(jobs)} jobs on {args.jobs} workers")
    rows = {s: [] for s in SCENES}
    done = 0
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futs = {ex.submit(fn): scene for scene, _, fn in jobs}
        for f in cf.as_completed(futs):
            scene = futs[f]
            try:
                rr = f.result()
            except Exception as e:      # a broken analysis must not stop the chart
                rr = [dict(scene=scene, status="failed", note=f"analysis: {e!r}"[:160])]
            rows[scene] += rr
            done += 1
            for r in rr:
                if r.get("status") != "ok":
                    print(f"  [{done}/{len(jobs)}] {scene} {r.get('label', '')} {r.get('dim', '')}D: "
                          f"{r.get('status')} {r.get('note', '')}")
            if done % 20 == 0:
                print(f"  [{done}/{len(jobs)}] {time.time() - t_start:.0f} s")
    order = {k: i for i, k in enumerate(M.KEYS)}
    for s, rr in rows.items():
        if not rr:
            continue
        rr.sort(key=lambda r: (r.get("dim", 0), r.get("m", 0), order.get(r.get("model"), 99),
                               -r.get("dx_mm", 0) if "dx_mm" in r else r.get("n", 0),
                               r.get("angle_deg", 0)))
        write_csv(os.path.join(args.results, f"{s}.csv"), rr)
    if zem_traces:
        np.savez(os.path.join(args.results, "zem_traces.npz"), **{k: np.c_[v] for k, v in zem_traces.items()})
    # energy histories for the drift chart
    hist = {}
    for k in (M.KEYS if "drift" in scenes else []):
        for dim in (3, 2):
            p = os.path.join(args.work, "drift", f"{dim}d_{k}", "energy.txt")
            if os.path.exists(p):
                hist[f"{dim}d_{k}"] = np.loadtxt(p)
    if hist:
        np.savez(os.path.join(args.results, "drift_traces.npz"), **hist)
    meta = dict(size=args.size, jobs=args.jobs, seconds=round(time.time() - t_start, 1),
                lammps=args.lmp, date=time.strftime("%Y-%m-%d %H:%M"), models=avail,
                host_cores=os.cpu_count(), scenes=scenes)
    info = os.path.join(args.results, "run_info.json")
    if args.only and os.path.exists(info):
        # keep the record of the full run; note the rerun
        with open(info) as fh:
            old = json.load(fh)
        old.setdefault("reruns", []).append(meta)
        meta = old
    with open(info, "w") as fh:
        json.dump(meta, fh, indent=1)
    print(f"done in {time.time() - t_start:.1f} s; CSVs in {args.results}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cmd", choices=["run", "charts"])
    ap.add_argument("--size", default="full", choices=list(SIZES))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--lmp", default="")
    ap.add_argument("--plugin", default=os.path.join(ROOT, "build", "plugin"))
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "bench-chart"))
    ap.add_argument("--doc", default=os.path.join(ROOT, "doc"))
    args = ap.parse_args()
    if args.cmd == "run":
        if not args.lmp:
            d = subprocess.run(["bash", os.path.join(ROOT, "cmake", "lammps.sh"), "print-dir"],
                               stdout=subprocess.PIPE, text=True).stdout.strip()
            args.lmp = os.path.join(d, "lmp")
        cmd_run(args)
    else:
        import charts
        charts.main(args.results, args.doc)


if __name__ == "__main__":
    main()
