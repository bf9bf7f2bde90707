"""The challenge report's speed and stability: speed against error at the reference load (every
run the store holds and the user's own, python/cmc/analysis/speed.py computes the numbers) and
the hard-case suite's results (cases/hard/, `ctest -L hard`, build/hard/<case>/summary.json).
cmc.report.challenge calls section(); this module only draws and tabulates."""
from __future__ import annotations
from typing import Any, Iterable, Sequence
import os

import numpy as np

from .common import fmt, load_json, md_table, plt, rel, savefig

from cmc.analysis import speed  # noqa: E402
from cmc.analysis.runs import REPO, load_store, record  # noqa: E402
from cmc import run_folder
from cmc._types import Json

PROBLEMS = (("hardwall", "hard wall"), ("adhesive", "with adhesion (μ_T = 3)"))


def user_points(summaries: Iterable[tuple[Json, str]], best: Json | None) -> list[speed.SpeedPoint]:
    """SpeedPoints of the user's runs at the reference load ([(summary, folder)])."""
    recs = []
    for s, folder in summaries:
        r = record(s, tag=os.path.basename(folder), command=f"cmc run ... --out {folder}", device="this machine",
                   date=None)
        r["field_bytes_peak"] = (s.get("model") or {}).get("field_bytes_peak")
        recs.append(r)
    return speed.speed_points(recs, best, "user")


def _marker(p):
    """The point's marker: a star for the user's runs, a cross for a run stopped before its
    tolerance, else a square on the GPU and a circle on the CPU."""
    if p.source == "user":
        return "*"
    if p.status != "converged":
        return "x"
    return "s" if p.backend == "cuda" else "o"


# What the markers mean, for the legend.
MARKERS = (("o", "CPU", "grey"), ("s", "GPU", "grey"), ("*", "yours", "grey"), ("x", "stopped before its tolerance", "grey"),
           ("s", "the best estimate's run, at its error bar", "none"))


def _draw(points, path):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4))
    methods = sorted({p.method for p in points})
    colours = {m: plt.cm.tab10(k % 10) for k, m in enumerate(methods)}
    for ax, (problem, words) in zip(axes, PROBLEMS):
        pts = [p for p in points if p.problem == problem and p.wall_s and p.error_a_r]
        for p in pts:
            ax.loglog(p.wall_s, p.error_a_r, _marker(p), ms=11 if p.source == "user" else 7, color=colours[p.method],
                      mfc="none" if p.is_best else colours[p.method])
            ax.annotate(f"{p.n}", (p.wall_s, p.error_a_r), fontsize=6, textcoords="offset points", xytext=(4, 3))
        front = speed.pareto_front(pts)
        if front:
            ax.step([p.wall_s for p in front], [p.error_a_r for p in front], "k--", where="post", lw=0.8,
                    label="Pareto front")
        for m in methods:
            if any(p.method == m for p in pts):
                ax.plot([], [], "-", lw=4, color=colours[m], label=m)
        for marker, words_, face in MARKERS:
            ax.plot([], [], marker, color="grey", mfc=face, ls="none", label=words_)
        ax.set_title(f"250 kPa, {words}", fontsize=10)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("relative error of a_r from the best estimate")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    savefig(fig, path)


def _row(p, front):
    where = "GPU" if p.backend == "cuda" else "CPU"
    err = lambda e: ("≤ " if p.is_best else "") + fmt(e, 2)  # noqa: E731 - the best run: its error bar
    return [p.problem.replace("hardwall", "hard wall"), p.method, f"{where}: {p.device}", f"{p.n}²",
            fmt(p.wall_s, 3), fmt(p.fft_pairs, 4), fmt(p.peak_mib, 4) + (f" ({p.peak_what})" if p.peak_what else ""),
            err(p.error_a_r), err(p.error_mean_gap), p.status, "yes" if p in front else "",
            "yours" if p.source == "user" else f"store: {p.tag}"]


def speed_lines(user_summaries: list[tuple[Json, str]], reference_dir: str, out_dir: str) -> list[str]:
    """The section's figure and table: the store's runs and the user's, at 250 kPa."""
    best = load_json(os.path.join(reference_dir, "challenge", "best_estimates.json")) or {}
    store = load_store(os.path.join(reference_dir, "challenge", "runs.json"))
    points = speed.speed_points(store, best) + user_points(user_summaries, best)
    lines = ["## Speed against error", ""]
    if not points:
        return lines + ["No runs at 250 kPa in the run store or in results/ yet (`scripts/main.sh --quick`).", ""]
    path = os.path.join(out_dir, "speed_vs_error.png")
    _draw(points, path)
    front = {p for problem, _ in PROBLEMS for p in speed.pareto_front([q for q in points if q.problem == problem])}
    lines += ["Every run at the reference load that the run store (`reference/challenge/runs.json`) holds, CPU and "
              "GPU, and yours (stars in the figure, \"yours\" in the table), as wall time against the relative error "
              "of a_r and of the mean gap from the best estimate of its problem "
              "(`reference/challenge/best_estimates.json`). The run whose values are the best estimate is drawn open "
              "at its own error bar (≤ in the table). Peak memory: the GPU's measured peak, or the bytes of the "
              "fields your run allocated (`summary.json` model.field_bytes_peak); the store has none for its CPU "
              "runs. Grid sizes label the points; the Pareto front joins the runs no other beats in both time and "
              "error. Speed here is wall time on the machine named; the benchmarks give it as ratios to the FFT pair "
              "(docs/performance.md).", "", f"![speed against error]({rel(path, out_dir)})", "",
              md_table(["problem", "method", "ran on", "grid", "wall (s)", "FFT pairs", "peak memory (MiB)",
                        "a_r error", "mean gap error", "status", "Pareto", "run"], [_row(p, front) for p in points]),
              ""]
    missing = speed.missing_methods(points, speed.EXPECTED_METHODS)
    if missing:
        lines += ["Not in the store at 250 kPa: " + "; ".join(f"{m} ({p.replace('hardwall', 'hard wall')})"
                                                             for p, m in missing)
                  + " (a run with `--set solver.precondition=false` or `--set solver.kind=\"adhesive_cg\"`, stored "
                  "with `scripts/store_runs.py`, adds its row).", ""]
    return lines


