#!/bin/bash
# The main job (`make run`): the flagship example, run with the built LAMMPS
# and plugin into build/flagship/, measured, and drawn.
# usage: examples/run-flagship.sh LMP PLUGIN_DIR
set -euo pipefail
LMP=$1; PLUGIN_DIR=$(cd "$2" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=$ROOT/build/flagship; mkdir -p "$OUT"; cd "$OUT"
export LAMMPS_PLUGIN_PATH=$PLUGIN_DIR LAMMPS_POTENTIALS=$ROOT/potentials OMP_NUM_THREADS=1
NP=${NP:-2}
echo "== PERI-NOSPD flagship: elastic wave in a steel bar ($NP MPI ranks)"
mpirun --allow-run-as-root -np "$NP" "$LMP" -in "$ROOT/examples/wave_bar/in.wave_bar" -log log.wave_bar -screen none
grep -A10 "^ *Step" log.wave_bar | head -11
/usr/bin/python3 "$ROOT/examples/wave_bar/measure.py" vx_profile.txt
echo "== outputs in $OUT: log.wave_bar, vx_profile.txt, wave_bar.png"
