#!/usr/bin/python3
"""The performance tables of docs/performance-tables.md, one per backend, made from stored measurements.

  performance_tables.py [--bench FILE ...] [--gpu FILE] [--cluster FILE] [--out FILE] [--check]

  --bench    Google Benchmark output of cmc_bench (`--benchmark_format=json`, or
             `--benchmark_out=FILE --benchmark_out_format=json`); several files are merged, a later
             one's benchmark replacing an earlier one's of the same name
             (default reference/performance/cpu-benchmark.json)
  --gpu      the CUDA backend's runs: the records with backend "cuda" of the run store
             reference/challenge/runs.json (scripts/gpu/store.py)
  --cluster  the distributed runs' measurements, reference/cluster/measurements.json
             (scripts/cluster/measure.py); the cost model is scripts/cluster/cost_model.py's
  --out      where to write (default docs/performance-tables.md; '-': standard output)
  --check    write nothing; exit 1 if --out differs from what the inputs make (a stale or
             hand-edited table), 0 if it is current

Every number is read from the inputs; nothing is typed in. Missing inputs become a line saying
which command makes them. Exit 2 on an unreadable input.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.report.performance_tables import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
