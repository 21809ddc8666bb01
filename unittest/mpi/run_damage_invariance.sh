#!/bin/bash
# Damage invariance: the same bonds break on 1, 2 and 4 MPI ranks, and a
# run split by a restart (2 ranks, then 1) breaks the same bonds as one
# uninterrupted run.
# usage: run_damage_invariance.sh LMP DIM "CRITERION" WORKDIR [MATERIAL]
# MATERIAL: default (elastic classical) or hs_plastic (3D: J2 in the
# bond-associated style)
set -euo pipefail
LMP=$1; DIM=$2; CRIT=$3; WORK=$4; MATERIAL=${5:-default}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
run() { # nprocs mode out
  "${MPIRUN[@]}" -np "$1" "$LMP" -in "$HERE/in.damage_invariance" -log "$3.log" -screen none \
    -var dim "$DIM" -var criterion "$CRIT" -var mode "$2" -var out "$3" \
    -var material "$MATERIAL"
}
run 1 full serial
run 2 full np2
run 4 full np4
run 2 first split
run 1 second split
for f in serial np2 np4 split; do grep -h "^BROKEN" $f.log | sed "s/^/$f: /"; done
/usr/bin/python3 "$HERE/compare_damage.py" 1e-12 1e-8 serial.dump np2.dump np4.dump split.dump
