#!/bin/bash
# min_style nospd/newton against LAMMPS's cg and fire, each to a force
# residual of 1e-8 of the applied load (bench/README.md, "Quasi-static
# solvers"): the plate with a hole at the chart's finest resolution (101
# across; default and hourglass stabilization), a notched plate, and the J2
# thick cylinder
# at 40 rings (7 load steps; FIRE at 20).  Writes results/newton.csv.
# usage: bash bench/newton/run.sh LMP [plate n=101] [cylinder rings=40]
set -euo pipefail
LMP=$1; N=${2:-101}; NR=${3:-40}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OUT="$HERE/results"; WORK=$(mktemp -d)
mkdir -p "$OUT"
export LAMMPS_PLUGIN_PATH=${LAMMPS_PLUGIN_PATH:-$ROOT/build/plugin}
csv="$OUT/newton.csv"
echo "scene,solver,loop_s,force_evaluations,iterations,final_fnorm,stop,ftol" > "$csv"
summarize() { # scene solver log ftol
  local loop evals iters fn stop
  loop=$(grep "^Loop time" "$3" | awk 'NR>1 {s+=$4} END {printf "%.3f", s}')
  evals=$(grep "Iterations, force evaluations" "$3" | awk '{e+=$6} END {print e}')
  iters=$(grep "Iterations, force evaluations" "$3" | awk '{e+=$5} END {print e}')
  fn=$(grep "Force two-norm" "$3" | tail -n 1 | awk '{print $NF}')
  stop=$(grep "Stopping criterion" "$3" | sed 's/.*= //' | sort | uniq -c | awk '{c=$1; $1=""; printf "%s%dx%s", (NR>1?";":""), c, $0}')
  echo "$1,$2,$loop,$evals,$iters,$fn,$stop,$4" | tee -a "$csv"
}
# plate: applied load norm = S/dx sqrt(2 n) (two rows of n points)
ftol=$(/usr/bin/python3 -c "print('%.4g' % (1e-8 * 10e6 / (0.05 / $N) * (2 * $N) ** 0.5))")
# from the chart's start (the far field's uniform strain) and from rest;
# the notched plate (an edge slit to the middle) from rest
for st in "default|peri/nospd|chart|hole" "hourglass|peri/nospd stabilization hourglass 0.2|chart|hole" \
          "default_rest|peri/nospd|rest|hole" \
          "hourglass_rest|peri/nospd stabilization hourglass 0.2|rest|hole" \
          "notch_default|peri/nospd|rest|notch" \
          "notch_hourglass|peri/nospd stabilization hourglass 0.2|rest|notch"; do
  IFS='|' read -r name pstyle start shape <<< "$st"
  for solver in newton cg fire; do
    [[ "$name" = *hourglass* ]] && [ "$solver" = cg ] && continue    # not a potential
    "$LMP" -in "$HERE/in.plate" -var n "$N" -var pstyle "$pstyle" -var solver $solver \
      -var ftol "$ftol" -var maxiter 200000 -var start $start -var shape $shape \
      -log "$WORK/plate_${name}_$solver.log" -screen none
    summarize "plate_${N}_$name" $solver "$WORK/plate_${name}_$solver.log" "$ftol"
  done
done
# cylinder: 7 load steps, each to 1e4 (1e-8 of the first step's load);
# FIRE at 20 rings only (4.5 minutes there; about 16 times that at 40)
for run in "$NR|newton" "$NR|cg" "20|newton" "20|fire"; do
  IFS='|' read -r nr solver <<< "$run"
  [ -f "$WORK/cyl$nr.data" ] ||
    /usr/bin/python3 "$ROOT/unittest/analytic/cylinder.py" data "$nr" "$WORK/cyl$nr.data" > /dev/null
  "$LMP" -in "$ROOT/unittest/analytic/in.cylinder" -var data "$WORK/cyl$nr.data" -var nr "$nr" \
    -var out "$WORK/cyl_$solver.dump" -var solver $solver -var ftol 1e4 \
    -log "$WORK/cyl${nr}_$solver.log" -screen none
  summarize "cylinder_${nr}_j2" $solver "$WORK/cyl${nr}_$solver.log" 1e4
done
rm -rf "$WORK"
