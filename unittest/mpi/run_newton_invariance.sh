#!/bin/bash
# min_style nospd/newton: the same displacements, stresses and plastic
# strain on 1, 2 and 4 MPI ranks (two plastic load steps), to TOL of the
# largest value.
# usage: run_newton_invariance.sh LMP WORKDIR [STYLE] ["SETTINGS"] [TOL] [FTOL]
set -euo pipefail
LMP=$1; WORK=$2; STYLE=${3:-peri/nospd}; SETTINGS=${4:-}; TOL=${5:-1e-10}; FTOL=${6:-100}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
for np in 1 2 4; do
  "${MPIRUN[@]}" -np $np "$LMP" -in "$HERE/in.newton_invariance" -log np$np.log -screen none \
    -var style "$STYLE" -var settings "$SETTINGS" -var out np$np -var ftol "$FTOL"
  n=$(grep -c "Stopping criterion = force tolerance" np$np.log) || true
  [ "$n" = 2 ] || { echo "FAIL: np $np: $n of 2 load steps reached the force tolerance"; exit 1; }
done
grep -h "nospd/newton [0-9]" np1.log | head -n 20
/usr/bin/python3 "$HERE/compare_dumps.py" "$TOL" np1.dump np2.dump np4.dump
