"""Grid refinement: observed order, Richardson extrapolation and the discretisation error of
a value from the sequence of grids that made it.

A sequence is the same case on grids of n, 2n, 4n ... points a side. Every function takes the
values coarsest first and is pure (numbers in, numbers out).

Its C++ twin is `cmc refine` (validation/Refine.cpp): the relative change between successive grids
(bands.relative_change here) and the observed order, fitted by least squares over every change
(validation/Validate.cpp fit_order) where observed_order takes the finest three grids; the two
agree on a power law (tests/analysis/test_refinement_and_family.py feeds observed_order the
numbers of tests/test_validate.cpp, Refinement.ChangesAndOrder). Richardson extrapolation and the
bands built on it live here only.
"""
from __future__ import annotations
from typing import Any, Sequence
import math
from .._types import Json

# A grid resolves the adhesion for a refinement pair when it resolves the cohesive zone as well
# as the scaled family's refinement grids do. The measure is the bistability number
# b = w dx / (E* rho^2) (summary.json surface_facts.bistability_number): the exponential law's
# cohesive zone is about E* rho^2 / w long (Turon et al., Eng. Fract. Mech. 74, 1665 (2007)), so b
# is the spacing in units of that zone. The family's refinement grids at mu_T = 3 have b = 1.66,
# 1.56 and 1.49 (s = 32, 16, 8; reference/challenge-scaled/scaled_family.json): the bound is the
# smallest.
REFINEMENT_BISTABILITY = 1.49

# The least order of convergence the finest three grids must show to be extrapolated: half the
# first order that the counted contact area has in the asymptotic range (a band of pixels along
# the contact lines).
MIN_ORDER = 0.5


def finite(x: Any) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)


def observed_order(v0: float, v1: float, v2: float, ratio: float = 2.0) -> float | None:
    """The order p of v(h) = v_inf + C h^p from three grids h, h/ratio, h/ratio^2 (coarsest first):
    p = log(|v0 - v1| / |v1 - v2|) / log(ratio). None where the two changes differ in sign or one
    of them is zero (no power law through them)."""
    c1, c2 = v0 - v1, v1 - v2
    if c1 == 0 or c2 == 0 or c1 * c2 < 0:
        return None
    return math.log(abs(c1) / abs(c2)) / math.log(ratio)


def richardson(coarse: float, fine: float, order: float, ratio: float = 2.0) -> float:
    """Richardson's extrapolation (Phil. Trans. R. Soc. A 210, 307 (1911)) of two grids h and
    h/ratio to h = 0 for a value that converges with the given order."""
    return fine + (fine - coarse) / (ratio ** order - 1.0)


def sequence_error(values: Sequence[float], ratio: float = 2.0) -> Json | None:
    """The discretisation error of the finest value of a refinement sequence (values coarsest
    first, each grid `ratio` times finer than the one before).

    - Three grids or more whose last two changes have one sign and shrink with an observed order
      p >= MIN_ORDER (the asymptotic range): |v_fine - v_inf| with v_inf Richardson's extrapolation
      of the finest pair with that order ("richardson").
    - Three grids or more that are not in the asymptotic range: the largest of the last two
      changes, no extrapolation ("largest change"): the value may still move by a step like
      the last ones.
    - Two grids: twice the last change ("first-order bound"). The order is not known from two
      grids; twice the change covers every order down to log2(1.5) = 0.58 (the finer value's
      error is change / (2^p - 1)), about MIN_ORDER, below which three grids are not
      extrapolated either. For order 1, the counted contact area's, the finer value lies at
      half the band (the leave-one-out test, tests/analysis/test_leave_one_out.py).

    Returns {"error", "method", "order", "v_inf", "changes"}, or None with fewer than two finite
    values."""
    if len(values) < 2 or not all(finite(v) for v in values):
        return None
    changes = [b - a for a, b in zip(values, values[1:])]
    out = {"changes": changes, "order": None, "v_inf": None}
    if len(values) >= 3:
        p = observed_order(values[-3], values[-2], values[-1], ratio)
        if p is not None and p >= MIN_ORDER:
            v_inf = richardson(values[-2], values[-1], p, ratio)
            return dict(out, error=abs(values[-1] - v_inf), method="richardson", order=p, v_inf=v_inf)
        return dict(out, error=max(abs(changes[-1]), abs(changes[-2])), method="largest change", order=p)
    return dict(out, error=2.0 * abs(changes[-1]), method="first-order bound")


