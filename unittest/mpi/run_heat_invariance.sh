#!/bin/bash
# fix nospd/heat: temperatures, heat fluxes and positions the same on 1, 2
# and 4 MPI ranks, across a restart split (2 ranks, then 1) and with -sf omp
# (2 threads), to TOL of the largest value.
# usage: run_heat_invariance.sh LMP WORKDIR [STYLE] ["SETTINGS"] [TOL] [FRAME]
set -euo pipefail
LMP=$1; WORK=$2; STYLE=${3:-peri/nospd}; SETTINGS=${4:-}; TOL=${5:-1e-12}; FRAME=${6:-reference}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
run() { # nprocs mode out [extra args]
  local np=$1 mode=$2 out=$3; shift 3
  "${MPIRUN[@]}" -np "$np" "$LMP" -in "$HERE/in.heat_invariance" -log "$out.log" -screen none \
    -var style "$STYLE" -var settings "$SETTINGS" -var mode "$mode" -var out "$out" \
    -var frame "$FRAME" "$@"
}
run 1 full serial
run 2 full np2
run 4 full np4
run 2 first split
run 1 second split
OMP_NUM_THREADS=2 run 1 full omp2 -sf omp -pk omp 2
grep -q "substep" serial.log || { echo "FAIL: no substep line"; exit 1; }
/usr/bin/python3 "$HERE/compare_dumps.py" "$TOL" serial.dump np2.dump np4.dump split.dump omp2.dump
