#!/usr/bin/env bash
# The test command (README.md, second command; CI runs exactly this through .ci/run):
# install what is missing, build, and run
#   1. every ctest test that is not labelled 'slow' (labels: quick = unit tests and CLI
#      checks, validation = analytic checks, challenge = the challenge cases at 256², hard
#      wall and adhesive; validation/validation.cmake);
#   2. the quick and validation tests again, built with AddressSanitizer and
#      UndefinedBehaviorSanitizer (scripts/sanitize.sh, build-asan/);
#   3. each fuzz target for 15 s (scripts/fuzz.sh, build-fuzz/);
#   4. the distributed build and its comparisons with serial runs at 1 and 2 MPI ranks
#      (scripts/mpi.sh, build-mpi/, ctest label 'mpi').
# Extra arguments go to ctest and run step 1 only, e.g. scripts/test.sh -L validation.
# CMC_TEST_SANITIZE=0 skips step 2, CMC_TEST_FUZZ_SECONDS=0 step 3 (or sets its seconds),
# CMC_TEST_MPI=0 step 4.
set -euo pipefail
cd "$(dirname "$0")/.."
# The arguments are checked before anything is installed or built: --help prints the lines
# above, and an option that is not one of ctest's selections below is refused (ctest itself
# would ignore it and run everything).
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[i]}" in
    -h | --help) usage; exit 0 ;;
    -R | -E | -L | -LE | -j | --timeout | --repeat | -I | --tests-regex | --exclude-regex | --label-regex | \
      --label-exclude | --parallel)
      ((i + 1 < ${#args[@]})) || { echo "scripts/test.sh: ${args[i]} needs a value (see scripts/test.sh --help)" >&2; exit 2; }
      ((i += 1)) ;;
    -j[0-9]* | -V | -VV | -N | --output-on-failure | --stop-on-failure | --rerun-failed | --schedule-random | \
      --no-tests=error | --timeout=* | --repeat=* | --parallel=*) ;;
    *) echo "scripts/test.sh: unknown argument '${args[i]}': expected ctest's -R, -E, -L, -LE, -j, -V, -N, ..." \
         "(see scripts/test.sh --help)" >&2; exit 2 ;;
  esac
done
scripts/setup.sh
status=0
stage() {  # stage NAME COMMAND...: run it, say how long it took, remember a failure
  local t0=$SECONDS rc=0
  "${@:2}" || rc=$?
  echo "cmc test: $1: $([ $rc -eq 0 ] && echo passed || echo "FAILED (exit $rc)") in $((SECONDS - t0)) s" >&2
  [ $rc -eq 0 ] || status=1
}
# FFT plans come from the wisdom built into cmc (the same bits on every run); with
# CMC_FFTW_PLANNER=measure they are timed at run time and kept in this wisdom file.
# Tests run two at a time: one thread each (threads of two processes on two cores
# only spin against each other).
export CMC_THREADS="${CMC_THREADS:-1}"
wisdom="${CMC_FFTW_WISDOM:-}"
stage tests env CMC_FFTW_WISDOM="${wisdom:-$PWD/build/fftw-wisdom}" \
  ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)" -LE slow "$@"
if [ $# -eq 0 ]; then
  [ "${CMC_TEST_SANITIZE:-1}" = 0 ] ||
    stage "sanitizer build and tests (build-asan)" env CMC_FFTW_WISDOM="${wisdom:-$PWD/build-asan/fftw-wisdom}" \
      scripts/sanitize.sh
  fuzz_seconds="${CMC_TEST_FUZZ_SECONDS:-15}"
  [ "$fuzz_seconds" = 0 ] || stage "fuzz build and ${fuzz_seconds} s per target (build-fuzz)" scripts/fuzz.sh "$fuzz_seconds"
  [ "${CMC_TEST_MPI:-1}" = 0 ] || stage "MPI build and distributed tests (build-mpi)" scripts/mpi.sh
fi
exit $status
