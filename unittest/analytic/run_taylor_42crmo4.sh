#!/bin/bash
# The 42CrMo4 Taylor bar (examples/taylor_bar/in.taylor_bar_42crmo4) at 10
# points across, to 80 us, against the finite-element result for the same
# scene and constants (Abaqus/Explicit, as listed by DynELA's
# documentation: final length 26.55-26.56 mm, impact face 11.16 mm): the
# length within 1 %, which the flow stress sets (0.8 % long at 10 across;
# without the rate term 1.9 % short, so a wrong rate term fails here), and
# the face within 10 % (6.5 % narrow; Silling's springs on the linear fit,
# which store the bulge's curvature, leave it 20 % narrow and fail: see the
# example's README).  ke + pe + plastic work constant to 1e-4.
# usage: run_taylor_42crmo4.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
DECKS="$ROOT/examples/taylor_bar"
mkdir -p "$WORK"; cd "$WORK"
rm -f steel.*.dump
"$LMP" -in "$DECKS/in.taylor_bar_42crmo4" -var deckdir "$DECKS" -var dx 0.64e-3 -var out steel \
  -log steel.log -screen none || { tail -n 5 steel.log; exit 1; }
/usr/bin/python3 "$HERE/check_taylor_energy.py" steel.log --tol 1e-4 --l0 32.4e-3 --band 0.75,0.85
last=$(ls steel.*.dump | sort -t. -k2 -n | tail -n 1)
/usr/bin/python3 "$ROOT/tools/taylor_bar.py" "$last" --spacing 0.64e-3 \
  --l0 32.4e-3 --d0 6.4e-3 --check 26.55e-3,11.16e-3,0.01,0.10
