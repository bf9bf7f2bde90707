"""Factors that scale the run store's times in the GPU plan's estimates (cmc.gpu_plan.plan) to the
present solver: its iterations over those of the program that made the stored runs, per
strategy, measured on the CPU by scripts/bench_iterations.sh (--before the older build) and
recorded in reference/performance/shape-iterations*.json, one file per inner tolerance.
Iteration counts do not depend on the device, and a solve's time on the GPU is about its
iterations times an iteration's time, so a stored GPU run's time times the factor is the
present solver's. A run started from a coarser grid is further scaled by the warm start's
iterations over the cold start's. Hard-wall runs are not scaled (not measured there: 1).
Standard library only: it runs on the GPU machine.
"""
import glob
import json
import math
import os
from collections.abc import Sequence
from typing import Any, Optional

Factors = dict[str, Any]  # one record's plan_factors, with its tolerance and source file


def load(root: str) -> list[Factors]:
    """[factors] of every record of the repository at root (each a dict with its tolerance),
    sorted by tolerance."""
    out = []
    for path in sorted(glob.glob(os.path.join(root, "reference", "performance", "shape-iterations*.json"))):
        with open(path) as f:
            factors = json.load(f).get("plan_factors")
        if factors and factors.get("tolerance"):
            out.append(dict(factors, source=os.path.relpath(path, root)))
    return sorted(out, key=lambda f: f["tolerance"])


def nearest(tables: Sequence[Factors], tolerance: Optional[float]) -> Optional[Factors]:
    """The record measured at the tolerance nearest (in its logarithm) to a stored run's."""
    if not tables:
        return None
    if not tolerance:
        return tables[0]
    log_tolerance = math.log10(tolerance)
    return min(tables, key=lambda f: abs(math.log10(f["tolerance"]) - log_tolerance))


def factor(kind: str, stage: str, tolerance: Optional[float], tables: Sequence[Factors]) -> float:
    """The factor a stored run's time of `kind` (at its inner `tolerance`) is scaled by for
    `stage` (1 for the hard wall, or where nothing was measured)."""
    f = None if kind.startswith("hardwall") else nearest(tables, tolerance)
    if f is None:
        return 1.0
    x = float(f.get("shape" if kind.startswith("shape") else "plain", 1.0))
    if stage.startswith("adhesive_from"):
        x *= f.get("warm_plain", 1.0)
    return x


def describe(tables: Sequence[Factors]) -> list[str]:
    """One line per record: its file, tolerance and factors."""
    keys = ("plain", "shape", "warm_plain")
    return [f"{f['source']} (inner tolerance {f['tolerance']:g}): "
            + ", ".join(f"{k} x{f[k]:.2f}{' at least' if f.get(k + '_is_lower_bound') else ''} ({f[k + '_grid']}²)"
                        for k in keys if k in f) for f in tables]
