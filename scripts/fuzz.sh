#!/usr/bin/env bash
# Fuzz cmc's input readers with libFuzzer (docs/developer/testing.md): the case parser with --set
# overrides (case), the ASCII and Fourier-list height readers (ascii_heights), the HDF5
# height reader on well-formed files of every shape (hdf5_heights) and the reader and
# scorer of `cmc check` (check_csv); on demand, the HDF5 reader on raw bytes (hdf5_bytes).
# Sources, seeds and what each target checks: tests/fuzz/README.md.
#
# usage: scripts/fuzz.sh [SECONDS per target, default 60] [TARGET ...]   (default: the four)
#
# Configures and builds ./build-fuzz (clang, -fsanitize=fuzzer,address,undefined; the FFT
# wisdom is taken from ./build when it is there), then runs each target for SECONDS with a
# per-input time limit of 1 s and a memory limit of 2048 MB, starting from its seeds
# (tests/fuzz/corpus/<target>, never written) and from what earlier runs found
# (build-fuzz/corpus/<target>, where new inputs go). Prints per target the executions and
# the result; a crash, sanitizer report, hang or memory blow-up leaves the input in
# build-fuzz/findings/<target>/ and makes the script exit 1.
# Replay one input: build-fuzz/fuzz_<target> FILE.   Environment: CMC_JOBS (build jobs).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
shift || true
all=(case ascii_heights hdf5_heights check_csv)
# On demand only: the HDF5 reader on raw file bytes, which finds bugs of libhdf5 1.10.8's
# decoder of corrupt files within minutes (tests/fuzz/README.md).
extra=(hdf5_bytes)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} ${extra[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target '$t' (known: ${all[*]} ${extra[*]})" >&2; exit 2; }
done
command -v clang++ >/dev/null || { echo "fuzz.sh: needs clang++ (Debian packages clang libclang-rt-dev libomp-dev; scripts/setup.sh installs them)" >&2; exit 2; }

jobs="${CMC_JOBS:-$(nproc 2>/dev/null || echo 2)}"
mkdir -p build-fuzz
if [ ! -f build-fuzz/CMakeCache.txt ]; then
  wisdom=()
  if [ -f build/generated/fftw_wisdom.cpp ]; then
    wisdom=(-DCMC_WISDOM_FROM="$PWD/build/generated/fftw_wisdom.cpp")
  else
    wisdom=(-DCMC_WISDOM_MAX_N=8)  # the readers do no FFTs: plan as little as possible
  fi
  # -O1 -g without NDEBUG: toml++'s internal assertions stay on.
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DCMAKE_C_FLAGS_DEBUG="-O1 -g" -DCMC_FUZZ=ON -DCMC_BUILD_TESTS=OFF -DCMC_BUILD_BENCHMARKS=OFF \
    "${wisdom[@]}" >build-fuzz/configure.log 2>&1 || { cat build-fuzz/configure.log >&2; exit 1; }
fi
cmake --build build-fuzz --target cmc_fuzz -j"$jobs" >build-fuzz/build.log 2>&1 || {
  tail -40 build-fuzz/build.log >&2; echo "fuzz.sh: build failed (build-fuzz/build.log)" >&2; exit 1; }

# Sanitizer reports end the run as a finding; leaks are findings too.
asan="detect_leaks=1:allocator_may_return_null=0"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
status=0
printf '%-14s %8s %12s %8s %8s  %s\n' target seconds executions exec/s corpus result
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t" "build-fuzz/findings/$t"
  dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
  log="build-fuzz/findings/$t/last-run.log"
  # hdf5_bytes feeds corrupt files to libhdf5, whose known bugs are suppressed by name
  # (tests/fuzz/*.supp; matching names in leaks needs the slow unwinder: libhdf5 has no
  # frame pointers); a failed huge allocation returns NULL, as it does outside ASan.
  export ASAN_OPTIONS="$asan" LSAN_OPTIONS=""
  if [ "$t" = hdf5_bytes ]; then
    export ASAN_OPTIONS="$asan:allocator_may_return_null=1:fast_unwind_on_malloc=0:suppressions=$PWD/tests/fuzz/asan.supp"
    export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0"
  fi
  rc=0
  "build-fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=1 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="build-fuzz/findings/$t/" "${dict[@]}" "build-fuzz/corpus/$t" "tests/fuzz/corpus/$t" \
    >"$log" 2>&1 || rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  corpus=$(find "build-fuzz/corpus/$t" -type f | wc -l)
  if [ "$rc" -eq 0 ]; then
    result="ok"
  else
    status=1
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    kind=$(grep -m1 -oE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer): [a-zA-Z-]+|runtime error|cmc fuzz: .*' "$log" || echo "exit $rc")
    result="FAILED: $kind; input ${artifact:-none}; log $log"
  fi
  printf '%-14s %8s %12s %8s %8s  %s\n' "$t" "$seconds" "${execs:-?}" "${rate:-?}" "$corpus" "$result"
done
exit $status