def own_refinement(grids: list[Json]) -> Json | None:
    """The challenge's own refinement of one sweep point (the same case, mu_T and load on grids
    of n, 2n, 4n... points a side): the error of the coarsest grid's value, measured on the
    challenge itself instead of transferred from the scaled family.

    grids: [{"nx", "dx_over_rho", "bistability", "value", "corrected"}] coarsest first (bistability:
    surface_facts.bistability_number; corrected: the perimeter-corrected contact fraction for a_r,
    else None), every grid converged, plain.

    The converged value is estimated by Richardson extrapolation of order 1 (the counted contact
    area errs by a band of pixels along the contact lines, proportional to dx) from each pair of
    successive grids whose coarser grid resolves the adhesion (bistability number <=
    REFINEMENT_BISTABILITY): v_inf = 2 v_fine - v_coarse. Independent estimates of the same value:
    the other pairs' extrapolations, with three grids or more Richardson's with the order observed
    on the finest three, and, for a_r, the finest grid's perimeter-corrected count (Yastrebov et
    al., Tribol. Int. 107, 2017). The band of the coarsest grid's value (relative to it) is
    |v_coarsest - v_inf| (v_inf from the finest pair) plus the largest distance of the other
    estimates from v_inf.

    With three grids or more, where the finest change is not at least MIN_ORDER below the one
    before (|v1 - v2| > 2^-MIN_ORDER |v0 - v1|, either sign) the grids are not in the asymptotic
    range and no band is made (the caller falls back to the family's).

    Returns {"band", "v_inf", "spread", "estimates", "order", "grids"} or None where no pair
    resolves the adhesion, the grids do not double, or they are not in the asymptotic range."""
    if len(grids) < 2 or any(g["nx"] != 2 * f["nx"] for f, g in zip(grids, grids[1:])):
        return None
    pairs = [(a, b) for a, b in zip(grids, grids[1:]) if a["bistability"] <= REFINEMENT_BISTABILITY]
    if not pairs:
        return None
    vals = [g["value"] for g in grids]
    if not all(finite(v) for v in vals) or vals[0] == 0:
        return None
    if len(vals) >= 3 and abs(vals[-2] - vals[-1]) > 2 ** -MIN_ORDER * abs(vals[-3] - vals[-2]):
        return None
    ests = [(f"Richardson {a['nx']}²/{b['nx']}²", richardson(a["value"], b["value"], 1.0)) for a, b in pairs]
    v_inf = ests[-1][1]
    order = None
    if len(vals) >= 3:
        order = observed_order(vals[-3], vals[-2], vals[-1])
        if order is not None and order > 0:  # monotone: Richardson with the observed order is one more estimate
            ests.append((f"Richardson of order {order:.2g}", richardson(vals[-2], vals[-1], order)))
    if finite(grids[-1].get("corrected")):
        ests.append((f"perimeter-corrected {grids[-1]['nx']}²", grids[-1]["corrected"]))
    spread = max(abs(v - v_inf) for _, v in ests)
    return {"band": (abs(vals[0] - v_inf) + spread) / abs(vals[0]), "v_inf": v_inf, "spread": spread, "estimates": ests,
            "order": order, "grids": [g["nx"] for g in grids]}


def own_band(grids: list[Json], index: int) -> Json | None:
    """own_refinement of a sequence (grids as own_refinement takes them) with the band of grid
    `index`'s value instead of the coarsest's: its distance from the estimated converged value
    plus the other estimates' spread, relative to it; "nx" its grid. None where a grid lacks its
    dx/rho or bistability number, own_refinement makes no band, or the value is 0."""
    if not all(finite(g["dx_over_rho"]) and finite(g["bistability"]) for g in grids):
        return None
    got = own_refinement(grids)
    v = grids[index]["value"]
    if got is None or not v:
        return None
    return dict(got, band=(abs(v - got["v_inf"]) + got["spread"]) / abs(v), nx=grids[index]["nx"])


def own_refinement_words(got: Json, name: str, unit: str = "") -> str:
    """One sentence on own_refinement's result for quantity `name` (values in `unit`, e.g. " m")."""
    grids = "², ".join(str(n) for n in got["grids"]) + "²"
    est = "; ".join(f"{w}: {v:.5g}{unit}" for w, v in got["estimates"])
    order = "" if got["order"] is None else f", observed order {got['order']:.2g}"
    return (f"{name} on {grids}{order}; converged value estimated at {got['v_inf']:.5g}{unit} ({est}): "
            f"+-{100 * got['band']:.3g} %")
