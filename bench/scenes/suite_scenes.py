"""The scenes of bench/scenes/run_suite.py: each runs one LAMMPS deck under
one setting at one level and returns (figure text, pass, wall seconds).

A setting is (name, style, stab, potential): the pair style with its form
keywords, the stabilization keywords, and whether the style is the gradient
of an energy (minimize by CG) or not (FIRE, or dynamics).  Levels: 0 is
the modest resolution (minutes on one core), 1 the finer one."""
import math
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'unittest', 'analytic'))
sys.path.insert(0, os.path.join(ROOT, 'bench', 'chart'))
sys.path.insert(0, os.path.join(ROOT, 'tools'))
from energy_balance import balance    # noqa: E402
import cylinder                       # noqa: E402

PY = sys.executable


def run(lmp, deck, work, variables, timeout=7200):
    """runs a deck in work; returns (error text or None, wall seconds)"""
    os.makedirs(work, exist_ok=True)
    cmd = [lmp, '-in', deck, '-log', 'log.lammps', '-screen', 'none']
    for k, v in variables.items():
        cmd += ['-var', k, str(v)]
    t0 = time.time()
    try:
        done = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=timeout)
        rc = done.returncode
    except subprocess.TimeoutExpired:
        rc = -9
    wall = time.time() - t0
    if rc == 0:
        return None, wall
    log = os.path.join(work, 'log.lammps')
    text = open(log).read() if os.path.exists(log) else ''
    errs = [l for l in text.splitlines() if l.startswith('ERROR')]
    if errs:
        msg = re.sub(r'^ERROR( on proc \d+)?: ', '', errs[-1])
        return 'stopped: ' + msg[:70], wall
    return 'stopped (rc %d%s)' % (rc, ', timeout' if rc == -9 else ''), wall


def tool(args, work):
    """runs a measuring script; its stdout"""
    done = subprocess.run([PY] + args, cwd=work, capture_output=True, text=True)
    return done.stdout + done.stderr


# -------------------------------------------------------------------------
def cylinder_scene(lmp, s, level, work):
    """thick cylinder, plane strain J2 (in.cylinder_lattice): plastic radius
    on each 15 deg ray and bore displacement against Hill, 3 %"""
    dx = (0.5e-3, 0.25e-3)[level]
    err, wall = run(lmp, os.path.join(HERE, 'in.cylinder_lattice'), work,
                    dict(dx=dx, style=s[1], stab=s[2], solver='cg' if s[3] else 'fire',
                         out='cyl.dump'))
    if err:
        return err, False, wall
    lines = open(os.path.join(work, 'cyl.dump')).read().splitlines()
    i = next(k for k, l in enumerate(lines) if l.startswith('ITEM: ATOMS'))
    cols = lines[i].split()[2:]
    rows = [dict(zip(cols, map(float, l.split()))) for l in lines[i + 1:]]
    worst, rays = 0.0, []
    for deg in range(0, 360, 15):
        rmax = None
        for v in rows:
            x0, y0 = v['f_ref[1]'], v['f_ref[2]']
            d = (math.degrees(math.atan2(y0, x0)) - deg + 180.0) % 360.0 - 180.0
            if abs(d) <= 7.5 and v['c_s[1]'] > 0.0:
                r = math.hypot(x0, y0)
                rmax = r if rmax is None else max(rmax, r)
        c = (rmax + 0.5 * dx) if rmax is not None else cylinder.A
        rays.append(c)
        worst = max(worst, abs(c - cylinder.C) / cylinder.C)
    inner = [v for v in rows if math.hypot(v['f_ref[1]'], v['f_ref[2]']) < cylinder.A + dx]
    ua, r_in = 0.0, 0.0
    for v in inner:
        r0 = math.hypot(v['f_ref[1]'], v['f_ref[2]'])
        ua += (v['x'] * v['f_ref[1]'] + v['y'] * v['f_ref[2]']) / r0 - r0
        r_in += r0
    ua, r_in = ua / len(inner), r_in / len(inner)
    eu = ua / cylinder.u_at(r_in) - 1.0
    text = 'c %.1f-%.1f mm (worst %.1f %%), u(a) %+.1f %%' % (
        min(rays) * 1e3, max(rays) * 1e3, 100 * worst, 100 * eu)
    return text, worst <= 0.03 and abs(eu) <= 0.03, wall


