#!/usr/bin/env bash
# Everything the challenge references need from one GPU machine, in one deadline
# (docs/user-guide/gpu.md, "Regenerating the challenge references on one GPU"):
#   scripts/gpu/full_plan.sh [--deadline S] [--out DIR] [--work DIR] [--pack DIR] [--gpu-workers W]
#                            [--cpu-workers C] [--scale K --cpu] [--skip P,...] [--keep-all]
# Three tracks side by side:
#   1. the reference plan (scripts/gpu/reference_plan.py) on the GPU: the finest grids, one run at
#      a time, into OUT/reference-plan.tgz;
#   2. the seed ensemble (scripts/ensemble.py: 250 kPa with and without adhesion, both load
#      sweeps, the Tabor points of seeds 1-16) on the GPU, W sweeps at a time, blocks of 4 seeds:
#      the 2048² runs leave the GPU idle between their small transforms, and the plan's runs
#      fill it;
#   3. the Tabor points of seeds 17-32 on the host's cores, C single-threaded runs at a time
#      (a 2048² hard-wall sweep to full contact takes a host core over 8 minutes: the GPU's).
# Both ensembles leave out what reference/challenge/ensemble/runs.json holds already.
# The ensemble's summaries (and the 250 kPa runs' result.h5, observables only) are packed into
# OUT/ensemble.tgz at the end; what the deadline stopped is resumable where it stands (the same
# command with --work pointing at it). --scale K --cpu runs all of it on the CPU backend at
# grids divided by K (the test command runs it so). Here, afterwards:
#   /usr/bin/python3 scripts/gpu/ingest.py OUT/reference-plan.tgz
#   /usr/bin/python3 scripts/ensemble_store.py OUT/ensemble.tgz
set -uo pipefail
cd "$(dirname "$0")/../.."
# reference_plan.py and ensemble.py are thin commands over the package cmc: its pure-Python
# modules from the checkout (cmc.gpu_plan.plan, cmc.ensemble_runner: standard library only, as
# the GPU machine's Python has none of our packages; ctest gpu_scripts.standard_library_only).
export PYTHONPATH="$PWD/python${PYTHONPATH:+:$PYTHONPATH}"
deadline=540 out=${OUT:-.} work=full-plan pack=.gpucarry gpu_workers=4 cpu_workers=$(($(nproc) - 6)) scale=1 cpu=0 skip="" keep=()
while [ $# -gt 0 ]; do
  case "$1" in
    --deadline) deadline=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --pack) pack=$2; shift 2 ;;
    --gpu-workers) gpu_workers=$2; shift 2 ;;
    --cpu-workers) cpu_workers=$2; shift 2 ;;
    --scale) scale=$2; shift 2 ;;
    --cpu) cpu=1; shift ;;
    --skip) skip=$2; shift 2 ;;
    --keep-all) keep=(--keep-all); shift ;;
    *) echo "scripts/gpu/full_plan.sh: unknown argument $1 (see the comment at its top)" >&2; exit 2 ;;
  esac
done
for v in "$deadline" "$gpu_workers" "$scale"; do
  case "$v" in '' | *[!0-9]*) echo "scripts/gpu/full_plan.sh: --deadline, --gpu-workers and --scale take whole numbers" >&2; exit 2 ;; esac
done
[ "$cpu_workers" -ge 1 ] 2>/dev/null || cpu_workers=1
[ -f "$pack/env.sh" ] || { echo "scripts/gpu/full_plan.sh: no $pack/env.sh: run scripts/gpu/pack.sh on the build machine" >&2; exit 2; }
mkdir -p "$out" "$work" || exit 2
out=$(cd "$out" && pwd)
. "$pack/env.sh"
t0=$(date +%s)
n=$((2048 / scale))
[ "$n" -ge 16 ] || n=16
# The ensembles call cmc by a name of their own: scripts/gpu/batch.sh stops what is left of
# each of its stages by the pack's program name, which must not reach the ensembles' runs.
ln -sf "$(cd "$pack/bin" && pwd)/cmc" "$work/cmc-ensemble"
ens=(/usr/bin/python3 scripts/ensemble.py --out "$work/ensemble" --n "$n" --cmc "$work/cmc-ensemble"
     --deadline $((deadline - 40)) --skip-stored reference/challenge/ensemble/runs.json)
[ "$scale" -gt 1 ] && ens+=(--set "surface.cutoff_wavelength=$(awk "BEGIN {print 0.1e-6 * $scale}")")
gpu_backend=cuda plan_cpu=()
[ "$cpu" = 1 ] && gpu_backend=cpu plan_cpu=(--cpu)
# The plan's own runs take the host threads they need; the ensembles one each.
CMC_THREADS=4 /usr/bin/python3 scripts/gpu/reference_plan.py --deadline "$deadline" --scale "$scale" "${plan_cpu[@]}" \
  --pack "$pack" --work "$work/plan" --tar "$out/reference-plan.tgz" ${skip:+--skip "$skip"} "${keep[@]}" >"$work/plan.log" 2>&1 &
plan=$!
"${ens[@]}" --backend "$gpu_backend" --workers "$gpu_workers" --block 4 \
  --kinds reference_hardwall,reference,hardwall_load,load,tabor --tabor-seeds 1-16 >"$work/ensemble-gpu.log" 2>&1 &
gpu=$!
"${ens[@]}" --backend cpu --workers "$cpu_workers" --block 1 --kinds tabor --seeds 17-32 \
  >"$work/ensemble-cpu.log" 2>&1 &
host=$!
wait $gpu $host
# The ensemble's pack: summaries and sweep tables; result.h5 of the 250 kPa runs (observables).
cp -f "$pack/build.txt" "$work/ensemble/build.txt" 2>/dev/null
(cd "$work" && cp -f plan/machine.txt ensemble/machine.txt 2>/dev/null
 find ensemble -path '*/.partial' -prune -o -type f \( -name summary.json -o -name 'sweep.json' -o -name '*.log' \
   -o -name machine.txt -o -name build.txt -o \( -name result.h5 -path 'ensemble/reference*' \) \) -print >ensemble.list &&
 tar czf "$out/ensemble.tgz.tmp" -T ensemble.list 2>/dev/null) &&
  mv "$out/ensemble.tgz.tmp" "$out/ensemble.tgz"
wait $plan
rc=$?
tail -n 4 "$work/ensemble-gpu.log" "$work/ensemble-cpu.log"
cat "$work/plan.log"
ls -la "$out"
echo "full_plan: done after $(($(date +%s) - t0)) s (reference plan exit $rc)"
[ -s "$out/reference-plan.tgz" ] && [ -s "$out/ensemble.tgz" ]
