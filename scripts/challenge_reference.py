#!/usr/bin/python3
"""Regenerate the challenge reference curves reference/challenge/<quantity>.csv (and
reference/challenge/README.md) from cmc's own challenge runs.

    /usr/bin/python3 scripts/challenge_reference.py [--results results] [--out reference/challenge] [--cmc build/cmc]
                                                    [--only tabor|reference-load]

Inputs (read only, SI, layout of solver/cmc/output/Writer.cpp):
  results/**/                         the runs at 250 kPa with summary.json + result.h5
                                      step_*/observables, of each problem (adhesion with mu_T = 3,
                                      also the scaled family's member s = 1, which is the
                                      challenge; the hard wall) -> items 1, 3, 4, 5, 9 from the
                                      finest run that has a coarser grid of the same case and
                                      strategy, their bands twice the change from that grid
  results/challenge-load-sweep/       adhesive load sweep, if present -> items 2, 8
  results/challenge-tabor-sweep/*/    adhesive Tabor sweep, if present -> items 6, 7
  results/challenge-tabor-sweep-n*/*/ the same sweep on finer grids (scripts/tabor_sweep.sh --grid N), if
                                      present: the bands of items 6, 7 where they resolve rho
  results/refine/reference-load-hardwall/refinement.json
                                      hard-wall refinement study (`cmc refine`), quoted in
                                      estimated_error for context only (the adhesive curves have
                                      no study yet)

The curves are the same numbers as reports/challenge/data/*.csv: the extraction
(run discovery, the step at the reference load, the observables subgroup, bin centres)
is the challenge report's (python/cmc/report/challenge_runs.py); the work is done in
python/cmc/references/. Bins with zero density are left out of
log-scaled curves (the checker would drop them anyway). This script computes no number
of its own: grid spacings relative to rho and lambda_s come from summary.json
surface_facts, the refinement changes from cmc refine, and cmc formats and writes each
file (`build/cmc reference --run-curve SPEC --out FILE`, validation/References.cpp
make_run_curve and write_curve), so tests/test_references.cpp re-formats them to
themselves. Output is a function of the inputs only: the `date` is the run's
summary.json modification time (UTC). Each file is written atomically. Nothing is
deleted: a quantity without data keeps no file only if none was there before (remove
stale files by hand).
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.references.challenge import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
