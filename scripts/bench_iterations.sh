#!/usr/bin/env bash
# Iterations of the adhesive challenge (the scaled family's s = 1 member: the challenge at
# 250 kPa, μ_T = 3, inner tolerance 1e-6) with the plain law and with the `shape`
# coarse-graining, on two grids, cold and started from the coarser grid's converged state
# (--start-from). Iteration counts do not depend on the device or the thread count's
# timing, so they are measured on the CPU; wall times are the run's own, noisy on a shared
# machine. Writes reference/performance/shape-iterations.json (or --json PATH): per run
# iterations, outer steps, FFT pairs, a_r, mean gap and solve time; per grid shape/plain;
# per doubling warm/cold; and the shape answer against the stored one of the same command
# (reference/challenge/runs.json, family-s1_shape-N).
#
# usage: scripts/bench_iterations.sh [--grids "2048 4096"] [--tolerance T] [--before BIN] [--no-warm]
#                                    [--out DIR] [--json PATH] [--jobs J]
#   --grids      the grids, coarse to fine (default "2048 4096"); the warm runs start each from the one before
#   --tolerance  the inner solves' tolerance (default 1e-6, the stored family runs')
#   --before     also the cold runs with another build's cmc (the program before a change):
#                its iterations against this build's are the factors scripts/gpu/reference_plan.py
#                scales the stored runs' times by
#   --no-warm    cold runs only
#   --out        where the runs go (default results/bench-iterations); finished runs are reused
#   --json       the record (default reference/performance/shape-iterations.json)
#   --jobs       runs at once, each on one thread (CMC_THREADS=1; default 2)
set -euo pipefail
cd "$(dirname "$0")/.."
grids="2048 4096" out=results/bench-iterations json=reference/performance/shape-iterations.json jobs=2
tolerance=1e-6 before="" warm=1
while [ $# -gt 0 ]; do
  case "$1" in
    --grids) grids="$2"; shift ;;
    --out) out="$2"; shift ;;
    --json) json="$2"; shift ;;
    --jobs) jobs="$2"; shift ;;
    --tolerance) tolerance="$2"; shift ;;
    --before) before="$2"; shift ;;
    --no-warm) warm=0 ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
    *) echo "bench_iterations: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "bench_iterations: --jobs '$jobs' is not a whole number from 1" >&2; exit 2; }
cmc=build/cmc
[ -x "$cmc" ] || { echo "bench_iterations: $cmc is not built (scripts/setup.sh)" >&2; exit 2; }
[ -z "$before" ] || [ -x "$before" ] || { echo "bench_iterations: --before '$before' is not an executable cmc" >&2; exit 2; }
/usr/bin/python3 -c "import sys; t = float(sys.argv[1]); sys.exit(0 if 0 < t < 1 else 1)" "$tolerance" 2>/dev/null ||
  { echo "bench_iterations: --tolerance '$tolerance' is not a number between 0 and 1" >&2; exit 2; }
case_file=cases/challenge/scaled-family.toml
family=(--set case.name=challenge-scaled-s1 --set surface.cutoff_wavelength=1e-07
        --set interaction.work_of_adhesion=0.05 --set output.fields=true --set solver.tolerance="$tolerance")

# one run: strategy, grid, name, [coarse run dir or "before"]
one() {
  local strategy=$1 n=$2 name=$3 from=${4:-} dir="$out/$3" extra=() bin=$cmc
  [ "$strategy" = shape ] && extra+=(--set interaction.coarse_graining=\"shape\")
  if [ "$from" = before ]; then bin=$before; elif [ -n "$from" ]; then extra+=(--start-from "$from"); fi
  if [ -f "$dir/summary.json" ] && [ "$dir/summary.json" -nt "$bin" ]; then return 0; fi
  echo "bench_iterations: $bin run $case_file --set grid.n=$n ${family[*]} ${extra[*]}" >&2
  CMC_THREADS=1 "$bin" run "$case_file" --out "$dir" --quiet "${family[@]}" --set grid.n="$n" "${extra[@]}" || [ $? -eq 3 ]
}
# a batch of runs, $jobs at a time; each argument "strategy n name [from]"
batch() {
  local running=0
  for r in "$@"; do
    # shellcheck disable=SC2086
    one $r &
    running=$((running + 1))
    if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
  done
  wait
}
mkdir -p "$out"
prev=""
for n in $grids; do
  batch "plain $n plain-$n" "shape $n shape-$n"
  [ -z "$before" ] || batch "plain $n before-plain-$n before" "shape $n before-shape-$n before"
  if [ -n "$prev" ] && [ $warm = 1 ]; then
    batch "plain $n plain-$n-from-$prev $out/plain-$prev" "shape $n shape-$n-from-$prev $out/shape-$prev"
  fi
  prev=$n
done
. scripts/python_path.sh  # the package cmc, which the table command calls
/usr/bin/python3 scripts/bench_iterations_table.py "$out" "$json" "$tolerance" $grids
