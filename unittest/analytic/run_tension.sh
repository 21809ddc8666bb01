#!/bin/bash
# usage: run_tension.sh LMP DIM PLANE "SETTINGS" WORKDIR
set -euo pipefail
LMP=$1; DIM=$2; PLANE=$3; SETTINGS=$4; WORK=$5
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$WORK"; cd "$WORK"
"$LMP" -in "$HERE/in.tension" -var dim "$DIM" -var settings "$SETTINGS" -var E 200e9 \
  -log tension.log -screen none || { tail -n 5 tension.log; exit 1; }
/usr/bin/python3 "$HERE/check_tension.py" tension.dump "$DIM" "$PLANE" 0.3 200e9
