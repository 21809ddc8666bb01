#!/bin/bash
# The zero-energy-mode warning on the scene it was calibrated on: the thick
# cylinder on a square lattice (bench/scenes/in.cylinder_lattice, dx = 0.5
# mm, 3768 points) with the default `silling 0.5` (a round plastic zone: no
# warning) and with `silling 0.05` (elastic pockets along the lattice axes:
# the warning, once).
# usage: run_zem_cylinder.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
HERE=$(cd "$(dirname "$0")" && pwd)
DECK=$(cd "$HERE/../.." && pwd)/bench/scenes/in.cylinder_lattice
mkdir -p "$WORK"; cd "$WORK"
for g in 0.5 0.05; do
  "$LMP" -in "$DECK" -var stab "silling $g" -var out "cyl_$g.dump" -log "cyl_$g.log" \
    -screen none || { tail -n 5 "cyl_$g.log"; exit 1; }
done
n05=$(grep -c "zero-energy modes" cyl_0.5.log || true)
n005=$(grep -c "zero-energy modes" cyl_0.05.log || true)
echo "warnings: silling 0.5: $n05, silling 0.05: $n005"
grep "zero-energy modes" cyl_0.05.log || true
[ "$n05" = 0 ] && [ "$n005" = 1 ] && grep -q "stabilization silling 0.05\` does not hold" cyl_0.05.log
