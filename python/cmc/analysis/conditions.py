"""The error band of an adhesive run from the scaled family, at the run's own conditions: its
strategy's error at its dx/rho measured at mu_T = 3 and 250 kPa, the larger error measured at
its own mu_T or load where the family was run there too, and the check of the band at those
other conditions (the condition stores, reference/challenge-scaled/conditions/).

A run is given by its summary.json (parsed); a member and its runs as family.py describes them.
"""
from __future__ import annotations
from typing import Any
import math

import numpy as np

from . import family
from .runs import get, strategy_of
from .._types import Json

SAME = 0.01  # a mu_T or load within 1 % of another is the same condition


def _same(a, b):
    return (a is None and b is None) or (a is not None and b is not None and abs(a / b - 1) < SAME)


def _positive(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x > 0


def run_strategy_error(summary: Json, short: str, members: list[Json] | None = None,
                       ) -> tuple[float, float | None, list[Any]] | None:
    """For a run with exponential adhesion: its dx over the case's range rho, and the relative error
    for `short` (a_r, a_rep, mean_gap) that its strategy (interaction.coarse_graining "range" or
    "shape", else "plain") has on the family at that dx/rho (family.strategy_errors over `members`,
    by default the measured ones), with what it was measured on; (dx/rho, None, []) where the family
    has no run near; None for other runs."""
    if get(summary, "case", "interaction", "kind") != "exponential":
        return None
    facts: Any = summary.get("surface_facts") or {}
    rho = facts.get("specified_range") or facts.get("interaction_range")
    g = summary.get("grid") or {}
    dx = g.get("dx_m") or g.get("dx")
    if not (_positive(rho) and _positive(dx)):
        return None
    k = dx / rho
    err, used = family.strategy_errors(family.measured_members() if members is None else members,
                                       strategy_of(summary), k)
    return k, (err or {}).get(short), used


def own_tabor(summary: Json) -> float | None:
    """The run's mu_T where it is not the challenge's 3 (within 1 %), else None: the condition whose
    store (condition_error's tabor) measures its band."""
    tabor = get(summary, "case", "interaction", "tabor")
    ok = isinstance(tabor, (int, float)) and not isinstance(tabor, bool) and math.isfinite(tabor)
    return tabor if ok and not _same(tabor, 3.0) else None


def condition_error(strategy: str, dx_over_rho: float, tabor: float | None = None, pressure: float | None = None,
                    members: list[Json] | None = None) -> tuple[Json | None, list[Any]]:
    """The strategy's error (family.strategy_errors) measured on the family at this condition (mu_T
    within 1 %, load within 1 %; None for the challenge's own 3 and 250 kPa), or (None, []) where no
    condition store holds it or no run is near this dx/rho."""
    ms = [m for m in (family.condition_members() if members is None else members)
          if _same(m.get("tabor"), tabor) and _same(m.get("pressure_Pa"), pressure)]
    return family.strategy_errors(ms, strategy, dx_over_rho) if ms else (None, [])


def run_band(summary: Json, short: str, members: list[Json] | None = None, conditions: list[Json] | None = None,
             ) -> tuple[float, float | None, float | None, float | None, list[Any]] | None:
    """The relative error band of an adhesive run for `short`: the larger of its strategy's error
    measured on the family at mu_T = 3 and 250 kPa (run_strategy_error over `members`) and, where
    the family was also run at the run's own mu_T (`conditions`, by default the condition stores),
    the error measured there. Returns (dx/rho, band, error at mu_T = 3, error at the run's mu_T,
    what the first was measured on), or None for runs without exponential adhesion; band None
    where neither is measured."""
    got = run_strategy_error(summary, short, members)
    if got is None:
        return None
    k, rel, used = got
    tabor, at = own_tabor(summary), None
    if tabor is not None:
        err, _ = condition_error(strategy_of(summary), k, tabor=tabor, members=conditions)
        at = None if err is None else err[short]
    both = [x for x in (rel, at) if x is not None]
    return k, (max(both) if both else None), rel, at, used


def load_bands(summary: Json, short: str, pressures: list[float], members: list[Json] | None = None,
               conditions: list[Json] | None = None) -> tuple[list[float] | None, str]:
    """Per load of an adhesive load sweep (pressures in Pa): the relative band for `short`, and a
    sentence on what it rests on. The band measured at mu_T = 3 and 250 kPa (run_band) holds at
    every load unless the family was also run at other loads (condition members with a
    "pressure_Pa"): then, at each load, the larger of it and the errors measured at the loads,
    interpolated linearly in log p between the measured loads (250 kPa's the first band) and held
    beyond them. (None, "") where nothing is measured at this dx/rho."""
    conditions = family.condition_members() if conditions is None else conditions
    got = run_band(summary, short, members, conditions)
    if got is None:
        return None, ""
    k, band, _, _, _ = got
    if band is None:
        return None, ""
    at = [(250e3, band)]
    for p in sorted({m["pressure_Pa"] for m in conditions if "pressure_Pa" in m and not _same(m["pressure_Pa"], 250e3)}):
        err, _ = condition_error(strategy_of(summary), k, tabor=own_tabor(summary), pressure=p, members=conditions)
        if err is not None:
            at.append((p, err[short]))
    at.sort()
    if len(at) == 1:
        return [band] * len(pressures), ""
    lp = np.log([a[0] for a in at])
    rel = np.interp(np.log(np.asarray(pressures, dtype=float)), lp, [a[1] for a in at])
    words = (f"the larger of the band at 250 kPa ({100 * band:.3g} %) and the error measured on the family's s = 32 "
             "member at the sweep's other loads (" + ", ".join(f"{p / 1e3:g} kPa: {100 * e:.3g} %" for p, e in at
                                                               if not _same(p, 250e3))
             + "; reference/challenge-scaled/conditions/p*/), interpolated in log p between the measured loads and "
             "held beyond them")
    return [max(band, float(r)) for r in rel], words


def condition_checks(members: list[Json] | None = None, reference: list[Json] | None = None) -> list[Json]:
    """One row per coarse run of each condition member (plain and strategies): its signed relative
    deviation from that member's reference per quantity, and the band the challenge's references
    take at that dx/rho from the family at mu_T = 3 and 250 kPa (strategy_errors over `reference`,
    by default the measured members): whether the band, assumed at this condition, holds there."""
    rows = []
    base = family.measured_members() if reference is None else reference
    for m in (family.condition_members() if members is None else members):
        ref = m["reference"]
        for r in sorted(m["runs"], key=lambda r: (-r["dx_over_rho"], r["role"])):
            strategy = r["role"].split("_")[0]
            if strategy not in ("plain",) + family.STRATEGIES or not r["role"].endswith("rho"):
                continue
            band, _ = family.strategy_errors(base, strategy, r["dx_over_rho"])
            row = {"tabor": m.get("tabor", 3.0), "pressure_Pa": m.get("pressure_Pa", 250e3), "s": m["s"],
                   "strategy": strategy, "n": r["n"], "dx_over_rho": r["dx_over_rho"]}
            for _, short, _ in family.FAMILY_QUANTITIES:
                q = ref[short]
                row[short] = {"deviation": family.deviation(r, ref, short),
                              "refinement": q["refinement_error"] / abs(q["value"]),
                              "band": None if band is None else band[short]}
            rows.append(row)
    return rows


def quantity_holds(q: Json) -> bool | None:
    """One quantity of a condition_checks row: |deviation| plus the reference's refinement error
    within the band; None without a band."""
    return None if q["band"] is None else abs(q["deviation"]) + q["refinement"] <= q["band"]


def condition_holds(row: Json) -> bool | None:
    """Whether the band at mu_T = 3 and 250 kPa holds a condition_checks row (a_r and the mean gap);
    None without a band."""
    out = [h for h in (quantity_holds(row[short]) for short in ("a_r", "mean_gap")) if h is not None]
    return None if not out else all(out)


def worst_failure(rows: list[Json]) -> tuple[Json, str] | None:
    """Of the condition_checks rows the band does not hold, the (row, quantity) whose |deviation| plus
    refinement error exceeds its band by the largest factor; None where the band holds them all."""
    bad = [r for r in rows if condition_holds(r) is False]
    if not bad:
        return None

    def excess(r, short):  # (|deviation| + refinement error) / band
        q = r[short]
        return -1.0 if not q["band"] else (abs(q["deviation"]) + q["refinement"]) / q["band"]
    return max(((r, k) for r in bad for k in ("a_r", "mean_gap")), key=lambda x: excess(*x))
