#!/usr/bin/env python3
"""The runs behind the challenge's best estimates, on one GPU within one deadline, packed into one
file that scripts/gpu/ingest.py turns into the run store and reference/challenge/.

    scripts/gpu/reference_plan.py [--deadline S] [--scale K] [--cpu] [--pack DIR] [--tar FILE]
                                  [--work DIR] [--skip P,...] [--keep-all] [--dry-run]

The plan, in order of what the references gain (each stage capped; a stage whose estimate does
not fit in the time left is dropped before anything starts, and the plan says so):
  1. the hard wall at 250 kPa on 8192² and 16384², and the challenge with the shape
     coarse-graining on 8192², with their observables (distributions, spectrum, cross sections:
     result.h5 without fields);
  2. the hard-wall load sweep on 2048² to 16384² (the adhesionless curves at every load);
  3. the adhesive load sweep with shape on 2048², 4096² and 8192² (items 2 and 8 at every load);
  4. the challenge with shape on 16384², with its observables (the headline's own run);
  5. the Tabor sweep on 8192²: plain where that grid resolves rho (mu_T <= 0.562), shape above;
  6. the plain challenge on 16384² with its fields, then on 32768² started from it (the
     challenge's own check of the shape strategy: plain approaching it from below).
Estimates come from the run store (reference/challenge/runs.json: the same kind of run on the
same backend, scaled by the grid's points where only another grid was run, and by the present
solver's iterations over the stored run's program's, measured on the CPU:
python/cmc/gpu_plan/iteration_scale.py)
plus a start-up allowance. After the plan, the dry run says what every stage together needs and
which stage is too long for a deadline of its own. Stages are kept in order while their estimates
fit in the deadline; each stage's cap is its estimate plus half (and 10 s), the deadline cuts the
last one short, and quasi-static solves stop themselves inside their cap (scripts/gpu/check.sh:
solver.max_seconds), so every run leaves its summary.

--scale K divides every grid by K and --cpu runs the same stages on the CPU backend: the whole
plan, end to end, at small grids (the test command runs it with --scale 64 --cpu). The pack is
scripts/gpu/pack.sh's (--pack, default .gpucarry); the results go to --tar (default
$OUT/reference-plan.tgz where $OUT is set), with the machine's description and the build's commit.
The work is cmc.gpu_plan.plan's (standard library only): scripts/gpu/full_plan.sh puts the
checkout's python/ on PYTHONPATH; by hand, `. scripts/python_path.sh` first.
"""
import os
import sys

from cmc.gpu_plan.plan import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__, os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))))
