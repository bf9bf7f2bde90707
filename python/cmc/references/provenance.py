"""What a challenge reference curve says about itself: its provenance (the run, its grid,
solver tolerance, date and command) and its error band with the sentence on what the band rests on."""
from __future__ import annotations
from typing import Any
import datetime
import json
import os
import sys

import numpy as np

from cmc.analysis import bands
from cmc.analysis.conditions import load_bands, run_strategy_error
from cmc.analysis.family import FAMILY_STORE
from cmc.analysis.runs import REPO as ROOT, dx_over_rho, strategy_of
from cmc.report.challenge_runs import band_floor
from cmc.report.common import CHALLENGE, STRATEGY_WORDS, load_json, roundoff_note, transfer_caveat
from .. import reference_files
from cmc import run_folder
from cmc._types import Json
from cmc.report.challenge_runs import Run


RHO, LAMBDA_S, P0 = CHALLENGE["rho"], CHALLENGE["lambda_s"], CHALLENGE["p0"]
GENERATOR = "scripts/challenge_reference.py (extraction: reports/challenge_report.py)"


# ------------------------------------------------------------------ the format: cmc writes it
def write_curve(cmc: str, c: Json, path: str) -> Any:
    """Has cmc format and write the curve (cmc.reference_files.write_curve); a refusal ends the script."""
    try:
        return reference_files.write_curve(cmc, c, path)
    except reference_files.CurveError as e:
        sys.exit(f"challenge_reference: {e}")


write_atomically = reference_files.write_atomically


# ------------------------------------------------------------------ provenance
def _rel(path):
    return os.path.relpath(os.path.abspath(path), ROOT)


def _mtime_utc(path):
    t = datetime.datetime.fromtimestamp(os.path.getmtime(path), tz=datetime.timezone.utc)
    return t.strftime("%Y-%m-%dT%H:%M:%SZ")


def _over_rho(run):
    """dx over the problem's range rho (cmc.analysis.runs.dx_over_rho: the specified range, not a
    coarse-grained law's longer one), NaN without one."""
    return dx_over_rho(run.s) or float("nan")


def _grid_text(run):
    """The grid, with dx/rho and dx/lambda_s as cmc computed them (summary.json surface_facts)."""
    facts = run.s.get("surface_facts") or {}
    if "dx_over_range" not in facts:  # no adhesion: no range to compare with
        return (f"{run.nx}x{run.ny}, dx = {run.dx * 1e9:.4g} nm = "
                f"{facts.get('dx_over_cutoff_wavelength', float('nan')):.3g} lambda_s (L = {run.size * 1e6:.4g} um)")
    return (f"{run.nx}x{run.ny}, dx = {run.dx * 1e9:.4g} nm = {_over_rho(run):.3g} rho "
            f"= {facts.get('dx_over_cutoff_wavelength', float('nan')):.3g} lambda_s "
            f"(L = {run.size * 1e6:.4g} um; rho = {RHO * 1e9:.4g} nm)")


def provenance(run: Run, steps: list[Json]) -> list[tuple[str, str]]:
    """make_run_curve's keys (cmc_version, case_file, grid, solver_tolerance, date, command)."""
    s = run.s
    solver = (s.get("case") or {}).get("solver") or {}
    raw = s.get("steps") or []
    res = [raw[st["k"]].get("residual") for st in steps if st["k"] < len(raw)]
    its = [raw[st["k"]].get("iterations") for st in steps if st["k"] < len(raw)]
    res = [r for r in res if isinstance(r, (int, float))]
    its = [i for i in its if isinstance(i, (int, float))]
    tol = f"{solver.get('tolerance', float('nan')):g} ({solver.get('kind', '?')}"
    if solver.get("kind") == "quasi_static":
        # Its residual is the tension change of one more outer step over w/rho, checked
        # against tension_tolerance; `tolerance` is that of the Polonsky-Keer inner solves.
        tol += f", tension_tolerance {solver.get('tension_tolerance', float('nan')):g}"
        if res:
            tol += f"; final tension residual <= {max(res):.3g}"
    elif res:
        tol += f"; final residual <= {max(res):.3g}"
    if its:
        tol += f", <= {int(max(its))} iterations"
    tol += f"; run status {s.get('status', '?')})"
    case_file = s.get("case_file") or "?"
    return [("cmc_version", str(s.get("cmc_version") or "?")), ("case_file", case_file),
            ("grid", _grid_text(run)), ("solver_tolerance", tol),
            ("date", _mtime_utc(run_folder.summary_path(run.folder))),
            ("command", f"cmc run {case_file} --out {_rel(run.folder)}{_overrides(s)}")]


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


