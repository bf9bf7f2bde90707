"""The command scripts/performance_tables.py: docs/performance-tables.md, one table per backend,
from the stored measurements."""
from __future__ import annotations
from typing import Any, Iterable, Sequence
import argparse
import json
import os
import subprocess
import sys

from cmc.analysis.runs import REPO as ROOT

DEFAULT_BENCH = "reference/performance/cpu-benchmark.json"
GPU_STORES = ("reference/challenge/runs.json",)  # the run store
DEFAULT_CLUSTER = "reference/cluster/measurements.json"
DEFAULT_OUT = "docs/performance-tables.md"
BENCH_COMMAND = ("CMC_THREADS=1 build/cmc_bench --benchmark_filter='(BM_FFTPair|BM_RowColumnPair|BM_PolonskyKeerIteration"
                 "|BM_PolonskyKeerIteration_plain)/(512|1024|2048)/|BM_QuasiStaticSolve/(512|1024)/' "
                 "--benchmark_repetitions=3 --benchmark_out=" + DEFAULT_BENCH + " --benchmark_out_format=json")


class InputError(Exception):
    pass


def load_json(path: str) -> Any:
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError:
        return None
    except ValueError as e:
        raise InputError(f"{path}: not JSON ({e})")


def table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return out


def num(v: float | None, digits: int = 3) -> str:
    if v is None:
        return "–"
    if isinstance(v, (int, float)) and v != 0 and (abs(v) >= 1e5 or abs(v) < 1e-3):
        return f"{v:.{digits - 1}e}"
    return f"{v:.{digits}g}"


# ------------------------------------------------------------------ CPU: cmc_bench
def bench_records(paths: Iterable[str]) -> tuple[dict[str, dict[str, Any]], Any]:
    """{benchmark family/arg: record} and the context of the last file read. Of repetitions the
    fastest (an iteration benchmark's by its ms_per_iteration): other work on the machine only
    ever adds time. Without repetitions, the median aggregate, else the mean."""
    records, context = {}, None
    for path in paths:
        data = load_json(path)
        if data is None:
            continue
        if not isinstance(data, dict) or "benchmarks" not in data:
            raise InputError(f"{path}: not Google Benchmark JSON (no 'benchmarks')")
        context = data.get("context", {})
        chosen: dict[str, Any] = {}
        for b in data["benchmarks"]:
            key = "/".join(b.get("run_name", b["name"]).split("/")[:2])
            rank = {"median": 1, "mean": 2}.get(b.get("aggregate_name"), 0 if b.get("run_type") != "aggregate" else None)
            if rank is None:
                continue
            cost = (rank, b.get("ms_per_iteration", ms(b)) if rank == 0 else 0.0)
            if key not in chosen or cost < chosen[key][0]:
                chosen[key] = (cost, b)
        records.update({k: v[1] for k, v in chosen.items()})
    return records, context


def ms(b: dict[str, Any]) -> float:
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
    return b["real_time"] * scale


def grids(records: dict[str, Any], family: str) -> list[int]:
    return sorted(int(k.split("/")[1]) for k in records if k.split("/")[0] == family)


def cpu_section(paths: Sequence[str]) -> list[str]:
    records, ctx = bench_records(paths)
    lines = ["## CPU", ""]
    if not records:
        return lines + [f"No benchmark output yet: `{BENCH_COMMAND}`.", ""]
    caches = {c.get("level"): c.get("size") for c in ctx.get("caches", []) if c.get("type") != "Instruction"}
    load = ctx.get("load_avg") or []
    lines += [f"Machine: {ctx.get('num_cpus', '?')} cores at {ctx.get('mhz_per_cpu', '?')} MHz, "
              f"L2 {caches.get(2, 0) // 1024} KiB, L3 {caches.get(3, 0) // 2**20} MiB; load average at the start "
              f"{', '.join(f'{x:.1f}' for x in load[:3]) or 'not recorded'}. One thread: on a machine shared with "
              "other work, threads that wait for each other at every pass slow down far more than one thread "
              "does. Each number is the fastest of the repetitions, since other work only adds time. Made by", "",
              f"    {BENCH_COMMAND}", ""]
    rows = [[f"{n}²", num(ms(records[f'BM_FFTPair/{n}'])) if f"BM_FFTPair/{n}" in records else "–",
             num(ms(records[f'BM_RowColumnPair/{n}'])) if f"BM_RowColumnPair/{n}" in records else "–"]
            for n in sorted(set(grids(records, "BM_FFTPair")) | set(grids(records, "BM_RowColumnPair")))]
    if rows:
        lines += ["One FFT pair (an r2c and a c2r transform of the grid), ms: FFTW's 2-D transforms and cmc's "
                  "row-column transforms (the fused sweeps of Polonsky–Keer).", ""]
        lines += table(["grid", "FFTW 2-D pair", "row-column pair"], rows) + [""]
    lines += iteration_table(records)
    lines += quasi_static_table(records)
    return lines


