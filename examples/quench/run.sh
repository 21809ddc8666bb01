#!/bin/bash
# The quench at several initial temperatures: runs in.quench for each T0
# (K), measures its edge cracks (measure.py) and draws them (quench.png).
# usage: examples/quench/run.sh LMP [DX] [T0 ...]
#   (default DX 0.2e-3; T0 573 673 773 873, i.e. 300-600 C; extra in.quench
#   variables through QUENCH_VARS, e.g. QUENCH_VARS="-var h 1e5")
# Writes quench_T0.log, quench_T0.dump and quench.png in the current folder.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
LMP=$1
DX=${2:-0.2e-3}
shift $(( $# > 1 ? 2 : 1 ))
TEMPS=${*:-573 673 773 873}
PY=/usr/bin/python3
dumps=()
for T0 in $TEMPS; do
  # shellcheck disable=SC2086
  "$LMP" -in "$HERE/in.quench" -var T0 "$T0" -var dx "$DX" -var out "quench_$T0" \
    ${QUENCH_VARS:-} -log "quench_$T0.log" -screen none
  echo "T0 $T0 K: $($PY "$HERE/measure.py" "quench_$T0.dump" "$DX" | tail -1)"
  dumps+=("quench_$T0.dump")
done
$PY "$HERE/plot_quench.py" quench.png "$DX" "${dumps[@]}"
