#!/usr/bin/python3
"""Axisymmetric explicit finite elements for a Taylor bar (numpy only).

What it is for: an independent continuum reference for examples/taylor_bar.
The same bar, anvil and Johnson-Cook constants as the peridynamic decks (the
constants read from potentials/plasticity.nospd, the bar from the decks'
defaults), solved with a standard finite-element method, so that the
peridynamic bar's length and footprint can be held against a converged
continuum solution of the same model, and not only against an experiment
that the constants may not reproduce.

    /usr/bin/python3 tools/taylor_fe.py --material ofhc_copper_jc --bar copper --nr 8
    /usr/bin/python3 tools/taylor_fe.py --material steel_42crmo4_jc --bar 42crmo4 --nr 8
    /usr/bin/python3 tools/taylor_fe.py --material steel_42crmo4_jc --bar 42crmo4 --check-elastic

prints progress lines and one line 'RESULT {json}' (lengths in m: L_f the
final length, D_face the impact-face diameter, energy_err the energy balance
at the end, max_abs_err its largest departure).  --bar sets R, L, v0 and the
end time (--R, --L, --v0, --tend override them); --nr sets the elements
across the radius (the axial count follows the aspect ratio, --nz).
--stop-ke F ends the run once the kinetic energy is below F times the
initial one (after 20 us).

Method (written from Belytschko, Liu & Moran, "Nonlinear finite elements for
continua and structures", ch. 4-6, and Wilkins' HEMP for the hoop term and
the artificial viscosity):

* Updated Lagrangian, 4-node quads in (r, z), 2x2 Gauss points with the
  axisymmetric weight 2 pi r.  Mean dilatation (Nagtegaal; B-bar): the
  deviatoric stress lives at the Gauss points, the pressure is one per
  element from its volume, p = -K ln(V/V0), so that the nodal forces are
  power-conjugate to the element's mean dilatation and the element does not
  lock under isochoric flow; the full 2x2 deviator leaves no hourglass
  modes.  (--integ full: a pressure per Gauss point from its own tr D, which
  locks; for comparison only.)
* Hypoelastic-plastic: D and W from the mid-step velocities on the current
  configuration, hoop rate v_r/r; Jaumann rotation of the deviator; radial
  return (backward Euler) for J2 with the Johnson-Cook flow stress
  (A + B eps_p^n)(1 + C ln(rate/rate0))(1 - T*^m).  The rate is the plastic
  rate of the step, solved in the return (--rate plastic, default), or the
  total equivalent deviatoric rate sqrt(2/3)|dev D| (--rate total, as the
  peridynamic code measures it).  Adiabatic heating
  dT = chi sigma_y d eps_p / (rho c_p) with the entry's 'heat cp chi' (no
  heating without it).
* Lumped (row-sum) mass; central differences; time step cfl L_e /
  (Q + sqrt(Q^2 + c^2)) with L_e = area / longest edge, every step.
* Rigid frictionless anvil at z = 0, kinematic: a node's v_z is clipped so
  that it does not pass z = 0; it slides radially and may lift off.  Axis
  nodes v_r = 0.
* Bulk viscosity q = rho L (b1 c |tr D| + b2^2 L tr D^2) in compression
  (b1 = 0.06, b2 = 1.2; --visc 0 without).
* Energy record: kinetic + elastic (deviatoric s:s/4G, volumetric
  K V0 (J ln J - J + 1)) + plastic work + viscous work - contact work,
  against the initial kinetic energy.

Limits: hypoelastic (Jaumann) rather than hyperelastic, with a pressure
linear in ln J (no equation of state); the anvil is frictionless and
kinematic (no penetration, no stiffness: not the peridynamic deck's
harmonic wall); no failure; the density is the material file's (the
peridynamic decks set theirs with 'set ... density', equal for the two
bars).  Checked: --check-elastic (a 5 m/s elastic bar: the face stress in
the one-dimensional stretch of the impact against rho c_bar v, and the
energy balance); --column (a quasi-static column on the anvil, C = 0, no
heating, against the uniaxial flow curve A + B eps_p^n, within 1 % from a
log strain of 0.1).
"""
import argparse
import json
import os
import sys
import time

