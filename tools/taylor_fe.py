#!/usr/bin/python3
"""Axisymmetric explicit updated-Lagrangian FE for Taylor impact (numpy only).

An independent continuum reference for examples/taylor_bar: the same bar,
anvil and Johnson-Cook constants (read from potentials/plasticity.nospd)
in a standard finite-element model, so that the peridynamic bar's length
and footprint can be held against a converged continuum solution with the
same constants rather than only against the experiment.  Limits: a
hypoelastic (Jaumann) stress update with a logarithmic pressure, a
frictionless kinematic anvil, no failure.

    /usr/bin/python3 tools/taylor_fe.py --material ofhc_copper_jc --bar copper --nr 8
    /usr/bin/python3 tools/taylor_fe.py --material steel_42crmo4_jc --bar 42crmo4 --nr 8

prints progress lines and one line "RESULT {json}" (L_f, D_face in m).

Written from the equations (Belytschko, Liu & Moran, "Nonlinear finite elements
for continua and structures", ch. 4-6; Wilkins' HEMP for the axisymmetric
hoop term and artificial viscosity).

* 4-node bilinear quads in (r, z), 2x2 Gauss points, mean-dilatation
  (Nagtegaal / B-bar): the deviatoric stress lives at the 4 Gauss points,
  the pressure is constant per element, computed from the element volume
  (p = -K ln(V/V0)); the nodal forces f = int B^T sigma dV with
  sigma = s_gp - (p + q) I are then exactly power-conjugate to the
  element-mean dilatation.  No hourglass modes (full 2x2 for the deviator).
  Option --integ full: pressure per Gauss point from its own tr D (locks).
* Hypoelastic-plastic: D and W from the nodal velocities v^{n-1/2} on the
  current configuration x^n, hoop rate v_r/r, Jaumann rate on the deviator,
  radial return (backward Euler) for J2 with Johnson-Cook flow stress.
  Rate term: equivalent plastic strain rate dEps/dt solved implicitly in the
  return (--rate plastic, default) or the total equivalent deviatoric rate
  sqrt(2/3)|dev D| (--rate total, as the peridynamic code does).
  Adiabatic heating dT = beta sigma_y dEps / (rho c_p).
* Lumped (row-sum, 2 pi r weighted) mass; central difference; dt = cfl * L_e
  / (Q + sqrt(Q^2 + c^2)), L_e = A / longest edge, recomputed every step.
* Rigid frictionless anvil z = 0 by kinematic constraint (v_z clipped so that
  z >= 0; nodes slide radially and may separate).  Axis nodes v_r = 0.
* Optional bulk viscosity q = rho L (b1 c |trD| + b2^2 L trD^2), trD < 0.
"""
import argparse, json, os, sys, time
import numpy as np

BARS = {'copper': dict(R=3.81e-3, L=25.4e-3, v0=190., tend=80e-6),     # in.taylor_bar
        '42crmo4': dict(R=3.2e-3, L=32.4e-3, v0=287., tend=80e-6)}   # in.taylor_bar_42crmo4


def read_material(path, name):
    """E, nu, rho and the johnson_cook / heat constants of one entry of a
    PERI-NOSPD material file (name E nu rho G0 keywords...)."""
    for line in open(path):
        words = line.split('#', 1)[0].split()
        if not words or words[0] != name:
            continue
        mat = dict(E=float(words[1]), nu=float(words[2]), rho=float(words[3]), beta=0.0, cp=1.0)
        if 'johnson_cook' not in words:
            sys.exit('taylor_fe.py: entry %s of %s has no johnson_cook flow law' % (name, path))
        k = words.index('johnson_cook')
        keys = ('A', 'B', 'n', 'C', 'rate0', 'm', 'Tref', 'Tmelt')
        mat.update(zip(keys, map(float, words[k + 1:k + 9])))
        if 'heat' in words:
            k = words.index('heat')
            mat['cp'], mat['beta'] = float(words[k + 1]), float(words[k + 2])
        return mat
    sys.exit('taylor_fe.py: no entry %s in %s' % (name, path))


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
    p = x[conn]                                   # (ne, 4, 2)
    e = np.roll(p, -1, axis=1) - p
    le = np.sqrt((e ** 2).sum(-1))
    d1 = p[:, 2] - p[:, 0]; d2 = p[:, 3] - p[:, 1]
    A = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    return A / le.max(1)


