#!/usr/bin/python3
"""Write the challenge's best estimates (reference/challenge/best_estimates.json) from the run
store (reference/challenge/runs.json) and the scaled family's stores, and print them.

    /usr/bin/python3 scripts/best_estimates.py [--store FILE] [--out FILE] [--family FILE]

Which run is best at each point and why is decided in python/cmc/analysis/best.py (the finest
converged run of the sequence with the smallest error in a_r; docs: the challenge's method).
The file is deterministic given the stores: scripts/challenge_reference.py, the challenge report,
`cmc check` (through reference/challenge/*.csv) and the README's headline table read it.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.references.best_estimates import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
