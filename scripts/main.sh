#!/usr/bin/env bash
# The main job (README, first command): install what is missing, build, then run the
# Contact Mechanics Challenge at the reference load (250 kPa) on the default grid
# (2048², the smallest that holds the whole surface spectrum), with and without
# adhesion, and write the challenge report (reports/challenge/index.md).
# Results: results/challenge-reference/ and results/challenge-hardwall/. The load and Tabor
# sweeps (quantities 2, 6-8) take about 25 min more: scripts/sweeps.sh runs them; until then the report
# draws the stored reference curves (reference/challenge/) and says so.
# A run interrupted half-way continues where it stopped when this is run again.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# FFT plans come from the wisdom built into cmc (the same bits on every run); with
# CMC_FFTW_PLANNER=measure they are timed at run time and kept in this wisdom file.
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
mkdir -p results
run() {  # case, output folder
  if [ -f "$2/summary.json" ] && grep -q '"status" : "converged"' "$2/summary.json" &&
     [ "$2/summary.json" -nt "$1" ] && [ "$2/summary.json" -nt build/cmc ]; then
    echo "main: $2 is up to date" >&2
    return 0
  fi
  echo "main: build/cmc run $1 --out $2" >&2
  build/cmc run "$1" --out "$2" --resume || [ $? -eq 3 ]   # 3: not converged, reported in the summary
}
[ -f cases/challenge/reference-load.toml ] && run cases/challenge/reference-load.toml results/challenge-reference
run cases/challenge/reference-load-hardwall.toml results/challenge-hardwall
scripts/report.sh --only challenge
echo "main: report in reports/challenge/index.md" >&2