import numpy as np

# The peridynamic decks' bars: examples/taylor_bar/in.taylor_bar (copper) and
# in.taylor_bar_42crmo4, run to 80 us in both
BARS = {'copper': dict(R=3.81e-3, L=25.4e-3, v0=190., tend=80e-6),
        '42crmo4': dict(R=3.2e-3, L=32.4e-3, v0=287., tend=80e-6)}
JC_KEYS = ('A', 'B', 'n', 'C', 'rate0', 'm', 'Tref', 'Tmelt')


# ---------------------------------------------------------------- material

def material_entries(path):
    """The entries of a PERI-NOSPD material file as (first line, words):
    the plugin's grammar (doc/pair_peri_nospd.rst, pair_coeff with a
    material file): '#' starts a comment anywhere, and an entry with fewer
    than five words (name E nu density G0) continues on the next line with
    words; the inelastic keywords follow those five."""
    words, first = [], 0
    with open(path) as f:
        for lineno, text in enumerate(f, 1):
            more = text.split('#', 1)[0].split()
            if not more:
                continue
            if not words:
                first = lineno
            words += more
            if len(words) >= 5:
                yield first, words
                words = []
    if words:
        sys.exit('taylor_fe.py: %s ends inside entry %s (line %d)' % (path, words[0], first))


def read_material(path, name):
    """E, nu, rho, the Johnson-Cook constants and the heating (cp, beta =
    the Taylor-Quinney fraction chi) of entry `name`; exits with a message
    on an entry without a complete johnson_cook block."""
    def numbers(words, k, count, what, line):
        vals = words[k + 1:k + 1 + count]
        try:
            if len(vals) < count:
                raise ValueError
            return [float(w) for w in vals]
        except ValueError:
            sys.exit('taylor_fe.py: %s, entry %s (line %d): %s needs %d numbers, got %s'
                     % (path, name, line, what, count, ' '.join(vals) or 'none'))

    for line, words in material_entries(path):
        if words[0] != name:
            continue
        E, nu, rho = numbers(words, 0, 3, 'E nu density', line)
        mat = dict(E=E, nu=nu, rho=rho, cp=1.0, beta=0.0)
        if 'johnson_cook' not in words:
            sys.exit('taylor_fe.py: %s, entry %s (line %d) has no johnson_cook flow stress; '
                     'this model needs one (johnson_cook A B n C rate0 m T_ref T_melt)'
                     % (path, name, line))
        mat.update(zip(JC_KEYS, numbers(words, words.index('johnson_cook'), 8,
                                        'johnson_cook (A B n C rate0 m T_ref T_melt)', line)))
        if 'heat' in words:
            mat['cp'], mat['beta'] = numbers(words, words.index('heat'), 2, 'heat (cp chi)', line)
        return mat
    sys.exit('taylor_fe.py: no entry %s in %s' % (name, path))


# ---------------------------------------------------------------- element

g = 1.0 / np.sqrt(3.0)
GP = np.array([[-g, -g], [g, -g], [g, g], [-g, g]])           # (xi, eta)
NXI = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)   # node natural coords
N_gp = 0.25 * (1 + GP[:, None, 0] * NXI[None, :, 0]) * (1 + GP[:, None, 1] * NXI[None, :, 1])
dNxi = 0.25 * NXI[None, :, 0] * (1 + GP[:, None, 1] * NXI[None, :, 1])   # (gp, node)
dNeta = 0.25 * NXI[None, :, 1] * (1 + GP[:, None, 0] * NXI[None, :, 0])


def mesh(R, L, nr, nz):
    r = np.linspace(0, R, nr + 1)
    z = np.linspace(0, L, nz + 1)
    Rg, Zg = np.meshgrid(r, z)                   # (nz+1, nr+1)
    x = np.stack([Rg.ravel(), Zg.ravel()], 1)
    conn = []
    for j in range(nz):
        for i in range(nr):
            a = j * (nr + 1) + i
            conn.append([a, a + 1, a + 1 + nr + 1, a + nr + 1])
    return x, np.array(conn)


