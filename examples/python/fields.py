#!/usr/bin/python3
"""PERI-NOSPD from Python: run a scene through LAMMPS's Python module, pull the
deformation gradient, the Cauchy stress and the damage into numpy, and plot.

A steel plate (2D, plane stress) with a pre-crack is given a uniform stretch
(eps_yy = 1e-3 across the crack, eps_xx = -3e-4).  Correspondence reproduces
a uniform deformation exactly, so every intact point first reports
F = I + eps and the plane-stress Hooke stress, and the crack faces carry the
damage.  Then the top and bottom rows are held and the plate relaxed
(minimize): the crack opens and the stress gathers at its tip.  The pictures
show the relaxed fields.

usage: fields.py [--out DIR] [--check]
  Needs LAMMPS's Python module and library (see the README, "Python"):
    PYTHONPATH=$(bash cmake/lammps.sh print-src)/python
    LD_LIBRARY_PATH=$(bash cmake/lammps.sh print-dir)
  and the plugin, through LAMMPS_PLUGIN_PATH or --plugin FILE.
  --check compares the fields with the closed form and exits 1 on a mismatch.
"""
import argparse
import os
import sys

import numpy as np
from lammps import LMP_STYLE_ATOM, LMP_TYPE_ARRAY, LMP_TYPE_VECTOR, lammps

E, NU, RHO = 200e9, 0.3, 7850.0
DX, NX, NY = 0.001, 40, 20
EXX, EYY = -3.0e-4, 1.0e-3

DECK = f"""
units           si
dimension       2
boundary        s s p
atom_style      peri
atom_modify     map array
lattice         sq {DX}
region          box block 0 {NX} 0 {NY} -0.5 0.5
create_box      1 box
create_atoms    1 box
set             group all density {RHO}
set             group all volume {DX * DX}
pair_style      peri/nospd strain small plane stress
pair_coeff      * * {E} {NU} {3.015 * DX}
# a crack from the left edge to the middle, cut before the first force call
fix             crack all nospd/damage none precrack 0.0 {NY * DX / 2 - DX / 2} {NX * DX / 2} {NY * DX / 2 - DX / 2}
compute         fields all nospd/atom F stress
compute         damage all damage/atom
"""


def run(plugin):
    lmp = lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    if plugin:
        lmp.command(f"plugin load {plugin}")
    lmp.commands_string(DECK)
    lmp.command("run 0")    # families, K, the pre-crack
    # the uniform stretch, applied to the reference positions
    nlocal = lmp.extract_global("nlocal")
    x = lmp.numpy.extract_atom("x", nelem=nlocal)
    x0 = lmp.numpy.extract_atom("x0", nelem=nlocal)
    x[:, 0] = x0[:, 0] * (1.0 + EXX)
    x[:, 1] = x0[:, 1] * (1.0 + EYY)
    lmp.command("run 0")
    uniform = pull(lmp, nlocal)
    # hold the top and bottom rows where the stretch put them, relax the rest
    lmp.commands_string(f"""
region          rows block INF INF {0.5} {NY - 0.5} INF INF units lattice side out
group           rows region rows
fix             hold rows setforce 0.0 0.0 0.0
min_modify      dmax {0.01 * DX}
minimize        0.0 1e-6 2000 20000
""")
    relaxed = pull(lmp, nlocal)
    lmp.close()
    return uniform, relaxed


def pull(lmp, nlocal):
    """reference positions, F (3x3), Cauchy stress (6) and damage, as numpy copies"""
    fields = lmp.numpy.extract_compute("fields", LMP_STYLE_ATOM, LMP_TYPE_ARRAY).copy()
    damage = lmp.numpy.extract_compute("damage", LMP_STYLE_ATOM, LMP_TYPE_VECTOR).copy()
    pos = lmp.numpy.extract_atom("x0", nelem=nlocal)[:, :2].copy()
    return pos, fields[:, :9].reshape(-1, 3, 3), fields[:, 9:15], damage


