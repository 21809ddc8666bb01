#!/bin/bash
# Wave speed in a bar against c0 = sqrt(E/rho): the wave_bar example, measured.
# usage: run_wave.sh LMP DIM WORKDIR
set -euo pipefail
LMP=$1; DIM=$2; WORK=$3
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$WORK"; cd "$WORK"
"$LMP" -in "$ROOT/examples/wave_bar/in.wave_bar" -var dim "$DIM" -log wave.log -screen none \
  || { tail -n 5 wave.log; exit 1; }
/usr/bin/python3 "$ROOT/examples/wave_bar/measure.py" vx_profile.txt
