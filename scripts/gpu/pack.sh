#!/usr/bin/env bash
# Pack a CUDA build made on this (Debian) machine for a GPU machine that has the CUDA
# runtime and cuFFT but none of our packages and no network (docs/user-guide/gpu.md):
# the programs, and every shared library they load that is neither the C/C++ runtime nor
# CUDA's, copied from this machine (ldd). Small enough (~30 MB) to travel with the checkout.
#
#   scripts/gpu/pack.sh [BUILD] [PACK]      (defaults: build-cuda, .gpucarry)
#
# PACK/bin: cmc, cmc_gpu_tests (and cmc_tests where built); PACK/lib: the libraries;
# PACK/env.sh: LD_LIBRARY_PATH for PACK/lib and the machine's CUDA libraries; PACK/build.txt:
# the commit the programs were built from. On the GPU
# machine: `. PACK/env.sh; PACK/bin/cmc_gpu_tests`, or scripts/gpu/check.sh.
# The build: cmake -S . -B build-cuda -DCMC_CUDA=ON -DCMAKE_CUDA_COMPILER=/usr/local/cuda/bin/nvcc
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build-cuda}
pack=${2:-.gpucarry}
[ -x "$build/cmc" ] && [ -x "$build/cmc_gpu_tests" ] ||
  { echo "scripts/gpu/pack.sh: $build/cmc or $build/cmc_gpu_tests missing: configure with -DCMC_CUDA=ON and build" >&2; exit 1; }
grep -q '^CMC_CUDA:BOOL=ON' "$build/CMakeCache.txt" ||
  { echo "scripts/gpu/pack.sh: $build is not a CUDA build (CMC_CUDA=ON)" >&2; exit 1; }
# nvcc keeps the host side of each __host__ __device__ lambda in per-unit statics, while the
# linker merges the lambda's wrapper code across units: two .cu files that instantiate the
# same such lambda make a program that calls a null pointer (contact/polonsky_keer/CudaBackend.cu, the note
# at pk::run_on_device). Refuse such a build before it travels to a GPU.
objs=$(find "$build/CMakeFiles" -name '*.cu.o' | sort)
shared=$(for o in $objs; do nm "$o" | awk '$2 ~ /^[WVT]$/ && $3 ~ /__nv_hdl_wrapper_t/ {print $3}' | sort -u; done |
  sort | uniq -d | head -3)
[ -z "$shared" ] ||
  { echo "scripts/gpu/pack.sh: a __host__ __device__ lambda is instantiated in more than one .cu file of $build (a null call on the GPU); first of them:" >&2
    echo "$shared" | c++filt | cut -c1-300 >&2; exit 1; }
rm -rf "$pack"
mkdir -p "$pack/bin" "$pack/lib"
progs=("$build/cmc" "$build/cmc_gpu_tests")
[ -x "$build/cmc_tests" ] && progs+=("$build/cmc_tests")
cp "${progs[@]}" "$pack/bin/"
# The machine brings its own C and C++ runtimes, OpenMP and CUDA.
ldd "${progs[@]}" | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | sort -u |
  grep -Ev '/(libc|libm|libdl|libpthread|librt|libresolv|libstdc\+\+|libgcc_s|libgomp|libcudart|libcufft|libcuda)\.so' |
  while read -r lib; do cp -L "$lib" "$pack/lib/"; done
cat >"$pack/env.sh" <<'ENV'
# Source me: the packed libraries, then the machine's CUDA runtime and cuFFT.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
cuda_lib=$(dirname "$(ls /usr/local/cuda/lib64/libcufft.so.* /usr/local/cuda*/targets/x86_64-linux/lib/libcufft.so.* /usr/lib/x86_64-linux-gnu/libcufft.so.* 2>/dev/null | head -1)" 2>/dev/null || true)
export LD_LIBRARY_PATH="$here/lib${cuda_lib:+:$cuda_lib}${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
ENV
# What built the pack, for the run store (scripts/gpu/store.py reads it from check.sh's output).
{ echo "commit $(git rev-parse --short=12 HEAD 2>/dev/null || echo unknown)$(git status --porcelain --untracked-files=no 2>/dev/null | grep -q . && echo -dirty)"
  echo "build $build"; } >"$pack/build.txt"
du -sh "$pack" | awk '{print "scripts/gpu/pack.sh: " $1 " in " $2}' >&2
