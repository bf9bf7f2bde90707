#!/usr/bin/env bash
# On a GPU machine, from a build packed by scripts/gpu/pack.sh (docs/user-guide/gpu.md):
#   scripts/gpu/check.sh [--pack DIR] [--out DIR] [--cap SECONDS] [--set KEY=VALUE ...] STAGE...
# --set: a case override added to every run of the stages (e.g. solver.tolerance=1e-8), and
# to the command each run records.
# Stages:
#   tests         the 'gpu' tests (tests/gpu: the CUDA backend against the CPU backend)
#   rerun         the 2048² adhesive challenge twice on the GPU: summary.json numbers compared
#                 bit for bit (timings aside)
#   hardwall:N    the hard-wall challenge at 250 kPa on an N² grid, on the GPU
#   hardwall_plain:N   the same without the stiffness preconditioner (solver.precondition =
#                 false: one real field less on the device, for a grid that does not fit with it;
#                 at 32768² the count is 69 GiB with it and 61 GiB without)
#   adhesive:N    the adhesive challenge at 250 kPa (quasi-static solver), on the GPU
#   shape:N       the same with the shape coarse-graining, at most 170 outer steps
#   tabor:N:MU    the challenge's Tabor sweep at mu_T = MU (cases/challenge/tabor-sweep.toml, one of
#                 the values in cases/challenge/tabor-values) on an N² grid, on the GPU: the sweep's
#                 refinement beyond the grids the CPU runs (run tag cuda-tabor_muMU-N)
#   shape_tabor:N:MU   the Tabor sweep's point MU with the shape coarse-graining (where plain does
#                 not resolve rho; run tag cuda-shape_tabor_muMU-N)
#   load:N, shape_load:N, hardwall_load:N   the load sweeps (cases/challenge/load-sweep*.toml):
#                 with adhesion plain or shape, and the hard wall
#   adhesive_from:N:M  the adhesive challenge on N² started from this folder's adhesive run on M²
#                 (cmc run --start-from; that run needs output.fields=true)
#   cpu-STAGE     any of the stages above but tests and rerun, on the CPU backend of the same build
# Each run prints one line: iterations, FFT pairs, solve time, the FFT pair time measured in
# the same run (cuFFT on the GPU, FFTW on the CPU), time per iteration and per pair in units
# of it, the share inside the transforms, a_r, repulsive a_r, mean gap, the GPU memory
# peak (nvidia-smi --loop-ms=200) and the status. Runs stop after --cap seconds
# (default 300): a stopped run says so, and leaves no numbers. So a quasi-static run (adhesive,
# shape, tabor) also gets solver.max_seconds = cap - margin unless a --set names that key: the
# solve then stops itself and the run still computes its observables and writes its summary
# (not_converged, where it stood) inside the cap. The margin is what a run takes outside its
# solve: 10 s + 20 s x (N/16384)² (measured on an H200, summary.json's run time
# minus its solve time: 13-15 s at 16384², 3.5-4.5 s at 8192²; the set-up before the run's
# clock adds a few seconds). A cap at or below the margin sets no limit.
set -uo pipefail
cd "$(dirname "$0")/../.."
pack=.gpucarry out=gpu-check cap=300 sets=()
tabor_values=$(grep -v '^#' cases/challenge/tabor-values)  # the Tabor sweep's mu_T
while [ $# -gt 0 ]; do
  case "$1" in
    --pack) pack=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --cap) cap=$2; shift 2 ;;
    --set) sets+=(--set "$2"); shift 2 ;;
    *) break ;;
  esac
done
[ -f "$pack/env.sh" ] || { echo "scripts/gpu/check.sh: no $pack/env.sh: run scripts/gpu/pack.sh on the build machine" >&2; exit 1; }
. "$pack/env.sh"
mkdir -p "$out"
[ -f "$pack/build.txt" ] && cp "$pack/build.txt" "$out/build.txt"  # the commit, for scripts/gpu/store.py
# The tests read the case files through the source path compiled into them.
export CMC_THREADS=${CMC_THREADS:-$(nproc)}
export CMC_SOURCE_DIR=$PWD  # where the tests find the case files

