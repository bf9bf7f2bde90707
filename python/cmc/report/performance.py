"""reports/performance/: speed against accuracy, and iteration time against FFT time.

Inputs (each optional; a missing one becomes a line in index.md saying what to run):
  results/performance/*.json   records written by a benchmark script, each
        {case, grid, tolerance, wall_s, iterations, fft_pairs, fft_pair_s,
         error: {quantity: value, ...}}
        (a file holds one record, a list of records, or {"records": [...]}).
  build/bench.json             Google Benchmark JSON (cmc_bench --benchmark_format=json):
        BM_FFTPair/N and BM_PolonskyKeerIteration/N, items_per_second = iterations
        (or FFT pairs) per second.
"""
from __future__ import annotations
import glob
import os
import re

import numpy as np

from .common import finite, fmt, gpu_row_head, gpu_section, label_axes, load_json, md_table, plt, savefig


def _records(perf_dir, notes):
    recs = []
    for f in sorted(glob.glob(os.path.join(perf_dir, "*.json"))):
        d = load_json(f, notes)
        if isinstance(d, dict) and isinstance(d.get("records"), list):
            d = d["records"]
        if isinstance(d, dict):
            d = [d]
        if not isinstance(d, list):
            notes.append(f"`{f}`: not a record or a list of records; skipped")
            continue
        for r in d:
            if isinstance(r, dict) and finite(r.get("wall_s")):
                r = dict(r)
                r["_file"] = os.path.basename(f)
                recs.append(r)
    return recs


def _speed_vs_error(recs, out_dir):
    quantities = sorted({q for r in recs for q, v in (r.get("error") or {}).items() if finite(v) and v > 0})
    figs = []
    for q in quantities:
        fig, ax = plt.subplots(figsize=(5.6, 4.4))
        cases = sorted({str(r.get("case", "?")) for r in recs})
        for c in cases:
            pts = sorted(((r["error"][q], r["wall_s"], r) for r in recs
                          if str(r.get("case", "?")) == c and finite((r.get("error") or {}).get(q))
                          and r["error"][q] > 0 and r["wall_s"] > 0), key=lambda t: t[1])
            if not pts:
                continue
            ax.loglog([p[1] for p in pts], [p[0] for p in pts], "o-", ms=4, label=c)
            for e, w, r in pts:
                ax.annotate(f"{r.get('grid', '')}, tol {fmt(r.get('tolerance'), 2)}", (w, e), fontsize=6,
                            textcoords="offset points", xytext=(3, 3))
        label_axes(ax, "wall time (s)", f"error of {q}", f"speed vs accuracy: {q}")
        path = os.path.join(out_dir, f"speed_vs_error_{re.sub(r'[^A-Za-z0-9_.-]', '_', q)}.png")
        savefig(fig, path)
        figs.append((q, path))
    return figs


_UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


# Counters that an iteration benchmark measures in its own run (bench/bench_common.hpp):
# the FFT pair of its grid, and the iteration's time in units of it.
_SAME_RUN = ("fft_pair_ms", "fft_pairs_per_iteration", "iteration_over_fft_pair", "time_per_fft_pair")
# Against the faster of FFTW's pair and cmc's row-column pair, where the benchmark has them
# (benchmarks of builds before the floor pair do not).
_FLOOR = ("floor_pair_ms", "iteration_over_floor_pair", "time_per_floor_pair")


def _bench(bench_path, notes):
    """{benchmark family: {N: seconds per item}} from Google Benchmark JSON, and
    {family: {N: {counter: value}}} of the same-run counters where a benchmark has them."""
    d = load_json(bench_path, notes)
    if not isinstance(d, dict) or not isinstance(d.get("benchmarks"), list):
        return None, d, {}
    fam, same = {}, {}
    for b in d["benchmarks"]:
        if not isinstance(b, dict):
            continue
        name = b.get("run_name") or b.get("name", "")
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") not in ("median", "mean"):
            continue
        m = re.match(r"^(BM_[A-Za-z0-9_]+)/(\d+)", name)
        if not m:
            continue
        family, n = m.group(1), int(m.group(2))
        ips = b.get("items_per_second")
        if finite(b.get("ms_per_iteration")) and b["ms_per_iteration"] > 0:
            t = 1e-3 * b["ms_per_iteration"]  # the benchmark's own count: the loop's iteration
        elif finite(ips) and ips > 0:
            t = 1.0 / ips
        elif finite(b.get("real_time")):
            t = b["real_time"] * _UNIT.get(b.get("time_unit", "ns"), 1e-9)
        else:
            continue
        # Prefer the median aggregate, then the mean, then the last plain run.
        rank = {"median": 2, "mean": 1}.get(b.get("aggregate_name"), 0)
        cur = fam.setdefault(family, {}).get(n)
        if cur is None or rank >= cur[1]:
            fam[family][n] = (t, rank)
            c = {k: b[k] for k in _SAME_RUN if finite(b.get(k)) and b[k] > 0}
            if len(c) == len(_SAME_RUN):
                c.update({k: b[k] for k in _FLOOR if finite(b.get(k)) and b[k] > 0})
                same.setdefault(family, {})[n] = c
    return {f: {n: v[0] for n, v in d2.items()} for f, d2 in fam.items()}, d, same


