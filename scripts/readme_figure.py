#!/usr/bin/python3
"""Draw the README's first figure from the stored references (cmc.report.readme_figure):

    /usr/bin/python3 scripts/readme_figure.py [--ref DIR] [--out PNG]
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.report.readme_figure import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
