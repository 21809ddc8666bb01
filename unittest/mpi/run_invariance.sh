#!/bin/bash
# Decomposition (1, 2, 4 MPI ranks) and restart invariance of one variant.
# usage: run_invariance.sh LMP DIM "SETTINGS" WORKDIR [STYLE] ["COEFF"] [TOL]
set -euo pipefail
LMP=$1; DIM=$2; SETTINGS=$3; WORK=$4; STYLE=${5:-peri/nospd}; COEFF=${6:-}; TOL=${7:-1e-12}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
run() { # nprocs mode out
  "${MPIRUN[@]}" -np "$1" "$LMP" -in "$HERE/in.invariance" -log "$3.log" -screen none \
    -var dim "$DIM" -var style "$STYLE" -var settings "$SETTINGS" -var mode "$2" -var out "$3" \
    -var coeff "$COEFF" -var rcb "${NOSPD_RCB:-no}" -var periodic "${NOSPD_PERIODIC:-no}"
}
run 1 full serial
run 2 full np2
run 4 full np4
# restart split in the middle, on 2 ranks, continued on 1
run 2 first split
run 1 second split
/usr/bin/python3 "$HERE/compare_dumps.py" "$TOL" serial.dump np2.dump np4.dump split.dump
# the stable time step estimate (the stiffness bound reads the partners'
# terms through ghosts) is the same line on every rank count
est() { grep -m1 "stable time step estimate" "$1.log" || true; }
if [ "$(est serial)" != "$(est np2)" ] || [ "$(est serial)" != "$(est np4)" ]; then
  echo "stable time step estimate differs between rank counts:"; est serial; est np2; est np4; exit 1
fi
