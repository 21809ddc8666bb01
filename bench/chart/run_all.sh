#!/bin/bash
# Speed against accuracy and the stability study (issue 7): regenerates every
# CSV under bench/chart/results/, every chart, and the tables and figures of
# doc/Howto_choose_model.rst, from scratch.
#
# usage: bash bench/chart/run_all.sh [size=full|reduced|smoke] [jobs=2]
# env:   LMP (LAMMPS executable; default: the one cmake/lammps.sh built)
#        PLUGIN_DIR (folder with nospdplugin.so; default: build/plugin,
#        built with `make plugin` when missing)
#
# full: ~25-30 minutes on 2 cores (2 LAMMPS processes, 1 core each);
# reduced: a few minutes, smaller resolutions; smoke: about a minute.
# Models whose style this LAMMPS/plugin lacks (peri/nospd/hs until it lands)
# are skipped and listed in results/skipped.csv.  The plate scene needs
# CalculiX (Debian package calculix-ccx): installed here when missing and
# running as root; without it the plate is compared with Heywood's formula only.
set -euo pipefail
SIZE=${1:-full}
JOBS=${2:-2}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
cd "$ROOT"
if [ -z "${LMP:-}" ]; then
  LMP=$(bash cmake/lammps.sh print-dir)/lmp
fi
PLUGIN_DIR=${PLUGIN_DIR:-$ROOT/build/plugin}
if [ ! -f "$PLUGIN_DIR/nospdplugin.so" ]; then
  echo "run_all.sh: no plugin in $PLUGIN_DIR: building it (make plugin)"
  make plugin
fi
if ! command -v ccx >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    echo "run_all.sh: installing CalculiX (calculix-ccx) for the FEM reference"
    DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx >/dev/null \
      || echo "run_all.sh: calculix-ccx could not be installed: plate uses Heywood only"
  else
    echo "run_all.sh: no ccx and not root: plate uses Heywood only (apt-get install calculix-ccx)"
  fi
fi
RESULTS=$HERE/results
rm -rf "$RESULTS"
mkdir -p "$RESULTS"
start=$(date +%s)
/usr/bin/python3 "$HERE/chart.py" run --size "$SIZE" --jobs "$JOBS" --lmp "$LMP" \
  --plugin "$PLUGIN_DIR" --results "$RESULTS" --work "$ROOT/build/bench-chart"
/usr/bin/python3 "$HERE/charts.py" "$RESULTS" "$ROOT/doc"
echo "run_all.sh: $SIZE chart regenerated in $(( $(date +%s) - start )) s"
