#!/bin/bash
# Thick-walled cylinder, plane strain, elastic-perfectly plastic J2, under
# internal pressure: 20 and 40 rings across the wall; the bore displacement
# and the plastic radius converge to Hill's solution at first order in the
# spacing, the extrapolated displacement and the finer radius within 3 %.
# usage: run_cylinder.sh LMP WORKDIR [NR1 NR2]
set -euo pipefail
LMP=$1; WORK=$2; NR1=${3:-20}; NR2=${4:-40}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
for nr in $NR1 $NR2; do
  /usr/bin/python3 "$HERE/cylinder.py" data "$nr" "cyl$nr.data"
  "$LMP" -in "$HERE/in.cylinder" -var data "cyl$nr.data" -var nr "$nr" -var out "cyl$nr.dump" \
    -log "cyl$nr.log" -screen none || { tail -n 5 "cyl$nr.log"; exit 1; }
done
/usr/bin/python3 "$HERE/cylinder.py" converge "$NR1" "cyl$NR1.dump" "$NR2" "cyl$NR2.dump" --tol 0.03