def geometry(x, conn):
    """Shape-function gradients, radius and volume (2 pi r det J) at the
    Gauss points of the current configuration (updated Lagrangian)."""
    xr = x[conn, 0]; xz = x[conn, 1]             # (ne, 4)
    j11 = xr @ dNxi.T; j12 = xz @ dNxi.T         # (ne, gp): dr/dxi, dz/dxi
    j21 = xr @ dNeta.T; j22 = xz @ dNeta.T
    det = j11 * j22 - j12 * j21
    # dN/dr = ( j22 dN/dxi - j12 dN/deta)/det ; dN/dz = (-j21 dN/dxi + j11 dN/deta)/det
    dNr = (j22[:, :, None] * dNxi[None] - j12[:, :, None] * dNeta[None]) / det[:, :, None]
    dNz = (-j21[:, :, None] * dNxi[None] + j11[:, :, None] * dNeta[None]) / det[:, :, None]
    rg = xr @ N_gp.T                              # (ne, gp)
    dV = 2 * np.pi * rg * det                     # weights are 1 for 2x2 Gauss
    return dNr, dNz, rg, dV, det


def char_length(x, conn):
    """Area over the longest edge: the length a dilatational wave crosses,
    which sets the stable step of a distorted element."""
    p = x[conn]                                   # (ne, 4, 2)
    e = np.roll(p, -1, axis=1) - p
    le = np.sqrt((e ** 2).sum(-1))
    d1 = p[:, 2] - p[:, 0]; d2 = p[:, 3] - p[:, 1]
    A = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    return A / le.max(1)


# ---------------------------------------------------------------- plasticity

def jc_flow(mat, ep, rate, T, C):
    Ts = np.clip((T - mat['Tref']) / (mat['Tmelt'] - mat['Tref']), 0.0, 1.0)
    hard = mat['A'] + mat['B'] * np.maximum(ep, 0.0) ** mat['n']
    rt = 1.0 + C * np.log(np.maximum(rate / mat['rate0'], 1.0))
    return hard * rt * (1.0 - Ts ** mat['m']), hard, rt, (1.0 - Ts ** mat['m'])


def radial_return(mat, C, qtr, ep, T, dt, G, rate_mode, rate_tot):
    """Solve qtr - 3G d = sy(ep + d, rate, T) for d >= 0 (vectorized):
    Newton safeguarded by bisection, since with the plastic rate d/dt in
    the log the flow stress has an infinite slope at d = rate0 dt."""
    B, n = mat['B'], mat['n']
    sy0, _, _, th = jc_flow(mat, ep, rate_tot if rate_mode == 'total' else 0.0 * ep, T, C)
    yl = qtr > sy0
    d = np.zeros_like(qtr)
    if not yl.any():
        return d, sy0, yl
    q = qtr[yl]; e = ep[yl]; t = th[yl]
    rtt = rate_tot[yl] if rate_mode == 'total' else None
    lo = np.zeros_like(q); hi = (q - sy0[yl]) / (3 * G)
    x = hi.copy()
    act = np.arange(len(q))
    for it in range(80):
        xa = x[act]; ea = e[act]
        epn = ea + xa
        hard = mat['A'] + B * epn ** n
        dhard = B * n * np.maximum(epn, 1e-12) ** (n - 1)
        if rate_mode == 'total':
            rt = 1 + C * np.log(np.maximum(rtt[act] / mat['rate0'], 1.0)); drt = 0.0
        else:
            ratio = xa / (dt * mat['rate0'])
            rt = 1 + C * np.log(np.maximum(ratio, 1.0))
            drt = np.where(ratio > 1.0, C / np.maximum(xa, 1e-300), 0.0)
        f = q[act] - 3 * G * xa - hard * rt * t[act]
        df = -3 * G - (dhard * rt + hard * drt) * t[act]
        pos = f > 0
        la = np.where(pos, xa, lo[act]); ha = np.where(pos, hi[act], xa)
        lo[act] = la; hi[act] = ha
        xn = xa - f / df
        bad = (xn <= la) | (xn >= ha) | ~np.isfinite(xn)
        xn = np.where(bad, 0.5 * (la + ha), xn)
        conv = (np.abs(xn - xa) <= 1e-14 + 1e-11 * np.abs(xa)) | (ha - la <= 1e-14 + 1e-12 * ha)
        x[act] = xn
        act = act[~conv]
        if len(act) == 0:
            break
    else:
        print('# return did not converge for', len(act), 'points', file=sys.stderr)
    d[yl] = x
    sy = sy0.copy()
    epn = e + x
    if rate_mode == 'total':
        rt = 1 + C * np.log(np.maximum(rtt / mat['rate0'], 1.0))
    else:
        rt = 1 + C * np.log(np.maximum(x / (dt * mat['rate0']), 1.0))
    sy[yl] = (mat['A'] + B * epn ** n) * rt * t
    return d, sy, yl


