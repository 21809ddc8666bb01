#!/bin/bash
# Thick-walled cylinder, plane strain, elastic-perfectly plastic J2, under
# internal pressure: 20 and 40 rings across the wall; the bore displacement
# and the plastic radius converge to Hill's solution at first order in the
# spacing, the extrapolated displacement and the finer radius within 3 %.
# With SOLVER newton each load step is solved by min_style nospd/newton to
# FTOL (the symmetry lines held); its Newton steps per load step are listed.
# usage: run_cylinder.sh LMP WORKDIR [NR1 NR2 [SOLVER [FTOL]]]
set -euo pipefail
LMP=$1; WORK=$2; NR1=${3:-20}; NR2=${4:-40}; SOLVER=${5:-cg}; FTOL=${6:-1e-10}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
for nr in $NR1 $NR2; do
  /usr/bin/python3 "$HERE/cylinder.py" data "$nr" "cyl$nr.data"
  "$LMP" -in "$HERE/in.cylinder" -var data "cyl$nr.data" -var nr "$nr" -var out "cyl$nr.dump" \
    -var solver "$SOLVER" -var ftol "$FTOL" -log "cyl$nr.log" -screen none ||
    { tail -n 5 "cyl$nr.log"; exit 1; }
  if [ "$SOLVER" = newton ]; then
    echo "rings $nr: Newton steps, force evaluations per load step:" \
      $(grep "Iterations, force evaluations" "cyl$nr.log" | awk '{printf "%s/%s ", $5, $6}')
    n=$(grep -c "Stopping criterion = force tolerance" "cyl$nr.log") || true
    [ "$n" = 7 ] || { echo "FAIL: $n of 7 load steps reached the force tolerance"; exit 1; }
    most=$(grep "Iterations, force evaluations" "cyl$nr.log" | awk '$5 > m {m = $5} END {print m}')
    [ "$most" -le 10 ] || { echo "FAIL: a load step took $most Newton steps (at most 10)"; exit 1; }
  fi
done
/usr/bin/python3 "$HERE/cylinder.py" converge "$NR1" "cyl$NR1.dump" "$NR2" "cyl$NR2.dump" --tol 0.03
