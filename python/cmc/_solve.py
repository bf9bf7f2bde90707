"""A solve on heights given as a numpy array: cmc.solve, its interactions and its Solution."""
from __future__ import annotations
from typing import Any, Callable
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ._cases import Result
from ._native import _core, flag, plain, renamed, CaseError
from ._types import Json


@dataclass(frozen=True)
class HardWall:
    """Non-penetration only (g >= 0): no adhesion."""

    def _keys(self):
        return {"kind": "hard_wall"}


@dataclass(frozen=True)
class Exponential:
    """The challenge's adhesion: energy per area -w exp(-g/rho) for g >= 0, peak tension w/rho.

    `w`: work of adhesion (J/m^2); `rho`: range (m). Or give `tabor` (Mueller's mu_T, with
    R = the surface's R_c) instead of `rho`. `coarse_graining`: "none", "range" or "shape"
    (cases/README.md, [interaction]).
    """
    w: float
    rho: Optional[float] = None
    tabor: Optional[float] = None
    coarse_graining: str = "none"

    def _keys(self):
        keys = {"kind": "exponential", "work_of_adhesion": self.w, "coarse_graining": self.coarse_graining}
        if self.rho is not None:
            keys["range"] = self.rho
        if self.tabor is not None:
            keys["tabor"] = self.tabor
        return keys


@dataclass(frozen=True)
class Dugdale:
    """Dugdale's law: constant tension sigma0 = w/h0 for g < h0.

    `w`: work of adhesion (J/m^2); `h0`: range (m); `smoothing`: the width (m) over which
    the tension ramps to zero around h0 (0: the smallest that keeps grid points stable).
    """
    w: float
    h0: float
    smoothing: float = 0.0

    def _keys(self):
        return {"kind": "dugdale", "work_of_adhesion": self.w, "range": self.h0, "smoothing": self.smoothing}


class Solution(Result):
    """A :class:`cmc.Result` of :func:`cmc.solve`, with the last load step at hand:
    ``pressure`` (Pa), ``displacement`` and ``gap`` (m) as (ny, nx) arrays, and its
    scalars (``mean_pressure``, ``force``, ``penetration``, ``mean_gap``,
    ``contact_fraction``, ``energy``, ``iterations``, ``residual``, ``message``) as attributes."""

    _SCALARS = ("mean_pressure", "force", "penetration", "mean_gap", "contact_fraction", "energy", "iterations",
                "residual", "message", "wall_s", "fft_pairs")

    @property
    def pressure(self) -> np.ndarray:
        return self.field("pressure")

    @property
    def displacement(self) -> np.ndarray:
        return self.field("displacement")

    @property
    def gap(self) -> np.ndarray:
        return self.field("gap")

    def __getattr__(self, name):
        if name in Solution._SCALARS:
            return self.steps[-1][name]
        raise AttributeError(f"'Solution' object has no attribute {name!r}")


_LABEL = "cmc.solve()"
# Case keys that stand for solve()'s arguments, for messages.
_ARGUMENTS = {
    "[grid] nx": "heights", "[grid] ny": "heights", "[grid] size_y": "size", "[grid] size": "size",
    "[grid] boundary": "boundary", "[material] contact_modulus": "modulus", "[solver] kind": "strategy",
    "[solver] tolerance": "tolerance", "[solver] max_iterations": "max_iterations",
    "[interaction] work_of_adhesion": "interaction", "[interaction] range": "interaction",
    "[interaction] tabor": "interaction", "[interaction] smoothing": "interaction",
    "[interaction] coarse_graining": "interaction", "[interaction]": "interaction",
}
_LOADS = {"pressure": "mean_pressure", "penetration": "penetration", "force": "force", "mean_gap": "mean_gap"}


def _heights_view(heights):
    """`heights` as a numpy array of real numbers, 1-D or 2-D and not empty, checked without a
    copy of an array given as one (a broadcast view stays a view until the case, its memory
    checked, says the grid fits)."""
    if isinstance(heights, np.ndarray):
        h = heights
    else:
        try:
            h = np.asarray(heights)
        except (TypeError, ValueError) as e:
            raise CaseError(f"{_LABEL}: heights: expected an array of numbers (metres), "
                            f"got {type(heights).__name__} ({e})") from None
    if h.dtype.kind not in "fiu":
        got = type(heights).__name__ if h.dtype.kind == "O" and h.ndim == 0 else f"an array of {h.dtype}"
        raise CaseError(f"{_LABEL}: heights: expected an array of real numbers (float or integer, metres), "
                        f"got {got}")
    if h.ndim not in (1, 2) or h.size == 0:
        raise CaseError(f"{_LABEL}: heights: expected a non-empty 2-D array (ny, nx) or a 1-D line, "
                        f"got shape {h.shape}")
    return h if h.ndim == 2 else h.reshape(1, -1)


