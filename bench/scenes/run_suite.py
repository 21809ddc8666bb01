#!/usr/bin/python3
"""The scene suite of issue 44: every zero-energy-mode setting in every
scene, one table scene x setting (the figure and pass/fail against its
target) and a chart of scenes passed against cost.

Scenes (suite_scenes.py; targets in the column heads):
  plate       plate with a hole in tension (bench/chart/in.plate): the
              displacement field within one hole radius of the edge against
              CalculiX (rigid motion removed), and sigma_yy there (RMS)
  wave        pulse speed in a 2D bar (bench/chart/in.wave) against c0
  cylinder    thick cylinder, plane strain J2, on a square lattice
              (in.cylinder_lattice): plastic radius on every 15 deg ray and
              bore displacement against Hill (unittest/analytic/cylinder.py)
  taylor      OFHC copper Taylor bar at 190 m/s (examples/taylor_bar)
              against the experiment (tools/taylor_bar.py)
  kalthoff    Kalthoff-Winkler plate (examples/kalthoff_winkler): crack
              angle from the notch tips (tools/crack_angle.py)
  branching   soda-lime glass (examples/crack_branching): branches, tip
              speed (tools/crack_tip.py)
  ball        steel ball shatters an aluminium plate (in.ball_plate) and
  perforation sphere through a Johnson-Cook 4340 plate
              (in.perforation_energy): energy created against dissipated
              (energy_balance.py)

usage: run_suite.py LMP [--level 0|1] [--only SCENE,...] [--settings 0,1,...]
                        [--jobs N] [--csv FILE] [--chart FILE.png] [--rst FILE]
       run_suite.py --from CSV [CSV...] [--chart FILE.png] [--rst FILE]
                        (the tables and chart of earlier runs)
Level 0 is the modest resolution (each scene seconds to minutes on one
core; the bond-associated rows 5-30x longer), level 1 the finer one.
LAMMPS_PLUGIN_PATH and LAMMPS_POTENTIALS must be set; the plate needs
CalculiX (calculix-ccx).  Work files go to a temporary folder.
"""
import argparse
import concurrent.futures as cf
import csv
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import suite_scenes as S    # noqa: E402

# name, pair style + form, stabilization keywords, is the style a potential
SETTINGS = [
    ("none", "peri/nospd", "none", True),
    ("silling 0.5 (default)", "peri/nospd", "silling 0.5", True),
    ("silling 0.05", "peri/nospd", "silling 0.05", True),
    ("silling 0.05 + fit quadratic", "peri/nospd", "silling 0.05 stabilization/fit quadratic", True),
    ("silling 0.5 + fit quadratic", "peri/nospd", "silling 0.5 stabilization/fit quadratic", True),
    ("hourglass 0.2", "peri/nospd", "hourglass 0.2", False),
    ("hourglass 0.5", "peri/nospd", "hourglass 0.5", False),
    ("wan", "peri/nospd", "wan", True),
    ("hs form II", "peri/nospd/hs form II", "none", True),
    ("hs form II + silling 0.5", "peri/nospd/hs form II", "silling 0.5", True),
    ("hs form I", "peri/nospd/hs form I", "none", False),
    ("hs form I + silling 0.5", "peri/nospd/hs form I", "silling 0.5", False),
]


def job(lmp, k, scene, level, work):
    key, _, fn = next(x for x in S.SCENES if x[0] == scene)
    d = os.path.join(work, '%s_%d' % (key, k))
    try:
        text, ok, wall = fn(lmp, SETTINGS[k], level, d)
    except Exception as e:    # a scene's measure failed: say so in the cell
        text, ok, wall = 'measure failed: %s' % str(e)[:60], False, 0.0
    return k, scene, text, ok, wall


