#!/bin/bash
# Throughput benchmark (not part of the test suite): LAMMPS's peri/pmb and
# peri/lps against peri/nospd variants, same scene, same machine, same run.
# usage: bench/run.sh LMP PLUGIN_DIR [n] [steps] [repeats]
# Writes bench/results/throughput.csv and prints ratios to peri/lps (best
# loop time of REPEATS runs per row, the repeats going round the rows).  Rows
# run on one core unless their launch says otherwise: omp2 = one rank with
# `-sf omp -pk omp 2`, np2 = `mpirun -np 2`, np2rcb = `mpirun -np 2` with
# tiled communication balanced by recursive bisection, d2 = the 2D plane-strain
# square (`-var dim 2`, BENCH_N2 points per side, default 200; peri/lps has
# no 2D form, so its ratio is to the 3D block's), p3 = the periodic n^3 box
# (`-var periodic yes`: no surfaces, ghosts to 2 delta), heat = the block with
# fix nospd/heat (`-var heat yes`).  BENCH_ONLY (an extended regular
# expression) keeps the rows whose launch:style|settings|coeff matches it;
# peri/lps always runs, for the ratio.
set -euo pipefail
LMP=$1; PLUGIN_DIR=$2; N=${3:-41}; STEPS=${4:-50}; REPEATS=${5:-3}
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=$HERE/results; mkdir -p "$OUT"
export LAMMPS_PLUGIN_PATH=$(cd "$PLUGIN_DIR" && pwd) OMP_NUM_THREADS=1
CSV=$OUT/throughput.csv
echo "model,settings,ranks,threads,points,steps,best_loop_s,point_steps_per_s,ratio_to_lps,state_bytes_per_point" > "$CSV"
# [launch:]style|pair_style keywords[|pair_coeff keywords after the horizon]
declare -a MODELS=("lps|" "pmb|" "nospd|stabilization none" "nospd|stabilization silling 0.5"
  "nospd|stabilization hourglass 0.2" "nospd|stabilization wan" "nospd|strain finite"
  "nospd|strain neohookean"
  "nospd|strain formula|energy 0.5*mu*(I1-3)-mu*log(J)+0.5*lambda*log(J)^2 param mu 1.538461538e10 param lambda 2.307692308e10"
  "nospd|strain formula|energy C10*(I1b-3)+C01*(I2b-3)+0.5*K*(J-1)^2 param C10 6e9 param C01 1.692307692e9 param K 3.333333333e10"
  "nospd|strain small|yield 1e9" "nospd|strain small|yield 2e6 hardening linear 1e9"
  "nospd|strain hencky|yield 2e6 hardening linear 1e9"
  "nospd|strain hencky|johnson_cook 2e6 1e8 0.3 0.01 1 1 293 1000 heat 900 0.9"
  "hs|form II" "hs|form II stencil no" "hs|form I"
  "hs|form II strain small|yield 2e6 hardening linear 1e9"
  "hs|form II strain hencky|yield 2e6 hardening linear 1e9"
  "omp2:nospd|stabilization silling 0.5" "np2:nospd|stabilization silling 0.5"
  "np2:lps|" "omp2:hs|form II" "np2rcb:nospd|stabilization silling 0.5" "np2rcb:lps|"
  "d2:nospd|stabilization silling 0.5" "d2:hs|form II" "d2:hs|form II stencil no"
  "p3:nospd|stabilization silling 0.5" "p3:hs|form II" "p3:hs|form II stencil no"
  "heat:nospd|stabilization silling 0.5")
