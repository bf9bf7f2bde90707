"""Speed against error: the runs of the challenge at its reference load (250 kPa), with and
without adhesion, CPU and GPU, every solver and strategy the run store holds, each as its cost
(wall time, FFT pairs, peak memory) against its error from the best estimate of its problem
(reference/challenge/best_estimates.json), and the Pareto front of each problem: the runs that
no other run beats in both time and error. The user's own runs (summary.json) join as records of
the same shape (runs.record). The challenge report draws and tabulates what these return.

The error of a run is |a_r - a_r,best| / a_r,best and the same for the mean gap; the run whose
values are the best estimate has none against itself, and is placed at the best estimate's own
relative error (its error bar) instead, marked as such.
"""
from typing import Any, Callable, Iterable, TypeGuard
from dataclasses import dataclass
import math
import re
from .._types import Json

REFERENCE_PRESSURE_PA = 250e3
CHALLENGE_TABOR = 3.0
# A run is at the reference load when its pressure is within this of 250 kPa (load control
# reaches it to round-off), and at the challenge's mu_T within this of 3 (a case that gives rho
# has 3.002 from its surface's R_c).
PRESSURE_MATCH = 1e-6
TABOR_MATCH = 0.01


@dataclass(frozen=True)
class SpeedPoint:
    """One run at the reference load: what it is, what it cost and how far it is from the best."""
    tag: str
    problem: str  # "hardwall" or "adhesive"
    method: str   # solver and strategy in words, e.g. "quasi-static, shape"
    backend: str  # "cpu" or "cuda"
    device: str
    n: int
    wall_s: float | None
    fft_pairs: float | None
    peak_mib: float | None
    peak_what: str  # how the peak was obtained ("GPU, measured", "fields, measured", "")
    status: str
    error_a_r: float | None
    error_mean_gap: float | None
    is_best: bool   # its values are the best estimate: its errors are the best estimate's error bars
    source: str     # "store" or "user"


def _finite(x: object) -> TypeGuard[float]:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _setting(command, key):
    """The value a command line sets for a case key with --set KEY=VALUE, or None."""
    m = re.search(r"--set\s+" + re.escape(key) + r"=(\S+)", command or "")
    return m.group(1).strip("\"'") if m else None


def method_of(record: Json) -> str:
    """The solver and strategy of a store record, in words: Polonsky-Keer (preconditioned or
    plain) for the hard wall; with adhesion the quasi-static solver (what a loading path runs by
    default) or the adhesive CG, with the record's strategy (plain, range, shape)."""
    command = record.get("command") or ""
    if record.get("problem") == "hardwall":
        plain = (_setting(command, "solver.precondition") or "true") == "false"
        return "Polonsky-Keer, " + ("plain" if plain else "preconditioned")
    solver = _setting(command, "solver.kind") or "quasi_static"
    words = {"quasi_static": "quasi-static", "adhesive_cg": "adhesive CG"}.get(solver, solver)
    return f"{words}, {record.get('strategy') or 'plain'}"


def at_reference_load(record: Json) -> bool:
    """Whether a record is one run of the challenge's problem at 250 kPa (a single step; with
    adhesion at mu_T = 3)."""
    p = record.get("pressure_Pa")
    if record.get("steps") or not _finite(p) or abs(p / REFERENCE_PRESSURE_PA - 1) > PRESSURE_MATCH:
        return False
    if record.get("problem") == "adhesive":
        mu = record.get("tabor")
        return _finite(mu) and abs(mu / CHALLENGE_TABOR - 1) < TABOR_MATCH
    return record.get("problem") == "hardwall"


def best_of(best: Json | None, problem: str | None) -> tuple[str | None, dict[str, tuple[float, float | None]]]:
    """(run tag, {quantity: (value, relative error)}) of a problem's best estimate at the reference
    load, or (None, {}) when the best estimates have none."""
    b = ((best or {}).get("reference_load") or {}).get(problem) or {}
    out = {}
    for q in ("a_r", "mean_gap"):
        v = (b.get("quantities") or {}).get(q) or {}
        if _finite(v.get("value")) and v["value"] != 0:
            out[q] = (v["value"], v.get("relative_error"))
    return b.get("run"), out


