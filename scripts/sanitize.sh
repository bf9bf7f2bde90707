#!/usr/bin/env bash
# The unit tests and the quick validation cases built with AddressSanitizer and
# UndefinedBehaviorSanitizer (docs/developer/testing.md; scripts/test.sh runs this after the tests).
#
# usage: scripts/sanitize.sh [ctest arguments]     default: -L 'quick|validation' -LE slow
#
# Configures and builds ./build-asan (GCC, -O1 -g, -fsanitize=address,undefined,
# float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer; the FFT wisdom
# is the main build's, ./build, so the plans are the same), then runs the tests with
# ctest. Any sanitizer report (a memory error, a leak, undefined behaviour) ends that
# test's process with an error, so the test fails with the report in its output.
# Environment: CMC_JOBS (build jobs).
set -euo pipefail
cd "$(dirname "$0")/.."

jobs="${CMC_JOBS:-$(nproc 2>/dev/null || echo 2)}"
mkdir -p build-asan
if [ ! -f build-asan/CMakeCache.txt ]; then
  wisdom=()
  [ -f build/generated/fftw_wisdom.cpp ] && wisdom=(-DCMC_WISDOM_FROM="$PWD/build/generated/fftw_wisdom.cpp")
  # Debug without NDEBUG and at -O1: assertions stay on, the build stays quick.
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DCMAKE_C_FLAGS_DEBUG="-O1 -g" \
    -DCMC_SANITIZE=address,undefined,float-cast-overflow -DCMC_BUILD_BENCHMARKS=OFF "${wisdom[@]}" \
    >build-asan/configure.log 2>&1 || { cat build-asan/configure.log >&2; exit 1; }
fi
cmake --build build-asan -j"$jobs" >build-asan/build.log 2>&1 || {
  grep -E "error|Error" build-asan/build.log | head -40 >&2; echo "sanitize.sh: build failed (build-asan/build.log)" >&2; exit 1; }

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:check_initialization_order=1:strict_init_order=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export CMC_FFTW_WISDOM="${CMC_FFTW_WISDOM:-$PWD/build-asan/fftw-wisdom}"
export CMC_THREADS="${CMC_THREADS:-1}"
# Two tests measure the process's peak memory (ru_maxrss) against a bound: under ASan its
# shadow memory and quarantine multiply the peak (measured 183 MB against 38 MB estimated),
# so they run in the plain build only.
[ $# -gt 0 ] || set -- -L 'quick|validation' -LE slow -E '^(Inputs\.CheckStreamsLargePredictions|Limits\.MemoryEstimateBoundsMeasuredPeak)$'
cd build-asan
ctest --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" "$@"