# the rows this run keeps, parsed once
declare -a STYLE SETTINGS COEFF LAUNCH
for m in "${MODELS[@]}"; do
  if [ -n "${BENCH_ONLY:-}" ] && [ "$m" != "lps|" ] && ! grep -Eq -- "$BENCH_ONLY" <<< "$m"; then continue; fi
  launch=1; [[ "$m" == *:* && "${m%%|*}" == *:* ]] && { launch=${m%%:*}; m=${m#*:}; }
  rest=${m#*|}; settings=${rest%%|*}; coeff=""
  [ "$rest" != "$settings" ] && coeff=${rest#*|}
  STYLE+=("${m%%|*}"); SETTINGS+=("$settings"); COEFF+=("$coeff"); LAUNCH+=("$launch")
done
nrows=${#STYLE[@]}
# Repeats go round the rows (row 1, row 2, ..., then row 1 again), not one
# row's repeats in a row: this kind of machine's speed drifts by tens of
# per cent over minutes, and a drift then spreads over every row instead of
# landing on one, so the ratios between rows hold better.  Each row keeps
# its best loop time, its points and its logged memory.
declare -a BEST POINTS MEM
# what a row's launch means: the command's prefix and suffix, n, ranks and threads
set_launch() {
  pre=(); post=(); n=$N; ranks=1; threads=1
  case $1 in
    omp2) post=(-sf omp -pk omp 2); threads=2 ;;
    np2) pre=(mpirun --allow-run-as-root -np 2); ranks=2 ;;
    np2rcb) pre=(mpirun --allow-run-as-root -np 2); post=(-var rcb yes); ranks=2 ;;
    d2) post=(-var dim 2); n=${BENCH_N2:-200} ;;
    p3) post=(-var periodic yes) ;;
    heat) post=(-var heat yes) ;;
  esac
}
for r in $(seq "$REPEATS"); do
  for k in $(seq 0 $((nrows - 1))); do
    style=${STYLE[$k]}; set_launch "${LAUNCH[$k]}"
    "${pre[@]}" "$LMP" -in "$HERE/in.block" -var n "$n" -var style "$style" \
      -var settings "${SETTINGS[$k]}" -var coeff "${COEFF[$k]}" -var steps "$STEPS" -log none \
      -screen "$OUT/screen.txt" "${post[@]}"
    t=$(grep "Loop time" "$OUT/screen.txt" | tail -1 | awk '{print $4}')
    BEST[$k]=$(awk -v a="${BEST[$k]:-1e30}" -v b="$t" 'BEGIN{print (b<a)?b:a}')
    POINTS[$k]=$(grep "Loop time" "$OUT/screen.txt" | tail -1 | awk '{print $(NF-1)}')
    MEM[$k]=$(awk '/bond and reference state/{print $(NF-1)}' "$OUT/screen.txt" | head -1)
  done
done
lps_rate=""
for k in $(seq 0 $((nrows - 1))); do
  style=${STYLE[$k]}; launch=${LAUNCH[$k]}; settings=${SETTINGS[$k]}; coeff=${COEFF[$k]}
  set_launch "$launch"
  best=${BEST[$k]}; points=${POINTS[$k]}; mem=${MEM[$k]}
  # the pair style's per-point work arrays: B with the stabilization scalar (10), T (9), moments (6)
  [ -n "$mem" ] && mem=$((mem + 25 * 8))
  rate=$(awk -v p="$points" -v s="$STEPS" -v t="$best" 'BEGIN{printf "%.4g", p*s/t}')
  [ "$style" = lps ] && [ "$launch" = 1 ] && lps_rate=$rate
  ratio=$(awk -v a="$rate" -v b="${lps_rate:-0}" 'BEGIN{ if (b>0) printf "%.3g", a/b; else print "" }')
  label="$settings${coeff:+ / $coeff}"
  [ "$launch" = np2rcb ] && label="$label [tiled, rcb]"
  [ "$launch" = d2 ] && label="$label [2D plane strain]"
  [ "$launch" = p3 ] && label="$label [periodic]"
  echo "peri/${style},$label,$ranks,$threads,$points,$STEPS,$best,$rate,$ratio,${mem:-}" >> "$CSV"
  [ "$style" = hs ] && style=nospd/hs
  printf "%-10s %-34s %dx%d %9s point-steps/s  x%-6s vs peri/lps  %s B/point\n" "peri/$style" "$label" \
    "$ranks" "$threads" "$rate" "$ratio" "${mem:-n/a}"
done
rm -f "$OUT/screen.txt"
echo "wrote $CSV"