# ---------------------------------------------------------------- the hard cases

def hard_summaries(dirs: Iterable[str]) -> list[tuple[str, Json]]:
    """(case name, summary) of every hard case's latest result under the folders (build/hard/<case>/)."""
    found: dict[str, tuple[float, Json]] = {}
    for d in dirs:
        for summary in run_folder.read_summaries(run_folder.find(d, recursive=False)):
            s, f = summary.data, summary.path
            if isinstance(s.get("validation"), list):
                name = ((s.get("case") or {}).get("case") or {}).get("name", os.path.basename(os.path.dirname(f)))
                if name not in found or os.path.getmtime(f) > found[name][0]:
                    found[name] = (os.path.getmtime(f), s)
    return [(n, s) for n, (_, s) in sorted(found.items())]


def verdict(checks: list[Json]) -> str:
    """The case's verdict from its checks' verdicts: pass, expected failure, or FAIL (naming them)."""
    bad = [c["quantity"] for c in checks if c.get("verdict", "pass" if c.get("pass") else "FAIL") in ("FAIL", "XPASS")]
    xfail = [c["quantity"] for c in checks if c.get("verdict") == "xfail"]
    if bad:
        return "FAIL: " + ", ".join(bad)
    return "pass" + (f" (expected failure: {', '.join(xfail)})" if xfail else "")


def history_curve(h: Any) -> tuple[np.ndarray, np.ndarray]:
    """(x, residual) of a summary's residual_history for drawing: x the iteration counted over
    the solves one after the other, NaN between solves (each its own line) and where the residual
    is not a positive number (0, "inf", "nan")."""
    xs, ys, offset, last_solve, last_it = [], [], 0, None, 0
    for solve, it, r in zip(h.get("solve", []), h.get("iteration", []), h.get("residual", [])):
        if last_solve is not None and solve != last_solve:
            offset += last_it + 1
            xs.append(np.nan), ys.append(np.nan)
        last_solve, last_it = solve, it
        xs.append(offset + it)
        ys.append(r if isinstance(r, (int, float)) and r > 0 else np.nan)
    return np.array(xs, dtype=float), np.array(ys, dtype=float)


def _history_figure(cases, path):
    cols = 4
    rows = max(1, (len(cases) + cols - 1) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(10, 1.9 * rows), squeeze=False)
    for ax in axes.flat:
        ax.set_visible(False)
    for ax, (name, s) in zip(axes.flat, cases):
        x, y = history_curve(s.get("residual_history") or {})
        if not np.isfinite(y).any():
            continue
        ax.set_visible(True)
        ax.semilogy(x, y, lw=0.7)
        ax.set_title(name.replace("hard-", ""), fontsize=7)
        ax.tick_params(labelsize=5)
    savefig(fig, path)


def hard_lines(dirs: Sequence[str], out_dir: str) -> list[str]:
    """The hard-case table (iterations, time, verdict) and the residual histories' figure."""
    cases = hard_summaries(dirs)
    lines = ["## Hard cases", ""]
    if not cases:
        return lines + ["No hard-case results yet (`ctest --test-dir build -L hard -j2` writes build/hard/; "
                        "docs/validation.md, \"Hard cases\").", ""]
    path = os.path.join(out_dir, "hard_residuals.png")
    _history_figure(cases, path)
    rows = []
    for name, s in cases:
        t, case = s.get("timing") or {}, s.get("case") or {}
        rows.append([name, (case.get("case") or {}).get("description", ""), (case.get("solver") or {}).get("kind", "?"),
                     f"{(s.get('grid') or {}).get('nx')}×{(s.get('grid') or {}).get('ny')}", s.get("status", "?"),
                     fmt(t.get("iterations")), fmt(t.get("wall_s"), 3), len(s["validation"]), verdict(s["validation"])])
    lines += ["The suite of cases that make contact solvers fail (`cases/hard/`: each case's header says why), with "
              "its stability checks (`docs/validation.md`, \"Hard cases\"). Iterations and time: the case's own solve "
              "(the checks' reruns not counted). Residual histories below, one panel per case: the residual the "
              "solver reports against the iterations of its solves, one after the other (the quasi-static solver: "
              "each outer step's tension change; a residual of 0 is not drawn; cases without a positive one have "
              "no panel).", "",
              md_table(["case", "why hard", "solver", "grid", "status", "iterations", "time (s)", "checks", "verdict"],
                       rows), "", f"![residual histories of the hard cases]({rel(path, out_dir)})", ""]
    return lines


def section(user_summaries: list[tuple[Json, str]], reference_dir: str, out_dir: str,
            hard_dirs: Sequence[str] | None = None) -> list[str]:
    """Both parts, for the challenge report."""
    hard_dirs = hard_dirs or [os.path.join(REPO, "build", "hard"), os.path.join(REPO, "results", "hard")]
    return speed_lines(user_summaries, reference_dir, out_dir) + hard_lines(hard_dirs, out_dir)
