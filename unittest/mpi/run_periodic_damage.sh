#!/bin/bash
# A uniform deformation of a periodic block breaks bonds uniformly on 1 and
# 2 ranks: the least and most damaged points agree, bonds broke, and both
# rank counts print the same line.
# usage: run_periodic_damage.sh LMP STYLE TILT WORKDIR
set -euo pipefail
LMP=$1; STYLE=$2; TILT=$3; WORK=$4
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
for np in 1 2; do
  mpirun --allow-run-as-root --oversubscribe -np $np "$LMP" -in "$HERE/in.periodic_damage" \
    -log np$np.log -screen none -var style "$STYLE" -var tilt "$TILT"
  grep -h "^DAMAGE" np$np.log | tail -1 > np$np.txt
  read -r _ lo hi broken < np$np.txt
  echo "np $np: damage $lo to $hi, $broken bonds broken"
  [ "$lo" = "$hi" ] || { echo "FAIL: damage not uniform on $np rank(s)"; exit 1; }
  awk -v b="$broken" 'BEGIN { exit !(b > 0) }' || { echo "FAIL: no bond broke"; exit 1; }
done
cmp -s np1.txt np2.txt || { echo "FAIL: 1 and 2 ranks differ"; cat np1.txt np2.txt; exit 1; }
echo "PASS"