def _overrides(summary):
    """The --set options the run was given, as far as its resolved case shows them: every key of
    the case file (with its bases) whose resolved value differs, and the strategy and backend keys
    when the file lacks them."""
    path = summary.get("case_file")
    try:
        from cmc.case_files import read_case_file  # with the bases it names
        file = read_case_file(os.path.join(ROOT, path) if path and not os.path.isabs(path) else path)
    except (OSError, TypeError, ValueError, ImportError):
        return ""
    case = summary.get("case") or {}
    out = []
    for sec, keys in sorted(case.items()):
        if not isinstance(keys, dict):
            continue
        for k, v in sorted(keys.items()):
            fv = (file.get(sec) or {}).get(k)
            absent = k not in (file.get(sec) or {})
            if (not absent and fv != v and not (isinstance(fv, (int, float)) and isinstance(v, (int, float))
                                                and abs(fv - v) <= 1e-12 * abs(v))) or \
                    (absent and (sec, k) == ("interaction", "coarse_graining") and v != "none") or \
                    (absent and (sec, k) == ("grid", "backend") and v != "cpu"):
                out.append(f" --set '{sec}.{k}={_toml_value(v)}'")
    return "".join(out)


# ------------------------------------------------------------------ hard-wall refinement (context)
HW_LABELS = {"contact_fraction": "contact fraction (raw)", "contact_fraction_corrected": "contact fraction (corrected)",
             "mean_gap": "mean gap", "max_gap": "max gap", "max_pressure": "max pressure",
             "n_patches": "number of patches", "mean_patch_area": "mean patch area",
             "largest_patch_area": "largest patch area", "contact_perimeter": "contact perimeter"}


def hardwall_refinement(folder: str) -> Json | None:
    """{observable: (coarse, fine, relative change)} between the two finest grids of the
    hard-wall study, as `cmc refine` wrote them (folder/refinement.json: values per grid and
    |fine - coarse| / |fine| between successive grids), and (n_coarse, n_fine); None without
    the file or without two converged grids."""
    t = load_json(os.path.join(folder, "refinement.json"))
    if not isinstance(t, dict) or len(t.get("grids") or []) < 2:
        return None
    if any(r.get("status") != "converged" for r in (t.get("runs") or [])[-2:]):
        return None
    n1, n2 = t["grids"][-2:]
    out = {}
    for row in t.get("rows") or []:
        k, vals, changes = row.get("observable"), row.get("values") or [], row.get("relative_changes") or []
        if k in HW_LABELS and len(vals) >= 2 and changes and all(isinstance(x, (int, float)) for x in
                                                                  (vals[-2], vals[-1], changes[-1])):
            out[k] = (vals[-2], vals[-1], changes[-1])
    return {"grids": (n1, n2), "changes": out, "folder": _rel(folder), "table": True}


def hw_context(hw: Json | None, keys: list[str]) -> str:
    if not hw:
        return "no hard-wall refinement study found either"
    n1, n2 = hw["grids"]
    parts = [f"{HW_LABELS[k]} {100 * hw['changes'][k][2]:.2g} %" for k in keys if k in hw["changes"]]
    return (f"for context only, the hard-wall problem at the same load changes between {n1}^2 and {n2}^2 "
            f"({hw['folder']}): " + ", ".join(parts))


def _bistable(run):
    b = ((run.s.get("surface_facts") or {}).get("bistability_number"))
    if isinstance(b, (int, float)) and b > 1:
        return f" and every grid point is bistable (w dx/(E* rho^2) = {b:.3g} > 1)"
    return ""


def adhesive_error(run: Run, hw: Json | None, keys: list[str], coarser: tuple[Run, Json] | None = None) -> str:
    """What an adhesive curve's error is not: the grid leaves rho unresolved. coarser: the grid
    the band was measured against, where there is one (the band then covers the grid error at
    this dx/rho alone)."""
    grid = (f"{run.nx}^2, dx = {run.dx * 1e9:.3g} nm = {_over_rho(run):.3g} rho, far coarser than the ~0.75 rho of "
            "the published solution")
    if coarser:
        return (f"NOT CONVERGED in rho: one adhesive case ({STRATEGY_WORDS[strategy_of(run.s)]}) on {grid}, so the "
                f"adhesive neck (range rho) is unresolved{_bistable(run)}; the band is the grid error between "
                f"{coarser}^2 and {run.nx}^2 alone, and the rest of the error is unknown and may be large (tens of per "
                "cent or more), above all in the tensile part, near contact lines and in patch statistics")
    return (f"NOT CONVERGED, not estimated by a refinement study: one adhesive run on one grid ({grid}), so the "
            f"adhesive neck (range rho) is unresolved{_bistable(run)}; the error is unknown and may be large (tens of "
            "per cent or more), above all in the tensile part, near contact lines and in patch statistics; "
            + hw_context(hw, keys) + " (between a curve and this one, compare shapes, not digits)")


