#!/usr/bin/env bash
# Whole-solve benchmark: the challenge surface at the reference load (250 kPa), with
# adhesion (adhesive CG) and without (Polonsky-Keer), on several grids. Prints, per run,
# what cmc measured in that run: iterations, FFT pairs, wall time of the solves, the time
# of one FFT pair of the run's operator (timed at its start), the solve time per FFT pair
# and per iteration in units of that pair time (target: 1.3 per iteration), and the
# answer: contact fraction a_r, repulsive a_r and mean gap.
#
# usage: scripts/bench_solvers.sh [--quick] [--cmc BIN] [--label NAME] [--out DIR]
#   --quick       small grids only (adhesive 256², 512²; hard wall 512², 1024²; ~1 min)
#   --cmc BIN     benchmark another build's cmc (e.g. an older solver) on the same cases
#   --label NAME  name of this set of runs in the table and under DIR (default: current)
#   --out DIR     where the runs go (default: results/bench); finished runs are reused
# Default set (about 15 minutes on 2 cores): adhesive 512², 1024², 2048²; hard wall 2048², 4096².
set -euo pipefail
cd "$(dirname "$0")/.."
cmc=build/cmc label=current out=results/bench quick=0
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --cmc) cmc="$2"; shift ;;
    --label) label="$2"; shift ;;
    --out) out="$2"; shift ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "bench_solvers: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
[ "$cmc" = build/cmc ] && scripts/setup.sh
[ -x "$cmc" ] || { echo "bench_solvers: $cmc is not an executable cmc" >&2; exit 2; }
if [ $quick = 1 ]; then runs="adhesive:256 adhesive:512 hardwall:512 hardwall:1024"
else runs="adhesive:512 adhesive:1024 adhesive:2048 hardwall:2048 hardwall:4096"; fi
mkdir -p "$out/$label"
for r in $runs; do
  kind=${r%%:*} n=${r##*:}
  case_file=cases/challenge/reference-load.toml
  [ "$kind" = hardwall ] && case_file=cases/challenge/reference-load-hardwall.toml
  dir="$out/$label/$kind-$n"
  if [ -f "$dir/summary.json" ] && [ "$dir/summary.json" -nt "$cmc" ]; then continue; fi
  echo "bench_solvers: $cmc run $case_file --set grid.n=$n" >&2
  "$cmc" run "$case_file" --set grid.n="$n" --out "$dir" --quiet || [ $? -eq 3 ]
done
/usr/bin/python3 - "$out/$label" "$label" $runs <<'PY'
import json, os, sys
top, label, runs = sys.argv[1], sys.argv[2], sys.argv[3:]
def get(d, *keys):
    for k in keys:
        if not isinstance(d, dict) or k not in d: return None
        d = d[k]
    return d
def fmt(v, f):
    return "—" if v is None else format(v, f)
print(f"| case ({label}) | grid | iterations | FFT pairs | solve s | FFT pair ms | time / pair | time / iteration | a_r | repulsive a_r | mean gap µm | status |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    kind, n = r.split(":")
    s = json.load(open(os.path.join(top, f"{kind}-{n}", "summary.json")))
    last = s["steps"][-1]
    t = s.get("timing", {})
    pair = t.get("fft_pair_s")
    solve = sum(st.get("wall_s", 0.0) for st in s["steps"])
    gap = last.get("mean_gap")
    print(f"| {kind} | {n}² | {t.get('iterations', last.get('iterations'))} | {fmt(t.get('fft_pairs'), '.0f')} | {solve:.1f} | "
          f"{fmt(None if pair is None else pair * 1e3, '.2f')} | {fmt(t.get('time_per_fft_pair'), '.2f')} | "
          f"{fmt(t.get('time_per_iteration'), '.2f')} | {fmt(last.get('contact_fraction'), '.5f')} | "
          f"{fmt(get(last, 'observables', 'repulsive_fraction'), '.5f')} | {fmt(None if gap is None else gap * 1e6, '.5f')} | {s['status']} |")
PY
