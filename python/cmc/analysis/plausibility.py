"""Whether a run may be trusted before it enters the run store, and whether a new best estimate
may replace the previous one without a word.

A stored record (runs.record) is impossible where a number is NaN or infinite, an area fraction
lies outside [0, 1], or the mean gap under a hard wall is negative; it is incomplete where the
grid, the load, a_r or the mean gap is missing. A run's summary.json is out of balance where a
step's force is not its mean pressure times the cell's area, or, under load control, its mean
pressure is not the load it was asked for. A best estimate on a finer grid than the previous
one is an outlier where its value lies outside the previous band by more than OUTLIER_WIDTHS
band widths (the band: the previous estimate's value +- its error).
"""
from __future__ import annotations
from typing import Any, Iterable
import math

from . import best, runs
from .._types import Json

FRACTIONS = ("a_r", "a_r_corrected", "a_rep")
REQUIRED = ("n", "pressure_Pa", "a_r", "mean_gap_m")
# A step's force against its mean pressure times the area: the program computes the one from
# the other (run/Driver.cpp), so they agree to round-off (measured: at most 2.2e-16 relative
# over the challenge's reference-load, load-sweep and Tabor cases, with and without adhesion,
# on 64²).
FORCE_RELATIVE = 1e-9
# A load-controlled step's mean pressure against the load asked for: the hard-wall solver
# scales its pressure to the load; the adhesive solvers meet it to 10 x tolerance x their
# pressure scale, max(w/rho, E* rms slope) (docs/user-guide/case-files.md, [solver] tolerance).
# Allowed: twice that, plus LOAD_RELATIVE of the load (measured over the same runs: at most
# 1.6e-13 of the load).
LOAD_RELATIVE = 1e-3
OUTLIER_WIDTHS = 3.0


def _number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def non_finite(value: Any, where: str = "") -> list[str]:
    """The places (dotted keys) in a parsed JSON value that hold NaN or an infinity."""
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in non_finite(v, f"{where}.{k}" if where else str(k))]
    if isinstance(value, list):
        return [p for i, v in enumerate(value) for p in non_finite(v, f"{where}[{i}]")]
    return [where] if isinstance(value, float) and not math.isfinite(value) else []


def record_problems(r: Json) -> list[str]:
    """Why a store record (runs.record) cannot be a result, as sentences; [] where it can."""
    out = [f"{p} is not finite" for p in non_finite(r)]
    if not isinstance(r.get("n"), int) or isinstance(r.get("n"), bool) or r["n"] < 1:
        out.append(f"n = {r.get('n')!r} is not a grid size")
    for key in REQUIRED[1:]:
        if not _number(r.get(key)):
            out.append(f"{key} is missing")
    rows = [r] + [dict(s, tag=f"step {k}") for k, s in enumerate(r.get("steps") or [])]
    for row in rows:
        at = "" if row is r else f" at {row['tag']}"
        for key in FRACTIONS:
            v: Any = row.get(key)
            if _number(v) and math.isfinite(v) and not 0.0 <= v <= 1.0:
                out.append(f"{key} = {v:g}{at} lies outside [0, 1]")
        gap: Any = row.get("mean_gap_m")
        if r.get("problem") == "hardwall" and _number(gap) and gap < 0.0:
            out.append(f"mean gap {gap:g} m{at} is negative under a hard wall")
    return out


def _get(d, *keys):
    for k in keys:
        if not isinstance(d, dict):
            return None
        d = d.get(k)
    return d


def _pressure_scale(summary):
    """The adhesive solvers' pressure scale, max(w/rho, E* rms slope), in Pa (0 where unknown)."""
    num = lambda x: x if _number(x) and math.isfinite(x) and x > 0 else 0.0  # noqa: E731
    elastic = num(_get(summary, "case", "material", "contact_modulus")) * \
        (num(_get(summary, "case", "surface", "rms_gradient")) or 1.0)
    w, rho = num(_get(summary, "case", "interaction", "work_of_adhesion")), \
        num(_get(summary, "case", "interaction", "range"))
    return max(elastic, w / rho if rho else 0.0)