def _bench_plot(fam, same, out_dir):
    fft = fam.get("BM_FFTPair", {})
    it = fam.get("BM_PolonskyKeerIteration", {})
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.2))
    if fft:
        ns = sorted(fft)
        a1.loglog(ns, [fft[n] * 1e3 for n in ns], "o-", label="FFT pair (r2c + c2r)")
    if it:
        ns = sorted(it)
        a1.loglog(ns, [it[n] * 1e3 for n in ns], "s-", label="Polonsky–Keer iteration")
    for fname, d in fam.items():
        if fname not in ("BM_FFTPair", "BM_PolonskyKeerIteration") and d:
            ns = sorted(d)
            a1.loglog(ns, [d[n] * 1e3 for n in ns], ".--", lw=0.8, label=fname)
    label_axes(a1, "grid points per side n (n × n grid)", "time (ms)", "time per FFT pair and per iteration")
    common = sorted(set(fft) & set(it))
    rows = []
    if same:
        # Ratios measured within each benchmark's own run: per iteration (solid) and per
        # FFT pair of the iteration (dashed).
        for k, (fname, d) in enumerate(sorted(same.items())):
            ns = sorted(d)
            col = f"C{k % 10}"
            a2.semilogx(ns, [d[n]["iteration_over_fft_pair"] for n in ns], "o-", color=col,
                        label=f"{fname}: per iteration")
            a2.semilogx(ns, [d[n]["time_per_fft_pair"] for n in ns], "s--", color=col, lw=0.8,
                        label=f"{fname}: per FFT pair")
            fl = [n for n in ns if "time_per_floor_pair" in d[n]]
            if fl:
                a2.semilogx(fl, [d[n]["time_per_floor_pair"] for n in fl], "^:", color=col, lw=0.8,
                            label=f"{fname}: per FFT pair, floor pair")
            rows += [[fname, n, fmt(d[n]["fft_pair_ms"], 4), fmt(d[n].get("floor_pair_ms"), 4),
                      fmt(fam.get(fname, {}).get(n, float("nan")) * 1e3, 4),
                      fmt(d[n]["fft_pairs_per_iteration"], 3), fmt(d[n]["iteration_over_fft_pair"], 3),
                      fmt(d[n]["time_per_fft_pair"], 3), fmt(d[n].get("time_per_floor_pair"), 3)] for n in ns]
        a2.axhspan(1.2, 1.3, color="tab:green", alpha=0.2, label="target 1.2–1.3")
        a2.axhline(1.0, color="gray", lw=0.8)
        top = max(v[q] for d in same.values() for v in d.values()
                  for q in ("iteration_over_fft_pair", "time_per_fft_pair", "time_per_floor_pair") if q in v)
        a2.set_ylim(0, max(2.0, top * 1.1))
    elif common:
        ratio = [it[n] / fft[n] for n in common]
        a2.semilogx(common, ratio, "o-", color="tab:red", label="iteration / FFT pair")
        a2.axhspan(1.2, 1.3, color="tab:green", alpha=0.2, label="target 1.2–1.3")
        a2.axhline(1.0, color="gray", lw=0.8)
        a2.set_ylim(0, max(2.0, max(ratio) * 1.1))
        rows = [["BM_PolonskyKeerIteration", n, fmt(fft[n] * 1e3, 4), "", fmt(it[n] * 1e3, 4), "",
                 fmt(it[n] / fft[n], 3), "", ""] for n in common]
    else:
        a2.text(0.5, 0.5, "needs BM_FFTPair/N and\nBM_PolonskyKeerIteration/N\nat the same N",
                ha="center", va="center", transform=a2.transAxes)
    a2.set_xlabel("grid points per side n")
    a2.set_ylabel("iteration time / FFT-pair time")
    a2.set_title("cost of one iteration in FFT pairs", fontsize=10)
    a2.legend(fontsize=6)
    path = os.path.join(out_dir, "iteration_vs_fft.png")
    savefig(fig, path)
    return path, rows


