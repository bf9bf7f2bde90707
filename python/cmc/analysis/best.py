"""Best estimates: for each point of the challenge (a load and mu_T, with or without adhesion),
the finest trustworthy result among the stored runs, with its error, decided from data.

Candidates. The runs at a point are grouped into refinement sequences (one case and strategy on
grids of n, 2n, 4n ...). Each sequence's candidate is its finest converged run whose coarser
grids (n/2, n/4 ...) are there to make its refinement error (refinement.sequence_error). An adhesive run that does
not resolve rho (dx > rho, or a bistability number above the family's refinement grids') also
carries the error its strategy has at its dx/rho on the scaled family (family.transferred_error;
at another mu_T than 3 the larger of that and the error measured at that mu_T). A candidate
whose strategy error is not measured at its spacing has no error and is not chosen. No error is
smaller than the round-off spread between builds and thread counts (roundoff_spread.json).

Choice. The candidate with the smallest total relative error in a_r (the quantity that
converges slowest) is the point's best estimate; every quantity of the point comes from it.
"""
from __future__ import annotations
from typing import Any, Iterable
import math

from . import family
from .refinement import REFINEMENT_BISTABILITY, sequence_error
from .._types import Json

QUANTITIES = (("a_r", "a_r"), ("a_rep", "a_rep"), ("mean_gap", "mean_gap_m"))  # (family short, record key)
SAME_POINT = 0.01  # two runs are at one point when their load and mu_T agree within 1 %


def _same(a, b, tol=SAME_POINT):
    if a is None or b is None:
        return a is None and b is None
    return abs(a / b - 1) <= tol


def at_point(records: Iterable[Json], problem: str, pressure: float, tabor: float | None = None) -> list[Json]:
    """The records of one problem ("adhesive" or "hardwall") at this load and mu_T."""
    return [r for r in records if r.get("problem") == problem and _same(r.get("pressure_Pa"), pressure)
            and (problem == "hardwall" or _same(r.get("tabor"), tabor))]


def sequences(records: Iterable[Json]) -> dict[tuple[Any, Any, Any], list[Json]]:
    """The records grouped into refinement sequences: one case, strategy and mu_T (exactly), grids
    doubling, one record per grid (the one solved to the tightest tolerance, then the latest).
    Returns {key: [records coarsest first]}."""
    groups: dict[tuple[Any, Any, Any], dict[int, list[Json]]] = {}
    for r in records:
        key = (r.get("case_name"), r.get("strategy"), r.get("tabor"))
        groups.setdefault(key, {}).setdefault(r["n"], []).append(r)
    out: dict[tuple[Any, Any, Any], list[Json]] = {}
    for key, by_n in groups.items():
        out[key] = [sorted(rs, key=lambda r: (r.get("tolerance") or 1.0, _neg_date(r)))[0]
                    for _, rs in sorted(by_n.items())]
    return out


def _neg_date(r):
    d = r.get("date") or ""
    return tuple(-ord(c) for c in d)


