"""Surfaces as numpy heights: the challenge's generator and the height-file readers."""
from __future__ import annotations
from typing import Any
import numpy as np
import warnings

from ._native import _core, length, path_text, plain, renamed, CaseError

_LABEL = "cmc.self_affine()"
_ARGUMENTS = {"[grid] n": "n", "[grid] size": "size", "[surface] hurst": "hurst",
              "[surface] rolloff_wavelength": "rolloff_wavelength",
              "[surface] cutoff_wavelength": "cutoff_wavelength", "[surface] rms_gradient": "rms_gradient",
              "[surface] seed": "seed"}


def self_affine(n: int, size: float, *, hurst: float = 0.8, rolloff_wavelength: float | None = None,
                cutoff_wavelength: float | None = None, rms_gradient: float = 1.0, seed: int = 28) -> np.ndarray:
    """The challenge's self-affine random surface on an n x n grid of side `size` (m).

    The generator of a case's ``[surface] kind = "self_affine"`` (the same heights for the
    same arguments): power spectrum flat up to the roll-off wavelength
    (default 0.2 size), falling as q^(-2(1+H)) to the cutoff wavelength (default 0.001
    size), rms gradient `rms_gradient` over the whole band, GSL mt19937 `seed`; min h = 0.
    A grid too coarse for the band gets the low-passed surface and a warning.
    Returns the heights in metres, shape (n, n). Arguments are checked as the case keys of
    the same names are (cases/README.md); a wrong one raises :class:`cmc.CaseError`.
    """
    surface = {"kind": "self_affine", "hurst": hurst, "rms_gradient": rms_gradient, "seed": seed}
    if rolloff_wavelength is not None:
        surface["rolloff_wavelength"] = rolloff_wavelength
    if cutoff_wavelength is not None:
        surface["cutoff_wavelength"] = cutoff_wavelength
    # Material and loading only complete the case; they play no part in the surface.
    sections: dict[str, dict[str, Any]] = {"case": {"name": "python-self-affine"}, "grid": {"n": n, "size": size},
                "material": {"contact_modulus": 1.0}, "surface": surface,
                "loading": {"control": "mean_pressure", "values": [0.0]}}
    sections = {s: {k: plain(v, f"{_LABEL}: {k}") for k, v in keys.items()} for s, keys in sections.items()}
    try:
        s = _core.self_affine(_core.case_from_sections(sections, _LABEL))
    except CaseError as e:
        raise renamed(e, _LABEL, _ARGUMENTS) from None
    if s["modes_dropped"]:
        warnings.warn(f"cmc.self_affine: the {n} x {n} grid holds {s['modes_total'] - s['modes_dropped']} of the "
                      f"{s['modes_total']} Fourier modes of the surface: it is low-passed at the grid's Nyquist "
                      f"wavelength (n >= {s['full_grid']} holds them all)", stacklevel=2)
    return s["heights"]


def read_heights(path: Any, size: float, format: str = "challenge_hdf5", *, dataset: str = "surface",
                 height_unit: str | None = None, n: int = 0) -> np.ndarray:
    """Heights in metres from a height file, in the formats a case file's surface reads.

    `format`: "challenge_hdf5" (the challenge's HDF5, dataset "surface"), "challenge_ascii"
    (its ASCII matrix), "fourier" (a list of "kx ky re im" lines, synthesised on an n x n
    grid; n = 0: the smallest that holds every mode), or a generic "hdf5" (dataset
    `dataset`) or "ascii" height map. `size`: the side of the box in metres (the challenge's
    is 1e-4). `height_unit`: metres per height unit of the file; by default `size` for the
    challenge's formats and Fourier lists (heights in units of L), 1 for the generic ones.
    Returns a (ny, nx) array, the file's own grid (row i at y = i dy). An unreadable or
    malformed file raises :class:`cmc.SurfaceFileError` naming it.
    """
    label = "cmc.read_heights()"
    size = length(size, f"{label}: size")
    unit = 0.0 if height_unit is None else length(height_unit, f"{label}: height_unit")
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise CaseError(f"{label}: n: expected an integer >= 0 (points per side; 0: the smallest grid), got {n!r}")
    try:
        return _core.read_heights(path_text(path, f"{label}: path"), str(format), size, str(dataset), unit, n)
    except CaseError as e:
        raise CaseError(f"{label}: {e}") from None