def jc_flow(mat, ep, rate, T, C):
    Ts = np.clip((T - mat['Tref']) / (mat['Tmelt'] - mat['Tref']), 0.0, 1.0)
    hard = mat['A'] + mat['B'] * np.maximum(ep, 0.0) ** mat['n']
    rt = 1.0 + C * np.log(np.maximum(rate / mat['rate0'], 1.0))
    return hard * rt * (1.0 - Ts ** mat['m']), hard, rt, (1.0 - Ts ** mat['m'])


def radial_return(mat, C, qtr, ep, T, dt, G, rate_mode, rate_tot):
    """Solve qtr - 3G d = sy(ep + d, rate, T) for d >= 0 (vectorized)."""
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


def run(args):
    mat = read_material(args.file, args.material); bar = dict(BARS[args.bar])
    if args.v0 is not None: bar['v0'] = args.v0
    if args.tend is not None: bar['tend'] = args.tend
    if args.R is not None: bar['R'] = args.R
    if args.L is not None: bar['L'] = args.L
    C = mat['C'] if args.C is None else args.C
    E, nu, rho0 = mat['E'], mat['nu'], mat['rho']
    G = E / (2 * (1 + nu)); K = E / (3 * (1 - 2 * nu))
    cd0 = np.sqrt((K + 4 * G / 3) / rho0)
    R, L, v0 = bar['R'], bar['L'], bar['v0']
    nr = args.nr; nz = args.nz or int(round(nr * L / R))
    x, conn = mesh(R, L, nr, nz)
    nn, ne = len(x), len(conn)
    cflat = conn.ravel()
    dNr, dNz, rg, dV, det = geometry(x, conn)
    V0e = dV.sum(1)
    # lumped mass, row sum of the 2 pi r weighted consistent mass
    mass = np.bincount(cflat, (rho0 * dV[:, :, None] * N_gp[None]).sum(1).ravel(), nn)
    m2 = mass[:, None]
    v = np.zeros_like(x); v[:, 1] = -v0
    if args.column:                               # quasi-static column test
        v[:, 1] = 0.0
    axis = x[:, 0] < 1e-12 * R
    top = x[:, 1] > L * (1 - 1e-9)
    face0 = x[:, 1] < 1e-12 * L
    s = np.zeros((ne, 4, 4))                      # deviator rr, zz, tt, rz at gp
    pgp = np.zeros((ne, 4))                       # pressure per gp (integ full)
    ep = np.zeros((ne, 4)); T = np.full((ne, 4), mat['Tref'])
    elastic = args.elastic
    heat = not args.noheat
    KE0 = 0.5 * (mass * (v ** 2).sum(1)).sum()
    Wp = 0.0; Wq = 0.0; Wc = 0.0
    t = 0.0; step = 0
    dt_prev = None
    f_prev = None
    hist = []
    b1, b2 = (0.06, 1.2) if args.visc else (0.0, 0.0)
    t0 = time.time()
    Fc_hist = []
    col_hist = []
    q = np.zeros(ne)
    while t < bar['tend']:
        dNr, dNz, rg, dV, det = geometry(x, conn)
        if (det <= 0).any():
            print('# negative Jacobian at t=%.3e us, step %d' % (t * 1e6, step)); break
        Vel = dV.sum(1)
        Le = char_length(x, conn)
        rho_e = rho0 * V0e / Vel
        # ---- rate of deformation from v^{n-1/2} on x^n
        vr = v[conn, 0]; vz = v[conn, 1]           # (ne,4)
        Drr = np.einsum('egi,ei->eg', dNr, vr)
        Dzz = np.einsum('egi,ei->eg', dNz, vz)
        dvrdz = np.einsum('egi,ei->eg', dNz, vr)
        dvzdr = np.einsum('egi,ei->eg', dNr, vz)
        Drz = 0.5 * (dvrdz + dvzdr); Wrz = 0.5 * (dvrdz - dvzdr)
        Dtt = (vr @ N_gp.T) / rg
        trD = Drr + Dzz + Dtt
        trDbar = (trD * dV).sum(1) / Vel
        if dt_prev is not None:
            h = dt_prev
            # Jaumann rotation of the deviator (W = [[0, w],[-w, 0]] in r,z)
            dw = Wrz * h
            srr, szz, stt, srz = s[..., 0], s[..., 1], s[..., 2], s[..., 3]
            rrr = srr + 2 * dw * srz
            rzz = szz - 2 * dw * srz
            rrz = srz + dw * (szz - srr)
            s_old = s.copy()
            tr3 = trD / 3.0
            s = np.stack([rrr + 2 * G * h * (Drr - tr3), rzz + 2 * G * h * (Dzz - tr3),
                          stt + 2 * G * h * (Dtt - tr3), rrz + 2 * G * h * Drz], -1)
            if not elastic:
                nrm = np.sqrt(s[..., 0] ** 2 + s[..., 1] ** 2 + s[..., 2] ** 2 + 2 * s[..., 3] ** 2)
                qtr = np.sqrt(1.5) * nrm
                rate_tot = np.sqrt(2.0 / 3.0) * np.sqrt((Drr - tr3) ** 2 + (Dzz - tr3) ** 2 + (Dtt - tr3) ** 2
                                                        + 2 * Drz ** 2)
                d, sy, yl = radial_return(mat, C, qtr.ravel(), ep.ravel(), T.ravel(), h, G,
                                          args.rate, rate_tot.ravel())
                d = d.reshape(ep.shape); sy = sy.reshape(ep.shape); yl = yl.reshape(ep.shape)
                fac = np.where(yl, sy / np.maximum(qtr, 1e-300), 1.0)
                s = s * fac[..., None]
                ep = ep + d
                dWp = sy * d                       # plastic work per current volume
                Wp += (dWp * dV).sum()
                if heat:
                    T = T + mat['beta'] * dWp / (rho_e[:, None] * mat['cp'])
            if args.integ == 'full':
                pgp = pgp - K * trD * h
        # pressure (element constant, total form) and bulk viscosity
        J = Vel / V0e
        p = -K * np.log(J)
        if args.visc:
            comp = np.minimum(trDbar, 0.0)
            q = rho_e * Le * (b1 * cd0 * (-comp) + b2 ** 2 * Le * comp ** 2)
            if dt_prev is not None:
                Wq += -(q * trDbar * Vel).sum() * dt_prev
        ptot = (pgp if args.integ == 'full' else p[:, None]) + q[:, None]
        srr_t = s[..., 0] - ptot; szz_t = s[..., 1] - ptot; stt_t = s[..., 2] - ptot; srz_t = s[..., 3]
        fr = (np.einsum('egi,eg->ei', dNr, srr_t * dV) + np.einsum('egi,eg->ei', dNz, srz_t * dV)
              + (stt_t * dV / rg) @ N_gp)
        fz = np.einsum('egi,eg->ei', dNr, srz_t * dV) + np.einsum('egi,eg->ei', dNz, szz_t * dV)
        fint = np.stack([np.bincount(cflat, fr.ravel(), nn), np.bincount(cflat, fz.ravel(), nn)], 1)
        # ---- time step
        Qv = b1 * cd0 + b2 ** 2 * Le * np.abs(np.minimum(trDbar, 0.0))
        cel = cd0 * np.sqrt(rho0 / rho_e)
        dt_new = args.cfl * (Le / (Qv + np.sqrt(Qv ** 2 + cel ** 2))).min()
        dt_new = min(dt_new, bar['tend'] - t + 1e-15)
        dtavg = dt_new if dt_prev is None else 0.5 * (dt_prev + dt_new)
        a = -fint / m2
        vold = v.copy()
        vn = v + dtavg * a
        vn[axis, 0] = 0.0
        if args.column:
            ramp = min(t / args.ramp, 1.0)
            vn[top, 0] = vn[top, 0]
            vn[top, 1] = -args.vcol * ramp
        # anvil: kinematic, frictionless
        ztr = x[:, 1] + dt_new * vn[:, 1]
        hit = ztr < 0.0
        vz_c = -x[hit, 1] / dt_new
        fc = mass[hit] * (vz_c - vn[hit, 1]) / dtavg
        vn[hit, 1] = vz_c
        Wc += (fc * 0.5 * (vold[hit, 1] + vn[hit, 1])).sum() * dtavg
        Fc = fc.sum()
        v = vn
        x = x + dt_new * v
        x[hit, 1] = 0.0
        t += dt_new; step += 1
        dt_prev = dt_new
        if step % args.every == 0 or t >= bar['tend']:
            KE = 0.5 * (mass * ((0.5 * (vold + v)) ** 2).sum(1)).sum()   # v^n, integer step
            Eel_dev = ((s[..., 0] ** 2 + s[..., 1] ** 2 + s[..., 2] ** 2 + 2 * s[..., 3] ** 2) / (4 * G) * dV).sum()
            if args.integ == 'full':
                Eel_vol = ((pgp ** 2) / (2 * K) * dV).sum()
            else:
                Eel_vol = (K * V0e * (J * np.log(J) - J + 1)).sum()
            Efl = KE + Eel_dev + Eel_vol + Wp + Wq - Wc
            Lz = x[:, 1].max() - x[:, 1].min()
            rec = dict(t=t, KE=KE, Eel=Eel_dev + Eel_vol, Wp=Wp, Wq=Wq, Wc=Wc, err=(Efl - KE0) / max(KE0, 1e-30),
                       L=Lz, Dface=2 * x[face0, 0].max(), Dmax=2 * x[:, 0].max(), epmax=ep.max(), Tmax=T.max(),
                       dt=dt_new, Fc=Fc, vzmean=(mass * v[:, 1]).sum() / mass.sum())
            if args.column:
                # axial force on the anvil; current area from the mid-height radius
                zc = x[:, 1]; Lc = zc.max()
                mid = np.argmin(np.abs(zc - 0.5 * Lc) + 1e3 * (x[:, 0] < x[:, 0].max() * 0.999))
                Rm = x[:, 0].max()
                rec.update(Lc=Lc, Rmax=Rm, Fc=Fc, Fi_top=fint[top, 1].sum())
            hist.append(rec)
            if step % (args.every * args.pevery) == 0:
                print('t=%7.2f us KE/KE0=%.4f L=%.3f mm Dface=%.3f epmax=%.3f Tmax=%.0f err=%+.2e dt=%.2e' % (
                    t * 1e6, KE / max(KE0, 1e-30), Lz * 1e3, rec['Dface'] * 1e3, rec['epmax'], rec['Tmax'], rec['err'], dt_new),
                    flush=True)
        if args.stop_ke and hist and hist[-1]['KE'] < args.stop_ke * KE0 and t > 20e-6:
            print('# stop: KE < %g KE0 at t = %.2f us' % (args.stop_ke, t * 1e6)); break
    wall = time.time() - t0
    fin = hist[-1]
    touching = x[:, 1] < 1e-9 * L
    Dtouch = 2 * x[touching, 0].max() if touching.any() else 0.0
    res = dict(material=args.material, bar=args.bar, nr=nr, nz=nz, ne=ne, C=C, visc=args.visc, rate=args.rate, integ=args.integ,
               cfl=args.cfl, v0=v0, tend=t, steps=step, wall_s=wall, L_f=fin['L'], D_face=fin['Dface'],
               D_touch=Dtouch, D_max=fin['Dmax'], KE_frac=fin['KE'] / max(KE0, 1e-30), energy_err=fin['err'],
               contact_loss_frac=-fin['Wc'] / max(KE0, 1e-30), visc_frac=fin['Wq'] / max(KE0, 1e-30),
               Wp_frac=fin['Wp'] / max(KE0, 1e-30), epmax=fin['epmax'], Tmax=fin['Tmax'],
               max_abs_err=max(abs(h['err']) for h in hist))
    print('RESULT ' + json.dumps(res), flush=True)
    if args.hist:
        np.save(args.hist, dict(hist=hist, x=x, conn=conn, ep=ep, T=T, res=res), allow_pickle=True)
    return res, hist