def iteration_table(records: dict[str, dict[str, Any]]) -> list[str]:
    rows = []
    for family, label in (("BM_PolonskyKeerIteration", "preconditioned"), ("BM_PolonskyKeerIteration_plain", "plain")):
        for n in grids(records, family):
            b = records[f"{family}/{n}"]
            rows.append([f"Polonsky–Keer, {label}", f"{n}²", num(b.get("ms_per_iteration")),
                         num(b.get("fft_pairs_per_iteration")), num(b.get("floor_pair_ms")),
                         num(b.get("time_per_floor_pair")), num(b.get("time_per_fft_pair")), num(b.get("fft_share"), 2)])
    if not rows:
        return []
    return (["The iteration of the solver's loop (the difference of a 10- and a 30-iteration solve from one warm "
             "start, each its fastest repetition), its FFT pairs, the floor pair (the faster of the two pairs timed "
             "in the same run), and the iteration's time per FFT pair in units of the floor pair and of FFTW's pair "
             "(1 would be a solver that does nothing but transforms); share: the part inside the transforms.", ""]
            + table(["solver", "grid", "ms / iteration", "FFT pairs / iteration", "floor pair ms",
                     "per pair (floor)", "per pair (FFTW)", "share"], rows) + [""])


def quasi_static_table(records: dict[str, dict[str, Any]]) -> list[str]:
    rows = []
    for n in grids(records, "BM_QuasiStaticSolve"):
        b = records[f"BM_QuasiStaticSolve/{n}"]
        rows.append([f"{n}²", num(ms(b) / 1e3), num(b.get("outer_steps")), num(b.get("fft_pairs_per_solve"), 4),
                     num(b.get("time_per_floor_pair")), num(b.get("contact_fraction"), 4),
                     "yes" if b.get("converged") == 1 else "no"])
    if not rows:
        return []
    return (["The challenge's adhesive solve (`cases/challenge/reference-load.toml`, quasi-static solver) whole:",
             ""] + table(["grid", "solve s", "outer steps", "FFT pairs", "per pair (floor)", "a_r", "converged"], rows)
            + [""])


def stored_section(path: str, heading: str, key: str, kind: type, missing: str) -> tuple[list[str], Any, Any]:
    """A section's heading and a stored JSON file's part `key` (of type kind), or, where the file
    is not there, the heading and a line saying what makes it (part None)."""
    data = load_json(path)
    lines = [f"## {heading}", ""]
    if data is None:
        return lines + [missing, ""], None, None
    part = data.get(key) if isinstance(data, dict) else None
    if not isinstance(part, kind):
        raise InputError(f"{path}: no '{key}' ({kind.__name__})")
    return lines, data, part


# ------------------------------------------------------------------ GPU: the stored runs with backend "cuda"
def gpu_section(path: str) -> list[str]:
    shown = os.path.relpath(path, ROOT)
    lines, _, recs = stored_section(path, "GPU", "records", list,
                                    f"No GPU runs stored (`{shown}`: scripts/gpu/check.sh, then scripts/gpu/store.py).")
    if recs is None:
        return lines
    recs = [r for r in recs if r.get("backend", "cuda") == "cuda"]
    order = {"hardwall": 0, "adhesive": 1, "shape": 2}
    is_tabor = lambda r: str(r.get("kind", "")).startswith("tabor")  # noqa: E731
    recs = sorted(recs, key=lambda r: (order.get(r.get("kind"), 3), (r.get("tabor") or 0) if is_tabor(r) else 0,
                                       r.get("n", 0)))
    rows = []
    for r in recs:
        per = f"{num(r.get('time_per_iteration'))} / {num(r.get('time_per_fft_pair'))}"
        case = f"Tabor sweep, μ_T = {r['tabor']:g}" if is_tabor(r) and r.get("tabor") else r.get("kind", "?")
        rows.append([device_name(r.get("device", "")), case, f"{r.get('n')}²", r.get("outer_steps") or "–",
                     r.get("iterations", "–"), num(r.get("fft_pairs"), 5), num(r.get("solve_s")),
                     num(1e3 * r["fft_pair_s"]) if r.get("fft_pair_s") else "–", per,
                     num(r.get("a_r"), 4), num(1e6 * r["mean_gap_m"], 6) if r.get("mean_gap_m") else "–",
                     num(r["gpu_peak_mib"] / 1024, 3) if r.get("gpu_peak_mib") else "–", r.get("status", "?")])
    lines += ["The challenge at 250 kPa on one GPU (`grid.backend = \"cuda\"`), as stored with each run's command "
              f"in `{shown}`; the pair is cuFFT's r2c + c2r of the grid timed in the same run, and the ratios "
              "are the solve's time per iteration and per FFT pair in units of it.", ""]
    lines += table(["device", "case", "grid", "outer steps", "iterations", "FFT pairs", "solve s", "cuFFT pair ms",
                    "per iteration / per pair", "a_r", "mean gap µm", "GPU peak GiB", "status"], rows) + [""]
    return lines


