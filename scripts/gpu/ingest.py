#!/usr/bin/python3
"""Turn the file scripts/gpu/reference_plan.py made on a GPU machine into the run store, the best
estimates and the challenge references:

    /usr/bin/python3 scripts/gpu/ingest.py PLAN.tgz [--store FILE] [--out DIR] [--results DIR] [--cmc build/cmc]
        [--replace] [--accept-outlier]

1. every run in it goes into the run store (scripts/gpu/store.py; device, date and commit from
   the file's machine.txt and build.txt): a converged run with an impossible value or out of
   force balance stops the ingest (exit 2); one not converged is listed and left out;
2. its run folders (summary.json and result.h5 with the observables) are copied to
   RESULTS/gpu/<date>/<tag>/, where scripts/report.sh and scripts/challenge_reference.py find them;
3. scripts/best_estimates.py rewrites best_estimates.json beside the curves, and
   scripts/apply_best_estimates.py the curves they decide (OUT, default reference/challenge).

The archive is untrusted input (python/cmc/gpu_plan/archive.py): its names, modes, size and numbers are
checked before anything is written. All or nothing: the new store, best estimates, curves and run
folders are made in a scratch folder and checked; only then do they replace the old ones, by
renames. Any failure leaves every file as it was; the same archive twice gives the same bytes.
A stored tag or run folder holding something else is replaced only with --replace. A best
estimate from a new, finer grid that lies outside the previous estimate's band by more than
three band widths (python/cmc/analysis/plausibility.py) is adopted only with --accept-outlier.
Defaults write into the repository; --store, --out and --results elsewhere leave it untouched.
Exit codes: 0 done, 2 the archive or an argument refused (nothing written), 1 a step failed
(nothing written).
"""
import os
import sys

from cmc.gpu_plan.ingest import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__, os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))))
