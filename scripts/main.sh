#!/usr/bin/env bash
# The main job (README, first command): install what is missing, build, then run
# the validation cases and print their summary table; results go to results/.
# (Once the challenge surface lands, this runs the challenge at the reference load.)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
mkdir -p results
echo "cmc main job: validation cases (cases/validation/*.toml) -> results/validation/" >&2
build/cmc validate cases/validation/*.toml --out results/validation
