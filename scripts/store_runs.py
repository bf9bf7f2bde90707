#!/usr/bin/python3
"""Store finished runs from `cmc run` output folders in the run store (reference/challenge/runs.json),
where the best estimates (scripts/best_estimates.py) find them.

    /usr/bin/python3 scripts/store_runs.py [--device TEXT] [--commit HASH] [--origin NAME] [--store FILE] RUN_DIR ...

Each RUN_DIR holds a summary.json (e.g. results/challenge-tabor-sweep-n4096/mu_T_0.01). Its record
(python/cmc/analysis/runs.py) is tagged <backend>-<kind>-<n> (kind as scripts/gpu/check.sh names
it: hardwall, adhesive, shape, tabor_mu<MU>); the date is the summary's modification day (UTC);
the command is rebuilt from the case file and the overrides the summary records. --device
defaults to this machine's CPU model and core count, --commit to this checkout's HEAD (with
"-dirty" when it has changes: the program may have been built from another state; pass the
right one when you know it).
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.store.runs import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
