#!/usr/bin/env bash
# Reports (run after the test command): reads build/validation/*/summary.json (and
# results/validation/), results/performance/*.json, build/bench.json and the challenge
# runs under results/challenge*/, and writes reports/validation/, reports/performance/
# and reports/challenge/ (index.md + PNG figures; see reports/README.md).
# Missing inputs become lines in the index.md files saying what to run.
# Extra arguments go to reports/make_reports.py, e.g. scripts/report.sh --only validation
set -euo pipefail
cd "$(dirname "$0")/.."
python=/usr/bin/python3
if [ ! -x "$python" ]; then
  echo "report.sh: $python not found: install python3, python3-matplotlib, python3-numpy, python3-h5py (scripts/setup.sh)" >&2
  exit 0
fi
. scripts/python_path.sh  # the package cmc (the build's) for the reports
exec "$python" reports/make_reports.py \
  --validation build/validation --validation results/validation \
  --results results --bench build/bench.json --reference reference --cases cases/challenge \
  --out reports "$@"