def _energy_scene(lmp, deck, variables, work):
    err, wall = run(lmp, os.path.join(HERE, deck), work, variables)
    if err:
        return err, False, wall
    created, dissipated, _ = balance(os.path.join(work, 'log.lammps'))
    if dissipated <= 0.0:    # the body ends with more energy than it got
        return 'gained energy (created %.3g, dissipated %.3g)' % (created, dissipated), False, wall
    ratio = created / dissipated
    return 'created %.2f %% of dissipated' % (100 * ratio), ratio <= 0.01, wall


def perforation_scene(lmp, s, level, work):
    """sphere through a 4340 plate, Johnson-Cook failure, contact, 600 m/s:
    energy created <= 1 % of the dissipated"""
    return _energy_scene(lmp, 'in.perforation_energy', dict(
        dx=(0.5e-3, 0.4e-3)[level], v0=600, th=10, style=s[1],
        settings='stabilization ' + s[2]), work)


def ball_scene(lmp, s, level, work):
    """steel ball shatters an aluminium plate at 200 m/s: energy created
    <= 1 % of what the broken bonds took"""
    return _energy_scene(lmp, 'in.ball_plate', dict(
        dx=(1e-3, 0.5e-3)[level], style=s[1], stab=s[2], th=50), work)


def taylor_scene(lmp, s, level, work):
    """OFHC copper Taylor bar at 190 m/s: length within 8 % and footprint
    within 10 % of the experiment (16.2 mm, 13.56 mm)"""
    dx = (0.762e-3, 0.508e-3)[level]
    err, wall = run(lmp, os.path.join(ROOT, 'examples', 'taylor_bar', 'in.taylor_bar'), work,
                    dict(dx=dx, style=s[1], stab=s[2], out='taylor'))
    if err:
        return err, False, wall
    last = sorted((f for f in os.listdir(work) if f.startswith('taylor.') and f.endswith('.dump')),
                  key=lambda f: int(f.split('.')[1]))[-1]
    out = tool([os.path.join(ROOT, 'tools', 'taylor_bar.py'), last, '--spacing', str(dx),
                '--l0', '25.4e-3', '--d0', '7.62e-3', '--check', '16.2e-3,13.56e-3,0.08,0.10'], work)
    lm = re.search(r'length ([\d.]+) vs [\d.]+ mm: ([-\d.]+) %', out)
    dm = re.search(r'diameter ([\d.]+) vs [\d.]+ mm: ([-\d.]+) %', out)
    if not (lm and dm):
        return 'no measure: ' + out.strip()[-60:], False, wall
    L, D = float(lm.group(1)), float(dm.group(1))
    text = 'L %.2f mm (%+.1f %%), D %.2f mm (%+.1f %%)' % (L, 100 * (L / 16.2 - 1),
                                                          D, 100 * (D / 13.56 - 1))
    return text, '2 passed' in out, wall


def _example(lmp, name, dx, s, work):
    """examples/NAME/in.NAME under setting s, without pictures"""
    return run(lmp, os.path.join(ROOT, 'examples', name, 'in.' + name), work,
               dict(dx=dx, style=s[1], stab=s[2], image='no'))


def kalthoff_scene(lmp, s, level, work):
    """Kalthoff-Winkler plate: crack angle 65-72 deg (the experiment ~70)"""
    err, wall = _example(lmp, 'kalthoff_winkler', (1e-3, 0.5e-3)[level], s, work)
    if err:
        return err, False, wall
    last = max((f for f in os.listdir(work) if f.startswith('dump.kalthoff_winkler.')),
               key=lambda f: int(f.rsplit('.', 1)[1]))
    out = tool([os.path.join(ROOT, 'tools', 'crack_angle.py'), last], work)
    m = re.search(r'mean crack angle ([\d.]+) deg', out)
    if not m:
        return 'no crack from the notch tips', False, wall
    ang = float(m.group(1))
    return 'angle %.1f deg' % ang, 65.0 <= ang <= 72.0, wall


def branching_scene(lmp, s, level, work):
    """soda-lime glass plate: the crack branches, mean tip speed < 0.6 c_R"""
    dx = (0.5e-3, 0.25e-3)[level]
    err, wall = _example(lmp, 'crack_branching', dx, s, work)
    if err:
        return err, False, wall
    log = open(os.path.join(work, 'log.lammps')).read()
    dt = float(re.search(r'^timestep\s+([\d.eE+-]+)', log, re.M).group(1))
    out = tool([os.path.join(ROOT, 'tools', 'crack_tip.py'), 'dump.crack_branching.*',
                '--timestep', repr(dt), '--spacing', repr(dx * 1e3)], work)
    v = re.search(r'mean tip speed \d+ m/s = ([\d.]+) c_R', out)
    b = re.search(r'branching: yes, first at x = ([\d.]+) mm', out)
    if not v:
        return 'crack did not run', False, wall
    speed = float(v.group(1))
    text = '%s, %.2f c_R' % ('branches at %s mm' % b.group(1) if b else 'no branch', speed)
    return text, bool(b) and speed < 0.6, wall


