"""The analytic references of cmc: Hertz, flat punches, periodic images, Westergaard's and
Johnson's wavy contacts, JKR, DMT and Maugis-Dugdale (solver/cmc/analytic/Analytic.hpp:
equations and citations).

Conventions: compressive pressure p > 0, gap g >= 0, penetration delta > 0 into the solid,
Estar the contact modulus, w the work of adhesion; any consistent units (SI throughout
cmc). Functions of numbers that return a number take numpy arrays as well (broadcast);
invalid arguments raise ValueError, a failed root search or quadrature RuntimeError.
"""
from __future__ import annotations
from typing import Any
from ._native import _core

_analytic = _core.analytic
__all__ = sorted(["hertz"] + [n for n in dir(_analytic) if not n.startswith("_")])
globals().update({n: getattr(_analytic, n) for n in __all__ if n != "hertz"})


def hertz(Estar: float, R: float, *, force: float | None = None, penetration: float | None = None,
          radius: float | None = None) -> Any:
    """The Hertz contact of a sphere of radius `R` (paraboloid h = r^2/(2R)) on a half-space of
    contact modulus `Estar`, from one of `force` F, `penetration` delta or contact `radius` a.

    Returns a HertzContact with radius a, penetration delta, force F and max_pressure p0
    (p(r) = p0 sqrt(1 - r^2/a^2): :func:`hertz_pressure`)."""
    given = {k: v for k, v in (("force", force), ("penetration", penetration), ("radius", radius)) if v is not None}
    if len(given) != 1:
        raise ValueError(f"cmc.analytic.hertz: give exactly one of force=, penetration=, radius= (got "
                         f"{', '.join(given) or 'none'})")
    (name, value), = given.items()
    return getattr(_analytic, "hertz_from_" + name)(Estar, R, value)
