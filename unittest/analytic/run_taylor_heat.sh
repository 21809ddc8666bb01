#!/bin/bash
# The Taylor bar with heat conduction (examples/taylor_bar/in.taylor_heat,
# about 15 s): insulated, so the thermal energy minus the plastic heating
# is the same at the start (to the thermo line's 8 digits), after the
# impact and after conduction (to 1e-9), the plastic
# heating is positive, and conduction lowers the hottest point.
# usage: run_taylor_heat.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
EX=$(cd "$(dirname "$0")/../../examples/taylor_bar" && pwd)
mkdir -p "$WORK"; cd "$WORK"
"$LMP" -in "$EX/in.taylor_heat" -var deckdir "$EX" -var ncool 200 -log heat.log -screen none || { tail -n 5 heat.log; exit 1; }
/usr/bin/python3 - heat.log <<'PY'
import re, sys
text = open(sys.argv[1]).read()
rows = re.findall(r"^AFTER (\w+): thermal energy (\S+) J, plastic heating (\S+) J, T max (\S+) K", text, re.M)
(_, e1, p1, t1), (_, e2, p2, t2) = [(r[0], float(r[1]), float(r[2]), float(r[3])) for r in rows]
start = re.search(r"^\s+0\s+0\s+\S+\s+\S+\s+\S+\s+\S+\s+\S+\s+\S+\s+(\S+)\s+(\S+)\s*$", text, re.M)
e0 = float(start.group(1))
# E0 from the thermo line (8 digits), the two AFTER lines to 1e-9
ok = p1 > 1.0 and abs((e1 - p1) - e0) < 1e-7 * e0 and abs((e2 - p2) - (e1 - p1)) < 1e-9 * e0 and t2 < t1
print(f"E0 {e0:.10g}; after impact E - plastic {e1 - p1:.10g} (plastic {p1:.6g} J, T max {t1:.5g} K); "
      f"after conduction {e2 - p2:.10g} (T max {t2:.5g} K): {'PASS' if ok else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
