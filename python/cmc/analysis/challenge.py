"""The challenge's best estimates, assembled from the run store and the scaled family: the
reference load with and without adhesion (a_r, repulsive a_r, mean gap, kappa and the ratio
of the two a_r), a_r and the mean gap against mu_T, and where the mean gap has its extremum
in mu_T. The result is what reference/challenge/best_estimates.json holds.
"""
from __future__ import annotations
from typing import Callable, Iterable
import json
import os

from . import best, extremum, family, runs
from .._types import Json

P0 = 250e3        # Pa, the reference load
ESTAR = 25e6      # Pa, E*
RMS_SLOPE = 1.0   # the surface's rms gradient: p~ = p / (E* rms slope)
TABOR_CASE = "challenge-tabor-sweep"
# The challenge's physics (problem definition, "Summary of default parameters"; the surface is the
# case files' realization, seed 28). Runs of other physics are left out of its best estimates.
PHYSICS = {"grid.size": 1e-4, "material.contact_modulus": 25e6, "surface.hurst": 0.8,
           "surface.rolloff_wavelength": 20e-6, "surface.cutoff_wavelength": 0.1e-6, "surface.rms_gradient": 1.0,
           "surface.seed": 28}
ROUNDOFF_STORE = os.path.join(family.REPO, "reference", "challenge", "roundoff_spread.json")
_ROUNDOFF_KEYS = {"contact_fraction": "a_r", "repulsive_fraction": "a_rep", "mean_gap": "mean_gap"}


def roundoff(path: str = ROUNDOFF_STORE) -> dict[str, float]:
    """The largest relative round-off spread per quantity (between builds and thread counts,
    scripts/roundoff_spread.py), {} where it was not measured."""
    try:
        with open(path) as f:
            big = json.load(f).get("largest") or {}
    except (OSError, ValueError):
        return {}
    return {_ROUNDOFF_KEYS[k]: v["relative"] for k, v in big.items() if k in _ROUNDOFF_KEYS and "relative" in v}


def reference_load(records: list[Json], members: list[Json] | None, conditions: list[Json] | None,
                   spread: dict[str, float] | None = None) -> Json:
    """The best estimates at 250 kPa with adhesion (mu_T = 3) and without, kappa = a_r / p~ of
    each, and the ratio of the two a_r."""
    adh = best.best_at(records, "adhesive", P0, 3.0, members, conditions, spread)
    hw = best.best_at(records, "hardwall", P0, None, members, conditions, spread)
    out = {"adhesive": adh, "hardwall": hw, "p_tilde": P0 / (ESTAR * RMS_SLOPE)}
    for name, est in (("adhesive", adh), ("hardwall", hw)):
        if est and "a_r" in est["quantities"]:
            q = est["quantities"]["a_r"]
            out[f"kappa_{name}"] = {"value": q["value"] / out["p_tilde"], "relative_error": q["relative_error"],
                                    "error": q["error"] / out["p_tilde"]}
    if adh and hw:
        out["ratio"] = best.ratio(adh["quantities"]["a_r"], hw["quantities"]["a_r"])
    return out


def tabor_values(records: Iterable[Json]) -> list[float]:
    """The distinct mu_T of the adhesive runs at the reference load (within best.SAME_POINT), ascending."""
    out: list[float] = []
    for mu in sorted(r["tabor"] for r in records if r.get("problem") == "adhesive" and r.get("tabor")
                     and best._same(r.get("pressure_Pa"), P0)):
        if not out or not best._same(mu, out[-1]):
            out.append(mu)
    return out


def tabor_curve(records: list[Json], members: list[Json] | None, conditions: list[Json] | None,
                spread: dict[str, float] | None = None) -> list[Json]:
    """The best estimate at every mu_T the store holds (at the reference load), ascending."""
    pts = [best.best_at(records, "adhesive", P0, mu, members, conditions, spread) for mu in tabor_values(records)]
    return [p for p in pts if p]


def pressures(records: Iterable[Json], problem: str) -> list[float]:
    """The distinct loads of the problem's runs (mu_T = 3 with adhesion), ascending."""
    out: list[float] = []
    for p in sorted(r["pressure_Pa"] for r in records if r.get("problem") == problem and r.get("pressure_Pa")
                    and (problem == "hardwall" or best._same(r.get("tabor"), 3.0))):
        if not out or not best._same(p, out[-1]):
            out.append(p)
    return out


def load_curve(records: list[Json], problem: str, members: list[Json] | None, conditions: list[Json] | None,
               spread: dict[str, float] | None = None) -> list[Json]:
    """The best estimate at every load the store holds for the problem (load sweeps' steps and
    single runs alike), ascending in load."""
    tabor = 3.0 if problem == "adhesive" else None
    pts = [best.best_at(records, problem, p, tabor, members, conditions, spread) for p in pressures(records, problem)]
    return [p for p in pts if p]


