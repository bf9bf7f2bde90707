#!/usr/bin/python3
"""Write the ensemble and realisation references (reference/challenge/ensemble/ and
reference/challenge/realisation/, each with adhesionless/) and their summary
(reference/challenge/ensemble/summary.json) from the seed ensemble's store and the best estimates:

    /usr/bin/python3 scripts/ensemble_references.py [--store FILE] [--best FILE] [--out DIR] [--seeds 1-32]
                                                    [--cmc build/cmc]

Per row (a load, or a mu_T): the mean over the ensemble's surfaces at its grid, times the grid
correction of cmc's own surface (seed 28: best estimate / its value on the ensemble's grid);
the band combines that correction's error with twice the standard error (ensemble) or the 95 %
prediction interval of one more surface (realisation). Rows where seed 28 has no best estimate
are left out. How it is done: python/cmc/analysis/ensemble.py. `cmc check --against` reads them.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.references.ensemble import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
