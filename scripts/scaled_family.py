#!/usr/bin/python3
"""The scaled challenge family: converged adhesive references where they are
affordable, and plain coarse runs beside them.

    /usr/bin/python3 scripts/scaled_family.py [--s 32 16] [--coarse 2 4] [--grids N ...] [--no-resolved]
                                              [--start-resolved] [--refinement-only] [--max-outer-resolved N]
                                              [--no-plain] [--no-hardwall]
                                              [--strategies range shape]
                                              [--results results/scaled-family] [--store reference/challenge-scaled]
                                              [--cmc build/cmc] [--set KEY=VALUE ...] [--dry-run]
                                              [--seed N] [--tabor MU] [--pressure PA]

Member s of the family is cases/challenge/scaled-family.toml with
surface.cutoff_wavelength = s x 0.1 µm and interaction.work_of_adhesion = s x 0.05 J/m²
(mu_T = 3, so rho(s) follows from the surface's R_c). For each s it runs, on the loading
branch at 250 kPa:
  resolved     the smallest power-of-two grid with dx <= 0.8 rho(s)   -> the reference value
               (and dx <= lambda_s/64, which only a lower mu_T than 3 makes the finer bound)
  refinement   half that grid (dx <= 1.6 rho(s))                        -> its refinement error
  plain_<k>rho the FFT-friendly grid (factors 2, 3, 5) nearest dx = k rho(s), for each k of
               --coarse (default 2 and 4, the spacings the resolution strategy targets; 6, 12
               and 24 match the challenge's own 8192², 4096² and 2048² in dx/rho AND dx/lambda_s,
               since rho/lambda_s is the same for every s)
  range_<k>rho, shape_<k>rho   the same grids with interaction.coarse_graining = "range" or "shape"
               (the two resolution strategies; --strategies picks)
  plain_n<N>, range_n<N>, shape_n<N>   explicit grids of --grids (the challenge itself, s = 1, which no
               grid here resolves: use --s 1 --no-resolved --grids 2048 4096)
--start-resolved starts the resolved run from the refinement run's answer (cmc run
--start-from, solver/cmc/output/CoarseStart.hpp; the refinement run then writes its fields
into n<N>-fields/): about 0.6 of a cold start's FFT pairs, with the same a_r where measured
(s = 32 at 2048²; s = 16 at 4096²); its record says so ("start_from"). The s = 8 member's
8192² run needs it, and still takes hours on 2 cores (1503 iterations in 73 outer steps and
2.4 h, unconverged); it resumes from its checkpoint.
--max-outer-resolved N caps the resolved run's outer steps (solver.max_outer_steps; cmc's
default 1000). A resumed run may lower the cap to just above the outer steps it has made
(docs/user-guide/command-line.md): it then stops there, status not_converged, and the
stored reference says so (its status and last tension change), for a run that creeps for
hours towards its tension tolerance (s = 8).
rho(s) is read from `cmc surface` (dx_over_range), never assumed. Runs go to
RESULTS/s<S>/n<N>/ through `cmc sweep`, one per case and set of overrides over its grids (its
table RESULTS/s<S>/sweep-<first role>.json): a finished run is kept, an interrupted one resumes.

--tabor MU and --pressure PA run the family at another condition than the challenge's
(mu_T = 3, 250 kPa): the Tabor sweep's and the load sweep's points (challenge items 2, 6, 7
and 8), whose error bands are the family's error measured at mu_T = 3 and 250 kPa. A
condition's runs go to RESULTS/conditions/<condition>/ and its store holds that condition
only (e.g. --store reference/challenge-scaled/conditions/mu_T1): it measures whether the
bands hold there (cmc.analysis.conditions, condition_checks), and the sweeps' references take the
larger of the two errors (run_band, load_bands); the challenge's own error bars (s = 1 at
250 kPa) take nothing from it. The hard-wall runs get the pressure too (mu_T is adhesion's).

--store merges into STORE/scaled_family.json (members and runs of this invocation replace
those with the same s and role; others are kept) and rewrites STORE/README.md from it:
STORE/scaled_family.json (every run: command, grid, dx/rho, tolerance,
iterations, FFT pairs, wall time, a_r, repulsive a_r, mean gap; per s the reference with
its refinement error) and STORE/README.md, each atomically. The reference of a quantity
is its value on the resolved grid; its refinement error is |resolved - refinement|, which
bounds the resolved grid's own error if the error falls at least linearly with dx (for
order p it is |difference| / (2^p - 1)); the README states it as such. Numbers come from
the runs' summary.json only.
"""
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.family.command import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
