#!/usr/bin/env python3
"""The record of scripts/bench_iterations.sh: its runs' iterations, shape/plain per grid,
warm/cold per doubling, this build against the one before (--before), each shape answer
against the stored one of the same command, and the factors scripts/gpu/reference_plan.py
scales the stored runs' times by (plan_factors: this build's iterations over the one
before's, per strategy, on the finest grid that has both; the warm start's over the cold).

usage: bench_iterations_table.py RUNS_DIR JSON_PATH TOLERANCE GRID [GRID ...]
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.bench_iterations import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
