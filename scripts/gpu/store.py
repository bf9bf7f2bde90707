#!/usr/bin/python3
"""Store runs made by scripts/gpu/check.sh in the run store (reference/challenge/runs.json).

    /usr/bin/python3 scripts/gpu/store.py --device "NVIDIA H200 143771 MiB" --date YYYY-MM-DD \
        [--commit HASH] [--origin NAME] [--store FILE] CHECK_OUT [CHECK_OUT ...]

CHECK_OUT: a folder check.sh wrote (--out): runs/<backend>-<kind>-<n>/summary.json and, beside
it, <tag>.command (the command as check.sh ran it), <tag>.gpu-memory (nvidia-smi's samples) and
build.txt (the commit the pack was built from, scripts/gpu/pack.sh). Each run becomes one record
(python/cmc/analysis/runs.py), replacing a record of the same tag. --commit overrides build.txt
(for packs made before it was written); --origin names the batch the runs came in (default: the
folder's name). A run that left no summary (stopped at its cap) or did not converge is listed
and not stored. A converged run is checked before it is stored (python/cmc/analysis/plausibility.py):
one with an impossible value, out of force balance, or whose tag does not match its grid makes
store.py exit 2 and store nothing. A tag the store holds with another record is replaced only
with --replace.
"""
import sys

from cmc.gpu_plan.store import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__))
