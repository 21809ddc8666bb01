#!/bin/bash
# LAMMPS's bpm/peri benchmark scene (bench/in.bpm_scene) with peri/pmb,
# peri/lps and our styles, same machine, same run, 1 core; best of REPEATS.
# Our ratios to peri/lps can be held against those LAMMPS publishes for
# bond_style bpm/peri on this scene.
# usage: bench/run_bpm_scene.sh [LMP] [PLUGIN_DIR] [REPEATS]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LMP=${1:-$(bash "$ROOT/cmake/lammps.sh" print-dir)/lmp}
export LAMMPS_PLUGIN_PATH=$(cd "${2:-$ROOT/build/plugin}" && pwd) OMP_NUM_THREADS=1
REPEATS=${3:-3}
TMP=$(mktemp -d); trap 'rm -rf "$TMP"' EXIT
lps=""
printf "%-12s %-32s %8s %14s %8s %10s\n" style settings loop_s point-steps/s vs_lps bytes/point
for m in "pmb|" "lps|" "nospd|stabilization none" "nospd|" "nospd|stabilization wan" \
         "nospd|strain finite" "hs|form II"; do
  style=${m%%|*}; settings=${m#*|}; best=""
  for r in $(seq "$REPEATS"); do
    "$LMP" -in "$ROOT/bench/in.bpm_scene" -var style "$style" -var settings "$settings" \
      -log none -screen "$TMP/screen"
    t=$(awk '/Loop time/{print $4}' "$TMP/screen" | tail -1)
    best=$(awk -v a="${best:-1e30}" -v b="$t" 'BEGIN{print (b<a)?b:a}')
  done
  rate=$(awk -v t="$best" 'BEGIN{printf "%.4g", 4096*200/t}')
  # the bonds fix's logged state plus the pair's per-point work arrays (25 doubles)
  mem=$(awk '/bond and reference state/{print $(NF-1)}' "$TMP/screen" | head -1)
  [ -n "$mem" ] && mem=$((mem + 25 * 8))
  [ "$style" = lps ] && lps=$rate
  ratio=$(awk -v a="$rate" -v b="${lps:-0}" 'BEGIN{if (b>0) printf "%.2f", a/b}')
  printf "%-12s %-32s %8s %14s %8s %10s\n" "$style" "${settings:-(default)}" "$best" "$rate" "$ratio" "${mem:-n/a}"
done
