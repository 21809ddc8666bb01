#!/bin/bash
# Mooney-Rivlin rubber strip (strain formula) to stretch 2: the middle's
# stress and lateral stretch against the homogeneous solution of the same W.
# usage: run_rubber.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$WORK"; cd "$WORK"
rm -f rubber_formula.out
"$LMP" -in "$ROOT/examples/rubber_formula/in.rubber_formula" -log rubber.log -screen none \
  || { tail -n 5 rubber.log; exit 1; }
/usr/bin/python3 "$ROOT/examples/rubber_formula/check.py" rubber_formula.out --tol 0.005
