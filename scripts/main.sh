#!/usr/bin/env bash
# The main job (README.md, first command): install what is missing, build, then run the
# Contact Mechanics Challenge at the default grid (2048², the smallest that holds the whole
# surface spectrum) and write the challenge report (reports/challenge/index.md):
#   - the reference load (250 kPa) with and without adhesion (quantities 1, 3, 4, 5, 9);
#   - with adhesion, the load sweep 12.5 kPa .. 100 MPa, to full contact (quantities 2 and
#     8), and the Tabor sweep mu_T = 0.001 .. 3 (quantities 6 and 7, 15 values).
# About 8 min on 2 cores after the build (docs/challenge/README.md). The report opens with the stored best estimates
# (reference/challenge/best_estimates.json: the finest runs the project has, CPU or GPU) and
# puts these runs beside them; scripts/sweeps.sh and scripts/gpu/reference_plan.py make the
# runs behind the best estimates.
#   scripts/main.sh            everything above
#   scripts/main.sh --quick    only the two runs at the reference load (about two minutes)
# Results: results/challenge-*/. A run interrupted half-way continues where it stopped
# when this is run again; finished runs are kept.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "main: unknown argument '$a' (expected --quick or nothing)" >&2; exit 2 ;;
  esac
done
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
run cases/challenge/reference-load.toml results/challenge-reference
run cases/challenge/reference-load-hardwall.toml results/challenge-hardwall
if [ $quick -eq 0 ]; then
  run cases/challenge/load-sweep.toml results/challenge-load-sweep
  scripts/tabor_sweep.sh
fi
scripts/report.sh --only challenge
echo "main: report in reports/challenge/index.md" >&2
