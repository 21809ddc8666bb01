#!/bin/bash
# Atoms deleted or lost after the families exist, or bonds stretched past
# the ghost cutoff under a damage fix (farbreak): the same bonds break, and
# the same forces follow, on 1, 2 and 4 MPI ranks.
# usage: run_vanish.sh LMP MODE COMPRESS WORKDIR
set -euo pipefail
LMP=$1; MODE=$2; COMPRESS=$3; WORK=$4
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
if [ "$MODE" = far ]; then
  # a partner that exists beyond the ghost cutoff: an error with the distance
  if "${MPIRUN[@]}" -np 2 "$LMP" -in "$HERE/in.vanish" -log far.log -screen none \
    -var mode far -var compress no -var out far; then
    echo "FAIL: no error"; exit 1
  fi
  grep -h "ERROR" far.log
  grep -q "away, beyond the ghost cutoff 0.004" far.log || { echo "FAIL: wrong error"; exit 1; }
  exit 0
fi
for np in 1 2 4; do
  "${MPIRUN[@]}" -np $np "$LMP" -in "$HERE/in.vanish" -log np$np.log -screen none \
    -var mode "$MODE" -var compress "$COMPRESS" -var out np$np
done
if [ "$MODE" = farbreak ]; then
  # with a damage fix, bonds stretched past the ghost cutoff break, alike on
  # every rank count (on one rank their partners are at hand, on several not)
  for np in 1 2 4; do grep -h "^BROKEN" np$np.log | sed "s/^/np$np: /"; done
  n=$(grep -h "^BROKEN" np1.log np2.log np4.log | sort -u | wc -l)
  [ "$n" = 1 ] || { echo "FAIL: bond counts differ between rank counts"; exit 1; }
  grep -q "stretched beyond the ghost cutoff" np1.log || { echo "FAIL: no far bond broke"; exit 1; }
  /usr/bin/python3 "$HERE/compare_damage.py" 1e-12 1e-8 np1.dump np2.dump np4.dump
  exit 0
fi
for np in 1 2 4; do grep -h "^BROKEN" np$np.log | sed "s/^/np$np: /"; done
# the same counts everywhere, and bonds did vanish
n=$(grep -h "^BROKEN" np1.log np2.log np4.log | sort -u | wc -l)
[ "$n" = 1 ] || { echo "FAIL: bond counts differ between rank counts"; exit 1; }
vanished=$(awk '/^BROKEN/{print $4}' np1.log)
awk -v v="$vanished" 'BEGIN{exit !(v > 0)}' || { echo "FAIL: no bond vanished"; exit 1; }
grep -q "bonds broken: their partner atoms no longer exist" np1.log ||
  { echo "FAIL: no warning about the vanished partners"; exit 1; }
/usr/bin/python3 "$HERE/compare_damage.py" 1e-12 1e-8 np1.dump np2.dump np4.dump
