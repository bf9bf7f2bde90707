"""The command scripts/bench_iterations_table.py: the record of scripts/bench_iterations.sh (its
runs' iterations and ratios, and the factors the GPU reference plan scales the stored runs' times
by: plan_factors, read by cmc.gpu_plan.iteration_scale) and its table."""
import json
import os
import re
import sys
from collections.abc import Sequence
from typing import Any, Optional

Record = dict[str, Any]  # a run's counts, a grid's entry or the factors, as the JSON record holds them
STORE = "reference/challenge/runs.json"


def unfinished_record(path: str) -> Optional[Record]:
    """Where a run was stopped before it converged: the counts of its last checkpoint (lower
    bounds), or None where it has none."""
    checkpoint = os.path.join(path, ".partial", "checkpoint.h5")
    if not os.path.exists(checkpoint):
        return None
    import h5py
    with h5py.File(checkpoint, "r") as f:
        progress = f["progress"][()].decode()
    counts = dict(re.findall(r"^(iterations|outer|fft_pairs) = ([0-9.]+)$", progress, re.M))
    if "iterations" not in counts:
        return None
    return {"iterations": int(counts["iterations"]), "outer_steps": int(counts.get("outer", 0)),
            "fft_pairs": float(counts.get("fft_pairs", 0)), "a_r": None, "mean_gap_m": None, "solve_s": None,
            "threads": 1, "status": "unfinished: stopped before it converged; its last checkpoint's counts (lower bounds)"}


def run_record(path: str) -> Optional[Record]:
    """What one finished run measured, an unfinished one's last checkpoint, or None."""
    summary = os.path.join(path, "summary.json")
    if not os.path.exists(summary):
        return unfinished_record(path)
    with open(summary) as f:
        s = json.load(f)
    last = s["steps"][-1]
    t = s.get("timing", {})
    return {"iterations": t.get("iterations", last.get("iterations")),
            "outer_steps": last.get("diagnostics", {}).get("outer_iterations"),
            "fft_pairs": t.get("fft_pairs"),
            "a_r": last.get("contact_fraction"),
            "mean_gap_m": last.get("mean_gap"),
            "solve_s": sum(st.get("wall_s", 0.0) for st in s["steps"]),
            "threads": s.get("grid", {}).get("threads"),
            "status": s["status"]}


def ratio(a: Optional[Record], b: Optional[Record], key: str = "iterations") -> Optional[float]:
    if a is None or b is None or not a.get(key) or not b.get(key):
        return None
    return float(a[key] / b[key])


def stored_shape(n: int) -> Optional[Record]:
    """The stored shape run of the same command on grid n (before this benchmark's solver)."""
    with open(STORE) as f:
        records = json.load(f)["records"]
    for r in records:
        if r["tag"] == f"family-s1_shape-{n}":
            return dict(r)
    return None


def against_stored(run: Optional[Record], n: int) -> Optional[Record]:
    old = stored_shape(n)
    if run is None or old is None or run["a_r"] is None:
        return None
    return {"stored_iterations": old["iterations"], "stored_a_r": old["a_r"],
            "stored_mean_gap_m": old["mean_gap_m"], "stored_solve_s": old["solve_s"],
            "iterations_ratio": run["iterations"] / old["iterations"],
            "a_r_relative_change": run["a_r"] / old["a_r"] - 1.0,
            "mean_gap_relative_change": run["mean_gap_m"] / old["mean_gap_m"] - 1.0}


def grid_entry(top: str, n: int, prev: Optional[int]) -> Record:
    """Grid n's runs and ratios (prev: the coarser grid the warm runs started from)."""
    cold = {k: run_record(os.path.join(top, f"{k}-{n}")) for k in ("plain", "shape")}
    entry: Record = {"n": n, "plain": cold["plain"], "shape": cold["shape"],
             "shape_over_plain": ratio(cold["shape"], cold["plain"]),
             "shape_against_stored": against_stored(cold["shape"], n)}
    for k in ("plain", "shape"):
        old = run_record(os.path.join(top, f"before-{k}-{n}"))
        if old is not None:
            entry[f"before_{k}"] = old
            entry[f"{k}_over_before"] = ratio(cold[k], old)
    if "before_plain" in entry:
        entry["before_shape_over_plain"] = ratio(entry.get("before_shape"), entry["before_plain"])
    if prev is not None:
        for k in ("plain", "shape"):
            warm = run_record(os.path.join(top, f"{k}-{n}-from-{prev}"))
            if warm is not None:
                entry[f"{k}_from_{prev}"] = warm
                entry[f"{k}_warm_over_cold"] = ratio(warm, cold[k])
    unfinished = [k for k, r in entry.items() if isinstance(r, dict) and r.get("status", "").startswith("unfinished")]
    if unfinished:
        entry["unfinished"] = unfinished  # their counts, and the ratios with them, are bounds
    return entry


