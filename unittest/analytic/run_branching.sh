#!/bin/bash
# Dynamic crack branching in soda-lime glass (examples/crack_branching):
# the crack must branch and its mean tip speed lie in 0.4-1.0 c_R, both
# measured from the damage dumps by tools/crack_tip.py, and the energy the
# run dissipates must match G0 times the crack area within 20 %.
# usage: run_branching.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
EX=$ROOT/examples/crack_branching
rm -rf "$WORK"; mkdir -p "$WORK"; cd "$WORK"
"$LMP" -in "$EX/in.crack_branching" -var image no -log branching.log -screen none \
  || { tail -n 5 branching.log; exit 1; }
dt=$(grep -m1 '^timestep *[0-9]' branching.log | awk '{print $2}')
/usr/bin/python3 "$ROOT/tools/crack_tip.py" 'dump.crack_branching.*' --timestep "$dt" \
  --check 0.4,1.0,branch --out tip.txt
# energy balance: what fracture dissipated against G0 x crack area (point
# volume dx^2 x 1 m, G0 of soda-lime glass in potentials/materials.nospd)
/usr/bin/python3 "$ROOT/unittest/analytic/check_fracture_energy.py" branching.log tip.txt \
  --volume 2.5e-7 --g0 3.8 --band 0.8,1.25
