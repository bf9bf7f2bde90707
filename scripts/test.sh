#!/usr/bin/env bash
# The test command (README, second command; CI runs exactly this through .ci/run):
# install what is missing, build, and run every ctest test that is not labelled
# 'slow' (labels: quick = unit tests and CLI checks, validation = analytic checks,
# challenge = the challenge cases at 256², hard wall and adhesive; validation/validation.cmake).
# Extra arguments go to ctest, e.g. scripts/test.sh -L validation
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# FFT plans come from the wisdom built into cmc (the same bits on every run); with
# CMC_FFTW_PLANNER=measure they are timed at run time and kept in this wisdom file.
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build/fftw-wisdom}"
cd build
# Tests run two at a time: one thread each (threads of two processes on two cores
# only spin against each other).
export CMC_THREADS="${CMC_THREADS:-1}"
ctest --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" -LE slow "$@"