def balance_problems(summary: Json) -> list[str]:
    """Why a run's steps are out of balance (summary.json, parsed), as sentences; [] where they
    are not or where the summary does not say enough to tell."""
    out = []
    size = [_get(summary, "grid", k) for k in ("size_x", "size_y")]
    area = size[0] * size[1] if all(_number(x) for x in size) else 0.0
    loading = _get(summary, "case", "loading") or {}
    values = loading.get("values") if loading.get("control") == "mean_pressure" else None
    tol = _get(summary, "case", "solver", "tolerance")
    slack = 20.0 * (tol if _number(tol) else 0.0) * _pressure_scale(summary)
    for k, s in enumerate(summary.get("steps") or []):
        p, force = s.get("mean_pressure"), s.get("force")
        if _number(p) and _number(force) and area > 0.0:
            if abs(force - p * area) > FORCE_RELATIVE * max(abs(force), abs(p * area)):
                out.append(f"step {k}: force {force:g} N is not its mean pressure {p:g} Pa times the area")
        index = s.get("index", k)
        if _number(p) and isinstance(values, list) and isinstance(index, int) and 0 <= index < len(values) \
                and _number(values[index]):
            want = values[index]
            if abs(p - want) > LOAD_RELATIVE * abs(want) + slack:
                out.append(f"step {k}: mean pressure {p:g} Pa, but the load asked for {want:g} Pa")
    return out


def _points(best):
    """(name, estimate) of every point of a best_estimates.json (parsed) that has one."""
    rl = best.get("reference_load") or {}
    out = [(f"250 kPa, {p}", rl.get(p)) for p in ("adhesive", "hardwall")]
    out += [(f"mu_T = {e.get('tabor'):g}", e) for e in best.get("tabor") or []]
    for problem, ests in (best.get("load_sweep") or {}).items():
        out += [(f"{problem} at {e.get('pressure_Pa', 0) / 1e3:g} kPa", e) for e in ests or []]
    return [(name, e) for name, e in out if isinstance(e, dict) and e.get("run")]


def outliers(old: Json, new: Json, widths: float = OUTLIER_WIDTHS, records: Iterable[Json] = ()) -> list[tuple[str, str, Json, Json]]:
    """The points whose new best estimate comes from a finer grid than the old one and lies
    outside the old band by more than `widths` band widths, in a_r or the mean gap; and, among
    `records` (the runs an ingest adds), each converged run finer than the old estimate at its
    point that lies that far outside it, whether or not it became the new estimate:
    [(point, quantity, old estimate, new estimate or {"run", "n", "quantities"} of the run)]."""
    before = dict(_points(old))
    out = []
    for name, e in _points(new):
        o = before.get(name)
        if o and e.get("n", 0) > o.get("n", 0):
            out += [(name, short, o, e) for short in _far(o, e, widths)]
    for name, o in before.items():
        for r in _finer_runs(o, records):
            got = {"run": r["tag"], "n": r["n"], "quantities": {"a_r": {"value": r.get("a_r")},
                                                                "mean_gap": {"value": r.get("mean_gap_m")}}}
            out += [(name, short, o, got) for short in _far(o, got, widths)
                    if not any(x[0] == name and x[1] == short and x[3].get("run") == r["tag"] for x in out)]
    return out


def _far(o, e, widths):
    """The quantities of e that lie outside o's band by more than `widths` band widths."""
    far = []
    for short in ("a_r", "mean_gap"):
        qo, qn = (o.get("quantities") or {}).get(short), (e.get("quantities") or {}).get(short)
        if not qo or not qn or not _number(qo.get("error")) or not _number(qn.get("value")):
            continue
        if abs(qn["value"] - qo["value"]) > (1.0 + widths) * qo["error"]:
            far.append(short)
    return far


def _finer_runs(o, records):
    """The converged runs (load sweeps' steps one by one) at estimate o's point on a finer grid."""
    if not records or o.get("problem") not in ("adhesive", "hardwall"):
        return []
    pts = best.at_point(runs.expand_steps(list(records)), o["problem"], o.get("pressure_Pa"), o.get("tabor"))
    return [r for r in pts if r.get("status") == "converged" and (r.get("n") or 0) > (o.get("n") or 0)]