def chart(rows, scenes, path):
    """scenes passed against the wall time over all scenes (relative to the
    default's), one marker per setting; settings that tie are spread a
    little vertically so that each stays visible"""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    base = sum(rows[(1, s)][2] for s in scenes if (1, s) in rows) or 1.0
    fig, ax = plt.subplots(figsize=(8, 4.8))
    markers = 'oxsD^v<>PX*h'
    seen = {}
    for k, (name, *_rest) in enumerate(SETTINGS):
        cells = [rows[(k, s)] for s in scenes if (k, s) in rows]
        if not cells:
            continue
        cost = sum(c[2] for c in cells) / base
        passed = sum(1 for c in cells if c[1])
        n = seen.get(passed, 0)
        seen[passed] = n + 1
        ax.scatter(cost, passed + 0.12 * n, s=45, marker=markers[k % len(markers)], label=name)
    ax.set_xscale('log')
    ax.set_xlabel('wall time over all scenes, relative to the default (one core each, two at a time)')
    ax.set_ylabel('scenes passed (of %d; ties spread upwards)' % len(scenes))
    ax.set_ylim(-0.5, len(scenes) + 0.5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc='upper right', ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def tables(rows, ks, scenes, rst=None):
    """the markdown table on stdout; with rst, a list-table into that file"""
    heads = [next(x[1] for x in S.SCENES if x[0] == s) for s in scenes]
    print('| setting | ' + ' | '.join(heads) + ' | passed |')
    print('|---|' + '---|' * (len(scenes) + 1))
    body = []
    for k in ks:
        cells = [rows.get((k, s), ('not run', False, 0.0)) for s in scenes]
        texts = ['%s: %s' % ('pass' if c[1] else '**FAIL**', c[0]) for c in cells]
        passed = '%d/%d' % (sum(c[1] for c in cells), len(cells))
        print('| %s | %s | %s |' % (SETTINGS[k][0], ' | '.join(texts), passed))
        body.append([SETTINGS[k][0]] + texts + [passed])
    if rst:
        with open(rst, 'w') as f:
            f.write('.. list-table::\n   :header-rows: 1\n   :stub-columns: 1\n\n')
            for row in [['setting'] + heads + ['passed']] + body:
                f.write('   * - %s\n' % row[0])
                for cell in row[1:]:
                    f.write('     - %s\n' % cell.replace('*', '\\*').replace('\\*\\*FAIL\\*\\*', '**FAIL**'))
            f.write('\n')


def read_csv(paths):
    """rows of earlier runs: {(setting index, scene): (text, ok, wall)}"""
    names = [x[0] for x in SETTINGS]
    rows = {}
    for p in paths:
        for r in csv.DictReader(open(p)):
            rows[(names.index(r['setting']), r['scene'])] = (r['figure'], r['pass'] == '1',
                                                            float(r['wall_s']))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('lmp', nargs='?', help='the LAMMPS executable (not with --from)')
    ap.add_argument('--level', type=int, default=0, choices=[0, 1])
    ap.add_argument('--only', default=None, help='scenes, e.g. cylinder,taylor')
    ap.add_argument('--settings', default=None, help='rows to run, 0-based, e.g. 1,2')
    ap.add_argument('--jobs', type=int, default=1)
    ap.add_argument('--csv', default=None)
    ap.add_argument('--chart', default=None)
    ap.add_argument('--rst', default=None, help='also write the table as an rst list-table')
    ap.add_argument('--from', dest='from_csv', nargs='+', default=None,
                    help='no runs: the tables and chart of earlier --csv files')
    a = ap.parse_args()
    ks = range(len(SETTINGS)) if a.settings is None else [int(k) for k in a.settings.split(',')]
    scenes = [x[0] for x in S.SCENES if a.only is None or x[0] in a.only.split(',')]
    if a.from_csv:
        rows = read_csv(a.from_csv)
        ks = [k for k in ks if any((k, s) in rows for s in scenes)]
        tables(rows, ks, scenes, a.rst)
        if a.chart:
            chart(rows, scenes, a.chart)
        return
    if not a.lmp:
        ap.error('the LAMMPS executable is needed to run the scenes')
    work = tempfile.mkdtemp(prefix='nospd_suite_')
    if 'plate' in scenes:    # the CalculiX field once, before the jobs share it
        S.plate_scene(a.lmp, SETTINGS[1], a.level, os.path.join(work, 'plate_warmup'))
    rows = {}
    writer = None
    if a.csv:
        fh = open(a.csv, 'w', newline='')
        writer = csv.writer(fh)
        writer.writerow(['setting', 'scene', 'level', 'pass', 'wall_s', 'figure'])
    with cf.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futs = [pool.submit(job, a.lmp, k, s, a.level, work) for k in ks for s in scenes]
        for f in cf.as_completed(futs):
            k, s, text, ok, wall = f.result()
            rows[(k, s)] = (text, ok, wall)
            print('%-30s %-12s %s %6.0f s  %s' % (SETTINGS[k][0], s, 'pass' if ok else 'FAIL', wall, text),
                  file=sys.stderr, flush=True)
            if writer:
                writer.writerow([SETTINGS[k][0], s, a.level, int(ok), round(wall, 1), text])
                fh.flush()
    tables(rows, ks, scenes, a.rst)
    if a.chart:
        chart(rows, scenes, a.chart)
    print('\n(level %d; work files: %s)' % (a.level, work))


if __name__ == '__main__':
    main()
