"""The second route to the challenge (s = 1): the scaled family's converged values extrapolated in
s, and how far that extrapolation can be used.

Per quantity (a_r, a_rep, mean_gap) the ratio R(s) = adhesive reference / adhesionless value of
each member with both is extrapolated to s = 1 and multiplied by the challenge's own adhesionless
value (its hard wall converges on grids a machine holds). Why the ratio: along the family
w/(E* lambda_s), rho/lambda_s, mu_T, the rms slope and p/(E* rms slope) stay fixed and only the
bandwidth lambda_r/lambda_s = 200/s changes, which moves the adhesionless values themselves a lot
(the mean gap follows the rms height, 3.06 um at s = 32 against 1.01 um at s = 1); the ratio
carries what adhesion adds.

Two models of the curve, each a straight line through the two members nearest s = 1: one in
log s (the bandwidth's octaves), one in s. Two points cannot tell them apart; a third member can
test them. The held-out check predicts the nearest member's R from the next two, with both lines:
where the two predictions bracket the measured R (within its error) for a quantity, the lines are
taken to bracket the curve at s = 1 too (an assumption one octave of evidence supports, not a
bound), and the value is their midpoint with half their distance as the model error. Without a
third member, or where the check does not bracket, the value is the midpoint and the model error
the whole distance between the lines (either could be wrong by that much). Error = model error +
the members' refinement errors carried through the lines' weights (the larger of the two lines')
+ the adhesionless value's refinement error.
"""
from __future__ import annotations
from typing import Any
import math

from . import family
from .._types import Json

# The route is not informative for a quantity whose error is more than this fraction of its value.
INFORMATIVE = 0.5


def line_at(pa: tuple[float, tuple[float, float]], pb: tuple[float, tuple[float, float]], x1: float,
            log: bool) -> tuple[float, float]:
    """A line through (s_a, R_a), (s_b, R_b) (each (s, (R, error))) at s = x1, in log s or in s:
    its value and the members' errors carried through its weights."""
    (xa, (Ra, ea)), (xb, (Rb, eb)) = pa, pb

    def f(x: float) -> float:
        return math.log(x) if log else float(x)

    t = (f(x1) - f(xa)) / (f(xb) - f(xa))
    return Ra + t * (Rb - Ra), abs(1 - t) * ea + abs(t) * eb


def member_ratio(member: Json, short: str) -> tuple[float, float]:
    """(R, error) of one member for `short`: its reference over its adhesionless value, the two
    values' relative refinement errors added."""
    ref, hw = member["reference"][short], member["adhesionless"][short]
    R = ref["value"] / hw["value"]
    return R, R * (ref["refinement_error"] / abs(ref["value"]) + hw["refinement_error"] / abs(hw["value"]))


def held_out(ratios: dict[Any, tuple[float, float]], sa: Any, sb: Any, sc: Any) -> Json:
    """The held-out check: member sa's R predicted from sb and sc on both lines, and whether the two
    predictions bracket the measured R within its error and the larger of their carried errors."""
    pb, pc = (sb, ratios[sb]), (sc, ratios[sc])
    p_log, pe_log = line_at(pb, pc, sa, True)
    p_lin, pe_lin = line_at(pb, pc, sa, False)
    Ra, ea = ratios[sa]
    lo, hi = min(p_log, p_lin), max(p_log, p_lin)
    return {"member": sa, "from": [sb, sc], "measured": Ra, "measured_error": ea,
            "log_s": p_log, "linear_s": p_lin,
            "bracketed": lo - max(pe_log, pe_lin) - ea <= Ra <= hi + max(pe_log, pe_lin) + ea}


def s_extrapolation(members: list[Json] | None = None) -> Json | None:
    """The second route (module docstring) from the family's members (by default its store's).
    Returns {"members": [s, ...], short: {"value", "error", "unit", "ratio_at_1", ...}} or None
    without two members with a reference and an adhesionless value, and the challenge's
    adhesionless value."""
    members = family.family_members() if members is None else members
    by_s = {m["s"]: m for m in members}
    ch = by_s.get(1, {}).get("adhesionless") or {}
    fam = sorted(s for s, m in by_s.items() if s > 1 and m.get("reference", {}).get("a_r") and m.get("adhesionless"))
    if len(fam) < 2 or not ch.get("a_r"):
        return None
    sa, sb = fam[0], fam[1]  # nearest s = 1 first
    sc = fam[2] if len(fam) > 2 else None
    out: Json = {"members": [sa, sb] + ([sc] if sc else [])}
    for _, short, unit in family.FAMILY_QUANTITIES:
        ratios = {s: member_ratio(by_s[s], short) for s in out["members"]}
        pa, pb = (sa, ratios[sa]), (sb, ratios[sb])
        R_log, e_log = line_at(pa, pb, 1, True)
        R_lin, e_lin = line_at(pa, pb, 1, False)
        check = held_out(ratios, sa, sb, sc) if sc else None
        half = bool(check and check["bracketed"])
        R_mid = 0.5 * (R_log + R_lin)
        model = abs(R_log - R_lin) * (0.5 if half else 1.0)
        hw1 = ch[short]
        value = R_mid * hw1["value"]
        err = (model + max(e_log, e_lin)) * abs(hw1["value"]) + abs(R_mid) * hw1["refinement_error"]
        out[short] = {"value": value, "error": err, "unit": unit, "ratio_at_1": R_mid, "ratio_at_1_log_s": R_log,
                      "ratio_at_1_linear_s": R_lin, "ratio_error_propagated": max(e_log, e_lin), "ratio_error_model": model,
                      "held_out": check,
                      "ratios": {str(s): {"value": r, "error": e} for s, (r, e) in ratios.items()},
                      "adhesionless_at_1": hw1}
    return out


def assessment(x: Json) -> Json:
    """How far s_extrapolation's result x can be used: {"checks": [(short, held_out)] for the
    quantities with a held-out check, "bracketed" / "not_bracketed": their names, "miss": the
    least distance of a line's prediction from the measured ratio in units of its error over the
    bracketed ones (None without), "loose": the quantities whose error is more than INFORMATIVE
    of their value}."""
    checks = [(short, x[short]["held_out"]) for _, short, _ in family.FAMILY_QUANTITIES if x[short].get("held_out")]
    inside = [short for short, h in checks if h["bracketed"]]
    misses = [abs(h[m] - h["measured"]) / h["measured_error"] for _, h in checks if h["bracketed"]
              for m in ("log_s", "linear_s") if h["measured_error"] > 0]
    return {"checks": checks, "bracketed": inside, "not_bracketed": [short for short, h in checks if not h["bracketed"]],
            "miss": min(misses) if misses else None,
            "loose": [short for _, short, _ in family.FAMILY_QUANTITIES
                      if x[short]["error"] > INFORMATIVE * abs(x[short]["value"])]}


def route_difference(a: Json, b: Json) -> float | None:
    """|a - b| over the sum of their errors, for two estimates {"value", "error"} of one quantity
    (a difference above 1 is a finding, not noise); None where both errors are 0."""
    both = a["error"] + b["error"]
    return abs(a["value"] - b["value"]) / both if both > 0 else None
