#!/usr/bin/python3
"""Run the challenge on many realisations of its surface spectrum (surface.seed), for the
ensemble and realisation references (python/cmc/analysis/ensemble.py):

    /usr/bin/python3 scripts/ensemble.py --out DIR [--kinds K1,K2,...] [--seeds 1-32] [--holdout 101-110]
        [--n 2048] [--backend cpu|cuda] [--workers W] [--threads T] [--block B] [--deadline S]
        [--cmc build/cmc] [--set KEY=VALUE ...] [--skip-stored STORE] [--tabor-seeds A-B] [--dry-run]

Kinds, in the order given (the default is every kind, in the order below):
  hardwall_load       the hard-wall load sweep (cases/challenge/load-sweep-hardwall.toml), on the
                      ensemble's seeds and the held-out ones
  reference_hardwall  the hard wall at 250 kPa with its observables (distributions, spectrum)
  reference           the same with the challenge's adhesion (cases/challenge/reference-load.toml)
  load                the adhesive load sweep, plain (cases/challenge/load-sweep.toml)
  tabor               the Tabor sweep's points (cases/challenge/tabor-values) at 250 kPa

Each unit of work is one kind on a block of B seeds: one `cmc sweep` over surface.seed (and
interaction.tabor for the Tabor points) into DIR/<kind>/<backend>-n<N>-s<first>-<last>/. W units
run at a time, each with CMC_THREADS=T. A unit still running at the deadline is stopped; its
sweep is resumable, so the same command later finishes it and skips what is done. Without fields:
result.h5 holds the observables alone. Exit 0 when every unit finished, 3 when the deadline
stopped some, 2 for bad arguments. --skip-stored STORE leaves out the seeds whose runs of a kind
on this grid the ensemble's store (reference/challenge/ensemble/runs.json) already holds, every
point converged (every mu_T for the Tabor points).
"""
import os
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.ensemble_runner import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__, os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))))