# ---------------------------------------------------------------- one step

def rate_of_deformation(m, v, dNr, dNz, rg):
    """D (rr, zz, tt, rz), the spin W_rz and tr D at the Gauss points from
    the mid-step velocities v^{n-1/2} on x^n; the hoop rate is v_r / r."""
    vr = v[m.conn, 0]; vz = v[m.conn, 1]           # (ne,4)
    Drr = np.einsum('egi,ei->eg', dNr, vr)
    Dzz = np.einsum('egi,ei->eg', dNz, vz)
    dvrdz = np.einsum('egi,ei->eg', dNz, vr)
    dvzdr = np.einsum('egi,ei->eg', dNr, vz)
    Drz = 0.5 * (dvrdz + dvzdr); Wrz = 0.5 * (dvrdz - dvzdr)
    Dtt = (vr @ N_gp.T) / rg
    return Drr, Dzz, Dtt, Drz, Wrz, Drr + Dzz + Dtt


def update_stress(m, st, D, h, dV, rho_e):
    """Deviatoric stress over the last step h: the Jaumann rotation keeps
    the rate objective under the bar's large rotations at the face, the
    elastic trial adds 2G dev D h, the radial return brings it back to the
    Johnson-Cook surface; the plastic work heats the point adiabatically."""
    Drr, Dzz, Dtt, Drz, Wrz, trD = D
    G = m.G
    # Jaumann rotation of the deviator (W = [[0, w],[-w, 0]] in r,z)
    dw = Wrz * h
    srr, szz, stt, srz = st.s[..., 0], st.s[..., 1], st.s[..., 2], st.s[..., 3]
    rrr = srr + 2 * dw * srz
    rzz = szz - 2 * dw * srz
    rrz = srz + dw * (szz - srr)
    tr3 = trD / 3.0
    s = np.stack([rrr + 2 * G * h * (Drr - tr3), rzz + 2 * G * h * (Dzz - tr3),
                  stt + 2 * G * h * (Dtt - tr3), rrz + 2 * G * h * Drz], -1)
    if not m.elastic:
        nrm = np.sqrt(s[..., 0] ** 2 + s[..., 1] ** 2 + s[..., 2] ** 2 + 2 * s[..., 3] ** 2)
        qtr = np.sqrt(1.5) * nrm
        rate_tot = np.sqrt(2.0 / 3.0) * np.sqrt((Drr - tr3) ** 2 + (Dzz - tr3) ** 2 + (Dtt - tr3) ** 2
                                                + 2 * Drz ** 2)
        d, sy, yl = radial_return(m.mat, m.C, qtr.ravel(), st.ep.ravel(), st.T.ravel(), h, G,
                                  m.rate, rate_tot.ravel())
        d = d.reshape(st.ep.shape); sy = sy.reshape(st.ep.shape); yl = yl.reshape(st.ep.shape)
        fac = np.ones_like(qtr)
        fac[yl] = sy[yl] / qtr[yl]                 # qtr > sy0 > 0 where yielding
        s = s * fac[..., None]
        st.ep = st.ep + d
        dWp = sy * d                               # plastic work per current volume
        st.Wp += (dWp * dV).sum()
        if m.heat:
            st.T = st.T + m.mat['beta'] * dWp / (rho_e[:, None] * m.mat['cp'])
    st.s = s
    if m.integ == 'full':
        st.pgp = st.pgp - m.K * trD * h


