# Sourced by the scripts that run the repository's Python (scripts/report.sh,
# scripts/sweeps.sh): PYTHONPATH gets the package cmc as the build made it (build/python:
# the compiled core beside links to python/cmc/), or its pure-Python modules from the source
# where the module is not built (cmc.analysis, cmc.report, cmc.references, ...), then
# reports/ and scripts/. ctest gives its tests the same (CMakeLists.txt). The Python scripts
# of scripts/ and reports/ are commands over the package, so by hand:
#   . scripts/python_path.sh && /usr/bin/python3 scripts/best_estimates.py
# A cmc installed with pip needs none of this for `import cmc`.
cmc_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cmc_package=$cmc_root/python
[ -d "$cmc_root/build/python/cmc" ] && cmc_package=$cmc_root/build/python
export PYTHONPATH="$cmc_package:$cmc_root/reports:$cmc_root/scripts${PYTHONPATH:+:$PYTHONPATH}"
unset cmc_root cmc_package
