"""The models the chart compares, and how each maps a material (E, nu) and a
horizon onto its own pair_style / pair_coeff lines.

peri/pmb (bond-based, Silling & Askari 2005): micromodulus
    c = 18 K / (pi delta^4)  (3D),
a bond-based model has nu = 1/4 in 3D whatever c is; we match Young's
modulus, K = E / (3 (1 - 2 nu)) with nu = 1/4, i.e. K = 2E/3.
peri/lps (ordinary state-based, Silling et al. 2007): bulk modulus
    K = E / (3 (1 - 2 nu)) and shear modulus G = E / (2 (1 + nu)).
Both are 3D only in LAMMPS (their constants and weighted volumes are the 3D
formulas; LAMMPS has no 2D branch in the PERI package), so they appear in the
3D scenes only.  Their critical stretch is set to 0.25, far beyond any strain
in these scenes, so no bond breaks (except in the damage scene).

peri/nospd (this package): pair_coeff E nu delta; in 2D plane stress with
the thickness equal to the spacing (point volumes are dx^3).
peri/nospd/hs (bond-associated, this package; when the plugin has it): same
coefficients, keyword form I or II, its own default ratio.
"""
import math

# key, label, pair style keyword string, potential?, 3D-only?
MODELS = [
    ("pmb", "peri/pmb", "peri/pmb", True, True),
    ("lps", "peri/lps", "peri/lps", True, True),
    ("none", "nospd none", "peri/nospd strain small stabilization none", True, False),
    ("silling", "nospd silling 0.5", "peri/nospd strain small stabilization silling 0.5", True, False),
    ("hourglass", "nospd hourglass 0.2", "peri/nospd strain small stabilization hourglass 0.2", False, False),
    ("wan", "nospd wan", "peri/nospd strain small stabilization wan", True, False),
    ("finite", "nospd finite+silling", "peri/nospd strain finite stabilization silling 0.5", True, False),
    ("hs1", "nospd/hs form I", "peri/nospd/hs form I", False, False),
    ("hs2", "nospd/hs form II", "peri/nospd/hs form II", True, False),
]
KEYS = [m[0] for m in MODELS]
LABEL = {m[0]: m[1] for m in MODELS}
STYLE = {m[0]: m[2] for m in MODELS}
POTENTIAL = {m[0]: m[3] for m in MODELS}
ONLY3D = {m[0]: m[4] for m in MODELS}
# does the energy LAMMPS reports belong to the forces?  peri/lps: no.  Its
# pair_peri_lps.cpp tallies the deviatoric energy with a factor 1/4 instead of
# 1/2 (0.5*evdwl through ev_tally(i,i,...)), so the reported energy is not the
# potential of its forces: its NVE energy wanders by tens of per cent at any
# time step and CG line searches stop early.  It is minimized by FIRE (forces
# only) like the styles that are not potentials.
ENERGY_OK = dict(POTENTIAL, lps=False)
# what a static scene uses to find equilibrium
SOLVER = {k: ("cg" if ENERGY_OK[k] else "fire") for k in KEYS}
COLOR = {"pmb": "#7f7f7f", "lps": "#000000", "none": "#d62728", "silling": "#1f77b4",
         "hourglass": "#ff7f0e", "wan": "#2ca02c", "finite": "#17becf", "hs1": "#9467bd",
         "hs2": "#e377c2"}
MARKER = {"pmb": "v", "lps": "^", "none": "x", "silling": "o", "hourglass": "s", "wan": "D",
          "finite": "P", "hs1": "<", "hs2": ">"}

S00 = 0.25       # PERI critical stretch: never reached in the elastic scenes


def register(key, label, style, potential, only3d=False):
    """a model beyond MODELS (the scene suite's settings), known to every
    table here; a static scene finds its equilibrium by CG if it is a
    potential, else by FIRE"""
    LABEL[key], STYLE[key], POTENTIAL[key], ONLY3D[key] = label, style, potential, only3d
    ENERGY_OK[key] = potential
    SOLVER[key] = "cg" if potential else "fire"


def model_nu(key, nu):
    """the Poisson ratio a model actually has"""
    return 0.25 if key == "pmb" else nu


def pair_lines(key, E, nu, delta, dim, dx, extra=""):
    """(pstyle, pcoeff) strings for the LAMMPS input"""
    if key == "pmb":
        K = 2.0 * E / 3.0
        c = 18.0 * K / (math.pi * delta ** 4)
        return "peri/pmb", f"* * {c:.10g} {delta:.10g} {S00} 0.0"
    if key == "lps":
        K = E / (3.0 * (1.0 - 2.0 * nu))
        G = E / (2.0 * (1.0 + nu))
        return "peri/lps", f"* * {K:.10g} {G:.10g} {delta:.10g} {S00} 0.0"
    style = STYLE[key]
    if dim == 2:
        style += f" plane stress thickness {dx:.10g}"
    if extra:
        style += " " + extra
    return style, f"* * {E:.10g} {nu} {delta:.10g}"