def pressure(m, st, Vel, Le, rho_e, trDbar):
    """Total pressure per Gauss point: mean dilatation's element pressure
    -K ln(V/V0) (or the Gauss point's, --integ full) plus the bulk
    viscosity, which damps the ringing behind the impact shock; its work
    goes to the energy record."""
    J = Vel / m.V0e
    p = -m.K * np.log(J)
    if m.visc:
        comp = np.minimum(trDbar, 0.0)
        st.q = rho_e * Le * (m.b1 * m.cd0 * (-comp) + m.b2 ** 2 * Le * comp ** 2)
        if st.dt_prev is not None:
            st.Wq += -(st.q * trDbar * Vel).sum() * st.dt_prev
    return (st.pgp if m.integ == 'full' else p[:, None]) + st.q[:, None], J


def internal_force(m, s, ptot, dNr, dNz, rg, dV):
    """f = int B^T sigma dV with sigma = s - p I, assembled on the nodes;
    the hoop stress enters through N/r (the axisymmetric B)."""
    srr_t = s[..., 0] - ptot; szz_t = s[..., 1] - ptot; stt_t = s[..., 2] - ptot; srz_t = s[..., 3]
    fr = (np.einsum('egi,eg->ei', dNr, srr_t * dV) + np.einsum('egi,eg->ei', dNz, srz_t * dV)
          + (stt_t * dV / rg) @ N_gp)
    fz = np.einsum('egi,eg->ei', dNr, srz_t * dV) + np.einsum('egi,eg->ei', dNz, szz_t * dV)
    return np.stack([np.bincount(m.cflat, fr.ravel(), m.nn), np.bincount(m.cflat, fz.ravel(), m.nn)], 1)


def time_step(m, Le, trDbar, rho_e, cfl):
    """The stable step of central differences with viscosity, every step:
    the elements at the face shrink in length as they flatten, and the
    wave speed follows the compressed density."""
    Qv = m.b1 * m.cd0 + m.b2 ** 2 * Le * np.abs(np.minimum(trDbar, 0.0))
    cel = m.cd0 * np.sqrt(m.rho0 / rho_e)
    return cfl * (Le / (Qv + np.sqrt(Qv ** 2 + cel ** 2))).min()


def anvil(m, x, vn, dt_new, dtavg):
    """Rigid frictionless anvil at z = 0, kinematic: a node that would pass
    z = 0 in the next step gets the v_z that lands it on the plane; its r is
    free (no friction) and it may lift off.  The impulse this takes is the
    contact force; returns the nodes in contact and the force per node."""
    ztr = x[:, 1] + dt_new * vn[:, 1]
    hit = ztr < 0.0
    vz_c = -x[hit, 1] / dt_new
    fc = m.mass[hit] * (vz_c - vn[hit, 1]) / dtavg
    vn[hit, 1] = vz_c
    return hit, fc


def energy_record(m, st, x, vold, fint, J, Fc):
    """The energy balance (kinetic at the integer step + elastic + plastic
    + viscous - contact work, relative to the initial kinetic energy) and
    the shape: length, face diameter, largest plastic strain and
    temperature."""
    v = st.v; s = st.s; G = m.G
    KE = 0.5 * (m.mass * ((0.5 * (vold + v)) ** 2).sum(1)).sum()   # v^n, integer step
    Eel_dev = ((s[..., 0] ** 2 + s[..., 1] ** 2 + s[..., 2] ** 2 + 2 * s[..., 3] ** 2) / (4 * G) * st.dV).sum()
    if m.integ == 'full':
        Eel_vol = ((st.pgp ** 2) / (2 * m.K) * st.dV).sum()
    else:
        Eel_vol = (m.K * m.V0e * (J * np.log(J) - J + 1)).sum()
    Efl = KE + Eel_dev + Eel_vol + st.Wp + st.Wq - st.Wc
    Lz = x[:, 1].max() - x[:, 1].min()
    rec = dict(t=st.t, KE=KE, Eel=Eel_dev + Eel_vol, Wp=st.Wp, Wq=st.Wq, Wc=st.Wc,
               err=(Efl - m.KE0) / max(m.KE0, 1e-30), L=Lz, Dface=2 * x[m.face0, 0].max(),
               Dmax=2 * x[:, 0].max(), epmax=st.ep.max(), Tmax=st.T.max(), dt=st.dt_prev, Fc=Fc,
               vzmean=(m.mass * v[:, 1]).sum() / m.mass.sum())
    if m.column:
        # axial force on the anvil and through the top row; current radius
        rec.update(Lc=x[:, 1].max(), Rmax=x[:, 0].max(), Fc=Fc, Fi_top=fint[m.top, 1].sum())
    return rec


