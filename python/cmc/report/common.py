"""Shared helpers of the cmc reports (reports/make_reports.py).

Only the Python standard library, numpy, matplotlib and h5py (Debian's python3-*
packages, run with /usr/bin/python3). Every reader returns None (and says why) instead
of raising on a missing or malformed input: a report never crashes on missing data.
"""
from __future__ import annotations
from typing import Any, Callable, Iterable, Sequence
import json
import math
import os

import numpy as np
from cmc._types import Json

try:
    import h5py  # noqa: F401
    HAVE_H5PY = True
except ImportError:  # pragma: no cover - depends on the machine
    HAVE_H5PY = False


from cmc.analysis.conditions import condition_holds, quantity_holds, worst_failure  # noqa: E402
from cmc.analysis.family import STRATEGIES, family_members, seed_members  # noqa: E402
from cmc.analysis.s_route import assessment  # noqa: E402
from cmc.analysis.transfer import realization_deviations, transfer_check, transfer_verdict  # noqa: E402
from cmc.analysis.runs import REPO, get  # noqa: E402,F401

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The challenge's parameters (problem definition, "Summary of default parameters").
CHALLENGE = {
    "Estar": 25e6,          # Pa, E* (rms gradient g = 1, so E* g = 25 MPa)
    "L": 1e-4,              # m, system size
    "lambda_r": 20e-6,      # m, roll-off wavelength
    "lambda_s": 0.1e-6,     # m, short-wavelength cutoff
    "rho": 2.071e-9,        # m, range of the exponential adhesion
    "gamma0": 50e-3,        # J/m^2
    "p0": 250e3,            # Pa, reference pressure
    "tabor": 3.0,
}


def load_json(path: str, notes: list[str] | None = None) -> Any:
    """The parsed JSON file, or None (with a note) when it is missing or malformed."""
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as e:
        if notes is not None:
            notes.append(f"`{path}` could not be read ({e}); skipped")
        return None


def case_name(summary: Json) -> str | None:
    """The run's case name: summary["case"]["case"]["name"] (the resolved case file) or
    summary["case"]["name"]."""
    c = summary.get("case")
    if isinstance(c, dict):
        n = get(c, "case", "name")
        if isinstance(n, str):
            return n
        if isinstance(c.get("name"), str):
            return c["name"]
    if isinstance(c, str):
        return c
    return None