def _gpu(reference_dir, notes):
    """The CUDA backend's stored runs (reference/challenge/runs.json): cost against the cuFFT pair."""
    recs, lines = gpu_section(reference_dir, "The CUDA backend (one GPU)", notes)
    if not recs:
        return lines
    lines += ["The challenge at 250 kPa with `grid.backend = \"cuda\"` (the Tabor sweep's rows at their own μ_T; "
              "command, device and date of each run in the store). The FFT pair is cuFFT's r2c + c2r of the grid, timed in the same run; the ratios divide the "
              "steps' solve time by it (per iteration, per FFT pair); \"in FFTs\" is the share of the solve time "
              "inside the transforms. The adhesive runs on the H100 ran their outer steps on the host, those on "
              "the H200 on the device (docs/user-guide/gpu.md).", ""]
    rows = []
    for r in recs:
        peak = r.get("gpu_peak_mib")
        rows.append(gpu_row_head(r) + [f"{r['device']}, {r.get('date', '?')}", r["iterations"],
                     fmt(r["fft_pairs"]), fmt(r["solve_s"], 4), fmt(r["fft_pair_s"] * 1e3, 4),
                     fmt(r["time_per_iteration"], 3), fmt(r["time_per_fft_pair"], 3), fmt(r["fft_share"], 2),
                     fmt(peak / 1024 if peak else None, 3), r["status"]])
    lines += [md_table(["case", "grid", "device, date", "iterations", "FFT pairs", "solve (s)", "FFT pair (ms)",
                        "per iteration", "per FFT pair", "in FFTs", "GPU peak (GiB)", "status"], rows), ""]
    return lines


def build(perf_dir: str, bench_path: str, out_dir: str, notes: list[str], reference_dir: str = "reference") -> str:
    os.makedirs(out_dir, exist_ok=True)
    lines = ["# Performance report", ""]
    recs = _records(perf_dir, notes) if os.path.isdir(perf_dir) else []
    lines += ["## Speed vs accuracy", ""]
    if not recs:
        lines += [f"No records in `{perf_dir}/*.json` yet: run the benchmark script that writes "
                  "records {case, grid, tolerance, wall_s, iterations, fft_pairs, fft_pair_s, error: {quantity: "
                  "value}} there (contract in reports/README.md), then `scripts/report.sh`.", ""]
    else:
        figs = _speed_vs_error(recs, out_dir)
        rows = []
        def grid_key(g):
            m = re.match(r"^\s*(\d+)", str(g))
            return (int(m.group(1)) if m else 0, str(g))

        for r in sorted(recs, key=lambda r: (str(r.get("case")), grid_key(r.get("grid")), r.get("wall_s", 0))):
            errs = ", ".join(f"{q} {fmt(v, 3)}" for q, v in sorted((r.get("error") or {}).items()))
            fp = r.get("fft_pairs")
            fps = r.get("fft_pair_s")
            it_per_fft = (r["wall_s"] / (fp * fps)) if finite(fp) and finite(fps) and fp > 0 and fps > 0 else None
            rows.append([r.get("case", "?"), r.get("grid", "?"), fmt(r.get("tolerance"), 3), fmt(r["wall_s"], 4),
                         fmt(r.get("iterations")), fmt(fp), fmt(fps, 3), fmt(it_per_fft, 3), errs])
        lines += [md_table(["case", "grid", "tolerance", "wall (s)", "iterations", "FFT pairs", "s / FFT pair",
                            "wall / (pairs × s/pair)", "errors"], rows), ""]
        if figs:
            for q, p in figs:
                lines += [f"![speed vs error: {q}]({os.path.basename(p)})", ""]
        else:
            lines += ["(no positive error values to plot)", ""]
    lines += ["## Iteration time vs FFT-pair time", ""]
    fam, raw, same = (None, None, {})
    if os.path.isfile(bench_path):
        fam, raw, same = _bench(bench_path, notes)
    if not fam:
        lines += [f"No Google Benchmark results in `{bench_path}`"
                  + (" (no BM_*/N entries)" if os.path.isfile(bench_path) else "")
                  + ": run `build/cmc_bench --benchmark_format=json --benchmark_out=build/bench.json "
                    "--benchmark_out_format=json` (or `build/cmc_bench --benchmark_format=json > build/bench.json`),"
                    " then `scripts/report.sh`.", ""]
    else:
        path, rows = _bench_plot(fam, same, out_dir)
        ctx = raw.get("context", {}) if isinstance(raw, dict) else {}
        lines += [f"From `{bench_path}` ({ctx.get('date', '')}, {ctx.get('num_cpus', '?')} CPUs, "
                  f"{ctx.get('host_name', '')}). The target (docs/performance.md) is an iteration "
                  "costing at most 1.2–1.3 FFT pairs. \"Per iteration\" is an iteration's time over the FFT-pair "
                  "time measured in the same benchmark's run (FFTW's 2-D pair; else over `BM_FFTPair`'s); \"per FFT "
                  "pair\" divides that by the iteration's FFT pairs; \"floor\" is the faster of FFTW's pair and cmc's "
                  "row-column pair, timed in the same run, and the last column divides by it. An "
                  "iteration benchmark's iteration is the loop's (the difference of two solves of different lengths, "
                  "setup excluded: its `setup_ms` counter); `BM_QuasiStaticSolve` stays a whole solve over its "
                  "iterations.", ""]
        if rows:
            lines += [md_table(["benchmark", "n", "FFT pair (ms)", "floor pair (ms)", "iteration (ms)",
                                "FFT pairs / iteration", "per iteration", "per FFT pair", "per FFT pair (floor)"],
                               rows), ""]
        lines += [f"![iteration vs FFT]({os.path.basename(path)})", ""]
    lines += _gpu(reference_dir, notes)
    return "\n".join(lines) + "\n"