# ---------------------------------------------------------------- driver

class Model:
    """Constants, mesh, lumped mass and boundary node sets."""

    def __init__(self, args, mat, bar):
        self.mat, self.bar = mat, bar
        self.C = mat['C'] if args.C is None else args.C
        E, nu, self.rho0 = mat['E'], mat['nu'], mat['rho']
        self.G = E / (2 * (1 + nu)); self.K = E / (3 * (1 - 2 * nu))
        self.cd0 = np.sqrt((self.K + 4 * self.G / 3) / self.rho0)
        R, L = bar['R'], bar['L']
        self.nr = args.nr or 8; self.nz = args.nz or int(round(self.nr * L / R))
        self.x0, self.conn = mesh(R, L, self.nr, self.nz)
        self.nn, self.ne = len(self.x0), len(self.conn)
        self.cflat = self.conn.ravel()
        _, _, _, dV, _ = geometry(self.x0, self.conn)
        self.V0e = dV.sum(1)
        # lumped mass, row sum of the 2 pi r weighted consistent mass
        self.mass = np.bincount(self.cflat, (self.rho0 * dV[:, :, None] * N_gp[None]).sum(1).ravel(), self.nn)
        self.axis = self.x0[:, 0] < 1e-12 * R
        self.top = self.x0[:, 1] > L * (1 - 1e-9)
        self.face0 = self.x0[:, 1] < 1e-12 * L
        self.elastic, self.heat, self.column = args.elastic, not args.noheat, args.column
        self.integ, self.rate, self.visc = args.integ, args.rate, args.visc
        self.b1, self.b2 = (0.06, 1.2) if args.visc else (0.0, 0.0)
        self.KE0 = None


class State:
    """What the step carries: positions, mid-step velocities, stress and
    internal variables at the Gauss points, the energy accounts."""

    def __init__(self, m, v0, column):
        self.x = m.x0.copy()
        self.v = np.zeros_like(self.x); self.v[:, 1] = -v0
        if column:                                  # quasi-static column test
            self.v[:, 1] = 0.0
        self.s = np.zeros((m.ne, 4, 4))             # deviator rr, zz, tt, rz at gp
        self.pgp = np.zeros((m.ne, 4))              # pressure per gp (integ full)
        self.ep = np.zeros((m.ne, 4)); self.T = np.full((m.ne, 4), m.mat['Tref'])
        self.q = np.zeros(m.ne)
        self.Wp = self.Wq = self.Wc = 0.0
        self.t = 0.0; self.step = 0; self.dt_prev = None