summary_line() {  # folder, label, peak MiB
  /usr/bin/python3 - "$1" "$2" "$3" <<'PY'
import json, sys
d, label, peak = sys.argv[1:4]
try:
    s = json.load(open(d + "/summary.json"))
except Exception as e:
    print(f"{label:26s} no summary ({e})"); sys.exit()
if not s.get("steps") or "timing" not in s:
    print(f"{label:26s} {s.get('status', '?')}: {s.get('message', '')}"); sys.exit()
t, st = s["timing"], s["steps"][-1]
solve_s = sum(x["wall_s"] for x in s["steps"])  # the solves alone (not the observables, not the writing)
o = st.get("observables", {})
print(f"{label:26s} {t['iterations']:6d} {t['fft_pairs']:8.1f} {solve_s:9.2f} {1e3*t['fft_pair_s']:9.3f} "
      f"{t['time_per_iteration']:7.2f} {t['time_per_fft_pair']:7.2f} {t['fft_share']:6.2f} "
      f"{st['contact_fraction']:.7f} {o.get('repulsive_fraction', float('nan')):.7f} "
      f"{1e6*st['mean_gap']:.7f} {peak:>7s} {s['status']}")
PY
}

run_case() {  # kind (hardwall|hardwall_plain|adhesive|shape|tabor_muMU|...), n, backend[, start-from n]
  local file=reference-load-hardwall extra=() shape=(--set 'interaction.coarse_graining="shape"')
  [ "$1" = adhesive ] && file=reference-load
  [ -n "${4:-}" ] && extra=(--start-from "$out/runs/$3-adhesive-$4")
  case "$1" in
    load) file=load-sweep ;;
    shape_load) file=load-sweep extra=("${shape[@]}") ;;
    hardwall_load) file=load-sweep-hardwall ;;
    shape_tabor_mu*) file=tabor-sweep extra=(--set "interaction.tabor=${1#shape_tabor_mu}" "${shape[@]}") ;;
  esac
  # The Tabor sweep as scripts/tabor_sweep.sh runs it (its case, its tolerance), at one mu_T.
  case "$1" in tabor_mu*) file=tabor-sweep extra=(--set "interaction.tabor=${1#tabor_mu}") ;; esac
  [ "$1" = hardwall_plain ] && extra=(--set solver.precondition=false)
  # The challenge (s = 1 of the scaled family) with the shape coarse-graining, stopped at
  # 170 outer steps as its stored 8192² CPU run was (reference/challenge-scaled).
  [ "$1" = shape ] && file=scaled-family extra=(--set case.name=challenge-scaled-s1 --set surface.cutoff_wavelength=1e-07
    --set interaction.work_of_adhesion=0.05 --set solver.max_outer_steps=170 --set 'interaction.coarse_graining="shape"')
  local tag="$3-$1-$2" dir="$out/runs/$3-$1-$2"
  rm -rf "$dir"
  local samples="$out/$tag.gpu-memory"
  : >"$samples"
  nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits --loop-ms=200 >"$samples" 2>/dev/null &
  local mon=$!
  case "$1" in
    adhesive | shape | tabor_mu* | shape_tabor_mu* | load | shape_load)
      case " ${sets[*]} " in
        *" solver.max_seconds="*) ;;
        *) local margin=$((10 + (20 * $2 * $2 + 16384 * 16384 - 1) / (16384 * 16384)))  # 10 s + ceil(20 s (N/16384)²)
          # solver.max_seconds bounds each load step's solve: a sweep shares the cap among its 14 loads.
          local steps=1
          case "$1" in load | shape_load) steps=14 ;; esac
          [ "$cap" -gt "$margin" ] && extra+=(--set "solver.max_seconds=$(((cap - margin) / steps))") ;;
      esac ;;
  esac
  local args=(run "cases/challenge/$file.toml" --set "grid.n=$2" --set "grid.backend=$3" --set output.fields=false
    "${extra[@]}" "${sets[@]}" --out "$dir")
  # The command as run, for the record (scripts/gpu/store.py stores it with the run).
  { printf 'cmc'; printf ' %q' "${args[@]}"; printf '   (scripts/gpu/check.sh %s)\n' "$stage"; } >"$out/$tag.command"
  timeout "$cap" "$pack/bin/cmc" "${args[@]}" >"$out/$tag.log" 2>&1
  local rc=$?
  kill "$mon" 2>/dev/null; wait "$mon" 2>/dev/null
  local peak
  peak=$(sort -n "$samples" 2>/dev/null | tail -1)
  [ $rc -eq 124 ] && echo "$tag: stopped after $cap s (--cap)" >>"$out/$tag.log"
  summary_line "$dir" "$tag" "${peak:-?}MiB"
  [ $rc -eq 0 ] || { echo "  $tag: exit $rc; last lines of its log:"; tail -3 "$out/$tag.log" | sed 's/^/    /'; echo; }
}

