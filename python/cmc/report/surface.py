"""The challenge report's words on which surface its runs used. cmc's best estimates and stored
references answer for cmc's own surface (the [surface] seed of cases/challenge/challenge-base.toml);
runs on a surface file (scripts/main.sh --surface FILE, or any case with [surface] kind = "file")
answer for that file's surface. This part names the file (path and SHA-256, from the results
folder's surface.json that scripts/surface_file.py writes), lists the runs that used it (their
summary.json), sets their rms height beside cmc's surface's, and points at the realisation
references, the fair comparison for a surface of its own. It computes nothing but ratios.
"""
from __future__ import annotations
from typing import TYPE_CHECKING, Any
import json
import os

from .common import fmt, get, md_table, read_reference_csv
from cmc._types import Json

if TYPE_CHECKING:
    from .challenge_runs import Run

P0 = 250e3


def manifest(results_dir: str) -> Json | None:
    """surface.json of a results folder of scripts/main.sh --surface, or None."""
    try:
        with open(os.path.join(results_dir, "surface.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def file_runs(runs: list[Run]) -> list[tuple[Run, str]]:
    """[(run, surface path)] of the runs whose case takes its surface from a file."""
    return [(r, get(r.s, "case", "surface", "path")) for r in runs if get(r.s, "case", "surface", "kind") == "file"]


def cmc_surface(reference_dir: str) -> tuple[Any, float | None]:
    """(seed, rms height in m) of the surface behind the hard-wall best estimate (its record in
    reference/challenge/runs.json), either None where not stored."""
    try:
        with open(os.path.join(reference_dir, "challenge", "best_estimates.json")) as f:
            tag = json.load(f)["reference_load"]["hardwall"]["run"]
        with open(os.path.join(reference_dir, "challenge", "runs.json")) as f:
            rec = next(r for r in json.load(f)["records"] if r.get("tag") == tag)
    except (OSError, ValueError, KeyError, TypeError, StopIteration):
        return None, None
    return (rec.get("physics") or {}).get("surface.seed"), rec.get("rms_height_m")


def headline_surfaces(results_dir: str, runs: list[Run], reference_dir: str) -> tuple[str, str] | None:
    """Words for the headline's columns, (best estimates', user's runs'), where the runs used a
    surface file; else None (the runs are on cmc's own surface, as the best estimates)."""
    if not file_runs(runs):
        return None
    seed, _ = cmc_surface(reference_dir)
    info = manifest(results_dir)
    name = os.path.basename(info["path"]) if info else "a surface file"
    return (f" (cmc's surface{f', seed {seed}' if seed is not None else ''})", f" on `{name}`")


def _rms(run):
    return get(run.s, "surface_facts", "rms_height")


def _runs_table(used, info):
    """One row per case and surface (a sweep's runs together)."""
    groups = {}
    for r, path in used:
        same = info is not None and path == info["path"] and get(r.s, "case", "surface", "format") == info["format"]
        rms = fmt(_rms(r) * 1e6 if _rms(r) else None, 5)
        groups.setdefault((r.label, r.s.get("surface", "?"), rms, same), []).append(r.folder)
    rows = [[label, len(folders), f"`{os.path.commonpath(folders) if len(folders) > 1 else folders[0]}`", surface, rms,
             "yes" if same else "**no**"] for (label, surface, rms, same), folders in groups.items()]
    return md_table(["case", "runs", "folder", "surface (summary.json)", "rms height (µm)", "this file"], rows)


# The realisation references at the headline's point: (problem, folder, quantity, x column, x there,
# the step's key, y column, scale, unit).
AT_250_KPA = ((False, "adhesionless", "contact_area_vs_pressure", "pressure_Pa", P0, "ar", "contact_fraction", 1.0, ""),
              (False, "adhesionless", "mean_gap_vs_pressure", "pressure_Pa", P0, "gap", "mean_gap_m", 1e6, " µm"),
              (True, "", "contact_area_vs_tabor", "tabor", 3.0, "ar", "contact_fraction", 1.0, ""),
              (True, "", "mean_gap_vs_tabor", "tabor", 3.0, "gap", "mean_gap_m", 1e6, " µm"))


def _realisation_rows(reference_dir, user):
    """Lines setting the user's runs at 250 kPa (user: {adhesive: (run, step) or None}) beside the stored
    realisation references at that point."""
    out = []
    for adhesive, sub, q, xcol, x, key, col, scale, unit in AT_250_KPA:
        got = read_reference_csv(os.path.join(reference_dir, "challenge", "realisation", sub, q + ".csv"))
        run_step = user.get(adhesive)
        mine = run_step[1].get(key) if run_step else None
        if got is None or mine is None or not {xcol, col, col + "_err"} <= set(got[1]):
            continue
        names, data = got[1], got[2]
        at = [row for row in data if abs(row[names.index(xcol)] / x - 1) < 0.01]
        if not at:
            continue
        ref, err = at[0][names.index(col)], at[0][names.index(col + "_err")]
        where = "μ_T = 3" if xcol == "tabor" else "without adhesion"
        out.append(f"- `{sub + '/' if sub else ''}{q}.csv` at 250 kPa, {where}: your run ({run_step[0].nx}²) "
                   f"{fmt(mine * scale, 5)}{unit}, the realisation reference {fmt(ref * scale, 5)} ± "
                   f"{fmt(err * scale, 2)}{unit}: " + ("inside its band" if abs(mine - ref) <= err else
                                                      f"**outside** its band, by {abs(mine - ref) / err:.2g} half-widths"))
    return out


def surface_section(results_dir: str, runs: list[Run], reference_dir: str, user: Any) -> list[str]:
    """The section on the runs' surface (lines), or [] where no run used a surface file.
    user: {adhesive: (run, step) at 250 kPa or None}, the runs the headline shows."""
    used = file_runs(runs)
    if not used:
        return []
    info = manifest(results_dir)
    seed, rms28 = cmc_surface(reference_dir)
    L = ["## Your surface", ""]
    if info:
        L.append(f"These runs take their surface from **`{info['path']}`** ({info['format']}, {info['points']}² points, "
                 f"{info['bytes']} bytes, SHA-256 `{info['sha256']}`; heights in units of L = 0.1 mm). They ran on "
                 f"{info['grid_points']}² (the file's grid, or the challenge's where the file is coarser and divides it: "
                 "cmc interpolates a coarser band-limited map and never down-samples).")
    else:
        L.append("These runs take their surface from a file (`[surface] kind = \"file\"`); no `surface.json` in "
                 f"`{results_dir}` records its checksum (`scripts/main.sh --surface FILE` writes one).")
    L += ["", "What each run's `summary.json` says it used:", "", _runs_table(used, info), ""]
    others = [r for r in runs if all(r is not u for u, _ in used)]
    if others:
        L += [f"**Also here, on other surfaces:** {', '.join(r.label for r in others)}.", ""]
    rms = [_rms(r) for r, _ in used if _rms(r)]
    ours = (f"cmc's own surface (self-affine, seed {seed}" if seed is not None else "cmc's own surface (self-affine")
    ours += f", rms height {rms28 * 1e6:.4g} µm)" if rms28 else ")"
    L.append(f"**Which surface each number is for.** The best estimates in the headline and the stored references "
             f"drawn in the figures (`reference/challenge/`, but the hatched realisation bands) are for {ours}, not "
             "for this one"
             + (f" (rms height {rms[0] * 1e6:.4g} µm, {100 * (rms[0] / rms28 - 1):+.2g} % of cmc's)" if rms and rms28 else "")
             + ". A difference between your runs and them holds the difference between the two surfaces, not only "
             "numerical error; `cmc check --against surface` is the question for a run on cmc's surface alone.")
    rows = _realisation_rows(reference_dir, user)
    if rows:
        rows = ["", "Your runs at 250 kPa beside it (their own grid error comes on top: the bands below):", ""] + rows
    L += ["", realisation_sentence(reference_dir)] + rows + [""]
    return L


def realisation_sentence(reference_dir: str) -> str:
    """Where the fair comparison for a surface of its own lives, and which of its files are stored."""
    root = os.path.join(reference_dir, "challenge", "realisation")
    files = sorted(os.path.relpath(os.path.join(d, f), root) for d, _, fs in os.walk(root) for f in fs if f.endswith(".csv"))
    stored = (f"stored: {', '.join(f'`{f}`' for f in files)}" if files else "none stored yet")
    return ("**The fair comparison for a surface of its own** is the realisation reference (`reference/challenge/"
            f"realisation/`, {stored}): its band holds 95 % of single surfaces of the challenge's spectrum, the "
            "organisers' included. `build/cmc check PRED.csv --quantity Q [--adhesionless] --against realisation` "
            "scores a curve against it (`docs/user-guide/checking-predictions.md`).")
