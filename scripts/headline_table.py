#!/usr/bin/python3
"""The README's headline results, generated from reference/challenge/best_estimates.json: the
block between the markers <!-- headline:begin --> and <!-- headline:end -->.

    /usr/bin/python3 scripts/headline_table.py [--check] [README.md]

Without --check the block is rewritten in place (the rest of the file untouched); with --check
nothing is written and the exit status is 1 when the block differs from what the best estimates
give (the docs check runs this), 2 when the file has no markers.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.report.headline_table import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