def relative_error(value: float | None, reference: tuple[float, float | None] | None) -> float | None:
    """|value - reference| / |reference|, None when either is missing."""
    if not _finite(value) or reference is None or not _finite(reference[0]):
        return None
    return abs(value - reference[0]) / abs(reference[0])


def _peak(record):
    """(peak memory in MiB, how obtained) of a record: the GPU's measured peak, else the fields'
    measured peak of a user's run (summary.json model.field_bytes_peak), else (None, "")."""
    if _finite(record.get("gpu_peak_mib")):
        return float(record["gpu_peak_mib"]), "GPU, measured"
    if _finite(record.get("field_bytes_peak")):
        return record["field_bytes_peak"] / 2**20, "fields, measured"
    return None, ""


def speed_point(record: Json, best: Json | None, source: str = "store") -> SpeedPoint:
    """The SpeedPoint of a record at the reference load."""
    tag_best, ref = best_of(best, record.get("problem"))
    is_best = source == "store" and record.get("tag") == tag_best
    err = {q: (ref[q][1] if is_best else relative_error(record.get(k), ref.get(q)))
           for q, k in (("a_r", "a_r"), ("mean_gap", "mean_gap_m"))}
    peak, how = _peak(record)
    return SpeedPoint(tag=record.get("tag", "?"), problem=record.get("problem", "?"), method=method_of(record),
                      backend=record.get("backend") or "cpu", device=record.get("device") or "",
                      n=int(record.get("n") or 0), wall_s=record.get("run_s") if _finite(record.get("run_s")) else None,
                      fft_pairs=record.get("fft_pairs") if _finite(record.get("fft_pairs")) else None,
                      peak_mib=peak, peak_what=how, status=record.get("status") or "?",
                      error_a_r=err["a_r"], error_mean_gap=err["mean_gap"], is_best=is_best, source=source)


def speed_points(records: Iterable[Json], best: Json | None, source: str = "store") -> list[SpeedPoint]:
    """The SpeedPoints of the records at the reference load, by problem, method, backend and grid."""
    pts = [speed_point(r, best, source) for r in records if at_reference_load(r)]
    return sorted(pts, key=lambda p: (p.problem, p.method, p.backend, p.n, p.tag))


def pareto_front(points: Iterable[SpeedPoint],
                 error: Callable[[SpeedPoint], Any] = lambda p: p.error_a_r) -> list[SpeedPoint]:
    """The points of one problem that no other beats in both wall time and error (lower or equal
    in both, lower in one), fastest first; points without a time or an error, and runs that
    stopped before their tolerance (a last state, not a result), take no part."""
    pts = [(p, p.wall_s, error(p)) for p in points
           if p.wall_s is not None and error(p) is not None and p.status == "converged"]
    front = [(t, e, p) for p, t, e in pts
             if not any(tq <= t and eq <= e and (tq < t or eq < e) for _, tq, eq in pts)]
    return [p for t, e, p in sorted(front, key=lambda x: (x[0], x[1]))]


def missing_methods(points: Iterable[SpeedPoint], expected: Iterable[tuple[str, str]]) -> list[tuple[str, str]]:
    """The methods of `expected` ([(problem, method)]) that no point has."""
    have = {(p.problem, p.method) for p in points}
    return [pm for pm in expected if pm not in have]


# The methods that speed against error compares: every solver and strategy of the project (the
# store may lack some; the report names those).
EXPECTED_METHODS = [("hardwall", "Polonsky-Keer, preconditioned"), ("hardwall", "Polonsky-Keer, plain"),
                    ("adhesive", "quasi-static, plain"), ("adhesive", "quasi-static, range"),
                    ("adhesive", "quasi-static, shape"), ("adhesive", "adhesive CG, plain")]
