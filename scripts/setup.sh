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
# The Python module cmc and its tests (python/python.cmake): pybind11, Python's headers, pytest;
# `pip install .` and its tests (setup.py, tests/install): setuptools, wheel, pip and venv.
packages+=(python3-dev pybind11-dev python3-pybind11 python3-pytest
           python3-setuptools python3-wheel python3-pip python3-venv)
# Property tests of the run store and the Python API (tests/gpu_store, tests/python): hypothesis.
packages+=(python3-hypothesis)
# The type check of the package python/cmc (ctest python.mypy): mypy.
packages+=(mypy)
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
# The FFT plans compiled into cmc are timed (FFTW_MEASURE) once per machine and kept in
# this machine's cache, so that every build and every clone here plans alike and gives the
# same bits (docs/developer/reproducibility.md). Keyed by FFTW's version, the CPU's model and flags
# and the core count, and by the planning tool's sources (a build that plans other
# transforms, e.g. RowColumnFourier's column blocks, does not take an older set);
# CMC_WISDOM_CACHE=off plans anew for this build and keeps nothing.
wisdom_cache=""
if [ "${CMC_WISDOM_CACHE:-on}" != off ] && [ -n "${XDG_CACHE_HOME:-${HOME:-}}" ]; then
  key=$({ pkg-config --modversion fftw3 2>/dev/null || true; grep -m1 "^model name" /proc/cpuinfo || true
          grep -m1 "^flags" /proc/cpuinfo || true; echo "$jobs"
          cat solver/tools/make_wisdom.cpp solver/cmc/grid/ColumnBlockPlans.hpp; } | sha256sum | cut -c1-16)
  wisdom_cache="${XDG_CACHE_HOME:-$HOME/.cache}/cmc/builtin-wisdom-$key.cpp"
fi
if [ -f build/CMakeCache.txt ]; then
  prev=$(sed -n 's/^CMC_WISDOM_FROM:FILEPATH=//p' build/CMakeCache.txt)
  if [ -n "$prev" ] && [ ! -f "$prev" ]; then  # a cache file removed since: keep the plans compiled in
    echo "cmc setup: $prev (the FFT plans this build was configured with) is gone; keeping build/generated's" >&2
    cmake -S . -B build -DCMC_WISDOM_FROM= >.cmake-configure.log 2>&1 || { cat .cmake-configure.log >&2; exit 1; }
  fi
else
  from=()
  if [ -n "$wisdom_cache" ] && [ -f "$wisdom_cache" ]; then
    echo "cmc setup: FFT plans from this machine's cache ($wisdom_cache)" >&2
    from=(-DCMC_WISDOM_FROM="$wisdom_cache")
  fi
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${from[@]}" >.cmake-configure.log 2>&1 || {
    cat .cmake-configure.log >&2; exit 1; }
fi
# FFT plans first, alone on the machine (they are timed; see solver/tools/make_wisdom.cpp).
cmake --build build --target cmc_builtin_wisdom 2>&1 | grep -E "error|Error" >&2 || true
# A build that planned its own, with the default extent, fills the cache.
if [ -n "$wisdom_cache" ] && [ ! -f "$wisdom_cache" ] && [ -s build/generated/fftw_wisdom.cpp ] &&
   grep -q "^CMC_WISDOM_MAX_N:STRING=4096$" build/CMakeCache.txt &&
   grep -q "^CMC_WISDOM_FROM:FILEPATH=$" build/CMakeCache.txt; then
  mkdir -p "$(dirname "$wisdom_cache")" &&
    cp build/generated/fftw_wisdom.cpp "$wisdom_cache.tmp.$$" && mv "$wisdom_cache.tmp.$$" "$wisdom_cache" &&
    echo "cmc setup: FFT plans kept for the next builds on this machine ($wisdom_cache)" >&2 || true
fi
cmake --build build -j"$jobs" 2>&1 | grep -E "error|Error|warning: unused" >&2 || true
test -x build/cmc || { echo "cmc setup: build failed; run 'cmake --build build' to see why" >&2; exit 1; }
