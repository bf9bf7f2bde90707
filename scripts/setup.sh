#!/usr/bin/env bash
# Install what cmc needs from Debian's packages, if anything is missing; then
# configure and build (Release) in ./build. Idempotent and quiet when all is there.
set -euo pipefail
cd "$(dirname "$0")/.."

# clang, libclang-rt-dev (libFuzzer and clang's sanitizer runtimes) and libomp-dev (OpenMP for
# clang): the fuzz build of scripts/fuzz.sh, which scripts/test.sh runs. libopenmpi-dev,
# openmpi-bin and libfftw3-mpi-dev: the distributed build of scripts/mpi.sh (same).
packages=(build-essential cmake pkg-config libfftw3-dev libgsl-dev libhdf5-dev libtomlplusplus-dev
          libgtest-dev libbenchmark-dev python3-matplotlib python3-numpy python3-h5py
          clang libclang-rt-dev libomp-dev
          libopenmpi-dev openmpi-bin libfftw3-mpi-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "cmc setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq >/dev/null
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >.cmake-configure.log 2>&1 || {
    cat .cmake-configure.log >&2; exit 1; }
fi
# FFT plans first, alone on the machine (they are timed; see solver/tools/make_wisdom.cpp).
cmake --build build --target cmc_builtin_wisdom 2>&1 | grep -E "error|Error" >&2 || true
cmake --build build -j"$jobs" 2>&1 | grep -E "error|Error|warning: unused" >&2 || true
test -x build/cmc || { echo "cmc setup: build failed; run 'cmake --build build' to see why" >&2; exit 1; }