def check(uniform, relaxed):
    """Under the uniform stretch F and the stress are the closed form at every
    intact point; the crack faces are damaged, and only they.  Relaxed, the
    crack tip carries more than the far field and the crack faces less."""
    pos, F, sigma, damage = uniform
    intact = damage == 0.0
    # plane stress: the plate thins by eps_zz = -nu/(1-nu) (eps_xx + eps_yy)
    Fexp = np.diag([1.0 + EXX, 1.0 + EYY, 1.0 - NU / (1 - NU) * (EXX + EYY)])
    sxx = E / (1 - NU * NU) * (EXX + NU * EYY)
    syy = E / (1 - NU * NU) * (EYY + NU * EXX)
    errF = np.abs(F[intact] - Fexp).max()
    errS = max(np.abs(sigma[intact, 0] - sxx).max(), np.abs(sigma[intact, 1] - syy).max(),
               np.abs(sigma[intact, 3]).max()) / abs(syy)
    ycrack = NY * DX / 2 - DX / 2
    faces = (np.abs(pos[:, 1] - ycrack) < DX) & (pos[:, 0] < NX * DX / 2 - 3.1 * DX)
    far = np.abs(pos[:, 1] - ycrack) > 3.1 * DX
    rpos, _, rsig, _ = relaxed
    d_tip = np.hypot(rpos[:, 0] - NX * DX / 2, rpos[:, 1] - ycrack)
    tip = rsig[d_tip < 1.6 * DX, 1].max()
    remote = np.median(rsig[rpos[:, 0] > NX * DX - 3 * DX, 1])
    face = np.abs(rsig[(np.abs(rpos[:, 1] - ycrack) < DX) & (rpos[:, 0] < 0.3 * NX * DX), 1]).mean()
    ok = True
    for name, good in [
        (f"F exact at {intact.sum()} intact points (max error {errF:.2e})", errF < 1e-12),
        (f"plane-stress Hooke stress there (relative error {errS:.2e})", errS < 1e-10),
        (f"{faces.sum()} crack-face points damaged (min {damage[faces].min():.3f})",
         faces.sum() > 0 and damage[faces].min() > 0.1),
        ("no damage three horizons from the crack line", np.all(damage[far] == 0.0)),
        (f"relaxed: crack-tip sigma_yy {tip / 1e6:.0f} MPa > 1.5 x far field {remote / 1e6:.0f} MPa",
         tip > 1.5 * remote),
        (f"relaxed: crack faces unloaded (sigma_yy {face / 1e6:.1f} MPa < 0.2 x far field)",
         face < 0.2 * remote),
    ]:
        print(("ok   " if good else "FAIL ") + name)
        ok &= bool(good)
    return ok


def plot(pos, F, sigma, damage, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 1, figsize=(7, 9), sharex=True)
    for ax, values, label in [(axes[0], F[:, 1, 1] - 1.0, "F_yy - 1"),
                              (axes[1], sigma[:, 1] / 1e6, "sigma_yy (MPa)"),
                              (axes[2], damage, "damage")]:
        sc = ax.scatter(pos[:, 0] * 1e3, pos[:, 1] * 1e3, c=values, s=18, marker="s",
                        cmap="viridis")
        fig.colorbar(sc, ax=ax, label=label)
        ax.set_aspect("equal")
        ax.set_ylabel("y (mm)")
    axes[2].set_xlabel("x (mm)")
    fig.suptitle("PERI-NOSPD fields in numpy: pre-cracked plate, stretched and relaxed")
    fig.tight_layout()
    path = os.path.join(out, "fields.png")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=".", help="folder for fields.png and fields.npz")
    ap.add_argument("--plugin", default=None, help="nospdplugin.so, if LAMMPS_PLUGIN_PATH is unset")
    ap.add_argument("--check", action="store_true", help="compare with the closed form")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    uniform, relaxed = run(args.plugin)
    pos, F, sigma, damage = relaxed
    np.savez(os.path.join(args.out, "fields.npz"), x0=pos, F=F, stress=sigma, damage=damage)
    plot(pos, F, sigma, damage, args.out)
    if args.check and not check(uniform, relaxed):
        sys.exit(1)


if __name__ == "__main__":
    main()
