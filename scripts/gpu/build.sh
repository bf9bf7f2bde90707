#!/usr/bin/env bash
# The half of the GPU bring-up that runs on the GPU machine: build cmc from the
# packages that scripts/gpu/fetch.sh unpacked on a Debian machine, with no network and none of
# our packages installed (seen there: Ubuntu 24.04, g++ 13, CMake 4, CUDA 13), and run the
# quick tests.
#
#   scripts/gpu/build.sh [BUNDLE] [BUILD]     (defaults: gpu-bundle, build-gpu)
#
# Every library and header is taken from BUNDLE/prefix, none from the machine: CMake's
# searches are re-rooted there (CMAKE_FIND_ROOT_PATH, mode ONLY) and pkg-config reads only the
# bundle's .pc files, with the bundle as its sysroot. The compiler, its C++ runtime and OpenMP
# are the machine's. BUILD/env.sh sets LD_LIBRARY_PATH to the bundle's libraries (HDF5 loads
# curl and its TLS libraries, which the binaries' run path does not reach): source it before
# running cmc from BUILD by hand.
#
# It builds the CPU backend. The CUDA backend is built on the Debian machine with the CUDA
# toolkit and carried with scripts/gpu/pack.sh (docs/user-guide/gpu.md): this script re-roots every
# search in the bundle, where CMake would not find the machine's CUDA toolkit.
set -euo pipefail
cd "$(dirname "$0")/../.."
bundle=$(cd "${1:-gpu-bundle}" 2>/dev/null && pwd) ||
  { echo "scripts/gpu/build.sh: no bundle folder ${1:-gpu-bundle}: make it with scripts/gpu/fetch.sh on a Debian 12 machine and copy it here" >&2; exit 1; }
build=${2:-build-gpu}
prefix=$bundle/prefix
arch=x86_64-linux-gnu
[ -d "$prefix/usr/lib/$arch" ] && [ -s "$bundle/packages.txt" ] ||
  { echo "scripts/gpu/build.sh: $bundle holds no unpacked packages (prefix/usr/lib/$arch, packages.txt): rerun scripts/gpu/fetch.sh" >&2; exit 1; }
command -v cmake >/dev/null || { echo "scripts/gpu/build.sh: cmake is missing on this machine" >&2; exit 1; }

libs="$prefix/usr/lib/$arch:$prefix/lib/$arch:$prefix/usr/lib/$arch/hdf5/serial"
export LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PKG_CONFIG_LIBDIR="$prefix/usr/lib/$arch/pkgconfig:$prefix/usr/share/pkgconfig"
export PKG_CONFIG_SYSROOT_DIR="$prefix"
unset PKG_CONFIG_PATH

if command -v nvcc >/dev/null; then
  echo "scripts/gpu/build.sh: $(nvcc --version | tail -1) found; building the CPU backend (the CUDA one: scripts/gpu/pack.sh on the build machine; docs/user-guide/gpu.md)" >&2
fi
jobs=$(nproc 2>/dev/null || echo 2)
mkdir -p "$build"
# HDF5: no h5cc wrapper (Debian's has /usr paths baked in): FindHDF5 then searches the
# re-rooted prefix, where Debian keeps the serial library under hdf5/serial.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_FIND_ROOT_PATH="$prefix" \
  -DCMAKE_FIND_ROOT_PATH_MODE_LIBRARY=ONLY -DCMAKE_FIND_ROOT_PATH_MODE_INCLUDE=ONLY \
  -DCMAKE_FIND_ROOT_PATH_MODE_PACKAGE=ONLY -DCMAKE_FIND_ROOT_PATH_MODE_PROGRAM=NEVER \
  -DHDF5_C_COMPILER_EXECUTABLE=HDF5_C_COMPILER_EXECUTABLE-NOTFOUND -DHDF5_ROOT=/usr/lib/$arch/hdf5/serial \
  -DCMAKE_BUILD_RPATH="$libs" ${CMC_GPU_CMAKE_ARGS:-} >"$build/configure.log" 2>&1 ||
  { tail -30 "$build/configure.log" >&2; echo "scripts/gpu/build.sh: configure failed (whole log: $build/configure.log)" >&2; exit 1; }
# Whatever CMake found must come from the bundle: a path outside it means the machine's own
# copy would be used, which this script promises not to do.
leaks=$(grep -E '^(FFTW|GSL|HDF5|TOMLPP|GTest|benchmark)[A-Za-z_]*(LIBRARY|LIBRARIES|INCLUDE_DIR|INCLUDE_DIRS|_DIR|LINK_LIBRARIES)[A-Z_]*:[A-Z]*=/' \
        "$build/CMakeCache.txt" | grep -v "=$prefix" | grep -v -- '-NOTFOUND$' || true)
[ -z "$leaks" ] || { echo "scripts/gpu/build.sh: these were found outside the bundle:" >&2; echo "$leaks" >&2; exit 1; }
printf 'export LD_LIBRARY_PATH="%s${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"\n' "$libs" >"$build/env.sh"
cmake --build "$build" -j"$jobs" 2>&1 | grep -E "error|Error|warning: unused" >&2 || true
[ -x "$build/cmc" ] || { echo "scripts/gpu/build.sh: the build failed (rerun: cmake --build $build)" >&2; exit 1; }

# The tests labelled python run /usr/bin/python3 with numpy, h5py (and matplotlib for the
# report's self-test), which an Ubuntu machine without our packages lacks.
skip=()
if ! /usr/bin/python3 -c "import numpy, h5py, matplotlib" 2>/dev/null; then
  skip=(-LE python)
  echo "scripts/gpu/build.sh: /usr/bin/python3 lacks numpy, h5py or matplotlib: the tests labelled python are left out" >&2
fi
cd "$build" && CMC_THREADS=${CMC_THREADS:-1} ctest -L quick -j"$jobs" --output-on-failure "${skip[@]}"
