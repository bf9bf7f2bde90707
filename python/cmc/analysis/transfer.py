"""Whether the scaled family's measured errors carry over to the challenge (s = 1): the transfer
check (a strategy's a_r over the plain run's at one dx/rho, at s = 1 and in each member), and the
strategies' deviations on other realizations of the surface against their targets.

A member and its runs as family.py describes them.
"""
from __future__ import annotations
from typing import Any, Iterable
import math

from . import family
from .._types import Json

# The targets of a resolution strategy at dx = 2 rho and 4 rho: the largest relative error of a_r
# and of the mean gap it may have there.
STRATEGY_TARGETS: dict[float, tuple[float, float]] = {2: (0.03, 0.005), 4: (0.06, 0.01)}
# The transfer holds where the ratios at s = 1 and in the members agree within this factor.
AGREE_FACTOR = 1.05


def transfer_check(members: list[Json] | None = None, strategy: str = "range") -> list[tuple[int, float, float, float, float]]:
    """Whether the family's members behave like the challenge (s = 1) on coarse grids: for each
    s = 1 grid with both a plain run and one of the strategy, the ratio strategy/plain of a_r
    there and in each member s > 1 at the same dx/rho (within family.NEAR_FACTOR). The ratio needs
    no converged answer, so a member whose resolved run is still missing takes part too. Returns
    [(n, dx/rho, ratio at s = 1, s, ratio in the family)]; [] when the store lacks the runs. The
    strategy errors transfer to s = 1 only if the ratios agree."""
    members = family.family_members() if members is None else members
    out = []
    for m1 in members:
        if m1["s"] != 1:
            continue
        runs1 = {r["role"]: r for r in m1["runs"]}
        for role, p1 in runs1.items():
            if not role.startswith("plain_") or strategy + "_" + role[6:] not in runs1:
                continue
            r1 = runs1[strategy + "_" + role[6:]]
            k = p1["dx_over_rho"]
            for m in members:
                if m["s"] == 1:
                    continue
                near = [r for r in m["runs"] if r["role"].endswith("rho") and r["role"].split("_")[0] in ("plain", strategy)
                        and abs(math.log(r["dx_over_rho"] / k)) < math.log(family.NEAR_FACTOR)]
                by = {r["role"].split("_")[0]: r for r in near}
                if "plain" in by and strategy in by:
                    out.append((p1["n"], k, r1["a_r"] / p1["a_r"], m["s"], by[strategy]["a_r"] / by["plain"]["a_r"]))
    return out


def transfer_verdict(rows: list[tuple[int, float, float, float, float]]) -> Json:
    """transfer_check's rows judged: {"grids": [((n, dx/rho, ratio at s = 1), [(s, ratio), ...
    largest s first]), ... finest grid first], "agree": every member's ratio within AGREE_FACTOR of
    the challenge's, "approach": on every grid the members' ratios come closer to the challenge's
    as s falls toward 1 (in log distance; at least two members each)}."""
    by_grid: dict[tuple[Any, Any, Any], list[tuple[Any, Any]]] = {}
    for n, k, a, s, b in rows:
        by_grid.setdefault((n, k, a), []).append((s, b))
    grids, approach = [], True
    for (n, k, a), fam in sorted(by_grid.items(), key=lambda x: -x[0][0]):
        fam.sort(reverse=True)
        grids.append(((n, k, a), fam))
        dist = [abs(math.log(b / a)) for _, b in fam]
        approach = approach and len(dist) > 1 and all(d1 < d0 for d0, d1 in zip(dist, dist[1:]))
    agree = all(abs(math.log(a / b)) < math.log(AGREE_FACTOR) for _, _, a, _, b in rows)
    return {"grids": grids, "agree": agree, "approach": approach}


def meets_target(k: float, da: float, dg: float) -> bool | None:
    """Whether deviations da (a_r) and dg (mean gap) at dx = k rho meet the strategy's targets;
    None where there is no target at that spacing."""
    if k not in STRATEGY_TARGETS:
        return None
    ta, tg = STRATEGY_TARGETS[k]
    return abs(da) <= ta and abs(dg) <= tg


def realization_deviations(members: list[tuple[Any, Json]], spacings: Iterable[float] = (2, 4),
                           kinds: Iterable[str] = ("plain",) + family.STRATEGIES,
                           ) -> tuple[list[dict[tuple[str, float], Json]], dict[tuple[str, float], Json]]:
    """Each realization's runs at dx = k rho against its own reference. members: [(seed, member)].
    Returns (per member {(kind, k): {"a_r", "mean_gap", "met"}} for the runs it has, deviations
    signed and relative, "met" meets_target's for the strategies and None for plain; per column
    (kind, k) {"largest": [largest |deviation| of a_r, of the mean gap], "met", "seen"}: how many
    realizations meet the target of the strategies, of how many)."""
    per: list[dict[tuple[str, float], Json]] = []
    cols: dict[tuple[str, float], Json] = {}
    for _, m in members:
        ref = m["reference"]
        runs = {r["role"]: r for r in m["runs"]}
        got: dict[tuple[str, float], Json] = {}
        for k in spacings:
            for kind in kinds:
                r = runs.get(f"{kind}_{k}rho")
                if not r:
                    continue
                da, dg = family.deviation(r, ref, "a_r"), family.deviation(r, ref, "mean_gap")
                col = cols.setdefault((kind, k), {"largest": [0.0, 0.0], "met": 0, "seen": 0})
                col["largest"] = [max(col["largest"][0], abs(da)), max(col["largest"][1], abs(dg))]
                ok = None if kind == "plain" else meets_target(k, da, dg)
                if ok is not None:
                    col["met"] += int(ok)
                    col["seen"] += 1
                got[kind, k] = {"a_r": da, "mean_gap": dg, "met": ok}
        per.append(got)
    return per, cols