def finite(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def md_table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A Markdown table."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        out.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in r) + " |")
    return "\n".join(out)


def fmt(x: Any, digits: int = 4) -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        if not math.isfinite(x):
            return str(x)
        if x == 0:
            return "0"
        if 1e-3 <= abs(float(x)) < 1e5:
            return f"{x:.{digits}g}"
        return f"{x:.{digits - 1}e}"
    return str(x)


def label_axes(ax: Any, xlabel: str, ylabel: str, title: str) -> None:
    """A report's axes: their labels, the title, a grid on every decade and a small legend."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def savefig(fig: Any, path: str) -> None:
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def read_reference_csv(path: str) -> tuple[dict[str, str], list[str], np.ndarray] | None:
    """A cmc reference CSV (reference/README.md): (metadata dict, column names, 2-D
    array with one column per name), or None if missing/malformed."""
    try:
        meta: dict[str, str] = {}
        names: list[str] | None = None
        rows: list[list[float]] = []
        with open(path) as f:
            for line in f:
                s = line.strip()
                if not s:
                    continue
                if s.startswith("#"):
                    body = s[1:].strip()
                    if names is None and ":" in body:
                        k, v = body.split(":", 1)
                        meta[k.strip()] = v.strip()
                    continue
                if names is None:
                    names = [c.strip() for c in s.split(",")]
                    continue
                rows.append([float(v) for v in s.split(",")])
        if names is None or not rows:
            return None
        return meta, names, np.array(rows)
    except (OSError, ValueError):
        return None


def write_csv(path: str, columns: Sequence[tuple[str, Sequence[float]]], header_comment: str | None = None) -> None:
    """Write columns [(name, values), ...] as CSV in the format `cmc check` reads."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    n = min(len(v) for _, v in columns)
    with open(path, "w") as f:
        if header_comment:
            for line in header_comment.splitlines():
                f.write(f"# {line}\n")
        f.write(",".join(name for name, _ in columns) + "\n")
        for i in range(n):
            f.write(",".join(f"{float(v[i]):.9e}" for _, v in columns) + "\n")


def rel(path: str, start: str) -> str:
    try:
        return os.path.relpath(path, start)
    except ValueError:
        return path


# ---------------------------------------------------------------- round-off spread
# Measured by scripts/roundoff_spread.py from pairs of runs of one case by two builds or at
# two thread counts.
ROUNDOFF_STORE = os.path.join(REPO, "reference", "challenge", "roundoff_spread.json")


def roundoff_note(path: str = ROUNDOFF_STORE, rel: Callable[[str], str] | None = None) -> str:
    """One sentence on round-off for error statements: a rerun of one build at one thread count
    gives the same bits; between builds and thread counts the measured spread (largest relative
    difference per quantity), or that it was not measured."""
    head = ("A rerun of one build at one thread count gives the same bits; another build (each plans its "
            "FFTs at build time) or thread count rounds differently")
    doc = load_json(path)
    big = (doc or {}).get("largest") or {}
    parts = [f"{v['relative']:.2g} in {v.get('label', k)}" for k, v in big.items()
             if isinstance(v, dict) and isinstance(v.get("relative"), (int, float))]
    if not parts:
        return head + ", a spread not measured here."
    where = rel(path) if rel else "reference/challenge/roundoff_spread.json"
    n = len(doc.get("comparisons") or [])
    return (head + f": the spread that causes, measured on {n} pair{'s' if n != 1 else ''} of runs (`{where}`), "
            "is at most " + ", ".join(parts) + " (relative), and is not added to the bands.")


# ---------------------------------------------------------------- the scaled challenge family
# Sentences and tables on the family's analysis (python/cmc/analysis: conditions, transfer,
# s_route), shared by scripts/scaled_family.py, scripts/challenge_reference.py and the challenge
# report. The numbers are the analysis package's; here they are only put into words.


STRATEGY_WORDS = {"plain": "the plain (unmodified) interaction", "range": "the range coarse-graining",
                  "shape": "the shape coarse-graining"}


def s_extrapolation_verdict(x: Json) -> str:
    """Sentences on how far the second route (s_route.s_extrapolation's result x) can be used: the
    held-out check, if there is one, and the quantities whose error is more than half their value
    (s_route.assessment)."""
    sa, sb = x["members"][0], x["members"][1]
    got = assessment(x)
    checks = got["checks"]
    text = ""
    if checks:
        h0 = checks[0][1]
        parts = [f"{short} {h['measured']:.4f} measured, {h['log_s']:.4f} (log s) and {h['linear_s']:.4f} (s) predicted"
                 for short, h in checks]
        text += (f"Held-out check: R at s = {h0['member']} predicted from s = {h0['from'][0]} and {h0['from'][1]}: "
                 + "; ".join(parts) + ". ")
        if got["bracketed"]:
            text += ("The two lines bracket the measured ratio for " + ", ".join(got["bracketed"]) + f", each line off "
                     f"by at least {got['miss']:.3g} times the measured ratio's error one octave out: so at s = 1, "
                     f"{math.log2(sa):.3g} octaves further, the value is their midpoint and half their distance its "
                     "model error (assumed to bracket there too; not a bound). ")
        if got["not_bracketed"]:
            text += ("They do not bracket it for " + ", ".join(got["not_bracketed"]) + ": the whole distance between "
                     "the lines is its model error. ")
    if got["loose"]:
        text += (f"With the members s = {sb} and {sa} this route is not informative for " + ", ".join(got["loose"])
                 + ": the error is more than half the value, mostly the distance between the two lines.")
    elif not checks:
        text += "A third member would test the two lines (the held-out check)."
    return text.strip()


def transfer_caveat(members: list[Json] | None = None, strategy: str = "range", brief: bool = False) -> str:
    """One sentence on the transfer check (transfer.transfer_check, transfer_verdict) for error
    statements, or "" when it cannot be made: per s = 1 grid the ratio there and in each member
    (largest s first), and whether the members approach the challenge's ratio as s falls toward 1.
    brief: the ratios and the verdict only (the report; docs/challenge/report-method.md says what
    the verdict means)."""
    rows = transfer_check(members, strategy)
    if not rows:
        return ""
    verdict = transfer_verdict(rows)
    parts = [f"{n}^2 (dx = {k:.3g} rho): " + ", ".join(f"{b:.3f} at s = {s}" for s, b in fam) + f", {a:.3f} at s = 1"
             for (n, k, a), fam in verdict["grids"]]
    text = f"Transfer check, a_r of the {strategy} run over the plain run at the same dx/rho: {'; '.join(parts)}. "
    if verdict["agree"]:
        return text + "They agree within 5 %, as the transfer assumes."
    if brief:
        return text + ("They do not agree but approach the challenge's as s falls toward 1: the band is indicative, "
                       "probably pessimistic." if verdict["approach"] else
                       "They do not agree: the band is indicative, not a bound.")
    nearest = min(s for _, _, _, s, _ in rows)
    with_ref = {m["s"] for m in (family_members() if members is None else members) if m.get("reference", {}).get("a_r")}
    nearer = ("a member nearer s = 1 (s = 8, resolved on 8192²)" if nearest not in with_ref or nearest > 8 else
              f"a member nearer s = 1 than s = {nearest}")
    if nearest not in with_ref:
        nearer = f"s = {nearest}'s resolved run (its ratio is measured, its errors are not yet)"
    if verdict["approach"]:
        return text + ("They do not agree, but they approach the challenge's as s falls toward 1, so the band (the "
                       "largest error over the members with a reference, hence that of the member farthest from "
                       f"s = 1) is indicative and probably pessimistic, not a bound; {nearer} would test the trend.")
    return text + ("They do not agree, so the family does not reproduce the challenge's coarse-grid behaviour and the "
                   f"band is indicative, not a bound; {nearer} is needed.")


def condition_summary(rows: list[Json], strategies: Sequence[str] = ("plain",)) -> str:
    """One sentence on the condition check (conditions.condition_checks rows) of the given
    strategies' runs, or "" without rows."""
    rows = [r for r in rows if r["strategy"] in strategies and condition_holds(r) is not None]
    if not rows:
        return ""
    bad = [r for r in rows if not condition_holds(r)]
    conds = sorted({(r["tabor"], r["pressure_Pa"]) for r in rows})
    words = ", ".join(f"μ_T = {t:g} at {p / 1e3:g} kPa" for t, p in conds)
    if not bad:
        return (f"At the other conditions measured ({words}) the band measured at μ_T = 3 and 250 kPa held every "
                f"{'/'.join(strategies)} run ({len(rows)}).")
    failure = worst_failure(rows)
    assert failure is not None  # `bad` is not empty
    worst, short = failure
    q = worst[short]
    return (f"At the other conditions measured ({words}) the band measured at μ_T = 3 and 250 kPa failed "
            f"{len(bad)} of {len(rows)} {'/'.join(strategies)} runs; the worst, μ_T = {worst['tabor']:g} at "
            f"{worst['pressure_Pa'] / 1e3:g} kPa on dx = {worst['dx_over_rho']:.2f} ρ: "
            f"{'a_r' if short == 'a_r' else 'mean gap'} {100 * q['deviation']:+.{1 if short == 'a_r' else 2}f} % "
            f"against a band of ±{100 * q['band']:.{1 if short == 'a_r' else 2}f} %.")


def condition_check_lines(rows: list[Json], strategies: Sequence[str] = ("plain",)) -> list[str]:
    """Markdown lines: the condition check's table (conditions.condition_checks rows of the given
    strategies)."""
    rows = [r for r in rows if r["strategy"] in strategies]
    if not rows:
        return []
    L = ["| μ_T | load (kPa) | run | dx/ρ | a_r: measured (ref. error) / band | mean gap: measured / band | band holds |",
         "|---|---|---|---|---|---|---|"]
    for r in rows:
        cells, holds = [], []
        for short in ("a_r", "mean_gap"):
            q = r[short]
            band = q["band"]
            cells.append(f"{100 * q['deviation']:+.1f} % ({100 * q['refinement']:.1f} %) / "
                         + ("—" if band is None else f"±{100 * band:.1f} %") if short == "a_r" else
                         f"{100 * q['deviation']:+.2f} % / " + ("—" if band is None else f"±{100 * band:.2f} %"))
            holds.append(quantity_holds(q))
        verdict = ("no band" if all(h is None for h in holds) else
                   "yes" if all(h in (True, None) for h in holds) else
                   "**no** (" + ", ".join(k for k, h in zip(("a_r", "mean gap"), holds) if h is False) + ")")
        L.append(f"| {r['tabor']:g} | {r['pressure_Pa'] / 1e3:g} | {r['strategy']}, s = {r['s']} on {r['n']}² | "
                 f"{r['dx_over_rho']:.2f} | {cells[0]} | {cells[1]} | {verdict} |")
    return L + [""]


def realization_members(reference_dir: str, case_seed: Any) -> dict[Any, list[tuple[Any, Json]]]:
    """The family's members on every stored realization of the surface: the main store's (the case
    file's seed, `case_seed`) and those of reference/challenge-scaled/seeds/*/ (scripts/scaled_family.py
    --seed N), as {s: [(seed, member), ...]} for the members with a reference, seeds in order."""
    by_s: dict[Any, list[tuple[Any, Json]]] = {}
    for m in family_members(os.path.join(reference_dir, "challenge-scaled", "scaled_family.json")):
        if m.get("reference", {}).get("a_r") and m["s"] > 1:
            by_s.setdefault(m["s"], []).append((m.get("seed", case_seed), m))
    for m in seed_members(os.path.join(reference_dir, "challenge-scaled")):
        by_s.setdefault(m["s"], []).append((m["seed"], m))
    for s in by_s:
        by_s[s].sort(key=lambda x: (x[0] is None, x[0] or 0))
    return by_s


def realization_rows(members: list[tuple[Any, Json]], spacings: Sequence[float] = (2, 4),
                     ) -> tuple[list[str], list[list[str]]]:
    """One row per realization (seed, member): the reference a_r and mean gap (± refinement error) and,
    for each spacing k and each of plain and the strategies, the deviation of that run's a_r and mean
    gap from the member's reference, marked met/not met against the strategies' targets
    (transfer.realization_deviations). Then a summary row: per column the largest |deviation| and,
    for the strategies, how many realizations meet the target. Returns (header, rows)."""
    kinds = ("plain",) + STRATEGIES
    header = ["seed", "ρ (nm)", "reference a_r", "reference mean gap (µm)"] + [
        f"{kind}, {k} ρ" for k in spacings for kind in kinds]
    per, cols = realization_deviations(members, spacings, kinds)
    rows = []
    for (seed, m), dev in zip(members, per):
        ref = m["reference"]
        row = [seed if seed is not None else "?", fmt(m["rho_m"] * 1e9, 4),
               f"{ref['a_r']['value']:.4g} ± {ref['a_r']['refinement_error']:.2g}",
               f"{ref['mean_gap']['value'] * 1e6:.4g} ± {ref['mean_gap']['refinement_error'] * 1e6:.2g}"]
        for k in spacings:
            for kind in kinds:
                d = dev.get((kind, k))
                if not d:
                    row.append("–")
                    continue
                cell = f"{100 * d['a_r']:+.1f} % / {100 * d['mean_gap']:+.2f} %"
                if d["met"] is not None:
                    cell += " (met)" if d["met"] else " (not met)"
                row.append(cell)
        rows.append(row)
    summary = ["largest", "", "", ""]
    for k in spacings:
        for kind in kinds:
            col = cols.get((kind, k))
            if col is None:
                summary.append("–")
                continue
            text = f"{100 * col['largest'][0]:.1f} % / {100 * col['largest'][1]:.2f} %"
            if col["seen"]:
                text += f"; target met on {col['met']} of {col['seen']}"
            summary.append(text)
    rows.append(summary)
    return header, rows


def gpu_runs(reference_dir: str, notes: list[str] | None = None) -> list[Json]:
    """The CUDA backend's runs in the run store (reference/challenge/runs.json, scripts/gpu/store.py),
    sorted by case and grid; [] when the store is missing."""
    d = load_json(os.path.join(reference_dir, "challenge", "runs.json"), notes)
    recs = d.get("records", []) if isinstance(d, dict) else []
    return sorted((r for r in recs if r.get("backend") == "cuda"), key=lambda r: (r["kind"], r["n"]))


def gpu_section(reference_dir: str, title: str, notes: list[str] | None = None) -> tuple[list[Json], list[str]]:
    """A report section on the stored GPU runs: (the records, the section's first lines); the
    lines say what to run where none are stored."""
    recs = gpu_runs(reference_dir, notes)
    lines = [f"## {title}", ""]
    if not recs:
        lines += [f"No GPU runs stored in `{reference_dir}/challenge/runs.json` yet (scripts/gpu/check.sh on a GPU "
                  "machine, then scripts/gpu/store.py; docs/user-guide/gpu.md).", ""]
    return recs, lines


GPU_KIND = {"hardwall": "hard wall", "hardwall_plain": "hard wall, no preconditioner", "adhesive": "adhesion (plain)", "shape": "adhesion, shape (s = 1 case)"}


def gpu_row_head(r: Json) -> list[str]:
    """A stored GPU run's first two cells: the case and the grid."""
    if r["kind"].startswith("tabor_mu"):  # check.sh's tabor:N:MU, one point of the Tabor sweep
        return [f"Tabor sweep, μ_T = {r['kind'][len('tabor_mu'):]}", f"{r['n']}²"]
    return [GPU_KIND.get(r["kind"], r["kind"]), f"{r['n']}²"]
