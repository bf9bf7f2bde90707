"""The scaled challenge family (reference/challenge-scaled/, scripts/scaled_family.py): its
stored members and the error a resolution strategy has on them at a given grid spacing.

A member is the challenge with lambda_s and w multiplied by s (mu_T = 3 kept), so that a
machine can resolve its range rho; its "reference" is that converged answer, and its runs
on coarse grids (roles plain_Krho, range_Krho, shape_Krho) measure what each strategy errs
by at dx = K rho. s = 1 is the challenge itself, which has no converged reference.
"""
from __future__ import annotations
from typing import Any, Iterable
import glob
import json
import math
import os
from .._types import Json

# The checkout (the build tree links these files: realpath finds the source).
REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", ".."))
FAMILY_STORE = os.path.join(REPO, "reference", "challenge-scaled", "scaled_family.json")

# (summary key, short name, unit) of the quantities the family records.
FAMILY_QUANTITIES = (("contact_fraction", "a_r", "1"), ("repulsive_fraction", "a_rep", "1"),
                     ("mean_gap", "mean_gap", "m"))
STRATEGIES = ("range", "shape")
# A family run stands for a spacing within this factor of it.
NEAR_FACTOR = 1.3


def _load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def family_members(path: str = FAMILY_STORE) -> list[Json]:
    """The members of a family store, or [] when there is none."""
    d = _load(path)
    return d.get("members", []) if isinstance(d, dict) else []


def seed_members(store_dir: str) -> list[Json]:
    """The members with a converged reference of every other realization stored beside a family
    store (STORE/seeds/*/scaled_family.json), each with its "seed"."""
    out = []
    for path in sorted(glob.glob(os.path.join(store_dir, "seeds", "*", "scaled_family.json"))):
        out += [m for m in family_members(path) if m.get("reference", {}).get("a_r")]
    return out


def measured_members(store: str = FAMILY_STORE) -> list[Json]:
    """The members a strategy's error is measured on: the store's and its other realizations'."""
    return family_members(store) + seed_members(os.path.dirname(store))


def condition_members(store_dir: str | None = None) -> list[Json]:
    """The members with a reference run at other conditions than the challenge's (mu_T = 3, 250 kPa;
    STORE/conditions/*/scaled_family.json), each with its "tabor" and/or "pressure_Pa"."""
    store_dir = store_dir or os.path.dirname(FAMILY_STORE)
    out = []
    for path in sorted(glob.glob(os.path.join(store_dir, "conditions", "*", "scaled_family.json"))):
        out += [m for m in family_members(path) if m.get("reference", {}).get("a_r")]
    return sorted(out, key=lambda m: (m.get("tabor", 3.0), m.get("pressure_Pa", 250e3), m["s"]))


def strategy_run_near(r: Json, strategy: str, dx_over_rho: float) -> bool:
    """Whether family run r stands for the strategy within NEAR_FACTOR of dx_over_rho. The
    resolved and refinement runs are plain runs too (about 0.8 and 1.6 rho); a plain run finer
    than the resolved one takes the resolved run's (resolving rho better is not expected to do
    worse)."""
    plain_grid = strategy == "plain" and r["role"] in ("resolved", "refinement")
    if strategy == "plain" and r["role"] == "resolved" and dx_over_rho <= r["dx_over_rho"]:
        return True
    return ((plain_grid or (r["role"].startswith(strategy + "_") and r["role"].endswith("rho")))
            and abs(math.log(r["dx_over_rho"] / dx_over_rho)) < math.log(NEAR_FACTOR))


def run_error(r: Json, ref: Json, short: str) -> float:
    """A family run's relative error for `short`: |run / reference - 1| plus the reference's own
    relative refinement error."""
    q = ref[short]
    return abs(r[short] / q["value"] - 1) + q["refinement_error"] / abs(q["value"])


def strategy_errors(members: list[Json], strategy: str, dx_over_rho: float) -> tuple[Json | None, list[Any]]:
    """The strategy's measured relative error per quantity at this dx/rho: the largest, over the
    members with a converged reference (of every realization given), of run_error for the run
    within NEAR_FACTOR of the spacing. Returns (errors, [what they rest on]) or (None, [])."""
    err: Json = {}
    used: list[Any] = []
    seeds: dict[Any, Any] = {}
    for m in members:
        ref = m.get("reference", {})
        if not ref.get("a_r"):
            continue
        for r in m["runs"]:
            if strategy_run_near(r, strategy, dx_over_rho):
                if "seed" in m:  # another realization: counted per s below
                    seeds.setdefault(m["s"], []).append(m["seed"])
                else:
                    used.append(f"s = {m['s']} at {r['n']}² (dx = {r['dx_over_rho']:.2f} rho)")
                for _, short, _ in FAMILY_QUANTITIES:
                    err[short] = max(err.get(short, 0.0), run_error(r, ref, short))
    for s_, ids in sorted(seeds.items(), reverse=True):
        used.append(f"s = {s_} on {len(ids)} other realization{'s' if len(ids) > 1 else ''} (seed{'s' if len(ids) > 1 else ''} "
                    f"{', '.join(str(i) for i in sorted(ids))})")
    return (err, used) if used else (None, [])


