#!/bin/bash
# 1D transient conduction in a bar at three resolutions (fix nospd/heat)
# usage: run_heat_bar.sh LMP WORKDIR
set -euo pipefail
LMP=$1; WORK=$2
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
for n in 40 80 160; do
  "$LMP" -in "$HERE/in.heat_bar" -var n $n -log bar_$n.log -screen none || { tail -n 5 bar_$n.log; exit 1; }
done
/usr/bin/python3 "$HERE/check_heat_bar.py" 0.2 40 80 160