def run(args):
    mat = read_material(args.file, args.material)
    bar = dict(BARS[args.bar])
    for key in ('v0', 'tend', 'R', 'L'):
        if getattr(args, key) is not None:
            bar[key] = getattr(args, key)
    m = Model(args, mat, bar)
    st = State(m, bar['v0'], args.column)
    m.KE0 = 0.5 * (m.mass * (st.v ** 2).sum(1)).sum()
    hist = []
    t0 = time.time()
    while st.t < bar['tend']:
        x = st.x
        dNr, dNz, rg, dV, det = geometry(x, m.conn)
        if (det <= 0).any():
            print('# negative Jacobian at t=%.3e us, step %d' % (st.t * 1e6, st.step)); break
        st.dV = dV
        Vel = dV.sum(1)
        Le = char_length(x, m.conn)
        rho_e = m.rho0 * m.V0e / Vel
        D = rate_of_deformation(m, st.v, dNr, dNz, rg)
        trDbar = (D[5] * dV).sum(1) / Vel           # the element's mean dilatation rate
        if st.dt_prev is not None:                  # the first step has no stress yet
            update_stress(m, st, D, st.dt_prev, dV, rho_e)
        ptot, J = pressure(m, st, Vel, Le, rho_e, trDbar)
        fint = internal_force(m, st.s, ptot, dNr, dNz, rg, dV)
        dt_new = time_step(m, Le, trDbar, rho_e, args.cfl)
        dt_new = min(dt_new, bar['tend'] - st.t + 1e-15)
        dtavg = dt_new if st.dt_prev is None else 0.5 * (st.dt_prev + dt_new)
        vold = st.v.copy()
        vn = st.v + dtavg * (-fint / m.mass[:, None])
        vn[m.axis, 0] = 0.0
        if args.column:
            vn[m.top, 1] = -args.vcol * min(st.t / args.ramp, 1.0)
        hit, fc = anvil(m, x, vn, dt_new, dtavg)
        st.Wc += (fc * 0.5 * (vold[hit, 1] + vn[hit, 1])).sum() * dtavg
        st.v = vn
        st.x = x + dt_new * vn
        st.x[hit, 1] = 0.0
        st.t += dt_new; st.step += 1
        st.dt_prev = dt_new
        if st.step % args.every == 0 or st.t >= bar['tend']:
            rec = energy_record(m, st, st.x, vold, fint, J, fc.sum())
            hist.append(rec)
            if st.step % (args.every * args.pevery) == 0:
                print('t=%7.2f us KE/KE0=%.4f L=%.3f mm Dface=%.3f epmax=%.3f Tmax=%.0f err=%+.2e dt=%.2e' % (
                    st.t * 1e6, rec['KE'] / max(m.KE0, 1e-30), rec['L'] * 1e3, rec['Dface'] * 1e3,
                    rec['epmax'], rec['Tmax'], rec['err'], dt_new), flush=True)
        if args.stop_ke and hist and hist[-1]['KE'] < args.stop_ke * m.KE0 and st.t > 20e-6:
            print('# stop: KE < %g KE0 at t = %.2f us' % (args.stop_ke, st.t * 1e6)); break
    wall = time.time() - t0
    fin = hist[-1]
    KE0 = max(m.KE0, 1e-30)
    touching = st.x[:, 1] < 1e-9 * bar['L']
    res = dict(material=args.material, bar=args.bar, nr=m.nr, nz=m.nz, ne=m.ne, C=m.C, visc=args.visc,
               rate=args.rate, integ=args.integ, cfl=args.cfl, v0=bar['v0'], tend=st.t, steps=st.step,
               wall_s=wall, L_f=fin['L'], D_face=fin['Dface'],
               D_touch=2 * st.x[touching, 0].max() if touching.any() else 0.0, D_max=fin['Dmax'],
               KE_frac=fin['KE'] / KE0, energy_err=fin['err'], contact_loss_frac=-fin['Wc'] / KE0,
               visc_frac=fin['Wq'] / KE0, Wp_frac=fin['Wp'] / KE0, epmax=fin['epmax'], Tmax=fin['Tmax'],
               max_abs_err=max(abs(h['err']) for h in hist))
    print('RESULT ' + json.dumps(res), flush=True)
    if args.hist:
        np.save(args.hist, dict(hist=hist, x=st.x, conn=m.conn, ep=st.ep, T=st.T, res=res), allow_pickle=True)
    return res, hist


