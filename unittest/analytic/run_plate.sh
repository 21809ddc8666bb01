#!/bin/bash
# Plate with a hole in tension (bench/chart/in.plate, 2D plane stress, 101
# points across, minimize) with the pair style's defaults: the displacement
# within one hole radius of the edge against CalculiX (stored in
# plate_fem_n101.txt, written by check_plate.py reference), within 3 %.
# usage: run_plate.sh LMP WORKDIR [pair_style keywords, e.g. "stabilization none"]
set -euo pipefail
LMP=$1; WORK=$2; EXTRA=${3:-}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
mkdir -p "$WORK"; cd "$WORK"
n=101; dx=$(/usr/bin/python3 -c "print(0.05/$n)")
"$LMP" -in "$ROOT/bench/chart/in.plate" -var n $n -var m 3 -var dim 2 -var out . \
  -var pstyle "peri/nospd plane stress thickness $dx $EXTRA" \
  -var pcoeff "* * 191e9 0.3 $(/usr/bin/python3 -c "print(3.01*$dx)")" \
  -var solver cg -var ftol 1e-3 -var maxiter 20200 -var dt 1e-8 \
  -log plate.log -screen none || { tail -n 5 plate.log; exit 1; }
/usr/bin/python3 "$HERE/check_plate.py" check ref.dump def.dump "$HERE/plate_fem_n101.txt" --tol 0.03
