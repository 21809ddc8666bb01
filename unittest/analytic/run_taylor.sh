#!/bin/bash
# The Taylor bar example (OFHC copper, Johnson-Cook with heating, 190 m/s
# onto the harmonic anvil) at 10 points across the diameter, to rest:
# ke + pe + plastic work constant to 1e-4 over the impact, the bar at rest
# with its energy dissipated, and shortened as much as a Taylor bar should.
# usage: run_taylor.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
mkdir -p "$WORK"; cd "$WORK"
rm -f taylor.*.dump
"$LMP" -in "$ROOT/examples/taylor_bar/in.taylor_bar" -var dx 0.762e-3 -var out taylor \
  -log taylor.log -screen none || { tail -n 5 taylor.log; exit 1; }
/usr/bin/python3 "$HERE/check_taylor_energy.py" taylor.log --tol 1e-4
