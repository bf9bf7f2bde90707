#!/usr/bin/env bash
# The long runs behind the stored challenge references (reference/challenge/ and
# reference/challenge/adhesionless/), then the references rewritten from them:
#   - quantities 2 and 8 (a_r and mean gap against load) with adhesion, 12.5 kPa .. 100 MPa,
#     and without it, to a_r ~ 1;
#   - quantities 6 and 7 (a_r and mean gap against mu_T = 0.001 .. 3, scripts/tabor_sweep.sh), and the
#     same sweep at mu_T <= 0.562 on 4096² and 8192², whose refinement gives the low-mu_T bands;
#   - the reference-load runs on the next finer grid (4096²), which give the distributions,
#     the spectrum and the headline numbers their bands, and the hard-wall sweep at five loads
#     on 4096², which gives the hard-wall sweep its band.
# All at the challenge's default grid (2048²) but the 4096² and 8192² ones. The main job
# (scripts/main.sh) runs the reference-load runs and the two adhesive sweeps itself; this
# adds the rest (on 2 cores: 6 min for the hard-wall sweep, about 5 min for the two 4096²
# reference-load runs, 51 min for the 4096² hard-wall sweep, measured with another job
# beside it, and about 75 min for the Tabor sweep's 4096² and 8192² runs at mu_T <= 0.562 and
# over an hour for mu_T = 1's), and the report
# draws their stored curves until they run. Every run resumes
# where it stopped: run this again after an interruption.
# cmc prints a progress line per load step (iterations, elapsed, estimated remaining).
#   scripts/sweeps.sh            (then scripts/report.sh --only challenge)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
mkdir -p results
run() {  # case, output folder, extra cmc arguments
  local case=$1 out=$2
  shift 2
  if [ -f "$out/summary.json" ] && grep -q '"status" : "converged"' "$out/summary.json"; then
    echo "sweeps: $out is done" >&2
    return 0
  fi
  echo "sweeps: build/cmc run $case --out $out $*" >&2
  build/cmc run "$case" --out "$out" --resume "$@" || [ $? -eq 3 ]   # 3: not converged, said in the summary
}
run cases/challenge/reference-load.toml results/challenge-reference
run cases/challenge/reference-load-hardwall.toml results/challenge-hardwall
run cases/challenge/reference-load-hardwall.toml results/challenge-hardwall-n4096 --set grid.n=4096
run cases/challenge/reference-load.toml results/challenge-reference-n4096 --set grid.n=4096
run cases/challenge/load-sweep-hardwall.toml results/challenge-load-sweep-hardwall
# The hard-wall sweep again on 4096² at five loads: the change between the grids is the
# band of the stored sweep (interpolated in log p between these loads).
run cases/challenge/load-sweep-hardwall.toml results/challenge-load-sweep-hardwall-n4096 --set grid.n=4096 \
  --set 'loading.values=[12.5e3,250e3,2.5e6,10e6,25e6]'
scripts/tabor_sweep.sh
# The Tabor sweep refined on the challenge itself where rho is long (a bistability number
# w dx/(E* rho^2) <= 1.49 on the coarser grid of a pair, as on the family's refinement grids:
# mu_T <= 0.562): the bands of items 6 and 7 there (python/cmc/analysis/refinement.py own_band). About 10
# min for the five 4096² runs and 65 min for the five 8192² ones on 2 cores.
low="0.001 0.00178 0.00316 0.00562 0.01 0.0178 0.0316 0.0562 0.1 0.178 0.316 0.562"
scripts/tabor_sweep.sh --grid 4096 --tabor "$low"
scripts/tabor_sweep.sh --grid 8192 --tabor "$low"
# mu_T = 1 on the same two grids (b = 1.26 and 0.63). On 4096² with inner solves to 1e-8: at the
# case's 1e-6 that run's outer iteration is held up by the inner solves' error and stops at its
# cap after 1000 outer steps (docs/theory/loading-branch.md, "Creep"); 4 min on 2 cores.
# On 8192² the same (at 1e-6 it crept for 156 outer steps and was stopped). The stored run was started from the 4096² one (--start-from) and
# took 66 min on 2 cores; this line starts from out of contact (not timed).
scripts/tabor_sweep.sh --grid 4096 --tabor 1.0 --set solver.tolerance=1e-8
scripts/tabor_sweep.sh --grid 8192 --tabor 1.0 --set solver.tolerance=1e-8
# The adhesive sweep: one quasi-static loading path from out of contact, 12.5 kPa .. 100 MPa.
run cases/challenge/load-sweep.toml results/challenge-load-sweep
# The Tabor runs join the run store, and the best estimates are made again from it (the curves
# of items 6 and 7, and the 250 kPa rows of items 2 and 8, come from them).
. scripts/python_path.sh  # the package cmc (the build's) and the modules reports/ shares
/usr/bin/python3 scripts/store_runs.py results/challenge-tabor-sweep*/mu_T_*
/usr/bin/python3 scripts/best_estimates.py
/usr/bin/python3 scripts/challenge_reference.py
echo "sweeps: references rewritten (reference/challenge/); scripts/report.sh --only challenge draws them" >&2