# ------------------------------------------------------------------ the strategy's error band
def strategy_band(run: Run, short: str,
                  elsewhere: str = "that it holds at this point's load and mu_T is assumed, not measured.",
                  ) -> tuple[float | None, str]:
    """For an exponential-adhesion run: the relative error for quantity `short` (a_r, mean_gap)
    that its strategy (range or shape coarse-graining, or plain) has on the scaled challenge family at the
    same dx/rho (cmc.analysis.conditions run_strategy_error: the family run within a factor 1.3 of
    this dx/rho, its deviation from the family's converged reference plus that reference's
    refinement error), and a sentence saying what it rests on (`elsewhere`: what the band is at other loads and
    mu_T). None where the family has no run near."""
    got = run_strategy_error(run.s, short)
    if got is None:
        return None, ""
    k, rel, used = got
    store = _rel(FAMILY_STORE)
    what = STRATEGY_WORDS[strategy_of(run.s)]
    if rel is None:
        return None, (f"{what} at dx = {k:.3g} rho: the scaled family ({store}) has no run of it within a factor "
                      "1.3 of this dx/rho, so no error band")
    return rel, (f"band: the error of {what} measured on the scaled challenge family at the same "
                 f"dx/rho ({k:.3g} rho; {'; '.join(used)}; {store}): +-{100 * rel:.3g} % (deviation from the "
                 "family's converged reference plus that reference's refinement error). Measured at mu_T = 3 and "
                 f"250 kPa; {elsewhere} " + roundoff_note(rel=_rel) + " " + transfer_caveat())


def add_abs_band(curve: Json, band: Any) -> Json:
    """Appends the error band to a curve: column <y>_err = the half-widths `band` (y's unit), '# band:'."""
    y = curve["columns"][1]
    curve["columns"].append((y[0] + "_err", y[1], "half-width of the error band: " + y[2], list(band)))
    curve["band"] = y[0] + "_err"
    curve["title"] = curve["title"].replace(" (not converged)", " (with error band)")
    return curve


def add_band(curve: Json, rels: list[float]) -> Json:
    """Appends a relative error band: half-width rel x |y| per point (bands.absolute_band)."""
    return add_abs_band(curve, bands.absolute_band(rels, curve["columns"][1][3]))


def with_band(curve: Json, run: Run, short: str) -> Json:
    """Adds the strategy's error band to a curve of one adhesive run (every point the same dx/rho),
    at least the floor the hard-wall bands have (band_floor: the mean gap is 0 in full contact,
    where a relative band would be 0)."""
    # Measured at other loads too (scripts/scaled_family.py --pressure): per load, the larger.
    rels, words = load_bands(run.s, short, curve["columns"][0][3])
    rel, text = (strategy_band(run, short, f"per load, {words}. At loads between and beyond those measured the "
                               "band is assumed.") if words else strategy_band(run, short))
    if text:
        curve["estimated_error"] = text
    if rel is None:
        return curve
    if rels is None or not words:
        rels = [rel] * len(curve["columns"][1][3])
    floor, what = band_floor(run, "ar" if short == "a_r" else "gap")
    ys = curve["columns"][1][3]
    if any(r * abs(v) < floor for r, v in zip(rels, ys)):
        curve["estimated_error"] += f" At least {what} where the relative band is smaller."
    return add_abs_band(curve, bands.absolute_band(rels, ys, floor))


# ------------------------------------------------------------------ curves
def _clean(x, y, log_x, log_y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    m = np.isfinite(x) & np.isfinite(y)
    if log_x:
        m &= x > 0
    if log_y:
        m &= y > 0
    return x[m], y[m], int(len(x) - m.sum())


def _with_refinement_band(curve, x, y, xc, yc, log_x, log_y, n, nc, base_error):
    """Adds the band 2 |y - y_coarser(x)| (bands.finest_grid_band) to a curve of the finest run at
    the reference load: points outside the coarser curve's range (or where both grids agree
    exactly) carry no band and are left out, and `sampling` says how many."""
    b = bands.finest_grid_band(x, y, xc, yc, log_x, log_y)
    keep = np.isfinite(b) & (b > 0)
    curve["columns"][0] = curve["columns"][0][:3] + (x[keep],)
    curve["columns"][1] = curve["columns"][1][:3] + (y[keep],)
    add_abs_band(curve, b[keep])
    dropped = int(len(x) - keep.sum())
    if dropped:
        extra = dict(curve["extra"])
        extra["sampling"] += (f"; {dropped} point(s) outside the {nc}^2 curve's range left out (no band there)")
        curve["extra"] = list(extra.items())
    med = float(np.median(b[keep] / np.abs(y[keep]))) if keep.any() else float("nan")
    curve["estimated_error"] = (f"band: per point, twice |this curve ({n}^2) - the same case on the next coarser grid "
                                f"({nc}^2)|, the coarser curve interpolated in the representation (median {100 * med:.2g} "
                                "% of the value): the two-grid first-order bound of the grid error "
                                "(python/cmc/analysis/bands.py finest_grid_band). " + base_error).strip()
    return curve
