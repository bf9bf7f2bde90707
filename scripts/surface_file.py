#!/usr/bin/python3
"""The challenge's cases on a surface of the user's: what scripts/main.sh --surface FILE runs.

  surface_file.py FILE [--cases DIR] [--results DIR]

Reads FILE's format and shape (the challenge's published layouts: an HDF5 file with one square
2-D dataset `surface`, a square real-space ASCII matrix, or a Fourier-coefficient list of lines
`kx ky re im`; heights in units of L = 0.1 mm, as the problem definition says) and its SHA-256,
then writes RESULTS/surfaces/<name>-<sha256's first 8 digits>/:
  cases/      the challenge's case files (--cases, default cases/challenge) with the surface of
              their base, challenge-base.toml, taken from FILE; the grid is the base's, or the
              file's where the file is finer or does not divide it (cmc never down-samples)
  surface.json  the file's path, format, points per side, bytes and SHA-256
and prints that folder. A file is rewritten only where its text changes, so finished runs stay
up to date. Exit 0: done; 2: FILE is missing or in none of the layouts (the message names it).
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.surface_file import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
