"""The local extremum of a sampled curve y(mu) on a logarithmic abscissa, with its error: where
the challenge's mean gap, as a function of the Tabor parameter, turns back toward the
hard-wall value.

The curve is sampled at points x = log10(mu). The extremum is bracketed by the sample that is
lower (higher, for a maximum) than both its neighbours; a parabola through that sample and its
neighbours locates it between them. A second parabola, least squares through the five samples
around it, is an independent estimate; their distance is the error of locating it on these
samples.
"""
from __future__ import annotations
from typing import Sequence
import math

import numpy as np
from .._types import Json
from numpy.typing import ArrayLike

# The widest step (in decades of mu) between a bracketing sample and its neighbours: wider, and
# the samples do not locate the extremum (the sweep's points are a quarter decade apart).
MAX_STEP_DECADES = 0.5


def _vertex(x, y):
    """The vertex (x*, y*, curvature) of the least-squares parabola through the points, or None
    where the points are too few or the parabola is flat."""
    if len(x) < 3:
        return None
    c2, c1, c0 = np.polyfit(x, y, 2)
    if c2 == 0:
        return None
    xv = -c1 / (2 * c2)
    return float(xv), float(c0 - c1 * c1 / (4 * c2)), float(c2)


def bracket(mu: Sequence[float] | np.ndarray, y: Sequence[float] | np.ndarray, kind: str = "min") -> int | None:
    """The index of the interior sample that is below (kind "min") or above ("max") both neighbours,
    the most extreme if there are several, or None where the extremum is not bracketed (it lies at
    an end of the samples or beyond)."""
    s = 1.0 if kind == "min" else -1.0
    inner = [i for i in range(1, len(y) - 1) if s * y[i] < s * y[i - 1] and s * y[i] < s * y[i + 1]]
    return min(inner, key=lambda i: s * y[i]) if inner else None


def locate(mu: ArrayLike, y: ArrayLike, kind: str = "min") -> Json | None:
    """The extremum of y(mu) on log10(mu) (mu ascending): {"mu", "y", "log10_mu_error", "y_error",
    "bracket": [mu_left, mu_right], "estimates": {...}} or None where it is not bracketed (or its
    neighbours lie more than MAX_STEP_DECADES away). The
    errors are those of locating it on these samples (the two parabolas' distance, at least a
    tenth of the bracket's half-width on the abscissa); the samples' own errors come on top
    (y_sample_error)."""
    mu_a, y_a = np.asarray(mu, float), np.asarray(y, float)
    order = np.argsort(mu_a)
    mu, y = mu_a[order], y_a[order]
    i = bracket(mu, y, kind)
    if i is None:
        return None
    x = np.log10(mu)
    if x[i + 1] - x[i] > MAX_STEP_DECADES or x[i] - x[i - 1] > MAX_STEP_DECADES:
        return None
    three = _vertex(x[i - 1:i + 2], y[i - 1:i + 2])
    lo, hi = max(0, i - 2), min(len(x), i + 3)
    five = _vertex(x[lo:hi], y[lo:hi]) if hi - lo >= 4 else None
    xv, yv, _ = three
    dx = abs(five[0] - xv) if five else abs(x[i + 1] - x[i - 1]) / 2
    dy = abs(five[1] - yv) if five else abs(y[i] - yv)
    dx = max(dx, 0.1 * (x[i + 1] - x[i - 1]) / 2)
    return {"mu": 10 ** xv, "y": yv, "log10_mu_error": dx, "y_error": dy,
            "bracket": [float(mu[i - 1]), float(mu[i + 1])], "sample": float(mu[i]),
            "estimates": {"three_point": {"mu": 10 ** xv, "y": yv},
                          "five_point": None if five is None else {"mu": 10 ** five[0], "y": five[1]}}}


def log_slope(mu: ArrayLike, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The slope dy/dlog10(mu) between successive samples, at the midpoints (geometric means):
    (mu_mid, slope) arrays, mu ascending."""
    mu, y = np.asarray(mu, float), np.asarray(y, float)
    order = np.argsort(mu)
    mu, y = mu[order], y[order]
    x = np.log10(mu)
    return 10 ** (0.5 * (x[1:] + x[:-1])), np.diff(y) / np.diff(x)


def combine(on_best: Json, on_grids: list[tuple[int, Json | None]]) -> Json:
    """The extremum located on the best-estimate curve (locate's result) with its grid error: the
    change of mu* and y* between the two finest grids that bracket it (on_grids: [(n, locate
    result)] coarsest first). Adds "log10_mu_grid_error", "y_grid_error" and the totals
    "log10_mu_total_error", "mu_range" and "y_total_error" (sample errors excluded)."""
    out = dict(on_best)
    found = [(n, g) for n, g in on_grids if g is not None]
    if len(found) >= 2:
        (_, a), (_, b) = found[-2], found[-1]
        out["log10_mu_grid_error"] = abs(math.log10(b["mu"]) - math.log10(a["mu"]))
        out["y_grid_error"] = abs(b["y"] - a["y"])
        out["grids"] = [n for n, _ in found[-2:]]
    else:
        out["log10_mu_grid_error"] = None
        out["y_grid_error"] = None
        out["grids"] = [n for n, _ in found]
    e = out["log10_mu_error"] + (out["log10_mu_grid_error"] or 0.0)
    out["log10_mu_total_error"] = e
    out["mu_range"] = [out["mu"] * 10 ** -e, out["mu"] * 10 ** e]
    out["y_total_error"] = out["y_error"] + (out["y_grid_error"] or 0.0)
    return out
