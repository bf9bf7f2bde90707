#!/usr/bin/python3
"""Measure the round-off spread of the challenge's results: the same case run by two builds,
or at two thread counts, compared step by step.

usage: scripts/roundoff_spread.py [--out reference/challenge/roundoff_spread.json] NAME:RUN_A:RUN_B [...]

A rerun of one build at one thread count gives the same bits (ctest rerun.same_bits). Two
builds may not: each plans its FFTs at build time (FFTW_MEASURE, timed), and plans that
round differently, or another thread count (another summation order), move the adhesive
solution where it is marginally stable (at dx = 24 rho every grid point is bistable). That
spread is part of the error of every adhesive number; this script measures it
from pairs of finished runs of the same case (same loads, step by step) and writes, per
pair and over all pairs, the largest relative difference of a_r, repulsive a_r and mean
gap, with each run's thread count and built-in wisdom fingerprint (summary.json grid; older
runs lack them). cmc.report.common roundoff_note() states it in the report and in the
references' provenance.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.roundoff_spread import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
