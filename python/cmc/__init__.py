"""cmc: rough, adhesive contact mechanics (the Contact Mechanics Challenge).

Pure-Python submodules (``cmc.analysis``: refinement, extrapolation, error bands and the
choice of best estimates) import without the compiled core; names of the core load it
on first use (PEP 562 module ``__getattr__``): ``import cmc`` alone loads nothing compiled.

The API (docs/user-guide/python.md), SI units throughout:

* ``cmc.Case.load(path, set={...})`` and ``cmc.run(case, out=None, progress=None)``: a case
  file checked as ``cmc run`` checks it, run by the same driver (the same numbers), kept in
  memory as a :class:`cmc.Result` (the summary as a dict, fields and observables as numpy
  arrays), written into a folder only when ``out`` is given;
* ``cmc.solve(heights, size, modulus, pressure=..., interaction=cmc.HardWall() |
  cmc.Exponential(w, rho) | cmc.Dugdale(w, h0), strategy=..., tolerance=...)``: a solve on
  heights given as a numpy array;
* ``cmc.self_affine(n, size, ...)``: the challenge's surface generator; ``cmc.read_heights``:
  the challenge's height files and the other formats a case file reads;
* ``cmc.analytic``: the analytic references (Hertz, Westergaard, JKR, Maugis-Dugdale, ...);
* ``cmc.check(prediction, quantity)``: a prediction (CSV file or array) scored against the
  stored reference curve, as ``cmc check`` scores it.

Bad input raises ``cmc.CaseError`` / ``cmc.InputError`` (both ``ValueError``) naming the
file, key or argument and what was expected.
"""
import importlib

# Each public name and the module of the package that defines it.
_API = {
    "Case": "_cases", "Result": "_cases", "run": "_cases",
    "solve": "_solve", "Solution": "_solve", "HardWall": "_solve", "Exponential": "_solve", "Dugdale": "_solve",
    "self_affine": "_surfaces", "read_heights": "_surfaces",
    "check": "_check", "CheckReport": "_check",
    "CaseError": "_native", "InputError": "_native", "SurfaceFileError": "_native",
}
_SUBMODULES = ("analytic", "analysis")
__all__ = sorted([*_API, *_SUBMODULES])


def __getattr__(name):
    if name in _API:
        value = getattr(importlib.import_module("cmc." + _API[name]), name)
        globals()[name] = value  # found once; later lookups do not come here
        return value
    if name in _SUBMODULES:
        return importlib.import_module("cmc." + name)
    raise AttributeError(f"module 'cmc' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
