#!/usr/bin/env bash
# The challenge's Tabor sweep (quantities 6 and 7): the reference load with every
# parameter fixed but the adhesion range, mu_T = 0.0562 .. 3 on a log grid (8 values, 10^(1/4) apart; 3 is the challenge's), one run each.
#   scripts/tabor_sweep.sh [--set grid.n=1024 ...]     (extra arguments go to cmc run)
# Results: results/challenge-tabor-sweep/mu_T_<value>/; finished runs are kept, an
# interrupted one resumes. Then scripts/report.sh draws the two figures.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# FFT plans come from the wisdom built into cmc (the same bits on every run); with
# CMC_FFTW_PLANNER=measure they are timed at run time and kept in this wisdom file.
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
for mu in 0.0562 0.1 0.178 0.316 0.562 1.0 1.78 3.0; do
  out="results/challenge-tabor-sweep/mu_T_$mu"
  if [ -f "$out/summary.json" ] && grep -q '"status" : "converged"' "$out/summary.json"; then
    echo "tabor_sweep: mu_T = $mu done ($out)" >&2
    continue
  fi
  echo "tabor_sweep: mu_T = $mu -> $out" >&2
  build/cmc run cases/challenge/tabor-sweep.toml --out "$out" --resume --set interaction.tabor="$mu" "$@" || [ $? -eq 3 ]
done
