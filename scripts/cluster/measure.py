#!/usr/bin/python3
"""Measure what the cluster cost model needs, on this machine (docs/user-guide/cluster.md).

usage: scripts/cluster/measure.py [--out reference/cluster/measurements.json] [--sizes 1024 2048 4096]
                                  [--solvers polonsky_keer adhesive_cg quasi_static]

For each grid side n and each distributed solver (Polonsky-Keer on the hard-wall
challenge, the adhesive CG and the quasi-static solver on the challenge with adhesion;
--solvers measures some of them again and keeps the stored runs of the others) it runs
the MPI build
(build-mpi/cmc; scripts/mpi.sh builds it) at 1 and 2 ranks, 10 iterations each (the
peak memory is reached in the first; the time of one FFT pair is timed by every run at
its start, summary.json timing.fft_pair_s), and records per run: the FFT pair's time,
the largest rank's peak resident memory (ru_maxrss) and a 64^2 run's peak (the memory
a process holds whatever the grid: libraries, MPI). The whole-solve counts (FFT pairs
of a converged run at 512^2 .. 2048^2, and the run's time per FFT pair) are taken from
the benchmark runs of scripts/bench_solvers.sh (results/bench/current) where present,
else from the stored measurements. scripts/cluster/cost_model.py turns these into the
table of docs/performance-tables.md.
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MPI = os.path.join(ROOT, "build-mpi", "cmc")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
SOLVERS = {
    "polonsky_keer": ("cases/challenge/reference-load-hardwall.toml", []),
    "adhesive_cg": ("cases/challenge/reference-load.toml", ['solver.kind="adhesive_cg"', "loading.max_halvings=0"]),
    # One outer step with a loose inner solve (a tension tolerance above 1 ends the loop
    # after the first step, whose cascade runs): every field of the solver is allocated
    # and used, in seconds rather than a whole solve.
    "quasi_static": ("cases/challenge/reference-load.toml",
                     ["solver.max_iterations=500", "solver.tolerance=1e-2", "solver.tension_tolerance=1.5"]),
}


def run(np_, case, sets, n, out):
    args = ["mpirun", "-np", str(np_), "--oversubscribe", MPI, "run", os.path.join(ROOT, case), "--out", out,
            "--quiet", "--set", f"grid.n={n}", "--set", "solver.max_iterations=10", "--set", "output.fields=false"]
    for s in sets:
        args += ["--set", s]
    probe = ("import resource, subprocess, sys; subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, "
             "stderr=subprocess.DEVNULL); print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    p = subprocess.run([sys.executable, "-c", probe] + args, env=ENV, capture_output=True, text=True, timeout=3600)
    peak_mb = int(p.stdout.split()[-1]) / 1024.0
    summary = json.load(open(os.path.join(out, "summary.json")))
    return {"n": n, "ranks": np_, "fft_pair_s": summary["timing"]["fft_pair_s"], "peak_mb_largest_rank": peak_mb}


def bench_counts():
    """FFT pairs of converged whole solves and their time per FFT pair (scripts/bench_solvers.sh)."""
    out = {}
    base = os.path.join(ROOT, "results", "bench", "current")
    for solver, prefix in (("adhesive_cg", "adhesive-cg-"), ("quasi_static", "adhesive-"), ("polonsky_keer", "hardwall-")):
        rows = []
        for n in (512, 1024, 2048, 4096):
            f = os.path.join(base, f"{prefix}{n}", "summary.json")
            if os.path.exists(f):
                t = json.load(open(f))["timing"]
                rows.append({"n": n, "fft_pairs": t["fft_pairs"], "time_per_fft_pair": t["time_per_fft_pair"]})
        if rows:
            out[solver] = rows
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "cluster", "measurements.json"))
    ap.add_argument("--sizes", type=int, nargs="+", default=[1024, 2048, 4096])
    ap.add_argument("--solvers", nargs="+", choices=sorted(SOLVERS), default=sorted(SOLVERS))
    a = ap.parse_args()
    if not os.path.exists(MPI):
        sys.exit(f"measure.py: {MPI} not found: run scripts/mpi.sh first (it builds the MPI program)")
    work = os.path.join(ROOT, "results", "cluster-measure")
    old = json.load(open(a.out)) if os.path.exists(a.out) else {}
    runs = {k: v for k, v in old.get("runs", {}).items() if k not in a.solvers}
    for solver in a.solvers:
        case, sets = SOLVERS[solver]
        runs[solver] = []
        for n in a.sizes:
            for np_ in (1, 2):
                r = run(np_, case, sets, n, os.path.join(work, f"{solver}-{n}-np{np_}"))
                print(f"{solver} {n}^2 np {np_}: FFT pair {r['fft_pair_s'] * 1e3:.2f} ms, "
                      f"largest rank {r['peak_mb_largest_rank']:.0f} MB", file=sys.stderr)
                runs[solver].append(r)
    baseline = run(1, SOLVERS["polonsky_keer"][0], [], 64, os.path.join(work, "baseline"))["peak_mb_largest_rank"]
    doc = {
        "what": "measurements for scripts/cluster/cost_model.py (docs/user-guide/cluster.md)",
        "command": "scripts/cluster/measure.py --sizes " + " ".join(map(str, a.sizes))
                   + " --solvers " + " ".join(a.solvers),
        "date": datetime.date.today().isoformat(),
        "dates": {**old.get("dates", {s_: old.get("date", "") for s_ in old.get("runs", {})}),
                  **{s_: datetime.date.today().isoformat() for s_ in a.solvers}},
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, {platform.platform()}",
        "threads_per_rank": int(os.environ.get("CMC_THREADS", "0")) or "all cores / ranks",
        "baseline_peak_mb": baseline,
        "runs": runs,
        "whole_solves": bench_counts() or old.get("whole_solves", {}),
    }
    tmp = a.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(tmp, a.out)
    print(f"measure.py: wrote {a.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