def check_elastic(args):
    """The elastic rebound of a 5 m/s bar (default: --v0 5 --tend 30e-6
    --every 1): between the radial ring-up after the impact and the return
    of the release wave from the rear (from 0.15 to 0.85 of 2 L / c_bar)
    the face carries the one-dimensional stress rho c_bar v; it must be
    within 1 %, and the energy balance within 2e-3 over the run.  At 16
    elements across by default: what the balance loses is the kinematic
    anvil's, first order in the element size (copper: 4.6e-3, 2.4e-3,
    1.2e-3 at 4, 8, 16 across; the stress is within 0.5 % at each)."""
    args.elastic = True
    args.v0 = 5.0 if args.v0 is None else args.v0
    args.tend = 30e-6 if args.tend is None else args.tend
    args.every = 1
    args.nr = 16 if args.nr is None else args.nr
    res, hist = run(args)
    mat = read_material(args.file, args.material)
    R = args.R or BARS[args.bar]['R']; L = args.L or BARS[args.bar]['L']
    cbar = np.sqrt(mat['E'] / mat['rho'])
    sig1d = mat['rho'] * cbar * args.v0
    t = np.array([h['t'] for h in hist]); Fc = np.array([h['Fc'] for h in hist])
    t2 = 2 * L / cbar
    win = (t >= 0.15 * t2) & (t < 0.85 * t2)
    sig = Fc[win].mean() / (np.pi * R ** 2)
    es = abs(sig / sig1d - 1); ee = res['max_abs_err']
    print('face stress %.1f MPa (mean from %.2f to %.2f us) vs rho c_bar v = %.1f MPa: %.2f %% (tolerance 1 %%)'
          % (sig / 1e6, 0.15 * t2 * 1e6, 0.85 * t2 * 1e6, sig1d / 1e6, 100 * es))
    print('energy balance: largest departure %.2e of the kinetic energy (tolerance 2e-3)' % ee)
    passed = int(es <= 0.01) + int(ee <= 2e-3)
    print('%d passed, %d failed' % (passed, 2 - passed))
    return passed == 2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument('--material', default='ofhc_copper_jc', help='entry of --file (needs johnson_cook)')
    ap.add_argument('--file', default=os.path.normpath(os.path.join(here, '..', 'potentials', 'plasticity.nospd')),
                    help='material file (default: the repository\'s potentials/plasticity.nospd)')
    ap.add_argument('--bar', default='copper', choices=sorted(BARS), help='R, L, v0 and end time of the deck')
    ap.add_argument('--nr', type=int, default=None,
                    help='elements across the radius (default 8, 16 with --check-elastic)')
    ap.add_argument('--nz', type=int, default=0, help='elements along the bar (default: square elements)')
    ap.add_argument('--R', type=float); ap.add_argument('--L', type=float)
    ap.add_argument('--v0', type=float); ap.add_argument('--tend', type=float)
    ap.add_argument('--C', type=float, help='replace the rate constant C')
    ap.add_argument('--cfl', type=float, default=0.3)
    ap.add_argument('--visc', type=int, default=1, help='bulk viscosity on (1) or off (0)')
    ap.add_argument('--rate', default='plastic', choices=['plastic', 'total'])
    ap.add_argument('--integ', default='mdil', choices=['mdil', 'full'])
    ap.add_argument('--elastic', action='store_true', help='no plasticity')
    ap.add_argument('--noheat', action='store_true', help='no adiabatic heating')
    ap.add_argument('--column', action='store_true', help='quasi-static column: the top row pushed down')
    ap.add_argument('--vcol', type=float, default=10.0, help='column: top speed (m/s)')
    ap.add_argument('--ramp', type=float, default=20e-6, help='column: time to reach it (s)')
    ap.add_argument('--every', type=int, default=20, help='steps between energy records')
    ap.add_argument('--pevery', type=int, default=50, help='records between printed lines')
    ap.add_argument('--stop-ke', '--stop_ke', dest='stop_ke', type=float, default=0.0,
                    help='end once the kinetic energy is below this fraction of the start (after 20 us)')
    ap.add_argument('--hist', default='', help='save the records and final state (.npy)')
    ap.add_argument('--check-elastic', action='store_true',
                    help='the elastic 5 m/s bar against rho c_bar v; exit 1 on a failure')
    args = ap.parse_args()
    if args.check_elastic:
        sys.exit(0 if check_elastic(args) else 1)
    run(args)


if __name__ == '__main__':
    main()
