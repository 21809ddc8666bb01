#!/bin/bash
# The quench example (examples/quench/in.quench) on a 20 mm plate at 0.25 mm
# spacing, 0.02 s of cooling: below the critical stretch (alpha dT0 under
# s_c (1 - scatter), dT0 = 40 K) no bond breaks; from 600 C cracks grow
# from the long edges into the plate; from 300 C fewer and shorter (the
# experiment's trend, Jiang et al. 2012).
# usage: run_quench.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
HERE=$(cd "$(dirname "$0")" && pwd)
EX="$HERE/../../examples/quench"
mkdir -p "$WORK"; cd "$WORK"
run() {    # T0 tend n
  "$LMP" -in "$EX/in.quench" -var T0 "$1" -var tend "$2" -var n "$3" -var dx 0.25e-3 \
    -var L 0.02 -var nshow 1000 -var out "q$1" -log "q$1.log" -screen none \
    || { tail -n 5 "q$1.log"; exit 1; }
}
run 333 0.02 10
run 873 0.02 40
run 573 0.02 40
# no __pycache__ in the source tree (measure.py is imported from there)
PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 - "$EX" <<'PY'
import re, sys
sys.path.insert(0, sys.argv[1])
import measure

dx = 0.25e-3
fail = False
def check(ok, what):
    global fail
    print(("ok   " if ok else "FAIL ") + what)
    fail |= not ok

log = open("q333.log").read()
sc = float(re.search(r"critical value per type pair: 1-1 ([0-9.e+-]+)", log).group(1))
broken = int(re.search(r"QUENCH DONE: .* bonds broken (\d+)", log).group(1))
check(7.5e-6 * 40 < 0.95 * sc, f"dT0 40 K is below the bound: alpha dT0 3e-4 < 0.95 s_c = {0.95 * sc:.3g}")
check(broken == 0, f"dT0 40 K: {broken} bonds broken (0)")
res = {}
for t0 in (873, 573):
    cracks, skin = measure.measure(measure.read_dump(f"q{t0}.dump"), dx)
    s = measure.summary(cracks)
    total = sum(c[2] for c in cracks)
    res[t0] = (s["n"], total)
    print(f"T0 {t0}: {s['n']} cracks, total length {1e3 * total:.2f} mm, skin {1e3 * skin:.2f} mm")
n6, l6 = res[873]
check(n6 >= 4 and l6 >= 4e-3, f"600 C: at least 4 edge cracks, 4 mm in all ({n6}, {1e3 * l6:.2f} mm)")
check(res[573][1] < l6 and res[573][0] <= n6, "300 C: fewer or as many cracks, shorter in all")
sys.exit(1 if fail else 0)
PY
