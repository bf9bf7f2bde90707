"""Error bands from the same case on another grid: the change of a value or a curve under one
refinement, the band of a curve or a cross-section profile on the finest grid of a sequence, the
bands of a hard-wall load sweep, and the interpolation in a quantity's representation that
compares curves sampled on different grids.

Every function is pure (numbers and arrays in, numbers and arrays out). A band is a half-width in
the quantity's own unit unless its name says "relative". A load-sweep step is a dict with "p"
(Pa), "ar", "gap" (m), "perimeter" and "converged", as the challenge report reads it.
"""
from __future__ import annotations
from typing import Any, Sequence
import numpy as np
from numpy.typing import ArrayLike

from .refinement import sequence_error


def relative_change(coarse: float | None, fine: float | None) -> float | None:
    """|coarse - fine| / |fine|: the change of a value under one refinement, relative to the finer
    grid's value, as `cmc refine` defines it (validation/Refine.cpp). None where either value is
    missing or the finer one is 0."""
    if coarse is None or not fine:
        return None
    return abs(coarse - fine) / abs(fine)


def absolute_band(relative: Sequence[float], values: Sequence[float], floor: float | None = None) -> list[float]:
    """Per point the half-width relative x |value|, at least `floor` where one is given."""
    if floor is None:
        return [r * abs(v) for r, v in zip(relative, values)]
    return [max(r * abs(v), floor) for r, v in zip(relative, values)]


def interp_curve(x: ArrayLike, xc: ArrayLike, yc: ArrayLike, logx: bool, logy: bool) -> np.ndarray:
    """The curve (xc, yc) at x, interpolated in the representation's axes (log where logx / logy);
    NaN where x lies outside the curve's range, or where a value is not finite or a logged one not
    positive."""
    xa, xca, yca = (np.asarray(a, dtype=float) for a in (x, xc, yc))
    m = np.isfinite(xca) & np.isfinite(yca) & ((xca > 0) if logx else True) & ((yca > 0) if logy else True)
    xca, yca = xca[m], yca[m]
    out = np.full(len(xa), np.nan)
    if len(xca) < 2:
        return out
    o = np.argsort(xca)
    xca, yca = xca[o], yca[o]

    def tx(v: np.ndarray) -> np.ndarray:
        return np.log(v) if logx else v

    ok = np.isfinite(xa) & ((xa > 0) if logx else True) & (xa >= xca[0]) & (xa <= xca[-1])
    yi = np.interp(tx(xa[ok]), tx(xca), np.log(yca) if logy else yca)
    out[ok] = np.exp(yi) if logy else yi
    return out


def refinement_band(x: ArrayLike, y: ArrayLike, xf: ArrayLike, yf: ArrayLike, logx: bool, logy: bool) -> np.ndarray:
    """|y - y_f(x)|: how far a curve moves on the next finer grid (xf, yf), interpolated at x by
    interp_curve. NaN where it has no value there."""
    return np.abs(np.asarray(y, dtype=float) - interp_curve(x, xf, yf, logx, logy))


def _two_grid_bound(coarse, fine):
    """Per point refinement.sequence_error of the two grids' values (coarser first): twice their
    difference, the two-grid first-order bound. NaN where either value is not finite."""
    out = [sequence_error([c, f]) for c, f in zip(coarse, fine)]
    return np.array([np.nan if e is None else e["error"] for e in out])


def finest_grid_band(x: ArrayLike, y: ArrayLike, xc: ArrayLike, yc: ArrayLike, logx: bool, logy: bool) -> np.ndarray:
    """The band of a curve (x, y) on the finest grid of a refinement sequence, from the same case's
    curve (xc, yc) on the next coarser grid: per point twice |y - y_c(x)| (_two_grid_bound), y_c
    interpolated at x by interp_curve. NaN where the coarser curve has no value there."""
    return _two_grid_bound(interp_curve(x, xc, yc, logx, logy), np.asarray(y, dtype=float))


def finest_profile_band(y: ArrayLike, v: ArrayLike, yc: ArrayLike, vc: ArrayLike, floor: float,
                        period: float | None = None) -> np.ndarray | None:
    """The band of a cross-section profile v(y) on the finest grid of a refinement sequence, from
    the same case's profile (yc, vc) on the next coarser grid, read as `cmc check` reads a curve
    (linear between its points; periodic with `period` where given, so that the whole line is
    covered): per point twice |v(y_i) - v_c(y_i)| (_two_grid_bound), at least `floor`
    (profile_floor). None where a value is not finite, the floor is not positive, or without a
    period the coarser profile does not cover the line."""
    y, v, yc, vc = (np.asarray(a, dtype=float) for a in (y, v, yc, vc))
    if len(y) < 2 or len(yc) < 2 or not (np.isfinite(v).all() and np.isfinite(vc).all()) or not floor > 0:
        return None
    if period is None and (y[0] < yc[0] or y[-1] > yc[-1]):
        return None
    return np.maximum(_two_grid_bound(np.interp(y, yc, vc, period=period), v), floor)


def profile_floor(key: str, tolerance: float, rms_height: float, contact_modulus: float,
                  rms_gradient: float) -> float:
    """The least band of a cross-section profile: the solver's tolerance in the problem's scale,
    times the rms height for the gap (key ending in "gap"), times E* times the rms slope for the
    stress (the challenge's unit of pressure)."""
    if key.endswith("gap"):
        return tolerance * rms_height
    return tolerance * contact_modulus * rms_gradient


