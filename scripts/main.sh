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
#   scripts/main.sh                 everything above
#   scripts/main.sh --quick         only the two runs at the reference load (about two minutes)
#   scripts/main.sh --surface FILE  the same runs on the surface in FILE (the challenge's published
#                                   layouts: HDF5, ASCII or Fourier list, heights in units of L)
# Results: results/challenge-*/; with --surface, results/surfaces/<file>-<sha256>/ and the report in
# reports/surfaces/<file>-<sha256>/challenge/ (docs/user-guide/your-surface.md). A run interrupted
# half-way continues where it stopped when this is run again; finished runs are kept.
set -euo pipefail
called_from="$PWD"
cd "$(dirname "$0")/.."
quick=0
surface=""
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --surface)
      [ -n "${2:-}" ] || { echo "main: --surface needs a file (the challenge's published HDF5, ASCII or Fourier list)" >&2; exit 2; }
      surface="$2"; shift ;;
    -h|--help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "main: unknown argument '$1' (expected --quick, --surface FILE or nothing)" >&2; exit 2 ;;
  esac
  shift
done
case "$surface" in ''|/*) ;; *) surface="$called_from/$surface" ;; esac  # a path as the caller meant it
if [ -n "$surface" ] && [ ! -f "$surface" ]; then
  echo "main: --surface $surface: no such file (expected the challenge's published HDF5, ASCII or Fourier list)" >&2
  exit 2
fi
scripts/setup.sh
# The cases and the folder their runs go to: the challenge's own, or with --surface a copy of
# them on the user's surface, in a folder of their own (scripts/surface_file.py).
cases=cases/challenge
root=results
reports=reports
if [ -n "$surface" ]; then
  . scripts/python_path.sh  # the package cmc (the build's), which scripts/surface_file.py calls
  root=$(/usr/bin/python3 scripts/surface_file.py "$surface" --cases "$cases" --results results) || exit $?
  cases="$root/cases"
  reports="reports/surfaces/$(basename "$root")"
fi
# FFT plans come from the wisdom built into cmc (the same bits on every run); with
# CMC_FFTW_PLANNER=measure they are timed at run time and kept in this wisdom file.
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
mkdir -p results
run() {  # case, output folder; a converged run newer than its case, their base and cmc is kept
  if [ -f "$2/summary.json" ] && grep -q '"status" : "converged"' "$2/summary.json" &&
     [ "$2/summary.json" -nt "$1" ] && [ "$2/summary.json" -nt "$(dirname "$1")/challenge-base.toml" ] &&
     [ "$2/summary.json" -nt build/cmc ]; then
    echo "main: $2 is up to date" >&2
    return 0
  fi
  echo "main: build/cmc run $1 --out $2" >&2
  # 3: not converged, reported in the summary; any other failure ends here with cmc's code (2: bad input)
  build/cmc run "$1" --out "$2" --resume || { rc=$?; [ $rc -eq 3 ] || exit $rc; }
}
run "$cases/reference-load.toml" "$root/challenge-reference"
run "$cases/reference-load-hardwall.toml" "$root/challenge-hardwall"
if [ $quick -eq 0 ]; then
  run "$cases/load-sweep.toml" "$root/challenge-load-sweep"
  scripts/tabor_sweep.sh --cases "$cases" --root "$root/challenge-tabor-sweep"
fi
scripts/report.sh --only challenge --results "$root" --out "$reports"
echo "main: report in $reports/challenge/index.md" >&2