header() {
  echo "run                        iters    pairs   solve_s  pair_ms  t/iter  t/pair  infft a_r       rep_a_r   gap_um   gpu_peak status"
}

nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>&1 | sed 's/^/GPU: /'
# A library the pack lacks and the machine does not have stops everything: say which.
missing=$(ldd "$pack"/bin/* 2>/dev/null | awk '/not found/ {print $1}' | sort -u | tr '\n' ' ')
[ -z "$missing" ] || { echo "scripts/gpu/check.sh: not found on this machine: $missing(pack them with scripts/gpu/pack.sh, or install them)" >&2; exit 1; }
"$pack/bin/cmc" --version 2>/dev/null | head -1
for stage in "$@"; do
  case "$stage" in
    tests)
      "$pack/bin/cmc_gpu_tests" 2>&1 | tee "$out/gpu_tests.log" | grep -E '^\[ +(OK|FAILED|SKIPPED|PASSED) |Failure|expected|cpu |Which is' ;;
    rerun)
      header
      run_case adhesive 2048 cuda; mv "$out/runs/cuda-adhesive-2048" "$out/runs/rerun-a"
      run_case adhesive 2048 cuda; mv "$out/runs/cuda-adhesive-2048" "$out/runs/rerun-b"
      /usr/bin/python3 - "$out/runs/rerun-a/summary.json" "$out/runs/rerun-b/summary.json" <<'PY'
import json, sys
skip = {"wall_s", "fft_s", "fft_share", "fft_pair_s", "time_per_fft_pair", "time_per_iteration",
        "row_column_pair_s", "floor_pair_s", "time_per_floor_pair"}
def strip(x):
    if isinstance(x, dict): return {k: strip(v) for k, v in x.items() if k not in skip}
    if isinstance(x, list): return [strip(v) for v in x]
    return x
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
print("rerun: summary.json numbers " + ("identical" if a == b else "DIFFER"))
PY
      ;;
    hardwall:*|hardwall_plain:*|adhesive:*|shape:*|load:*|shape_load:*|hardwall_load:*) header; run_case "${stage%%:*}" "${stage#*:}" cuda ;;
    cpu-hardwall:*|cpu-hardwall_plain:*|cpu-adhesive:*|cpu-shape:*|cpu-load:*|cpu-shape_load:*|cpu-hardwall_load:*)
      k=${stage#cpu-}; header; run_case "${k%%:*}" "${k#*:}" cpu ;;
    adhesive_from:*:*|cpu-adhesive_from:*:*)
      backend=cuda k=$stage
      [ "${stage#cpu-}" != "$stage" ] && backend=cpu k=${stage#cpu-}
      n=${k#adhesive_from:} n=${n%%:*} m=${k##*:}
      [ -f "$out/runs/$backend-adhesive-$m/result.h5" ] ||
        { echo "scripts/gpu/check.sh: $stage: no $out/runs/$backend-adhesive-$m/result.h5 to start from (run adhesive:$m with output.fields=true first)" >&2; continue; }
      header; run_case adhesive "$n" "$backend" "$m" ;;
    tabor:*:*|cpu-tabor:*:*|shape_tabor:*:*|cpu-shape_tabor:*:*)
      backend=cuda k=$stage kind=tabor_mu
      [ "${stage#cpu-}" != "$stage" ] && backend=cpu k=${stage#cpu-}
      [ "${k#shape_}" != "$k" ] && kind=shape_tabor_mu k=${k#shape_}
      n=${k#tabor:} n=${n%%:*} mu=${k##*:}
      case " $tabor_values " in
        *" $mu "*) ;;
        *) echo "scripts/gpu/check.sh: $stage: mu_T $mu is not one of the Tabor sweep's ($tabor_values)" >&2; exit 2 ;;
      esac
      case "$n" in '' | *[!0-9]*) echo "scripts/gpu/check.sh: $stage: expected tabor:N:MU (N points a side)" >&2; exit 2 ;; esac
      header; run_case "$kind$mu" "$n" "$backend" ;;
    *) echo "scripts/gpu/check.sh: unknown stage $stage" >&2; exit 2 ;;
  esac
done
