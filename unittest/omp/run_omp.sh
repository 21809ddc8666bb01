#!/bin/bash
# The /omp styles (`-sf omp`, 2 threads) against the plain ones, same deck,
# one MPI rank: forces, positions and broken bonds the same to 1e-12, and
# the run must really use the /omp styles (LAMMPS warns "No /omp style for
# force computation currently active" when it falls back).
# usage: run_omp.sh LMP KIND DIM "ARG" WORKDIR
#   KIND = pair:   ARG = pair_style settings|pair_coeff keywords (in.invariance)
#   KIND = hs:     the same with peri/nospd/hs
#   KIND = damage: ARG = damage criterion (in.damage_invariance)
set -euo pipefail
LMP=$1; KIND=$2; DIM=$3; ARG=$4; WORK=$5
MPIDIR=$(cd "$(dirname "$0")/../mpi" && pwd)
mkdir -p "$WORK"; cd "$WORK"
run() { # out [suffix args...]
  local out=$1; shift
  if [ "$KIND" != damage ]; then
    local style=peri/nospd; [ "$KIND" = hs ] && style=peri/nospd/hs
    "$LMP" -in "$MPIDIR/in.invariance" -log "$out.log" -screen none "$@" \
      -var dim "$DIM" -var style $style -var settings "${ARG%%|*}" -var mode full \
      -var out "$out" -var coeff "$(echo "$ARG" | sed -n 's/^[^|]*|//p')"
  else
    "$LMP" -in "$MPIDIR/in.damage_invariance" -log "$out.log" -screen none "$@" \
      -var dim "$DIM" -var criterion "$ARG" -var mode full -var out "$out"
  fi
}
OMP_NUM_THREADS=1 run plain
OMP_NUM_THREADS=2 run omp2 -sf omp -pk omp 2
if grep -q "No /omp style" omp2.log; then
  echo "FAIL: -sf omp ran the plain styles"; grep "No /omp style" omp2.log; exit 1
fi
# is_active(pair_style,peri/nospd/omp); `info fixes` names the fix styles
grep -h "^STYLES" plain.log omp2.log
grep -q "^STYLES pair .* 1$" omp2.log || { echo "FAIL: -sf omp did not pick the /omp pair style"; exit 1; }
if [ "$KIND" = damage ]; then
  grep -q "style = nospd/damage/omp" omp2.log || { echo "FAIL: -sf omp did not pick fix nospd/damage/omp"; exit 1; }
fi
if [ "$KIND" != damage ]; then
  /usr/bin/python3 "$MPIDIR/compare_dumps.py" 1e-12 plain.dump omp2.dump
else
  for f in plain omp2; do grep -h "^BROKEN" $f.log | sed "s/^/$f: /"; done
  /usr/bin/python3 "$MPIDIR/compare_damage.py" 1e-12 1e-8 plain.dump omp2.dump
fi
