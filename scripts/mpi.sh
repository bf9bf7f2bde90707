#!/usr/bin/env bash
# The distributed build and its tests (docs/user-guide/cluster.md; scripts/test.sh
# runs this after the tests): configures and builds ./build-mpi with -DCMC_MPI=ON (the
# program only; Open MPI and FFTW's MPI interface from Debian, installed by
# scripts/setup.sh; the FFT wisdom is the main build's), then runs the tests labelled
# 'mpi' (tests/mpi_test.py: runs at 1 and 2 ranks against the serial build ./build).
#
# usage: scripts/mpi.sh [ctest arguments]     default: -L mpi
# Environment: CMC_JOBS (build jobs).
set -euo pipefail
cd "$(dirname "$0")/.."

jobs="${CMC_JOBS:-$(nproc 2>/dev/null || echo 2)}"
mkdir -p build-mpi
if [ ! -f build-mpi/CMakeCache.txt ]; then
  wisdom=()
  [ -f build/generated/fftw_wisdom.cpp ] && wisdom=(-DCMC_WISDOM_FROM="$PWD/build/generated/fftw_wisdom.cpp")
  cmake -S . -B build-mpi -DCMAKE_BUILD_TYPE=Release -DCMC_MPI=ON -DCMC_BUILD_TESTS=OFF -DCMC_BUILD_BENCHMARKS=OFF \
    -DCMC_SERIAL_CMC="$PWD/build/cmc" "${wisdom[@]}" >build-mpi/configure.log 2>&1 || {
    cat build-mpi/configure.log >&2; exit 1; }
fi
cmake --build build-mpi -j"$jobs" --target cmc >build-mpi/build.log 2>&1 || {
  grep -E "error|Error" build-mpi/build.log | head -40 >&2; echo "mpi.sh: build failed (build-mpi/build.log)" >&2; exit 1; }
# Open MPI refuses to run as root unless told (CI containers run as root), and two ranks
# on a machine with fewer free slots need oversubscription.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export CMC_THREADS="${CMC_THREADS:-1}"
[ $# -gt 0 ] || set -- -L mpi
ctest --test-dir build-mpi --output-on-failure "$@"