def _chain(seq, top):
    """The doubling chain of grids in seq that ends at record `top`, coarsest first."""
    chain = [top]
    by_n = {r["n"]: r for r in seq}
    while chain[0]["n"] % 2 == 0 and chain[0]["n"] // 2 in by_n:
        chain.insert(0, by_n[chain[0]["n"] // 2])
    return chain


def resolved(r: Json) -> bool:
    """Whether an adhesive run resolves rho: dx <= rho and a bistability number no larger than the
    family's refinement grids' (then its refinement sequence measures its whole grid error)."""
    k, b = r.get("dx_over_rho"), r.get("bistability_number")
    return k is not None and b is not None and k <= 1.0 and b <= REFINEMENT_BISTABILITY


def _strategy_error(r, short, members, conditions):
    """The transferred strategy error of an unresolved adhesive run for `short`, or None."""
    got = family.transferred_error(members, r["strategy"], r["dx_over_rho"], short)
    if got is None:
        return None
    err, rule = got["error"], got["rule"]
    if r.get("tabor") is not None and not _same(r["tabor"], 3.0):
        at = [family.member_error_at(m, r["strategy"], r["dx_over_rho"], short)
              for m in conditions if _same(m.get("tabor"), r["tabor"]) and "pressure_Pa" not in m]
        at = [a[0] for a in at if a is not None]
        if at and max(at) > err:
            err, rule = max(at), rule + f"; larger at mu_T = {r['tabor']:g} itself (conditions store), which is taken"
    return {"error": err, "rule": rule}


def candidate(seq: list[Json], top: Json, members: list[Json] | None, conditions: list[Json] | None,
              roundoff: dict[str, float] | None = None) -> Json:
    """The estimate that run `top` gives with the grids of its sequence below it: per quantity the
    value, the refinement error, the strategy error (adhesive runs that do not resolve rho) and
    their sum, absolute and relative. "usable" is False where an error could not be made."""
    chain = _chain(seq, top)
    out = {"run": top["tag"], "n": top["n"], "strategy": top.get("strategy"), "device": top.get("device"),
           "backend": top.get("backend"), "dx_over_rho": top.get("dx_over_rho"),
           "grids": [{"n": r["n"], "tag": r["tag"], "status": r["status"]} for r in chain],
           "quantities": {}, "usable": True}
    for short, key in QUANTITIES:
        v = top.get(key)
        if v is None or not math.isfinite(v):
            continue
        out["quantities"][short] = _quantity(top, chain, short, key, members, conditions, roundoff)
    ar = out["quantities"].get("a_r", {})
    out["usable"] = ar.get("error") is not None
    return out


def _quantity(top, chain, short, key, members, conditions, roundoff):
    """One quantity of a candidate: value, refinement (sequence_error), strategy error, and the
    total error, absolute and relative to the value (the relative one None at a value of 0, e.g.
    the mean gap in full contact)."""
    v = top[key]
    ref = sequence_error([r.get(key) for r in chain])
    q = {"value": v, "refinement": None if ref is None else dict(ref, relative=ref["error"] / abs(v) if v else None)}
    err = None if ref is None else ref["error"]
    if top.get("problem") == "adhesive" and not resolved(top):
        q["strategy_error"] = _strategy_error(top, short, members, conditions)
        err = None if (err is None or q["strategy_error"] is None) else err + q["strategy_error"]["error"] * abs(v)
    floor = (roundoff or {}).get(short)
    if err is not None and floor is not None and err < floor * abs(v):
        err, q["roundoff_floor"] = floor * abs(v), True
    least = resolution(top, short)
    if err is not None and least and err < least:
        err, q["resolution_floor"] = least, True
    q["error"] = err
    q["relative_error"] = None if err is None or not v else err / abs(v)
    return q


def resolution(r: Json, short: str) -> float | None:
    """The least error a run's value can have: one grid point for an area fraction (1/n²), the
    solver's tolerance times the rms height for the mean gap; None where unknown."""
    if short in ("a_r", "a_rep"):
        return 1.0 / r["n"] ** 2 if r.get("n") else None
    tol, h = r.get("tolerance"), r.get("rms_height_m")
    return tol * h if tol and h else None


def _rank(c):
    """A candidate's rank: its relative error in a_r, else (a_r = 0) its absolute error."""
    q = c["quantities"]["a_r"]
    return q["relative_error"] if q["relative_error"] is not None else q["error"]


def sequence_candidate(seq: list[Json], members: list[Json] | None, conditions: list[Json] | None,
                       roundoff: dict[str, float] | None = None) -> Json | None:
    """A sequence's candidate: its finest converged run whose grids below make an error (a finest
    run with no coarser grid to compare with, e.g. 16384² with 8192² missing, gives way to the
    next converged one that has them); the finest converged run, unusable, where none has; None
    where no run converged."""
    done = [r for r in seq if r.get("status") == "converged"]
    cands = [candidate(seq, top, members, conditions, roundoff) for top in reversed(done)]
    return next((c for c in cands if c["usable"]), cands[0] if cands else None)


def best_at(records: Iterable[Json], problem: str, pressure: float, tabor: float | None,
            members: list[Json] | None, conditions: list[Json] | None,
            roundoff: dict[str, float] | None = None) -> Json | None:
    """The best estimate at one point: the usable candidate with the smallest relative error in
    a_r, with every other candidate it was chosen over. None where no run at the point converged."""
    cands = [c for seq in sequences(at_point(records, problem, pressure, tabor)).values()
             for c in [sequence_candidate(seq, members, conditions, roundoff)] if c]
    usable = [c for c in cands if c["usable"]]
    if not usable:
        return None
    best = min(usable, key=_rank)
    others = [_passed_over(c) for c in cands if c is not best]
    return dict(best, problem=problem, pressure_Pa=pressure, tabor=tabor, passed_over=others)


def _passed_over(c):
    """What the choice of a point's best estimate passed over: each other candidate's run, value,
    error and last refinement change of a_r (a check on the chosen one: e.g. plain on the same grid
    as shape, and the direction it is still moving in)."""
    q = c["quantities"].get("a_r", {})
    ref = q.get("refinement") or {}
    last = ref.get("changes", [None])[-1] if ref else None
    return {"run": c["run"], "n": c["n"], "strategy": c["strategy"], "a_r": q.get("value"),
            "a_r_relative_error": q.get("relative_error"),
            "a_r_last_change": None if last is None or not q.get("value") else last / q["value"]}


def ratio(a: Json, b: Json) -> Json | None:
    """a/b of two estimates' quantity entries, relative errors added; None where b's value is 0
    or a relative error is unknown (a value of 0 has none): no ratio to give."""
    if not b["value"] or a.get("relative_error") is None or b.get("relative_error") is None:
        return None
    v = a["value"] / b["value"]
    rel = a["relative_error"] + b["relative_error"]
    return {"value": v, "relative_error": rel, "error": rel * abs(v)}


def leave_one_out(records: Iterable[Json], members: list[Json] | None, conditions: list[Json] | None,
                  roundoff: dict[str, float] | None = None) -> list[Json]:
    """The band rules tested on the stored sequences: at every point, for every sequence whose
    finest converged grid has at least two coarser ones below it, the candidate made without that
    finest grid, and whether the finest grid's value lies inside its band, per quantity. Returns
    [{"problem", "pressure_Pa", "tabor", "sequence", "quantity", "n", "value", "error", "finest_n",
    "finest", "deviation" (|finest - value| / error), "inside"}]."""
    out = []
    for problem, pressure, tabor in _points(records):
        for key, seq in sequences(at_point(records, problem, pressure, tabor)).items():
            done = [r for r in seq if r.get("status") == "converged"]
            if len(done) < 3:
                continue
            top = done[-1]
            cand = sequence_candidate([r for r in seq if r["n"] < top["n"]], members, conditions, roundoff)
            if not cand or not cand["usable"]:
                continue
            for short, key_ in QUANTITIES:
                q = cand["quantities"].get(short)
                if q is None or q["error"] is None or top.get(key_) is None:
                    continue
                dev = abs(top[key_] - q["value"])
                out.append({"problem": problem, "pressure_Pa": pressure, "tabor": tabor, "sequence": list(key),
                            "quantity": short, "n": cand["n"], "value": q["value"], "error": q["error"],
                            "finest_n": top["n"], "finest": top[key_],
                            "deviation": dev / q["error"] if q["error"] else math.inf,
                            "inside": dev <= q["error"]})
    return out


def _points(records):
    """The distinct (problem, load, mu_T) of the records, loads and mu_T within SAME_POINT."""
    pts = []
    for r in records:
        if r.get("pressure_Pa") is None or r.get("problem") not in ("adhesive", "hardwall"):
            continue
        tabor = r.get("tabor") if r["problem"] == "adhesive" else None
        if not any(p[0] == r["problem"] and _same(p[1], r["pressure_Pa"]) and _same(p[2], tabor) for p in pts):
            pts.append((r["problem"], r["pressure_Pa"], tabor))
    return sorted(pts, key=lambda p: (p[0], p[1], p[2] or 0.0))
