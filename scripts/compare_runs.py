#!/usr/bin/python3
"""Compare two run folders (or two folders of run folders) bit for bit.

usage: scripts/compare_runs.py A B [--ignore KEY ...]

Every number and string of each summary.json (the wall-clock keys are left out: they
differ on every run; the counts in "timing", iterations and FFT pairs, are compared) and
every dataset and attribute of each result.h5 must be identical, and present in both.
Prints each difference and exits 1 if there is one, 0 if everything is identical. A
folder holding summary.json is one run; otherwise each subfolder holding one is compared
with its namesake in B. A run in A whose namesake in B has no summary.json is a difference.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.compare_runs import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
