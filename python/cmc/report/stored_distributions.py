"""The stored challenge references of items 1, 3, 4, 5 and 9 (reference/challenge/ and its
adhesionless/, scripts/challenge_reference.py) drawn into the challenge report's figures: each
curve with its band as the file stores it (column `# band:`), its grid named in the legend and in
the table row. The report's own runs are drawn beside them, each with the band its own results
give; a stored band belongs to the stored grid and is not lent to another.

A stored reference is the dict of cmc.report.challenge_runs._stored: {path, meta, x, y, band}.
"""
from __future__ import annotations
from typing import Any
import re

import numpy as np

from .common import CHALLENGE, fmt
from cmc._types import Json


def grid_name(ref: Json) -> str:
    """The stored curve's grid as the tables write it: "8192²" for 8192x8192."""
    grid = ref["meta"].get("grid", "?").split(",")[0].strip()
    m = re.fullmatch(r"(\d+)x(\d+)", grid)
    return f"{m.group(1)}²" if m and m.group(1) == m.group(2) else grid


def problem(adhesive: bool) -> str:
    return "with adhesion" if adhesive else "without adhesion"


def band_words(ref: Json) -> str:
    """The table's band cell: where the band is stored and, as the file's `estimated_error` says,
    the grid it was measured against and its median."""
    words = ref["meta"].get("estimated_error", "")
    coarser = re.search(r"next coarser grid \((\d+)\^2", words)
    median = re.search(r"median ([^,;)]+)", words)
    how = (f"2 × |{grid_name(ref)} − {coarser.group(1)}²|" if coarser else "its `estimated_error`") + (
        f", median {median.group(1).strip()}" if median else "")
    return f"as stored (`{ref['path']}`, `{ref['meta'].get('band')}`): {how}"


def _lower(y, b, log_y):
    """The lower edge of a band; on a log axis at least a thousandth of the value."""
    return np.maximum(y - b, y * 1e-3) if log_y else y - b


def draw_stored_curve(ax: Any, ref: Json | None, adhesive: bool, xunit: float, yunit: float, log_y: bool) -> list[list[Any]]:
    """Draws a stored distribution or spectrum (x and y times xunit, yunit) with its band as stored
    on ax; returns the table rows, [problem, run, p (kPa), points, range, band], or [] without a
    stored curve or band."""
    if ref is None or ref["band"] is None:
        return []
    x, y, b = (np.asarray(ref[k], dtype=float) for k in ("x", "y", "band"))
    label = f"{problem(adhesive)}: stored reference, {grid_name(ref)}"
    line, = ax.plot(x * xunit, y * yunit, "--", lw=0.8, label=label)
    ax.fill_between(x * xunit, _lower(y, b, log_y) * yunit, (y + b) * yunit, color=line.get_color(), alpha=0.15,
                    lw=0, label=f"band as stored ({grid_name(ref)})")
    return [[problem(adhesive), f"stored reference ({grid_name(ref)})", fmt(CHALLENGE["p0"] / 1e3, 4), len(x),
             f"{fmt(x.min() * xunit, 3)} – {fmt(x.max() * xunit, 3)}", band_words(ref)]]


def draw_stored_profiles(zoom_axes: Any, refs: tuple[Json | None, Json | None], adhesive: bool, y_centre: float,
                         ) -> list[list[Any]]:
    """Draws the stored cross sections (refs: the gap's and the stress's, either None) with their
    bands as stored into the zoom panels (gap in nm, stress in MPa) within 1 um of y_centre;
    returns the table rows, [problem, run, x (um) as the file's title gives it, points, band]."""
    rows = []
    for ax, ref, scale in zip(zoom_axes, refs, (1e9, 1e-6)):
        if ref is None or ref["band"] is None:
            continue
        y, v, b = (np.asarray(ref[k], dtype=float) for k in ("x", "y", "band"))
        z = np.abs(y - y_centre) <= 1e-6
        line, = ax.plot(y[z] * 1e6, v[z] * scale, "--", lw=0.8,
                        label=f"{problem(adhesive)}: stored reference, {grid_name(ref)}")
        ax.fill_between(y[z] * 1e6, (v - b)[z] * scale, (v + b)[z] * scale, color=line.get_color(), alpha=0.15,
                        lw=0, step="mid", label=f"band as stored ({grid_name(ref)})")
        ax.legend(fontsize=6)
        x0 = re.search(r"along x = (\S+) um", ref["meta"].get("title", ""))
        rows.append([problem(adhesive), f"stored reference ({grid_name(ref)}), {ref['meta'].get('y')}",
                     x0.group(1) if x0 else "?", len(y), band_words(ref)])
    return rows
