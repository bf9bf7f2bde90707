#!/usr/bin/env bash
# Whole-solve benchmark: the challenge surface at the reference load (250 kPa), with
# adhesion (the quasi-static loading-branch solver, 'adhesive', beside the adhesive
# CG, 'adhesive-cg', kept runnable for this comparison) and without (Polonsky-Keer), on
# several grids. Prints, per run,
# what cmc measured in that run: iterations, FFT pairs, wall time of the solves, the time
# of one FFT pair of the run's operator (timed at its start; FFTW's 2-D pair, and the
# row-column pair of Polonsky-Keer's fused sweeps where they run), the solve time per FFT
# pair (against FFTW's pair, and against the faster of the two: the floor) and per
# iteration in units of FFTW's pair (target: 1.3 per FFT pair), the share of
# the solve time spent inside the transforms (the rest is the solver's passes), and the
# answer: contact fraction a_r, repulsive a_r and mean gap.
#
# usage: scripts/bench_solvers.sh [--quick] [--cmc BIN] [--label NAME] [--out DIR]
#   --quick       small grids only (adhesive and adhesive-cg 256², 512²; hard wall 512², 1024²; ~1 min)
#   --cmc BIN     benchmark another build's cmc (e.g. an older solver) on the same cases
#   --label NAME  name of this set of runs in the table and under DIR (default: current)
#   --out DIR     where the runs go (default: results/bench); finished runs are reused
# Also runs the hard wall on the surface of the ContactMechanics timings in
# docs/performance.md (short cutoff 4 grid spacings; 'hardwall-peer')
# and writes speed-against-error records to results/performance/bench-LABEL.json for
# reports/performance/ (scripts/report.sh): per run, the relative error of a_r and of the
# mean gap against the finest grid of the same kind (so the finest has none).
# Default set (about 15 minutes on 2 cores): adhesive and adhesive-cg 512², 1024², 2048²;
# hard wall 2048², 4096².
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
if [ $quick = 1 ]; then runs="adhesive:256 adhesive-cg:256 adhesive:512 adhesive-cg:512 hardwall:512 hardwall:1024 hardwall-peer:512"
else runs="adhesive:512 adhesive-cg:512 adhesive:1024 adhesive-cg:1024 adhesive:2048 adhesive-cg:2048 hardwall:1024 hardwall:2048 hardwall:4096 hardwall-peer:512 hardwall-peer:1024 hardwall-peer:2048"; fi
mkdir -p "$out/$label"
for r in $runs; do
  kind=${r%%:*} n=${r##*:}
  case_file=cases/challenge/reference-load.toml extra=()
  [ "${kind%%-*}" = hardwall ] && case_file=cases/challenge/reference-load-hardwall.toml
  [ "$kind" = adhesive-cg ] && extra=(--set solver.kind=adhesive_cg)
  # The ContactMechanics comparison surface (bench/bench_kernels.cpp): the same spectrum
  # cut at 4 grid spacings (L = 1e-4 m).
  [ "$kind" = hardwall-peer ] && extra=(--set surface.cutoff_wavelength="$(/usr/bin/python3 -c "print(4e-4/$n)")")
  dir="$out/$label/$kind-$n"
  if [ -f "$dir/summary.json" ] && [ "$dir/summary.json" -nt "$cmc" ]; then continue; fi
  echo "bench_solvers: $cmc run $case_file --set grid.n=$n ${extra[*]}" >&2
  "$cmc" run "$case_file" --set grid.n="$n" "${extra[@]}" --out "$dir" --quiet || [ $? -eq 3 ]
done
mkdir -p results/performance
/usr/bin/python3 - "$out/$label" "$label" $runs <<'PY'
import json, os, sys
top, label, runs = sys.argv[1], sys.argv[2], sys.argv[3:]
# ContactMechanics (Pastewka group), Polonsky-Keer CG at its default tolerance, on the
# 'hardwall-peer' surface, measured on a 2-core machine like ours (iterations, wall s;
# docs/performance.md).
PEER = {512: (43, 2.2), 1024: (75, 16.5), 2048: (132, 148.0)}
def get(d, *keys):
    for k in keys:
        if not isinstance(d, dict) or k not in d: return None
        d = d[k]
    return d
def fmt(v, f):
    return "—" if v is None else format(v, f)
print(f"| case ({label}) | solver | grid | iterations | FFT pairs | solve s | FFT pair ms | row-column pair ms | time / pair | time / floor pair | time / iteration | in FFTs | a_r | repulsive a_r | mean gap µm | status |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    kind, n = r.split(":")
    s = json.load(open(os.path.join(top, f"{kind}-{n}", "summary.json")))
    last = s["steps"][-1]
    t = s.get("timing", {})
    pair = t.get("fft_pair_s")
    solve = sum(st.get("wall_s", 0.0) for st in s["steps"])
    gap = last.get("mean_gap")
    print(f"| {kind} | {get(s, 'case', 'solver', 'kind')} | {n}² | {t.get('iterations', last.get('iterations'))} | {fmt(t.get('fft_pairs'), '.0f')} | {solve:.1f} | "
          f"{fmt(None if pair is None else pair * 1e3, '.2f')} | {fmt(1e3 * t['row_column_pair_s'] if t.get('row_column_pair_s') else None, '.2f')} | "
          f"{fmt(t.get('time_per_fft_pair'), '.2f')} | {fmt(t.get('time_per_floor_pair'), '.2f')} | "
          f"{fmt(t.get('time_per_iteration'), '.2f')} | {fmt(t.get('fft_share'), '.2f')} | {fmt(last.get('contact_fraction'), '.5f')} | "
          f"{fmt(get(last, 'observables', 'repulsive_fraction'), '.5f')} | {fmt(None if gap is None else gap * 1e6, '.5f')} | {s['status']} |")

# Speed against error: each run against the finest grid of its kind.
summ = {}
for r in runs:
    kind, n = r.split(":")
    summ[(kind, int(n))] = json.load(open(os.path.join(top, f"{kind}-{n}", "summary.json")))
records = []
for (kind, n), s in sorted(summ.items()):
    finest = max(m for (k, m) in summ if k == kind)
    ref = summ[(kind, finest)]["steps"][-1]
    last = s["steps"][-1]
    err = {}
    if n != finest:
        for q, key in (("a_r", "contact_fraction"), ("mean_gap", "mean_gap")):
            if last.get(key) is not None and ref.get(key):
                err[q] = abs(last[key] / ref[key] - 1.0)
    t = s.get("timing", {})
    records.append({"case": f"cmc {kind} ({get(s, 'case', 'solver', 'kind')})", "grid": f"{n}²",
                    "tolerance": get(s, "case", "solver", "tolerance"),
                    "wall_s": sum(st.get("wall_s", 0.0) for st in s["steps"]),
                    "iterations": t.get("iterations"), "fft_pairs": t.get("fft_pairs"),
                    "fft_pair_s": t.get("fft_pair_s"), "error": err,
                    "reference": f"{kind} at {finest}²"})
    if kind == "hardwall-peer" and n in PEER:
        it, wall = PEER[n]
        records.append({"case": "ContactMechanics hardwall-peer (note)", "grid": f"{n}²", "wall_s": wall,
                        "iterations": it, "error": {},
                        "source": "ContactMechanics on a 2-core machine (docs/performance.md)"})
path = os.path.join("results", "performance", f"bench-{label}.json")
tmp = path + ".tmp"
with open(tmp, "w") as f:
    json.dump({"records": records}, f, indent=1)
os.replace(tmp, path)
print(f"\nspeed-against-error records: {path} (scripts/report.sh draws reports/performance/)")
peer = [(n, summ[("hardwall-peer", n)]) for n in sorted(PEER) if ("hardwall-peer", n) in summ]
if peer:
    print("\n| hard wall, peer surface | cmc iterations | cmc solve s | ContactMechanics iterations | ContactMechanics s | speed-up |")
    print("|---|---|---|---|---|---|")
    for n, s in peer:
        wall = sum(st.get("wall_s", 0.0) for st in s["steps"])
        it, cw = PEER[n]
        print(f"| {n}² | {s['timing'].get('iterations')} | {wall:.2f} | {it} | {cw} | {cw / wall:.1f}x |")
PY
