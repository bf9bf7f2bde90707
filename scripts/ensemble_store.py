#!/usr/bin/python3
"""Store the seed ensemble's runs (scripts/ensemble.py, or the ensemble.tgz of
scripts/gpu/full_plan.sh) in reference/challenge/ensemble/runs.json, one record per point:

    /usr/bin/python3 scripts/ensemble_store.py SOURCE [SOURCE ...] [--store FILE] [--device D] [--date D]
                                               [--commit C] [--origin NAME]

SOURCE: a folder scripts/ensemble.py wrote (--out), or the archive of one. An archive is read in
memory and never unpacked: only regular files named like the ensemble's (KIND/UNIT/surface.seed_N/
[interaction.tabor_MU/]summary.json, and machine.txt) are read, each at most 4 MiB, at most
20,000 of them; anything else in it is refused (exit 2). Device, date and commit come from the
archive's machine.txt and build.txt where not given. A point whose summary is impossible (a_r
outside [0, 1], a negative mean gap, a value that is not finite) is not stored, and is named.
A record replaces one of the same tag (kind, backend, grid, seed, mu_T).
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.store.ensemble import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
