#!/usr/bin/env bash
# Run scripts/gpu/check.sh's stages on a GPU machine lent for minutes, within one deadline (docs: GPU):
#   scripts/gpu/batch.sh [--deadline SECONDS] [--pack DIR] [--work DIR] [--tar FILE] [--keep-h5 MIB] STAGE[@CAP][,KEY=VALUE...] ...
# Runs scripts/gpu/check.sh's stages (tests, rerun, adhesive:N, ...) one after another: each
# stopped after CAP seconds (default 300; a stopped run prints its last progress lines; a
# quasi-static run stops its own solve before that, check.sh's solver.max_seconds), none
# started with less than 25 s to the deadline (default 540 s after the start), each with its
# own case overrides (KEY=VALUE, as cmc's --set). After every stage the results so far
# (check.sh's --out folder, --work, default gpu-check: summaries, logs, the commands as run,
# the GPU memory samples; no fields; with --keep-h5 MIB also each result.h5 smaller than MIB MiB,
# i.e. the observables of runs written without fields) are packed into FILE (default $OUT/gpu-check.tgz where
# $OUT is set, else gpu-check.tgz), so a command stopped at its limit still returns every
# finished stage. Example, on the device machine:
#   DEADLINE=540 scripts/gpu/batch.sh tests rerun adhesive:8192@120 adhesive:16384@240,solver.tolerance=1e-8
# then, here: tar xzf gpu-check.tgz; scripts/gpu/store.py --device ... --date ... gpu-check
set -uo pipefail
cd "$(dirname "$0")/../.."
deadline=${DEADLINE:-540} pack=.gpucarry tar=${OUT:+$OUT/}gpu-check.tgz work=gpu-check keep_h5=0
while [ $# -gt 0 ]; do
  case "$1" in
    --deadline) deadline=$2; shift 2 ;;
    --pack) pack=$2; shift 2 ;;
    --tar) tar=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --keep-h5)
      case "${2:-}" in '' | *[!0-9]*) echo "scripts/gpu/batch.sh: --keep-h5 needs a size in MiB (got '${2:-}')" >&2; exit 2 ;; esac
      keep_h5=$2; shift 2 ;;
    --*) echo "scripts/gpu/batch.sh: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || { echo "scripts/gpu/batch.sh: no stage given (e.g. tests rerun adhesive:8192@120)" >&2; exit 2; }
# Every stage's cap is read before any stage runs: a typo stops the batch at once, not after
# the stages before it.
for spec in "$@"; do
  first=${spec%%,*} cap=300
  [ "$first" != "${first%@*}" ] && cap=${first##*@}
  case "$cap" in '' | *[!0-9]*) echo "scripts/gpu/batch.sh: $spec: expected STAGE@SECONDS" >&2; exit 2 ;; esac
done
t0=$(date +%s)
left() { echo $((deadline - ($(date +%s) - t0))); }
save() {  # the files of $work but checkpoints, XDMF and HDF5 (result.h5 under --keep-h5 MIB kept)
  (cd "$(dirname "$work")" && find "$(basename "$work")" -path '*/.partial' -prune -o -type f ! -name '*.xdmf' \
     \( ! -name '*.h5' -o \( -name result.h5 -size -"$((keep_h5 * 1024))"k \) \) -print) >"$tar.list" &&
    tar czf "$tar.tmp" -C "$(dirname "$work")" -T "$tar.list" && mv "$tar.tmp" "$tar"
  rm -f "$tar.list"
}
mkdir -p "$work"
for spec in "$@"; do
  IFS=, read -r -a parts <<<"$spec"
  stage=${parts[0]%@*} cap=300
  [ "${parts[0]}" != "$stage" ] && cap=${parts[0]##*@}
  sets=()
  for kv in "${parts[@]:1}"; do sets+=(--set "$kv"); done
  l=$(left)
  if [ "$l" -lt 25 ]; then echo "== $spec: skipped ($l s to the deadline)"; continue; fi
  [ "$cap" -gt "$l" ] && cap=$l
  echo "== $spec (cap $cap s, $l s to the deadline)"
  # check.sh stops each run at its cap; the outer timeout is for a stage of several runs.
  timeout $((2 * cap + 30)) scripts/gpu/check.sh --pack "$pack" --out "$work" --cap "$cap" "${sets[@]}" "$stage"
  pkill -f "^$pack/bin/cmc" 2>/dev/null  # a run the timeout left behind (cmc, cmc_gpu_tests)
  save
done
echo "== done after $(($(date +%s) - t0)) s; results in $tar"