if __name__ == '__main__':
    ap = argparse.ArgumentParser()
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument('--material', default='ofhc_copper_jc', help='entry of --file')
    ap.add_argument('--file', default=os.path.join(here, '..', 'potentials', 'plasticity.nospd'))
    ap.add_argument('--bar', default='copper', choices=sorted(BARS))
    ap.add_argument('--nr', type=int, default=8)
    ap.add_argument('--nz', type=int, default=0)
    ap.add_argument('--R', type=float); ap.add_argument('--L', type=float)
    ap.add_argument('--v0', type=float); ap.add_argument('--tend', type=float)
    ap.add_argument('--C', type=float)
    ap.add_argument('--cfl', type=float, default=0.3)
    ap.add_argument('--visc', type=int, default=1)
    ap.add_argument('--rate', default='plastic', choices=['plastic', 'total'])
    ap.add_argument('--integ', default='mdil', choices=['mdil', 'full'])
    ap.add_argument('--elastic', action='store_true')
    ap.add_argument('--noheat', action='store_true')
    ap.add_argument('--column', action='store_true')
    ap.add_argument('--vcol', type=float, default=10.0)
    ap.add_argument('--ramp', type=float, default=20e-6)
    ap.add_argument('--every', type=int, default=20)
    ap.add_argument('--pevery', type=int, default=50)
    ap.add_argument('--stop_ke', type=float, default=0.0)
    ap.add_argument('--hist', default='')
    run(ap.parse_args())
