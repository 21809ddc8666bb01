#!/bin/bash
# Soak: 100,000 steps of a 3D fracture run (damage, contact) on 2 MPI ranks,
# once in one go and once as five 20,000-step segments chained through
# restart files, each segment a new LAMMPS process.  The two must end with
# the same damage at every point (and the same positions and forces to
# round-off).  Not part of ctest: about 10 minutes on 2 cores.
# usage: bench/soak/run_soak.sh [LMP] [PLUGIN_DIR] [WORKDIR]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
LMP=${1:-$(bash "$ROOT/cmake/lammps.sh" print-dir)/lmp}
PLUGIN_DIR=$(cd "${2:-$ROOT/build/plugin}" && pwd)
WORK=${3:-$ROOT/build/soak}
mkdir -p "$WORK"; cd "$WORK"; rm -f soak.*.restart
export LAMMPS_PLUGIN_PATH=$PLUGIN_DIR OMP_NUM_THREADS=1
MPIRUN=(mpirun --allow-run-as-root -np 2)
IN=$ROOT/bench/soak/in.soak
t0=$(date +%s)
"${MPIRUN[@]}" "$LMP" -in "$IN" -var mode full -var seg 0 -var out full -log full.log -screen none
t1=$(date +%s)
for seg in 1 2 3 4 5; do
  "${MPIRUN[@]}" "$LMP" -in "$IN" -var mode segment -var seg $seg -var out chained \
    -log segment$seg.log -screen none
done
t2=$(date +%s)
echo "one run: $((t1 - t0)) s; five segments: $((t2 - t1)) s"
grep -h "^SOAK" full.log | sed 's/^/full:    /'
for seg in 1 2 3 4 5; do grep -h "^SOAK" segment$seg.log | sed "s/^/seg $seg:   /"; done
/usr/bin/python3 "$ROOT/unittest/mpi/compare_damage.py" 1e-9 1e-6 full.dump chained.dump