def _load_keys(loads):
    given = {k: v for k, v in loads.items() if v is not None}
    if len(given) != 1:
        raise CaseError(f"{_LABEL}: give exactly one of pressure=, penetration=, force=, mean_gap= (got "
                        f"{', '.join(given) or 'none'})")
    (name, value), = given.items()
    values = plain(value, f"{_LABEL}: {name}")
    return name, {"control": _LOADS[name], "values": values if isinstance(values, list) else [values]}


def solve(heights: Any, size: float | tuple[float, float], modulus: float, pressure: Any = None, *,
          penetration: Any = None, force: Any = None, mean_gap: Any = None,
          interaction: HardWall | Exponential | Dugdale | None = None, strategy: str = "auto",
          tolerance: float | None = None, max_iterations: int | None = None, boundary: str = "periodic",
          observables: bool = False, progress: Callable[[Json], Any] | None = None) -> Solution:
    """Press the rigid indenter `heights` onto an elastic half-space and solve.

    `heights`: the indenter's heights h in metres, a (ny, nx) array (row i at y = i dy,
    x fastest; the gap is g = h - penetration + u) or a 1-D line (a plane-strain problem).
    `size`: the side along x in metres (square grid cells: the side along y is size ny/nx).
    `modulus`: the contact modulus E* in Pa. The load: one of `pressure` (mean pressure,
    Pa), `penetration` (m), `force` (N) or `mean_gap` (m); a number, or a sequence for
    load steps solved in order, each from the last. `interaction`: :class:`HardWall`
    (default), :class:`Exponential` or :class:`Dugdale`. `strategy`: "auto",
    "polonsky_keer", "adhesive_cg" or "quasi_static" (cases/README.md, [solver] kind);
    `tolerance`, `max_iterations`: the solver's (its defaults where None). `boundary`:
    "periodic" or "free". `observables`: compute the challenge's observables per step.
    `progress`: as for :func:`cmc.run`. Ctrl-C stops the solve (KeyboardInterrupt).

    The arguments are checked as a case file is (cases/README.md): a wrong one raises
    :class:`cmc.CaseError` naming it; so does a height that is NaN or infinite.
    Returns a :class:`Solution` (SI units).
    """
    h = _heights_view(heights)
    ny, nx = h.shape
    if interaction is None:
        interaction = HardWall()
    if not hasattr(interaction, "_keys"):
        raise CaseError(f"{_LABEL}: interaction: expected cmc.HardWall(), cmc.Exponential(w, rho) or "
                        f"cmc.Dugdale(w, h0), got {type(interaction).__name__}")
    if progress is not None and not callable(progress):
        raise CaseError(f"{_LABEL}: progress: expected a callable or None, got {type(progress).__name__}")
    grid = {"nx": nx, "ny": ny, "size": size, "boundary": boundary}
    if ny > 1 and nx != ny and isinstance(plain(size, f"{_LABEL}: size"), (int, float)):
        grid["size_y"] = size * ny / nx
    load, loading = _load_keys({"pressure": pressure, "penetration": penetration, "force": force,
                                "mean_gap": mean_gap})
    solver: dict[str, Any] = {"kind": strategy}
    if tolerance is not None:
        solver["tolerance"] = tolerance
    if max_iterations is not None:
        solver["max_iterations"] = max_iterations
    sections = {"case": {"name": "python-solve"}, "grid": grid, "material": {"contact_modulus": modulus},
                "surface": {"kind": "flat"}, "interaction": interaction._keys(),
                "loading": loading,
                "solver": solver, "output": {"fields": True},
                "observables": {"enabled": flag(observables, f"{_LABEL}: observables")}}
    sections = {s: {k: plain(v, f"{_LABEL}: [{s}] {k}") for k, v in keys.items()} for s, keys in sections.items()}
    try:
        case = _core.case_from_sections(sections, _LABEL)  # the grid's memory checked before h is copied
        return Solution(_core.run(case, np.ascontiguousarray(h, dtype=np.float64), "", progress))
    except CaseError as e:
        raise renamed(e, _LABEL, {**_ARGUMENTS, "[loading] values": load}) from None