# -------------------------------------------------------------------------
# plate with a hole and wave speed: the jobs of bench/chart/chart.py, with a
# suite setting registered as a chart model
_FEM = {}


def _chart(s, work, lmp):
    import chart
    import models as M
    key = 'suite'
    M.register(key, s[0], '%s strain small stabilization %s' % (s[1], s[2]), s[3])
    R = chart.Runner(lmp, os.environ['LAMMPS_PLUGIN_PATH'], work)
    return chart, R, key


def plate_scene(lmp, s, level, work):
    """plate with a hole in tension, 2D plane stress: displacement field
    within one hole radius of the edge against CalculiX, 3 %"""
    import plate_fem
    chart, R, key = _chart(s, work, lmp)
    if 'field' not in _FEM:
        import shutil
        if shutil.which('ccx') is None:
            return 'no CalculiX (apt-get install calculix-ccx)', False, 0.0
        plate_fem.run(os.path.join(work, 'fem'), 'stress', 0.3, 48, 80)
        _FEM['field'] = {('stress', 0.3): plate_fem.FemField(os.path.join(work, 'fem', 'fem.npz'))}
    n = (101, 161)[level]
    row = chart.plate_job(R, key, 2, n, 3, _FEM['field'], None)[0]
    if row['status'] != 'ok':
        return 'stopped: ' + row.get('note', '')[:70], False, row['wall_s']
    # the displacement of every point within one hole radius of the edge
    # (unittest/analytic/check_plate.py's measure; the chart's err_u leaves
    # out the row next to the hole, where the error is largest)
    import check_plate
    x, y = check_plate.points(n)
    u, _ = _FEM['field'][('stress', 0.3)].at(x, y)
    ref = os.path.join(work, 'plate_fem.txt')
    with open(ref, 'w') as f:
        for k in range(len(x)):
            f.write('%.10e %.10e %.10e %.10e\n' % (x[k], y[k], u[k, 0], u[k, 1]))
    d = os.path.join(work, 'plate', '2d_%s_m3_n%d' % (key, n))
    out = tool([os.path.join(ROOT, 'unittest', 'analytic', 'check_plate.py'), 'check',
                os.path.join(d, 'ref.dump'), os.path.join(d, 'def.dump'), ref], work)
    m = re.search(r'displacement error ([\d.]+) %', out)
    if not m:
        return 'no measure: ' + out.strip()[-60:], False, row['wall_s']
    eu = float(m.group(1)) / 100
    text = 'u %.1f %%, sigma_yy near the hole %.1f %% (RMS)' % (100 * eu, 100 * row['err'])
    return text, eu <= 0.03, row['wall_s']


def wave_scene(lmp, s, level, work):
    """pulse speed in a 2D bar against c0 = sqrt(E/rho), 3 %"""
    chart, R, key = _chart(s, work, lmp)
    row = chart.wave_job(R, key, 2, (1e-3, 0.5e-3)[level], 3, None)[0]
    if row['status'] != 'ok':
        return 'stopped: ' + row.get('note', '')[:70], False, row['wall_s']
    return 'c/c0 %+.1f %%' % (100 * row['err_signed']), row['err'] <= 0.03, row['wall_s']


SCENES = [
    ('plate', 'plate with a hole (u vs CalculiX, 3 %)', plate_scene),
    ('wave', 'wave speed (3 %)', wave_scene),
    ('cylinder', 'thick cylinder (Hill: c on 24 rays and u(a), 3 %)', cylinder_scene),
    ('taylor', 'Taylor bar (L 8 %, D 10 % of experiment)', taylor_scene),
    ('kalthoff', 'Kalthoff-Winkler (65-72 deg)', kalthoff_scene),
    ('branching', 'glass branching (branches, < 0.6 c_R)', branching_scene),
    ('ball', 'ball on plate (created <= 1 %)', ball_scene),
    ('perforation', 'JC perforation (created <= 1 %)', perforation_scene),
]