def profile_band(y: ArrayLike, v: ArrayLike, yf: ArrayLike, vf: ArrayLike, floor: float) -> np.ndarray | None:
    """The band of a cross-section profile v(y) against the same case's profile (yf, vf) on the
    next finer grid, read as `cmc check` reads a curve (linear between its points): per point y_i
    the largest |v(y') - v_f(y')| over the finer points y' between y_i's neighbours that are
    nearest to it (on a grid twice as fine: y_i itself and the two midpoints beside it), so that
    the band, interpolated as the checker does, holds the finer profile everywhere; at least
    `floor` (profile_floor), which is the band where both grids agree exactly. None where the
    finer profile does not cover the line, a value is not finite, or the floor is not positive."""
    ya, va, yfa, vfa = (np.asarray(a, dtype=float) for a in (y, v, yf, vf))
    inside = (yfa >= ya[0]) & (yfa <= ya[-1])
    yfa, vfa = yfa[inside], vfa[inside]
    if len(ya) < 2 or not np.isfinite(vfa).all() or not np.isfinite(va).all() or len(yfa) < len(ya):
        return None
    d = np.abs(np.interp(yfa, ya, va) - vfa)
    b = np.zeros(len(ya))
    # A finer point on a coarse one counts for it alone; one between two counts for both.
    np.maximum.at(b, np.searchsorted(ya, yfa, "right") - 1, d)
    np.maximum.at(b, np.searchsorted(ya, yfa, "left"), d)
    if not floor > 0:
        return None
    return np.maximum(b, floor)


def sweep_floor(key: str, nx: int, ny: int, tolerance: float, rms_height: float) -> tuple[float, str]:
    """(least band, its words) of a load-sweep point, for key "ar" or "gap": one grid point
    (1/N^2, the count's quantum) for a_r, the solver's tolerance times the rms height for the mean
    gap (exact where the mean gap is 0, in full contact)."""
    if key == "ar":
        return 1.0 / (nx * ny), f"one grid point (1/{nx}^2)"
    return tolerance * rms_height, "the solver's tolerance times the rms height"


def measured_sweep_band(steps: list[dict[str, Any]], finer_steps: list[dict[str, Any]], key: str, n: int,
                        nf: int) -> tuple[list[float] | None, str]:
    """Band of a hard-wall load sweep on n^2 points from the same sweep on nf^2 points: at a load
    both ran, the change between the grids. Elsewhere the change per unit of what it scales with,
    interpolated linearly in log p between the loads both ran and held beyond them: for a_r the
    contact perimeter (the counted area's grid error is a boundary effect: it vanishes at full
    contact), for the mean gap the value itself. (None, "") with fewer than two shared loads."""
    fine = {round(st["p"], 6): st[key] for st in finer_steps if st["converged"] and st.get(key) is not None}
    per = key == "ar" and all(st.get("perimeter") is not None for st in steps)
    scale = (lambda st: st["perimeter"]) if per else (lambda st: abs(st[key] or 0.0))
    meas = [(st["p"], abs(st[key] - fine[round(st["p"], 6)]) / scale(st))
            for st in steps if st.get(key) and round(st["p"], 6) in fine and scale(st) > 0]
    if len(meas) < 2:
        return None, ""
    lp = np.log([m[0] for m in meas])
    ratio = np.interp(np.log([st["p"] for st in steps]), lp, [m[1] for m in meas])
    band = [b * scale(st) for b, st in zip(ratio, steps)]
    return band, (f"the change from {n}^2 to {nf}^2 measured at {len(meas)} loads ("
                  + ", ".join(f"{m[0] / 1e6:.4g}" for m in meas) + " MPa); between and beyond them the change per unit "
                  + ("contact perimeter" if per else "of the value") + " interpolated linearly in log p and held")


def hardwall_sweep_band(steps: list[dict[str, Any]], key: str, n: int, floor: tuple[float, str],
                        finer: tuple[int, list[dict[str, Any]]] | None = None,
                        reference: tuple[dict[str, Any], dict[str, Any], int, int] | None = None,
                        ) -> tuple[list[float] | None, str]:
    """Per-step band of a hard-wall load sweep on n^2 points for key "ar" or "gap", with a sentence
    saying how; (None, "") without one. floor: sweep_floor's (value, words), the least band.

    Measured where the same sweep ran on a finer grid (finer = (nf, its steps)):
    measured_sweep_band. Otherwise modelled from the grid change of the run at 250 kPa (reference =
    (step on n0^2, step on n1^2, n0, n1), used where n0 = n). a_r: the counted area's grid error is
    a boundary effect, first order in dx times the contact perimeter, so the change at 250 kPa is
    scaled by each step's perimeter over that at 250 kPa. Mean gap: the relative change at 250 kPa
    at every load (assumed)."""
    least, least_words = floor
    if finer is not None:
        band, how = measured_sweep_band(steps, finer[1], key, n, finer[0])
        if band:
            return [max(b, least) for b in band], how + ", at least " + least_words
    if reference is None:
        return None, ""
    a0, a1, n0, n1 = reference
    change = relative_change(a0.get(key), a1.get(key))
    if change is None or n0 != n:
        return None, ""
    if key == "ar":
        p0 = a0.get("perimeter")
        if not p0 or any(st.get("perimeter") is None for st in steps):
            return None, ""
        d0 = abs(a0["ar"] - a1["ar"])
        band = [max(d0 * st["perimeter"] / p0, least) for st in steps]
        return band, (f"the change of a_r at 250 kPa from {n0}^2 to {n1}^2 ({d0:.3g}) scaled by each load's "
                      "contact perimeter over that at 250 kPa (the counted area's grid error is a boundary effect), "
                      "at least " + least_words)
    band = [max(change * abs(st["gap"]), least) for st in steps]
    return band, (f"the relative change of the mean gap at 250 kPa from {n0}^2 to {n1}^2 "
                  f"({100 * change:.2g} %) at every load (assumed), at least " + least_words)