def plan_factors(grids_out: list[Record], tolerance: float) -> Record:
    """This build's iterations over the one before's per strategy, and the warm start's over
    the cold, each from the finest grid that has them."""
    f: Record = {"tolerance": tolerance}
    for key, name in (("plain_over_before", "plain"), ("shape_over_before", "shape"),
                      ("plain_warm_over_cold", "warm_plain"), ("shape_warm_over_cold", "warm_shape")):
        have = [e for e in grids_out if e.get(key) is not None and not (name.endswith("shape") and e.get("unfinished"))]
        if have:
            f[name], f[name + "_grid"] = have[-1][key], have[-1]["n"]
    # A finer grid's shape run against the stored run of the same command (the older program's,
    # which iterated like the build before at 2048²): converged, the factor measured on the
    # finest grid; stopped unconverged, a lower bound there, the larger of the two kept.
    for e in grids_out:
        run, old = e.get("shape"), stored_shape(e["n"])
        if not (run and old and "shape" in f) or e["n"] <= f["shape_grid"]:
            continue
        ratio = run["iterations"] / old["iterations"]
        if not run["status"].startswith("unfinished"):
            f["shape"], f["shape_grid"] = ratio, e["n"]
            f.pop("shape_is_lower_bound", None)
        elif ratio > f["shape"]:
            f["shape"], f["shape_grid"], f["shape_is_lower_bound"] = ratio, e["n"], True
    return f


def write_record(top: str, path: str, tolerance: float, grids: list[int]) -> None:
    """The record of the runs under top on the grids, written atomically to path, and its table."""
    grids_out: list[Record] = []
    prev: Optional[int] = None
    for n in grids:
        grids_out.append(grid_entry(top, n, prev))
        prev = n
    record = {"what": "iterations of the challenge (scaled family s = 1, 250 kPa, mu_T = 3) with the "
                      "plain law and the shape coarse-graining, cold, started from the coarser grid, and "
                      "with the build before (scripts/bench_iterations.sh); one thread a run, wall times "
                      "noisy on the shared 2-core machine",
              "tolerance": tolerance, "plan_factors": plan_factors(grids_out, tolerance),
              "grids": grids_out}
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(record, f, indent=1)
    os.replace(tmp, path)
    print_table(grids_out)
    print(f"\nrecord: {path}")


def fmt(v: Optional[float], f: str) -> str:
    return "—" if v is None else format(v, f)


def print_table(grids: list[Record]) -> None:
    print("| grid | run | iterations | outer steps | a_r | mean gap µm | solve s | status |")
    print("|---|---|---|---|---|---|---|---|")
    for e in grids:
        for k, r in e.items():
            if isinstance(r, dict) and "iterations" in r:
                print(f"| {e['n']}² | {k} | {r['iterations']} | {fmt(r['outer_steps'], 'd')} | {fmt(r['a_r'], '.6f')} | "
                      f"{fmt(None if r['mean_gap_m'] is None else r['mean_gap_m'] * 1e6, '.6f')} | {fmt(r['solve_s'], '.0f')} | {r['status']} |")
        for k in ("shape_over_plain", "before_shape_over_plain", "plain_over_before", "shape_over_before",
                  "plain_warm_over_cold", "shape_warm_over_cold"):
            if k in e:
                print(f"| {e['n']}² | {k.replace('_over_', '/')} | {fmt(e[k], '.2f')} | | | | | |")
        if e.get("unfinished"):
            print(f"| {e['n']}² | unfinished: {', '.join(e['unfinished'])} | their counts are lower bounds, "
                  "and so are the ratios over a finished run | | | | | |")


def main(argv: Sequence[str], doc: str) -> int:
    """scripts/bench_iterations_table.py RUNS_DIR JSON_PATH TOLERANCE GRID...; exit 2 for bad numbers."""
    if len(argv) < 4:
        sys.exit(doc)
    try:
        tol, grid_list = float(argv[2]), [int(g) for g in argv[3:]]
    except ValueError:
        print(f"bench_iterations_table: expected a tolerance and whole-number grids, got {list(argv[2:])}", file=sys.stderr)
        return 2
    write_record(argv[0], argv[1], tol, grid_list)
    return 0