def member_error_at(member: Json, strategy: str, dx_over_rho: float, short: str,
                    ) -> tuple[float, list[float]] | None:
    """One member's relative error for `short` with the strategy at this spacing: that of its run
    within NEAR_FACTOR of it, else interpolated linearly in log(dx/rho) between the runs at the
    nearest measured spacings on either side (the error varies smoothly with the spacing, and
    the family measures it at 2, 4, 6 ... rho). Returns (error, [dx/rho of the runs used]) or None
    where the member has no reference or the spacing is outside its runs' range."""
    ref = member.get("reference", {})
    if not ref.get(short):
        return None
    runs = [r for r in member["runs"] if r["role"].startswith(strategy + "_") and r["role"].endswith("rho")]
    near = [r for r in runs if abs(math.log(r["dx_over_rho"] / dx_over_rho)) < math.log(NEAR_FACTOR)]
    if near:
        r = min(near, key=lambda r: abs(math.log(r["dx_over_rho"] / dx_over_rho)))
        return run_error(r, ref, short), [r["dx_over_rho"]]
    below = [r for r in runs if r["dx_over_rho"] < dx_over_rho]
    above = [r for r in runs if r["dx_over_rho"] > dx_over_rho]
    if not below or not above:
        return None
    a = max(below, key=lambda r: r["dx_over_rho"])
    b = min(above, key=lambda r: r["dx_over_rho"])
    t = math.log(dx_over_rho / a["dx_over_rho"]) / math.log(b["dx_over_rho"] / a["dx_over_rho"])
    return (1 - t) * run_error(a, ref, short) + t * run_error(b, ref, short), [a["dx_over_rho"], b["dx_over_rho"]]


def nearest_members(members: list[Json], count: int = 2) -> list[Json]:
    """The members with a reference whose s is among the `count` smallest above 1, with every
    realization of each: the members whose coarse grids behave most like the challenge's (the
    transfer check: the ratio of a strategy's a_r to plain's at one dx/rho approaches the
    challenge's as s falls toward 1)."""
    with_ref = [m for m in members if m.get("reference", {}).get("a_r") and m["s"] > 1]
    keep = sorted({m["s"] for m in with_ref})[:count]
    return [m for m in with_ref if m["s"] in keep]


def transferred_error(members: list[Json], strategy: str, dx_over_rho: float, short: str) -> Json | None:
    """The error a strategy has at this spacing, transferred from the family to the challenge:
    the largest member_error_at over the realizations of the members nearest s = 1
    (nearest_members). Returns {"error", "members": [(s, seed, error, spacings)], "rule"} or
    None where none of them measured the spacing."""
    rows = []
    for m in nearest_members(members):
        got = member_error_at(m, strategy, dx_over_rho, short)
        if got is not None:
            rows.append((m["s"], m.get("seed"), got[0], got[1]))
    if not rows:
        return None
    s_used = sorted({r[0] for r in rows})
    return {"error": max(r[2] for r in rows), "members": rows,
            "rule": (f"largest over the family's members nearest s = 1 (s = {', '.join(str(s) for s in s_used)}; "
                     f"{len(rows)} realizations) at dx = {dx_over_rho:.3g} rho, interpolated in log(dx/rho) between "
                     "their measured spacings, plus their references' refinement errors")}


def deviation(r: Json, ref: Json, short: str) -> float:
    """A run's signed relative deviation from a member's reference for `short`: r / reference - 1."""
    return r[short] / ref[short]["value"] - 1


def member_reference(resolved: Json, refinement: Json) -> Json:
    """A member's reference from its resolved run and the refinement run (the same case on half the
    points), per quantity: the resolved value, with |resolved - refinement| as its refinement error
    (it bounds the resolved grid's own error if the error falls at least linearly with dx)."""
    return {short: {"value": resolved[short], "unit": unit, "refinement_error": abs(resolved[short] - refinement[short]),
                    "grid": resolved["n"], "coarser_grid": refinement["n"], "status": resolved["status"]}
            for _, short, unit in FAMILY_QUANTITIES}


def adhesionless(runs: list[Json]) -> Json:
    """A member's hard-wall values from its two finest converged hard-wall runs (roles hardwall_*):
    a_r (the perimeter-corrected contact fraction; the repulsive area is the whole contact without
    adhesion) and the mean gap, each with |finest - next| as its refinement error. {} without two
    such runs."""
    hw = sorted((r for r in runs if r["role"].startswith("hardwall") and r["status"] == "converged"),
                key=lambda r: -r["n"])
    if len(hw) < 2 or hw[0]["a_r_corrected"] is None or hw[1]["a_r_corrected"] is None:
        return {}
    out = {}
    for short, key in (("a_r", "a_r_corrected"), ("a_rep", "a_r_corrected"), ("mean_gap", "mean_gap")):
        out[short] = {"value": hw[0][key], "refinement_error": abs(hw[0][key] - hw[1][key]),
                      "grid": hw[0]["n"], "coarser_grid": hw[1]["n"]}
    return out


def challenge_estimates(members: list[Json], realizations: Iterable[Json] = ()) -> None:
    """Sets "estimates" on each member without a reference (the challenge, s = 1): each strategy
    run's value with the strategy's error measured on the family at the same dx/rho (and, as
    rho/lambda_s is the same for every s, the same dx/lambda_s), over the members and the other
    realizations given; removes it from the members with a reference."""
    measured = list(members) + list(realizations)
    for m in members:
        if m.get("reference", {}).get("a_r"):
            m.pop("estimates", None)
            continue
        rows = []
        for r in m["runs"]:
            strategy = r["role"].split("_")[0]
            if strategy not in STRATEGIES:
                continue
            err, used = strategy_errors(measured, strategy, r["dx_over_rho"])
            row = {"role": r["role"], "n": r["n"], "dx_over_rho": r["dx_over_rho"], "measured_on": used}
            for _, short, _ in FAMILY_QUANTITIES:
                row[short] = {"value": r[short], "error": None if err is None else err[short] * abs(r[short])}
            rows.append(row)
        m["estimates"] = rows