def device_name(text: str) -> str:
    """'NVIDIA H200 143771 MiB (driver ...)' -> 'H200'."""
    words = text.split()
    return words[1] if len(words) > 1 and words[0] == "NVIDIA" else (text or "?")


# ------------------------------------------------------------------ cluster: measurements.json
def cluster_section(path: str) -> list[str]:
    lines, data, runs = stored_section(path, "Cluster", "runs", dict,
                                       f"No measurements stored (`{DEFAULT_CLUSTER}`: scripts/cluster/measure.py).")
    if runs is None:
        return lines
    rows = [[solver, f"{r['n']}²", r["ranks"], num(1e3 * r["fft_pair_s"]), num(r["peak_mb_largest_rank"], 4)]
            for solver in sorted(runs) for r in sorted(runs[solver], key=lambda r: (r["n"], r["ranks"]))]
    lines += [f"Measured by `{data.get('command', 'scripts/cluster/measure.py')}` on {data.get('machine', '?')}, "
              "one thread per rank: one distributed FFT pair and the largest rank's peak memory.", ""]
    lines += table(["solver", "grid", "ranks", "FFT pair ms", "peak MB, largest rank"], rows) + [""]
    model = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "cluster", "cost_model.py"), "--markdown",
                            "--measurements", path], capture_output=True, text=True)
    if model.returncode != 0:
        raise InputError(f"scripts/cluster/cost_model.py failed: {model.stderr.strip()}")
    kept = [ln for ln in model.stdout.splitlines() if not ln.startswith("- measured")]
    lines += ["The challenge at the reference resolution extrapolated from them "
              "(`scripts/cluster/cost_model.py --markdown`: the fewest ranks, a power of two, that keep a rank "
              "within 3.5 GB and the run within 24 hours; a parallel efficiency of 0.5 assumed):", ""]
    return lines + kept + [""]


# ------------------------------------------------------------------ main
def render(bench: Sequence[str], gpu: str, cluster: str) -> str:
    lines = ["# Performance tables", "",
             "Generated by `/usr/bin/python3 scripts/performance_tables.py` from the measurements stored in "
             "`reference/`; do not edit by hand (ctest `docs.performance_tables` fails when this file is not what "
             "the script makes). What the numbers mean: [performance](performance.md).", ""]
    lines += cpu_section(bench) + gpu_section(gpu) + cluster_section(cluster)
    return "\n".join(lines).rstrip("\n") + "\n"


def main(argv: list[str] | None = None, doc: str | None = None) -> int:
    ap = argparse.ArgumentParser(description=(doc or __doc__).split("\n")[0])
    ap.add_argument("--bench", nargs="+", default=[DEFAULT_BENCH])
    ap.add_argument("--gpu", default=None, help="default: the first of " + ", ".join(GPU_STORES) + " that exists")
    ap.add_argument("--cluster", default=DEFAULT_CLUSTER)
    ap.add_argument("--out", default=DEFAULT_OUT)
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args(argv)
    at = lambda p: p if os.path.isabs(p) else os.path.join(ROOT, p)  # noqa: E731
    gpu = a.gpu or next((p for p in GPU_STORES if os.path.exists(at(p))), GPU_STORES[-1])
    try:
        text = render([at(p) for p in a.bench], at(gpu), at(a.cluster))
    except (InputError, KeyError, TypeError) as e:
        print(f"performance_tables: {e}", file=sys.stderr)
        return 2
    if a.out == "-":
        sys.stdout.write(text)
        return 0
    out = at(a.out)
    if a.check:
        try:
            with open(out, encoding="utf-8") as f:
                same = f.read() == text
        except OSError:
            same = False
        print(f"performance_tables: {os.path.relpath(out, ROOT)} "
              + ("is current" if same else "is not what the stored measurements make: run "
                                           "/usr/bin/python3 scripts/performance_tables.py"))
        return 0 if same else 1
    tmp = out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, out)
    print(f"performance_tables: wrote {os.path.relpath(out, ROOT)}")
    return 0

