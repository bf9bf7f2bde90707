#!/usr/bin/python3
"""The cost of the challenge at large grids on a cluster (docs/user-guide/cluster.md).

usage: scripts/cluster/cost_model.py [--measurements reference/cluster/measurements.json]
                                     [--memory-per-rank-gb 3.5] [--efficiency 0.5]
                                     [--sizes 16384 32768 65536] [--markdown]

From scripts/cluster/measure.py's measurements on one machine at 1 and 2 ranks, and
these stated assumptions:

  memory   a rank holds its baseline (the 64^2 run's peak: libraries, MPI) plus its slab
           of every field: (peak - baseline) / (points / ranks) bytes a point, measured at
           2 ranks on the largest grid. The ranks are the fewest (a power of two) that
           keep a rank within --memory-per-rank-gb (3.5 GB: a 4 GB-per-core node).
  time     one FFT pair of the whole grid on one core costs c N log2 N, c from the
           largest grid at 1 rank; on P ranks it costs c N log2 N / (P e), e the parallel
           efficiency: --efficiency (0.5: slab-decomposed FFTs over a network, whose
           all-to-all transposes move every point twice per transform; an assumption,
           not measured here). The efficiency measured here at 2 ranks on one machine
           (shared memory) is printed beside it as an upper bound.
  solves   a converged run's FFT pairs grow with the grid as a power law fitted to the
           whole solves of scripts/bench_solvers.sh at 1024^2 and 2048^2 (the challenge
           at the reference load; Delta x = 24 rho at 2048^2, 0.74 rho at 65536^2, where
           the adhesion is resolved and the iteration count may differ: an
           extrapolation over five doublings, the largest uncertainty here), and a run
           costs that many pairs times its measured time per pair (the passes besides
           the transforms).

Prints one row per grid and solver: points, ranks, memory per rank, FFT pairs, hours.
"""
import argparse
import json
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--measurements", default=os.path.join(ROOT, "reference", "cluster", "measurements.json"))
    ap.add_argument("--memory-per-rank-gb", type=float, default=3.5)
    ap.add_argument("--efficiency", type=float, default=0.5)
    ap.add_argument("--hours", type=float, default=24.0, help="the longest run wanted (ranks are added until it fits)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[16384, 32768, 65536])
    ap.add_argument("--markdown", action="store_true", help="a Markdown table (as in docs/performance-tables.md)")
    a = ap.parse_args()
    if not os.path.exists(a.measurements):
        sys.exit(f"cost_model.py: {a.measurements} not found: run scripts/cluster/measure.py first")
    m = json.load(open(a.measurements))
    base = m["baseline_peak_mb"] * 2**20
    rows = []
    notes = []
    for solver, runs in m["runs"].items():
        nmax = max(r["n"] for r in runs)
        one = next(r for r in runs if r["n"] == nmax and r["ranks"] == 1)
        two = next(r for r in runs if r["n"] == nmax and r["ranks"] == 2)
        N = float(nmax) ** 2
        bpp = (two["peak_mb_largest_rank"] * 2**20 - base) / (N / 2)
        c = one["fft_pair_s"] / (N * math.log2(N))
        e2 = one["fft_pair_s"] / (2 * two["fft_pair_s"])
        solves = m["whole_solves"].get(solver)
        if not solves or len(solves) < 2:
            sys.exit(f"cost_model.py: no whole-solve counts for {solver} in {a.measurements}")
        s1, s2 = sorted(solves, key=lambda r: r["n"])[-2:]
        alpha = math.log(s2["fft_pairs"] / s1["fft_pairs"]) / math.log(s2["n"] / s1["n"])
        ratio = s2["time_per_fft_pair"]
        notes.append(f"{solver}: {bpp:.0f} bytes a point (measured at {nmax}^2, 2 ranks); one FFT pair "
                     f"{one['fft_pair_s'] * 1e3:.1f} ms at 1 rank, {two['fft_pair_s'] * 1e3:.1f} ms at 2 ranks "
                     f"(efficiency {e2:.2f} on one machine; {a.efficiency} assumed on a cluster); FFT pairs grow as "
                     f"n^{alpha:.2f} ({s1['fft_pairs']:.0f} at {s1['n']}^2, {s2['fft_pairs']:.0f} at {s2['n']}^2); "
                     f"{ratio:.2f} pair-times per FFT pair in a whole solve")
        for n in a.sizes:
            Np = float(n) ** 2
            pairs = s2["fft_pairs"] * (n / s2["n"]) ** alpha
            ranks = 1
            cost = lambda P: (base + bpp * Np / P, c * Np * math.log2(Np) / (P * a.efficiency))
            # The slab decomposition gives every rank at least one row: at most n ranks.
            while ranks < n and (cost(ranks)[0] > a.memory_per_rank_gb * 1e9 or
                                 pairs * ratio * cost(ranks)[1] / 3600.0 > a.hours):
                ranks *= 2
            mem, pair = cost(ranks)
            hours = pairs * ratio * pair / 3600.0
            rows.append((solver, n, ranks, mem / 1e9, pair, pairs, hours))
    if a.markdown:
        print("| solver | grid | Δx / ρ | ranks | memory per rank | one FFT pair | FFT pairs (extrapolated) | hours |")
        print("|---|---|---|---|---|---|---|---|")
        for solver, n, ranks, mem, pair, pairs, hours in rows:
            print(f"| {solver} | {n}² | {24.0 * 2048 / n:.2g} | {ranks} | {mem:.2f} GB | {pair:.2f} s | "
                  f"{pairs:,.0f} | {hours:.1f} |")
    else:
        print(f"{'solver':14s} {'grid':>7s} {'ranks':>6s} {'GB/rank':>8s} {'pair s':>8s} {'FFT pairs':>10s} {'hours':>7s}")
        for solver, n, ranks, mem, pair, pairs, hours in rows:
            print(f"{solver:14s} {n:7d} {ranks:6d} {mem:8.2f} {pair:8.2f} {pairs:10.0f} {hours:7.1f}")
    print()
    for s in notes:
        print("- " + s)
    print(f"- measured {m['date']} on {m['machine']} ({m['command']})")


if __name__ == "__main__":
    main()