def grid_sweeps_of(records: Iterable[Json], key: str, only: Callable[[Json], bool] | None = None,
                   ) -> dict[int, tuple[list[float], list[float]]]:
    """{n: (mu list, values list)} of the Tabor sweep's case run plain and converged on each grid,
    for the record key (e.g. "a_r", "mean_gap_m"), mu ascending; only: a further test of a record."""
    out: dict[int, list[tuple[float, float]]] = {}
    for r in records:
        if r.get("case_name") == TABOR_CASE and r.get("strategy") == "plain" and r.get("status") == "converged" \
                and best._same(r.get("pressure_Pa"), P0) and r.get(key) is not None and (only is None or only(r)):
            out.setdefault(r["n"], []).append((r["tabor"], r[key]))
    return {n: ([m for m, _ in sorted(v)], [x for _, x in sorted(v)]) for n, v in out.items()}


def _rises(values):
    return all(a <= b for a, b in zip(values, values[1:]))


def monotonicity(curve: list[Json], records: list[Json]) -> Json:
    """Whether a_r rises with mu_T on the best-estimate curve, and where it does not: each fall
    between neighbouring points, with the two points' grids and whether the fall lies inside
    their error bars; and, per grid the sweep ran on (three points or more), whether it rises
    over all its points and over those where the grid resolves rho (best.resolved), with the
    largest mu_T it resolves."""
    pts = [(p["tabor"], p["quantities"]["a_r"], p["n"]) for p in curve if "a_r" in p["quantities"]]
    falls = [{"from": a[0], "to": b[0], "grids": [a[2], b[2]], "fall": a[1]["value"] - b[1]["value"],
              "inside_bars": a[1]["value"] - b[1]["value"] <= a[1]["error"] + b[1]["error"]}
             for a, b in zip(pts, pts[1:]) if b[1]["value"] < a[1]["value"]]
    every = grid_sweeps_of(records, "a_r")
    resolved = grid_sweeps_of(records, "a_r", best.resolved)
    grids = {n: {"rises": _rises(v), "rises_where_resolved": _rises(resolved.get(n, ([], []))[1]),
                 "resolved_up_to": max(resolved[n][0]) if resolved.get(n, ([], []))[0] else None}
             for n, (mus, v) in every.items() if len(mus) >= 3}
    return {"monotonic": not falls, "falls": falls, "grids": grids}


def mean_gap_extremum(curve: list[Json], records: list[Json]) -> Json | None:
    """Where the mean gap has its local minimum in mu_T, located on the best-estimate curve, with
    the error of locating it there, the change between the two finest complete grid sweeps, and
    the curve's own band at the samples around it; None where the curve does not bracket it."""
    pts = [(p["tabor"], p["quantities"]["mean_gap"]) for p in curve if "mean_gap" in p["quantities"]]
    got = extremum.locate([m for m, _ in pts], [q["value"] for _, q in pts], "min")
    if got is None:
        return None
    grids = sorted(grid_sweeps_of(records, "mean_gap_m").items())
    on_grids = [(n, extremum.locate(mus, gaps, "min")) for n, (mus, gaps) in grids]
    out = extremum.combine(got, on_grids)
    near = [q["error"] or 0.0 for m, q in pts if out["bracket"][0] <= m <= out["bracket"][1]]
    out["y_sample_error"] = max(near) if near else None
    out["y_total_error"] += out["y_sample_error"] or 0.0
    out.update(a_r_log_slope_around(out["mu"], records))
    return out


def a_r_log_slope_around(mu: float, records: list[Json]) -> Json:
    """a_r's slope against log10 mu_T on one grid: the finest whose sweep, over the mu_T where it
    resolves rho, brackets mu with five points or more (neighbouring best estimates may come from
    different grids, whose step is not a slope; where rho is not resolved the counted area errs by
    a band of pixels along the contact lines). {} where no grid qualifies."""
    sweeps = [(n, v) for n, v in sorted(grid_sweeps_of(records, "a_r", best.resolved).items())
              if v[0] and min(v[0]) < mu < max(v[0]) and len(v[0]) >= 5]
    if not sweeps:
        return {}
    n, (mus, ar) = sweeps[-1]
    mu_s, slope = extremum.log_slope(mus, ar)
    return {"a_r_log_slope_grid": n, "a_r_log_slope_resolved_up_to": float(max(mus)),
            "a_r_log_slope": [{"tabor": float(m), "slope": float(x)} for m, x in zip(mu_s, slope)]}


def of_physics(records: Iterable[Json], physics: Json | None = PHYSICS) -> list[Json]:
    """The records of runs that solve the given physics (all of them where physics is None);
    records without a physics entry are taken to be the challenge's."""
    return [r for r in records if physics is None or runs.same_physics(r.get("physics") or {}, physics)]


def build(records: list[Json], members: list[Json] | None = None, conditions: list[Json] | None = None,
          spread: dict[str, float] | None = None, physics: Json | None = PHYSICS) -> Json:
    """Everything best_estimates.json holds, from the run store's records (those of the given
    physics: the challenge's by default), the family's stores and the round-off spread."""
    records = of_physics(records, physics)
    members = family.measured_members() if members is None else members
    conditions = family.condition_members() if conditions is None else conditions
    spread = roundoff() if spread is None else spread
    records = runs.expand_steps(records)
    curve = tabor_curve(records, members, conditions, spread)
    return {"reference_load": reference_load(records, members, conditions, spread), "roundoff": spread,
            "load_sweep": {pb: load_curve(records, pb, members, conditions, spread) for pb in ("adhesive", "hardwall")},
            "tabor": curve, "a_r_monotonicity": monotonicity(curve, records),
            "mean_gap_extremum": mean_gap_extremum(curve, records)}
