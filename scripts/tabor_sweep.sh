#!/usr/bin/env bash
# The challenge's Tabor sweep (quantities 6 and 7): the reference load with every
# parameter fixed but the adhesion range, mu_T = 0.001 .. 3 on a log grid (15 values, 10^(1/4)
# apart, listed in cases/challenge/tabor-values; 3 is the challenge's), one run each.
#   scripts/tabor_sweep.sh [--grid N] [--tabor "MU MU ..."] [--cases DIR --root DIR] [--set key=value ...]
#   (the rest goes to cmc sweep)
#   --tabor: these mu_T only (any positive numbers, e.g. points between the sweep's near the
#   mean gap's minimum); CMC=path: another cmc binary (e.g. a build
#   with -DCMC_WISDOM_MAX_N=8192 for --grid 8192, whose FFTs the default build plans by estimate).
# Results: results/challenge-tabor-sweep/mu_T_<value>/ on the case's 2048² grid, or
# results/challenge-tabor-sweep-n<N>/mu_T_<value>/ with --grid N (the refinement of the
# sweep on the challenge itself: scripts/challenge_reference.py reads the 4096² and 8192²
# sweeps for the bands at low mu_T, where those grids resolve the adhesion). Finished runs are kept, an
# interrupted one resumes. Then scripts/report.sh draws the two figures.
# Grids the CPU cannot hold (16384²) ran on a GPU: scripts/gpu/check.sh tabor:N:MU (docs/user-guide/gpu.md),
# its summary.json copied to results/challenge-tabor-sweep-n<N>/mu_T_<MU>/ (the report marks it GPU).
# --cases DIR --root DIR: DIR/tabor-sweep.toml into ROOT/mu_T_<value>/ (scripts/main.sh --surface:
# the challenge's cases on the user's surface, in a results folder of their own).
set -euo pipefail
cd "$(dirname "$0")/.."
root=results/challenge-tabor-sweep
given_root=""
cases=cases/challenge
extra=()
all=$(grep -v '^#' cases/challenge/tabor-values)
mus="$all"
while [ $# -gt 0 ]; do
  case "$1" in
    --grid)
      case "${2:-}" in
        ''|*[!0-9]*) echo "tabor_sweep: --grid needs a number of points per side, e.g. --grid 4096 (got '${2:-}')" >&2; exit 2 ;;
      esac
      root="results/challenge-tabor-sweep-n$2"
      extra=(--set "grid.n=$2")
      shift 2 ;;
    --tabor)
      for mu in ${2:-}; do
        [[ "$mu" =~ ^[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?$ ]] && [[ ! "$mu" =~ ^[0.]+$ ]] ||
          { echo "tabor_sweep: --tabor: '$mu' is not a positive number (the sweep's: $all)" >&2; exit 2; }
      done
      [ -n "${2:-}" ] || { echo "tabor_sweep: --tabor needs a list of mu_T, e.g. --tabor \"0.0562 0.1\"" >&2; exit 2; }
      mus="$2"
      shift 2 ;;
    --cases|--root)
      [ -n "${2:-}" ] || { echo "tabor_sweep: $1 needs a folder" >&2; exit 2; }
      if [ "$1" = --cases ]; then cases="$2"; else given_root="$2"; fi
      shift 2 ;;
    *) break ;;
  esac
done
root="${given_root:-$root}"
cmc="${CMC:-build/cmc}"
scripts/setup.sh
# FFT plans come from the wisdom built into cmc (the same bits on every run); with
# CMC_FFTW_PLANNER=measure they are timed at run time and kept in this wisdom file.
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
# One cmc sweep over the values (docs/user-guide/sweep.md): a finished run is kept, an
# interrupted one resumes, one not converged is reported (exit 3) and the sweep goes on.
values=$(echo $mus | tr ' ' ',')
"$cmc" sweep "$cases/tabor-sweep.toml" --out "$root" --over "interaction.tabor=$values" \
  --folder 'mu_T_{interaction.tabor}' ${extra[@]+"${extra[@]}"} "$@" || [ $? -eq 3 ]
