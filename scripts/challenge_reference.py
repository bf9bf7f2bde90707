#!/usr/bin/python3
"""Regenerate the challenge reference curves reference/challenge/<quantity>.csv (and
reference/challenge/README.md) from cmc's own challenge runs.

    /usr/bin/python3 scripts/challenge_reference.py [--results results] [--out reference/challenge] [--cmc build/cmc]
                                                    [--only tabor|reference-load]

Inputs (read only, SI, layout of solver/cmc/output/Writer.cpp):
  results/**/                         the runs at 250 kPa with summary.json + result.h5
                                      step_*/observables, of each problem (adhesion with mu_T = 3,
                                      also the scaled family's member s = 1, which is the
                                      challenge; the hard wall) -> items 1, 3, 4, 5, 9 from the
                                      finest run that has a coarser grid of the same case and
                                      strategy, their bands twice the change from that grid
  results/challenge-load-sweep/       adhesive load sweep, if present -> items 2, 8
  results/challenge-tabor-sweep/*/    adhesive Tabor sweep, if present -> items 6, 7
  results/challenge-tabor-sweep-n*/*/ the same sweep on finer grids (scripts/tabor_sweep.sh --grid N), if
                                      present: the bands of items 6, 7 where they resolve rho
  results/refine/reference-load-hardwall/refinement.json
                                      hard-wall refinement study (`cmc refine`), quoted in
                                      estimated_error for context only (the adhesive curves have
                                      no study yet)

The curves are the same numbers as reports/challenge/data/*.csv: the extraction
(run discovery, the step at the reference load, the observables subgroup, bin centres)
is imported from reports/challenge_report.py. Bins with zero density are left out of
log-scaled curves (the checker would drop them anyway). This script computes no number
of its own: grid spacings relative to rho and lambda_s come from summary.json
surface_facts, the refinement changes from cmc refine, and cmc formats and writes each
file (`build/cmc reference --run-curve SPEC --out FILE`, validation/References.cpp
make_run_curve and write_curve), so tests/test_references.cpp re-formats them to
themselves. Output is a function of the inputs only: the `date` is the run's
summary.json modification time (UTC). Each file is written atomically. Nothing is
deleted: a quantity without data keeps no file only if none was there before (remove
stale files by hand).
"""
import argparse
import datetime
import glob
import json
import os
import sys

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
from challenge_report import (Run, _centers, _find_runs, _merged_sweeps, _observables,  # noqa: E402
                              _reference_load_runs, _stopped, band_floor, finer_sweep, grid_change, hardwall_sweep_band,
                              sweep_band)  # (the report's extraction)
from cmc import reference_files  # noqa: E402
from cmc.analysis import bands  # noqa: E402
from cmc.analysis.conditions import condition_checks, load_bands, run_band, run_strategy_error  # noqa: E402
from cmc.analysis.family import FAMILY_STORE  # noqa: E402
from cmc.analysis.refinement import REFINEMENT_BISTABILITY, own_refinement_words  # noqa: E402
from cmc.analysis.runs import dx_over_rho, strategy_of, tabor_of  # noqa: E402
from common import (CHALLENGE, STRATEGY_WORDS, case_name, condition_summary, get, load_json,  # noqa: E402
                    read_reference_csv, roundoff_note, transfer_caveat)

RHO, LAMBDA_S, P0 = CHALLENGE["rho"], CHALLENGE["lambda_s"], CHALLENGE["p0"]
GENERATOR = "scripts/challenge_reference.py (extraction: reports/challenge_report.py)"


# ------------------------------------------------------------------ the format: cmc writes it
def write_curve(cmc, c, path):
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


def provenance(run, steps):
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
            ("date", _mtime_utc(os.path.join(run.folder, "summary.json"))),
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


def hardwall_refinement(folder):
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


def hw_context(hw, keys):
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


def adhesive_error(run, hw, keys, coarser=None):
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
def strategy_band(run, short, elsewhere="that it holds at this point's load and mu_T is assumed, not measured."):
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


def add_abs_band(curve, band):
    """Appends the error band to a curve: column <y>_err = the half-widths `band` (y's unit), '# band:'."""
    y = curve["columns"][1]
    curve["columns"].append((y[0] + "_err", y[1], "half-width of the error band: " + y[2], list(band)))
    curve["band"] = y[0] + "_err"
    curve["title"] = curve["title"].replace(" (not converged)", " (with error band)")
    return curve


def add_band(curve, rels):
    """Appends a relative error band: half-width rel x |y| per point (bands.absolute_band)."""
    return add_abs_band(curve, bands.absolute_band(rels, curve["columns"][1][3]))


def with_band(curve, run, short):
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
    if not words:
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


def reference_load_curves(run, hw, notes, coarser=None):
    """Items 1, 3, 4, 5, 9 from the finest run at the reference load; `coarser` = (run, step) of
    the same case on the next coarser grid gives them their bands."""
    obs, st = _observables(run, notes)
    if not obs:
        return [], st
    fobs = _observables(coarser[0], notes)[0] if coarser else {}
    nc = coarser[0].nx if coarser else None
    # The summary and result.h5 must belong to the same run (a run may be being rewritten).
    with h5py.File(run.h5path, "r") as f:
        g = f.get(f"step_{int(st['index']):04d}")
        p_h5 = float(g.attrs.get("mean_pressure", float("nan"))) if g is not None else float("nan")
    if not (abs(p_h5 - st["p"]) <= 1e-9 * abs(st["p"])):
        raise SystemExit(f"challenge_reference: {run.h5path} (p = {p_h5}) and its summary.json (p = {st['p']}) "
                         "differ: the run is being rewritten; retry when it has finished")
    prov = provenance(run, [st])
    label = (f"at p = {st['p'] / 1e3:.5g} kPa (target {P0 / 1e3:g} kPa), step {int(st['index'])}, "
             f"branch {st['branch'] or '?'}, contact fraction {st['ar']:.4g}")
    params = (f"challenge defaults (E* = {run.Estar / 1e6:g} MPa, L = {run.size * 1e3:g} mm, H = 0.8, "
              f"lambda_r = 20 um, lambda_s = 0.1 um, gamma0 = 50 mJ/m^2, rho = {RHO * 1e9:.4g} nm, "
              f"mu_T = {run.run_tabor:.4g}) {label}" if run.adhesive and run.run_tabor else
              f"challenge surface without adhesion (hard wall; E* = {run.Estar / 1e6:g} MPa, L = "
              f"{run.size * 1e3:g} mm, H = 0.8, lambda_r = 20 um, lambda_s = 0.1 um) {label}")
    conv = " (not converged)" if run.adhesive else ""
    base = (lambda keys: adhesive_error(run, hw, keys, nc if fobs else None)) if run.adhesive else (lambda keys: "")
    curves = []

    def hist(q, item, title, ek, dk, log_x, log_y, xcol, ycol, rep, keys, what):
        if ek not in obs or dk not in obs or len(obs[ek]) != len(obs[dk]) + 1:
            return
        x, y, dropped = _clean(_centers(obs[ek], log_x), obs[dk], log_x, log_y)
        samp = (f"{len(obs[dk])} bins from result.h5 step_{int(st['index']):04d}/observables/{ek}, {dk}: "
                f"{'geometric' if log_x else 'arithmetic'} bin centres; {what}")
        if dropped:
            samp += f"; {dropped} empty bin(s) left out (zero density on a log axis)"
        c = dict(name=q, quantity=q, item=item, title=title + f", cmc {run.nx}^2{conv}",
                 columns=[xcol + (x,), ycol + (y,)], x=xcol[0], y=ycol[0], representation=rep,
                 extra=prov + [("parameters", params), ("sampling", samp), ("generator", GENERATOR)],
                 estimated_error=base(keys) or "no band: no run of this case on a coarser grid")
        if ek in fobs and dk in fobs and len(fobs[ek]) == len(fobs[dk]) + 1:
            _with_refinement_band(c, x, y, _centers(fobs[ek], log_x), fobs[dk], log_x, log_y, run.nx, nc, base(keys))
        curves.append(c)

    hist("patch_size_distribution", 1, "Challenge item 1: contact patch size distribution", "patch_area_edges",
         "patch_area_density", True, True, ("patch_area_m2", "m^2", "contact patch area, bin centre"),
         ("density_per_m2", "1/m^2", "probability density of the patch area, normalised over patches"), "log-log",
         ["n_patches", "mean_patch_area", "largest_patch_area"], "density normalised over patches")
    hist("gap_distribution", 3, "Challenge item 3: gap distribution", "gap_hist_edges", "gap_hist_density", True, True,
         ("gap_m", "m", "gap g, bin centre"), ("density_per_m", "1/m", "probability density of the gap, "
                                                                           "contact points excluded"),
         "log-log", ["mean_gap", "max_gap", "contact_fraction"], "contact points excluded")
    hist("stress_distribution", 4, "Challenge item 4: interfacial stress distribution", "stress_hist_edges",
         "stress_hist_density", False, True, ("stress_Pa", "Pa", "interfacial stress, compressive > 0, bin centre"),
         ("density_per_Pa", "1/Pa", "probability density of the stress, p = 0 excluded"), "lin-log",
         ["max_pressure", "contact_fraction_corrected"], "p = 0 excluded")

    q, C = obs.get("stress_spectrum_q"), obs.get("stress_spectrum_C")
    if q is not None and C is not None and len(q) == len(C) and len(q) > 1:
        x, y, dropped = _clean(q, C, True, True)
        samp = f"{len(q)} wavenumbers from result.h5 step_{int(st['index']):04d}/observables/stress_spectrum_q, _C"
        if dropped:
            samp += f"; {dropped} non-positive value(s) left out"
        keys = ["max_pressure", "contact_perimeter"]
        c = dict(name="stress_spectrum", quantity="stress_spectrum", item=5,
                 title=f"Challenge item 5: interfacial stress spectrum, cmc {run.nx}^2{conv}",
                 columns=[("q_per_m", "1/m", "wavenumber q", x),
                          ("C_Pa2m2", "Pa^2 m^2", "isotropic stress spectrum, integral d^2q C = variance", y)],
                 x="q_per_m", y="C_Pa2m2", representation="log-log",
                 extra=prov + [("parameters", params), ("sampling", samp), ("generator", GENERATOR)],
                 estimated_error=base(keys) or "no band: no run of this case on a coarser grid")
        qc, Cc = fobs.get("stress_spectrum_q"), fobs.get("stress_spectrum_C")
        if qc is not None and Cc is not None and len(qc) == len(Cc):
            _with_refinement_band(c, x, y, qc, Cc, True, True, run.nx, nc, base(keys))
        curves.append(c)

    ys = obs.get("cross_section_y")
    x0 = ((run.s.get("case") or {}).get("observables") or {}).get("cross_section_x")
    where = f"x = {x0 * 1e6:.4g} um" if isinstance(x0, (int, float)) else "the cross section"
    for q, key, col, keys in (("cross_section_gap", "cross_section_gap", ("gap_m", "m", "gap g along the line"),
                               ["mean_gap", "contact_fraction"]),
                              ("cross_section_pressure", "cross_section_pressure",
                               ("pressure_Pa", "Pa", "interfacial stress along the line, compressive > 0"),
                               ["max_pressure", "contact_fraction_corrected"])):
        v = obs.get(key)
        if ys is None or v is None or len(v) != len(ys):
            continue
        x, y, _ = _clean(ys, v, False, False)
        what = "gap" if q.endswith("gap") else "stress"
        c = dict(name=q, quantity=q, item=9, title=f"Challenge item 9: {what} along {where}, cmc {run.nx}^2{conv}",
                 columns=[("y_m", "m", f"position y along {where}") + (x,), col + (y,)],
                 x="y_m", y=col[0], representation="lin-lin",
                 extra=prov + [("parameters", params),
                               ("sampling", f"every grid point of the line ({len(x)}), from result.h5 "
                                            f"step_{int(st['index']):04d}/observables/cross_section_*"),
                               ("generator", GENERATOR)],
                 estimated_error=(base(keys) or "no band: no run of this case on a coarser grid"))
        b, floor = (finest_profile_band(run, key, x, y, fobs["cross_section_y"], fobs[key])
                    if "cross_section_y" in fobs and key in fobs else (None, None))
        if b is not None:
            add_abs_band(c, b)
            c["estimated_error"] = (
                f"band: per point y_i, twice |this profile ({run.nx}^2) - the same case's on the next coarser grid "
                f"({nc}^2, linear between its points, periodic)| at y_i, the two-grid first-order bound "
                "(python/cmc/analysis/bands.py finest_profile_band); at least "
                f"{floor:.3g} {col[1]} (the solver's tolerance times "
                + ("the rms height" if what == "gap" else "E* times the rms slope") + "; median "
                f"{float(np.median(b)):.3g}, largest {float(np.max(b)):.3g} {col[1]}, at a contact line, which moves by "
                "up to a grid spacing between the grids). " + base(keys)).strip()
        curves.append(c)
    return curves, st


def finest_profile_band(run, key, y, v, yc, vc):
    """(band, floor) of the finest run's cross-section profile v(y) (key cross_section_gap or
    _pressure) from the same case's profile (yc, vc) on the next coarser grid:
    bands.finest_profile_band over the periodic line (length L), at least bands.profile_floor from
    the run's solver tolerance, rms height, E* and rms slope. (None, None) without a band."""
    floor = bands.profile_floor(key, get(run.s, "case", "solver", "tolerance") or 0.0,
                                get(run.s, "surface_facts", "rms_height") or 0.0, run.Estar,
                                get(run.s, "case", "surface", "rms_gradient") or 1.0)
    b = bands.finest_profile_band(y, v, yc, vc, floor, period=run.size)
    return (None, None) if b is None else (b, floor)


# ------------------------------------------------------------------ which runs the distributions come from
# The scaled family's member s = 1 is the challenge itself (lambda_s = 0.1 um, w = 50 mJ/m^2):
# the headline's coarse-grained runs are this case. The report leaves the family's runs out.
CHALLENGE_MEMBER = "challenge-scaled-s1"


def member_runs(results):
    """The converged runs of case CHALLENGE_MEMBER under `results`, with mu_T the problem's
    (cmc.analysis.runs.tabor_of: the specified range, not a coarse-grained law's)."""
    out = []
    for f in sorted(glob.glob(os.path.join(results, "**", "summary.json"), recursive=True)):
        s = load_json(f)
        if isinstance(s, dict) and case_name(s) == CHALLENGE_MEMBER and s.get("status") == "converged":
            r = Run(s, os.path.dirname(f))
            r.run_tabor = tabor_of(s)
            out.append(r)
    return out


def distribution_pair(runs, adhesive):
    """The runs items 1, 3, 4, 5 and 9 come from: of every case and strategy at the reference load
    with result.h5 (the report's _reference_load_runs, one case at a time), the finest grid that
    has a coarser grid of the same case, and that coarser grid, as [(run, step) coarser, (run,
    step) finest]; on a tie the case with more grids, then the first by name. A case with one
    grid alone: [(run, step)] of the finest such; [] without any."""
    cases = sorted({(r.name, strategy_of(r.s)) for r in runs if os.path.isfile(r.h5path)})
    seqs = [_reference_load_runs([r for r in runs if (r.name, strategy_of(r.s)) == c and os.path.isfile(r.h5path)],
                                 adhesive) for c in cases]
    seqs = [q for q in seqs if q]
    if not seqs:
        return []
    best = max(seqs, key=lambda q: (len(q) >= 2, q[-1][0].nx, len(q)))
    return best[-2:]


def load_sweep_curves(runs, hw, adhesive, ref_pair):
    """Items 2 and 8 of one problem from its load sweep with the most converged loads, on the
    finest grid among those (several runs of the same case and grid joined, as the report joins
    them: reports/challenge_report.py _merged_sweeps). Adhesive: the strategy's band;
    adhesionless: the change to the same sweep on a finer grid where one ran (a refinement run
    of a few loads), else the grid change of the run at the reference load (ref_pair, coarsest
    first), applied at every load (hardwall_sweep_band)."""
    all_sweeps = _merged_sweeps(runs)
    merged = [m for m in all_sweeps if m[0].adhesive == adhesive]
    if not merged:
        return []
    r, pts, shared = max(merged, key=lambda m: (sum(1 for s in m[1] if s["converged"]), m[0].nx or 0))
    finer = finer_sweep(all_sweeps, r)
    pts = [s for s in pts if s["converged"]]
    ps = np.array([s["p"] for s in pts])
    if len(pts) < 2 or not np.all(np.diff(ps) > 0):
        return []
    used = list(dict.fromkeys(s["run"] for s in pts))
    provs = [provenance(u, [s for s in pts if s["run"] is u]) for u in used]
    prov = provs[0]
    if len(used) > 1:
        prov = [(k, v if k not in ("solver_tolerance", "command", "date") else
                 " ; ".join(dict(pv)[k] for pv in provs)) for k, v in prov]
    samp = (f"{len(pts)} converged load steps, sorted by mean pressure"
            + (f", joined from {len(used)} runs ({', '.join(_rel(u.folder) for u in used)}); where two share a load "
               "the step of the longer continuation is kept" if len(used) > 1 else "")
            + ("" if adhesive else "; the hard wall (no adhesion)"))
    title_tail = " (not converged)" if adhesive else ""
    curves = []
    for q, item, key, short, col, keys, rep in (
            ("contact_area_vs_pressure", 2, "ar", "a_r", ("contact_fraction", "1", "relative contact area a_r"),
             ["contact_fraction", "contact_fraction_corrected"], "log-log"),
            ("mean_gap_vs_pressure", 8, "gap", "mean_gap", ("mean_gap_m", "m", "mean gap"), ["mean_gap"], "log-lin")):
        vals = [s[key] for s in pts]
        if any(v is None for v in vals):
            continue
        c = dict(name=q, quantity=q, item=item,
                 title=f"Challenge item {item}: {q.replace('_', ' ')}" + ("" if adhesive else " without adhesion")
                       + f", cmc {r.nx}^2{title_tail}",
                 columns=[("pressure_Pa", "Pa", "mean pressure", ps), col + (vals,)], x="pressure_Pa", y=col[0],
                 representation=rep, extra=prov + [("sampling", samp), ("generator", GENERATOR)],
                 estimated_error=adhesive_error(r, hw, keys) if adhesive else "no band: no refinement of the run at 250 kPa")
        if adhesive:
            c = with_band(c, r, short)
        else:
            band, how = hardwall_sweep_band(ref_pair, r, pts, key, finer)
            if band:
                add_abs_band(c, band)  # absolute: exact where the value is 0
                src = (f"{_rel(r.folder)}, {_rel(finer[0].folder)}" if finer and how.startswith("the change from")
                       else _grid_change_of(ref_pair, key)[1])
                c["estimated_error"] = f"band per point: {how} ({src}). " + roundoff_note(rel=_rel)
        curves.append(c)
    return curves


def _grid_change_of(pair, key):
    """(relative change, 'N^2 to M^2 (folders)') of a step quantity between the two coarsest grids."""
    got = grid_change(pair, key)
    return got and (got[0], f"{got[1].nx}^2 to {got[2].nx}^2 ({_rel(got[1].folder)}, {_rel(got[2].folder)})")


def tabor_curves(runs, hw):
    """Items 6 and 7 (adhesive Tabor sweep), when run."""
    curves = []
    # Tabor sweep: one run per mu_T (at the reference load) on the grid with the most mu_T (at least
    # 2), the coarser where two have as many: the sweep on a finer grid (scripts/tabor_sweep.sh
    # --grid N) measures that curve's error (sweep_band), as the reference load's 4096² run does.
    by_grid = {}
    for r in runs:
        st = r.reference_step()
        # A run that stopped before its tolerance is no reference point (the report lists it as such).
        if r.run_tabor is not None and st is not None and not r.is_load_sweep() and not _stopped(r, st):
            by_grid.setdefault((r.nx, r.ny), {})[round(r.run_tabor, 9)] = (r, st)
    grids = [g for g in sorted(by_grid, key=lambda g: (-len(by_grid[g]), g[0] * g[1])) if len(by_grid[g]) >= 2]
    if grids:
        items = [by_grid[grids[0]][k] for k in sorted(by_grid[grids[0]])]
        r0 = items[-1][0]
        prov = provenance(r0, [items[-1][1]])
        prov[1] = ("case_file", ", ".join(sorted({r.s.get("case_file") or "?" for r, _ in items})))
        prov[5] = ("command", "scripts/tabor_sweep.sh (one run per mu_T: " +
                   ", ".join(_rel(r.folder) for r, _ in items) + ")")
        mus = [r.run_tabor for r, _ in items]
        for q, item, col, keys in (("contact_area_vs_tabor", 6, ("contact_fraction", "1", "relative contact area a_r",
                                                                  [st["ar"] for _, st in items]),
                                    ["contact_fraction", "contact_fraction_corrected"]),
                                   ("mean_gap_vs_tabor", 7, ("mean_gap_m", "m", "mean gap",
                                                             [st["gap"] for _, st in items]), ["mean_gap"])):
            if any(v is None for v in col[3]):
                continue
            c = dict(name=q, quantity=q, item=item,
                     title=f"Challenge item {item}: {q.replace('_', ' ')} at 250 kPa, cmc {r0.nx}^2 (not converged)",
                     columns=[("tabor", "1", "Tabor coefficient mu_T", mus), col], x="tabor", y=col[0],
                     representation="log-lin",
                     extra=prov + [("sampling", f"{len(items)} runs, the step nearest 250 kPa of each"),
                                   ("generator", GENERATOR)],
                     estimated_error=adhesive_error(r0, hw, keys))
            # A band where every run carries the strategy's measured error (each mu_T has its
            # own rho, hence its own dx/rho).
            short = "a_r" if item == 6 else "mean_gap"
            bands = [strategy_band(r, short) for r, _ in items]
            if all(rel is not None for rel, _ in bands):
                # Where the family was run at the point's own mu_T too (scripts/scaled_family.py
                # --tabor, reference/challenge-scaled/conditions/), the band is the larger of the
                # two measured errors: the one at mu_T = 3 alone does not hold at every mu_T.
                rels, per, measured, owns, own_mus = [], [], [], [], []
                for (r, _), m, (rel, _) in zip(items, mus, bands):
                    _, band, _, at, _ = run_band(r.s, short)  # max(rel, at)
                    b, own = sweep_band(r, short, runs)  # the challenge's own refinement where it applies
                    rels.append(b)
                    per.append(f"mu_T = {m:.3g}: +-{100 * rels[-1]:.3g} %"
                               + (f" (own refinement; the family's: {100 * band:.3g} %)" if own else
                                  "" if at is None else f" (at mu_T = {m:.3g}: {100 * at:.3g} %; "
                                                        f"at mu_T = 3: {100 * rel:.3g} %)"))
                    if own:
                        owns.append(f"mu_T = {m:.3g}: " + own_refinement_words(own, short, " m" if short == "mean_gap" else ""))
                        own_mus.append(m)
                    elif at is not None:
                        measured.append(f"{m:.3g}")
                add_band(c, rels)
                c["own_refinement"] = own_mus
                cond = os.path.join(os.path.dirname(_rel(FAMILY_STORE)), "conditions")
                c["estimated_error"] = (
                    f"band per point ({', '.join(per)}). "
                    + (f"Where the sweep was refined on the challenge itself and the finer pair of grids resolves "
                       f"the adhesion (bistability number w dx/(E* rho^2) <= {REFINEMENT_BISTABILITY:g} on its coarser grid, "
                       "as on the family's refinement grids; scripts/tabor_sweep.sh --grid N): the "
                       "challenge's own grid error, Richardson extrapolation of order 1 plus the spread of the other "
                       "estimates of the converged value (python/cmc/analysis/refinement.py own_band; " + "; ".join(owns)
                       + "). Elsewhere: " if owns else "")
                    + f"the strategy's error measured on the scaled challenge "
                    f"family ({_rel(FAMILY_STORE)}) at that point's dx/rho (deviation from the family's converged "
                    "reference plus that reference's refinement error), measured at mu_T = 3 and 250 kPa"
                    + (f", and where the family was also run at the point's own mu_T ({', '.join(measured)}; "
                       f"{cond}/mu_T*/, s = 32) the larger of the two. At the other mu_T it is assumed, not measured. "
                       if measured else "; that it holds at the other mu_T is assumed, not measured. ")
                    + roundoff_note(rel=_rel) + " " + transfer_caveat())
            elif any(text for _, text in bands):
                missing = [f"{m:.3g}" for m, (rel, _) in zip(mus, bands) if rel is None]
                c["estimated_error"] = ("no error band: the scaled family has no run of this strategy "
                                        f"near the dx/rho of mu_T = {', '.join(missing)} (scripts/scaled_family.py "
                                        "--coarse K adds one). " + c["estimated_error"])
            curves.append(c)
    return curves


# ------------------------------------------------------------------ README
ALL = [("patch_size_distribution", 1), ("contact_area_vs_pressure", 2), ("gap_distribution", 3),
       ("stress_distribution", 4), ("stress_spectrum", 5), ("contact_area_vs_tabor", 6), ("mean_gap_vs_tabor", 7),
       ("mean_gap_vs_pressure", 8), ("cross_section_gap", 9), ("cross_section_pressure", 9)]
MISSING_HOW = {2: "`build/cmc run cases/challenge/load-sweep.toml --out results/challenge-load-sweep`",
               8: "`build/cmc run cases/challenge/load-sweep.toml --out results/challenge-load-sweep`",
               6: "`scripts/tabor_sweep.sh` (results/challenge-tabor-sweep/mu_T_*/)",
               7: "`scripts/tabor_sweep.sh` (results/challenge-tabor-sweep/mu_T_*/)"}


def files_table(curves):
    """The README's table of stored files, one row per curve in the challenge's item order."""
    have = {c["quantity"]: c for c in curves}
    L = ["| file | item | columns (SI) | repr. | points | band | run | grid |", "|---|---|---|---|---|---|---|---|"]
    for q, item in ALL:
        c = have.get(q)
        if c is None:
            continue
        grid = dict(c["extra"])["grid"].split(" (")[0]
        run = " ; ".join(cmd.split("--out ")[-1].split(" --set ")[0] for cmd in dict(c["extra"])["command"].split(" ; "))
        L.append(f"| `{q}.csv` | {item} | `{c['columns'][0][0]}`, `{c['columns'][1][0]}` | {c['representation']} | "
                 f"{len(c['columns'][0][3])} | {'yes' if c.get('band') else 'no'} | `{run}` | {grid} |")
    return L + [""]


def _sweep_band_words(curves, pair):
    """The adhesionless README's sentence on the load sweep's bands."""
    sweep = {c["quantity"]: c for c in curves}.get("contact_area_vs_pressure")
    if sweep is None:
        return ""
    if "best estimates" in sweep.get("title", ""):
        return ("The load sweep's rows are best estimates (`../best_estimates.json`), each with the error of its own "
                "refinement sequence (the file's `estimated_error` and column `grid_n`).")
    if sweep.get("estimated_error", "").startswith("band per point: the change from"):
        how = ("the change to the same sweep on a grid twice as fine, measured at the loads both ran and interpolated "
               "in log p between them (each file's `estimated_error` says which loads and runs)")
    elif len(pair) >= 2:
        (r0, a), (r1, b) = pair[0], pair[1]
        how = (f"(only run on {r0.nx}²) the change at 250 kPa between {r0.nx}² and {r1.nx}² (contact fraction "
               f"{a['ar']:.5g} → {b['ar']:.5g}, mean gap {a['gap'] * 1e6:.6g} → {b['gap'] * 1e6:.6g} µm), for a_r "
               "scaled by each load's contact perimeter (the counted area's grid error is a boundary effect; at least "
               "one grid point), for the mean gap the same relative change at every load (assumed; at least the "
               "solver's tolerance times the rms height)")
    else:
        return ""
    return (f"The load sweep's band is {how}: a change under one refinement, a lower estimate of the grid error; the "
            "counted contact area converges as dx, its perimeter-corrected value much faster.")


def readme_adhesionless(curves, pair, dist=()):
    """The README of reference/challenge/adhesionless/. pair: the hard-wall runs at 250 kPa, coarsest
    first (the load sweep's modelled band); dist: [(run, step) coarser, finest] behind items 1, 3, 4,
    5 and 9 (distribution_pair)."""
    L = ["# Challenge reference curves without adhesion", "",
         "The challenge's surface pressed on the half-space with the hard wall alone (no adhesion): the adhesionless "
         "counterpart that the problem definition compares with (with adhesion, about half as much contact area "
         "again at a few per cent contact). `cmc check PRED.csv --quantity Q --adhesionless` scores against these files. Same "
         "format and provenance as [../README.md](../README.md); generated by the same command "
         "(`/usr/bin/python3 scripts/challenge_reference.py`). Items 6 and 7 (against the Tabor parameter) have no "
         "adhesionless counterpart.", "", "## Files", ""] + files_table(curves)
    sweep_words = _sweep_band_words(curves, pair)
    if len(dist) >= 2 or sweep_words:
        L += ["## Accuracy", "", "The hard-wall problem converges under refinement (no adhesion range to resolve)."
              + (f" Items 1, 3, 4, 5 and 9 come from {dist[1][0].nx}² (`{_rel(dist[1][0].folder)}`); their bands are "
                 f"twice the change of each curve from {dist[0][0].nx}² (`{_rel(dist[0][0].folder)}`) to "
                 f"{dist[1][0].nx}²: per point for the distributions and the spectrum (the coarser curve interpolated "
                 "in the representation), at the same y for the cross sections (there at least the solver's tolerance "
                 "in the problem's scale). That is the two-grid first-order bound (`python/cmc/analysis/bands.py`, "
                 "`refinement.py` `sequence_error`): it covers a power-law convergence of any order down to "
                 "log2(1.5) = 0.58, and the counted contact area and the patch statistics converge as dx." if len(dist) >= 2 else "")
              + (" " + sweep_words if sweep_words else ""), ""]
    commands = run_commands(dist[-1][0], dist[-1][1], dist[0] if len(dist) >= 2 else None) if dist else []
    L += ["## Regenerate", "", "```"] + (commands or [
          "build/cmc run cases/challenge/reference-load-hardwall.toml --out results/challenge-hardwall",
          "build/cmc run cases/challenge/reference-load-hardwall.toml --set grid.n=4096 --out results/challenge-hardwall-n4096"]) + [
          "build/cmc run cases/challenge/load-sweep-hardwall.toml --out results/challenge-load-sweep-hardwall",
          "build/cmc run cases/challenge/load-sweep-hardwall.toml --set grid.n=4096 "
          "--set 'loading.values=[12.5e3,250e3,2.5e6,10e6,25e6]' --out results/challenge-load-sweep-hardwall-n4096",
          "/usr/bin/python3 scripts/challenge_reference.py", "```", ""]
    sweep = {c["quantity"]: c for c in curves}.get("contact_area_vs_pressure")
    joined = sweep is not None and " ; " in dict(sweep["extra"]).get("command", "")
    L += ["(all in `scripts/sweeps.sh`" + ("; the stored sweep joins several runs of the same case and grid: each "
                                          "file's `command` line names them" if joined else "") + ").", ""]
    return "\n".join(L)


def _stored_block(path, first, last=None):
    """The paragraphs of a stored README from the one starting with `first` through the one
    starting with `last` (or the first alone), as lines; [] where it has none."""
    try:
        with open(path, encoding="utf-8") as f:
            paras = f.read().split("\n\n")
    except OSError:
        return []
    i = next((k for k, p in enumerate(paras) if p.startswith(first)), None)
    if i is None:
        return []
    j = i if last is None else next((k for k in range(i, len(paras)) if paras[k].startswith(last)), i)
    return "\n\n".join(paras[i:j + 1]).split("\n") + [""]


def _own_refinement_sentence(banded):
    """The README's words on the Tabor sweep's points whose band is the challenge's own refinement
    (tabor_curves' "own_refinement": their mu_T), one sentence per set of mu_T."""
    by = {}
    for c in banded:
        if c.get("own_refinement"):
            by.setdefault(tuple(c["own_refinement"]), []).append(f"`{c['quantity']}.csv`")
    return "".join(
        f"At μ_T = {', '.join(f'{m:.3g}' for m in mus)} the band{'s' if len(files) > 1 else ''} of "
        f"{' and '.join(files)} {'are' if len(files) > 1 else 'is'} instead the challenge's own grid error, measured "
        "by refining the sweep itself (`scripts/tabor_sweep.sh --grid N`) where the finer pair of grids resolves the "
        f"adhesion (bistability number w dx/(E\\* ρ²) ≤ {REFINEMENT_BISTABILITY:g} on its coarser grid, as on the "
        "family's refinement grids): Richardson extrapolation of order 1 plus the spread of "
        "the other estimates of the converged value (`python/cmc/analysis/refinement.py` `own_band`); it needs no transfer "
        "from the family. " for mus, files in by.items())


def run_commands(run, step, coarser):
    """The lines of the README's regenerate block that rerun the runs behind items 1, 3, 4, 5, 9
    (their provenance's command), [] without them."""
    if run is None or step is None:
        return []
    out = ["build/" + dict(provenance(run, [step]))["command"] + "   # items 1, 3, 4, 5, 9"]
    if coarser:
        out.append("build/" + dict(provenance(coarser[0], [coarser[1]]))["command"] + "   # their bands")
    return out


def accuracy_head(ref_run):
    """The first paragraph of the README's accuracy section: the grids, against rho."""
    if ref_run is None:
        return ("The adhesive runs use the challenge's grid 2048² (dx = 48.8 nm = λ_s/2.05 ≈ 24 ρ, ρ = 2.071 nm), far "
                "coarser than the ≈ 0.75 ρ of the published solution (65536²). The adhesive neck is not resolved and "
                "every grid point is bistable, so these curves are **not converged**.")
    return (f"Items 1, 3, 4, 5 and 9 come from {ref_run.nx}² (dx = {ref_run.dx * 1e9:.3g} nm = {_over_rho(ref_run):.3g} ρ, "
            f"ρ = {RHO * 1e9:.4g} nm; {STRATEGY_WORDS[strategy_of(ref_run.s)]}), far coarser than the ≈ 0.75 ρ of the "
            "published solution (65536²): the adhesive neck is not resolved"
            + _bistable(ref_run).replace(" and every", ", every").replace("rho^2", "ρ²")
            + ", so these curves are **not converged** in ρ. The other files name their grids (the table above).")


def distribution_paragraphs(curves):
    """The README's paragraphs on the bands of items 1, 3, 4, 5 and 9."""
    L = []
    if any(c.get("band") for c in curves if c["item"] in (1, 3, 4, 5)):
        L += ["**Distributions and spectrum** (items 1, 3, 4, 5): the band is, per point, twice the change of the "
              "curve from the same case on the next coarser grid to this one (the coarser curve interpolated in the "
              "representation; points outside its range are left out): the two-grid first-order bound "
              "(`python/cmc/analysis/bands.py` `finest_grid_band`, `refinement.py` `sequence_error`), which covers "
              "a power-law convergence of any order down to log2(1.5) = 0.58. It bounds the grid error of the numerics at "
              "this dx/ρ only: both grids leave ρ unresolved, which the family measures for a_r and the mean gap "
              "only. Each file's `estimated_error` gives the median relative half-width.", ""]
    else:
        L += ["The distributions (items 1, 3, 4, 5) have **no error estimate**: no run of the reference-load case "
              "on a coarser grid with observables.", ""]
    if any(c.get("band") for c in curves if c["item"] == 9):
        L += ["**Cross sections** (item 9): the band is, per point, twice the change of the profile from the same "
              "case on the next coarser grid (linear between its points, periodic) to this one, at the same y "
              "(`bands.py` `finest_profile_band`); at least the solver's tolerance in the problem's scale (times the "
              "rms height for the gap, times E* times the rms slope for the stress), which is the band wherever both "
              "grids agree exactly. It is large at contact lines, which move by up to a grid spacing between the "
              "grids, so a prediction from another grid may fail there by many band widths; its median says more "
              "(`cmc check` prints both).", ""]
    else:
        L += ["The **cross sections** (item 9) have no error estimate: no run of the reference-load case on a "
              "coarser grid.", ""]
    return L


def readme(curves, out_dir, hw, ref_run, ref_step, keep_from=None, keep_bands=False, coarser=None):
    """The README of reference/challenge/. keep_from (--only): a stored README whose paragraphs
    on the reference-load run and the hard-wall refinement are kept where their runs are not at
    hand, and with keep_bands (--only reference-load) those on the bands of the curves not
    recomputed. coarser: (run, step) of the grid that gives ref_run's curves their bands."""
    have = {c["quantity"]: c for c in curves}
    L = ["# Challenge reference curves", "",
         "`cmc check PRED.csv --quantity Q` compares a prediction with `reference/challenge/Q.csv` by default. "
         "These curves come from **cmc's own runs** (`source: cmc run`), not from the published solution of the "
         "Contact Mechanics Challenge, and are **not converged**: see *Accuracy* below. The format is described in "
         "[../README.md](../README.md); the provenance (cmc version, case file, grid, solver tolerance, date, "
         "command) is in each file's header.", "",
         "Generated by `/usr/bin/python3 scripts/challenge_reference.py` (deterministic given the runs; the "
         "`date` is the run's summary.json modification time). Do not edit the CSV files by hand.", "",
         "## Files", ""] + files_table(curves) + [
         "Without adhesion (the same surface under the hard wall alone): [adhesionless/](adhesionless/README.md), "
         "`cmc check --adhesionless`.", ""]
    if ref_run is not None and ref_step is not None:
        L += [f"Items 1, 3, 4, 5 and 9 are the step at p = {ref_step['p']:.6g} Pa (target 250 kPa) of "
              f"`{_rel(ref_run.folder)}` (case `{ref_run.s.get('case_file')}`, {ref_run.name}: the challenge's "
              f"problem, exponential adhesion with μ_T = {ref_run.run_tabor:.4g}); contact fraction "
              f"{ref_step['ar']:.4g} (perimeter-corrected {ref_step['ar_corr'] or float('nan'):.4g}), mean gap "
              f"{(ref_step['gap'] or float('nan')) * 1e9:.4g} nm, {int(ref_step['n_patches'] or 0)} patches"
              + (f"; their bands from the same case on {coarser[0].nx}² (`{_rel(coarser[0].folder)}`)" if coarser else "")
              + ". The extraction is the challenge report's (`reports/challenge_report.py`), except that empty bins "
              "are left out of log-scaled curves.", ""]
    elif keep_from:
        L += _stored_block(keep_from, "Items 1, 3, 4, 5 and 9 are the step")
    miss = [(q, item) for q, item in ALL if q not in have]
    if miss:
        L += ["## Not yet computed", "", "No file, because no adhesive run has the data yet:", ""]
        for q, item in miss:
            how = MISSING_HOW.get(item, "a run at the reference load with observables and fields "
                                        "(`cases/challenge/reference-load.toml`)")
            L.append(f"- `{q}` (item {item}): not yet computed, run {how}, then regenerate.")
        L.append("")
    banded = [have[q] for q, _ in ALL if q in have and have[q].get("band")]  # the files table's order
    L += ["## Accuracy", "", accuracy_head(ref_run), ""]
    if banded and keep_bands and keep_from:
        L += _stored_block(keep_from, "**Error bands.**", "**Caveat.**")
    elif banded:
        checks = condition_checks()
        L += ["**Error bands.** " + ", ".join(f"`{c['quantity']}.csv`" for c in banded) + " carry the reference's "
              "own uncertainty as a column (`# band: <y>_err`, the half-width in y's unit), and `cmc check` scores a "
              "prediction against it (inside the band passes; outside, it says by how much in units of the band). "
              "The band is the error that the run's strategy (the plain interaction, or the range coarse-graining) "
              "has on the scaled challenge family (`reference/challenge-scaled/`: converged at s = 32, "
              "dx = 0.8 ρ(s)) at the same dx/ρ: its deviation from the family's converged value plus that value's "
              "refinement error. It was measured at μ_T = 3 and 250 kPa. Where the family was also run at a sweep's "
              "other points (`reference/challenge-scaled/conditions/`, `scripts/scaled_family.py --tabor` and "
              "`--pressure`) the band is the larger of the two measured errors: per μ_T for the Tabor sweep, per "
              "load for the load sweep (interpolated in log p between the measured loads and held beyond them); "
              "at the points not measured the band is **assumed** (each file's `estimated_error` says which). "
              + _own_refinement_sentence(banded)
              + (condition_summary(checks) + " (`reference/challenge-scaled/README.md`, \"The bands at "
                 "other conditions\".) " if checks else "")
              + roundoff_note(rel=_rel), "",
              "**Caveat.** " + (transfer_caveat() or "No transfer check possible (the store lacks the runs)."), ""]
    L += distribution_paragraphs(curves)
    if hw:
        n1, n2 = hw["grids"]
        L += [f"For context only, the **hard-wall** problem at the same load (`{hw['folder']}`"
              + (", `refinement.md`" if hw["table"] else "") + f") changes between {n1}² and {n2}² by:", "",
              f"| observable | {n1}² | {n2}² | relative change |", "|---|---|---|---|"]
        for k, (a, b, d) in hw["changes"].items():
            L.append(f"| {HW_LABELS[k]} | {a:.6g} | {b:.6g} | {100 * d:.2g} % |")
        L += ["", f"(SI units; relative change = |value at {n2}² − value at {n1}²| / |value at {n2}²|, from "
              "`cmc refine`'s refinement.json. The raw contact "
              "fraction converges slowly, the perimeter-corrected one much faster.) The hard-wall curves are in "
              "[adhesionless/](adhesionless/README.md).", ""]
    elif keep_from:
        L += _stored_block(keep_from, "For context only, the **hard-wall**", "(SI units;")
    L += ["## Regenerate", "",
          "One command runs everything behind these files (and `adhesionless/`), resumable, then rewrites them: "
          "`scripts/sweeps.sh` (hours on 2 cores; the commands it runs, with their `--set` options, are also in "
          "each file's `command` line). Its parts:", "",
          "```"] + (run_commands(ref_run, ref_step, coarser) or [
          "build/cmc run cases/challenge/reference-load.toml --out results/challenge-reference   # items 1, 3, 4, 5, 9",
          "build/cmc run cases/challenge/reference-load.toml --set grid.n=4096 --out results/challenge-reference-n4096"
          "   # their bands"]) + [
          "build/cmc run cases/challenge/load-sweep.toml --out results/challenge-load-sweep     # items 2, 8",
          "scripts/tabor_sweep.sh                                                                 # items 6, 7",
          "/usr/bin/python3 scripts/roundoff_spread.py NAME:RUN_A:RUN_B ...  # round-off spread: one case by two "
          "builds or thread counts (roundoff_spread.json, its command line)",
          "/usr/bin/python3 scripts/scaled_family.py --s 32 --coarse 2 4 6 8 12 24 --store reference/challenge-scaled"
          "   # the strategy bands",
          "/usr/bin/python3 scripts/challenge_reference.py        # rewrites reference/challenge/*.csv and this README",
          "build/cmc check reports/challenge/data/gap_distribution__challenge-reference_2048.csv --quantity gap_distribution",
          "```", "",
          "A finer grid of the same case (`--set grid.n=N`, twice the finest) becomes the source of items 1, 3, 4, 5 "
          "and 9 once its run is in `results/`, with its band from the grid before it; "
          "`scripts/challenge_reference.py --only reference-load` rewrites those alone.", ""]
    return "\n".join(L)


def stored_curve(path, quantity, item):
    """A stored reference CSV read back as the curve that wrote it (the fields the README uses),
    or None: what --only tabor keeps of the curves it does not recompute."""
    got = read_reference_csv(path)
    if got is None:
        return None
    meta, names, data = got
    cols = [(n, meta.get(f"unit.{n}", "").split(" (")[0], "", list(data[:, i])) for i, n in enumerate(names)]
    prov = [(k, meta[k]) for k in ("cmc_version", "case_file", "grid", "solver_tolerance", "date", "command") if k in meta]
    return dict(name=meta.get("name", quantity), quantity=quantity, item=item, title=meta.get("title", ""),
                columns=cols, representation=meta.get("representation", ""), band=meta.get("band"),
                extra=prov, estimated_error=meta.get("estimated_error", ""))


def write_curves(cmc, curves, out):
    for c in curves:
        path = os.path.join(out, c["quantity"] + ".csv")
        text = write_curve(cmc, c, path)
        print(f"challenge_reference: {_rel(path)}: {len(c['columns'][0][3])} points, {len(text)} bytes")


def kept_curves(out, curves):
    """The stored curves of `out` other than `curves`' quantities, read back (stored_curve)."""
    new = {c["quantity"] for c in curves}
    kept = [stored_curve(os.path.join(out, q + ".csv"), q, item) for q, item in ALL if q not in new]
    return [c for c in kept if c is not None]


def only_tabor(a, runs, hw):
    """--only tabor: items 6 and 7 from the Tabor sweep's runs, the other stored curves kept."""
    curves = tabor_curves([r for r in runs if r.name.startswith("challenge-tabor")], hw)
    if len(curves) != 2:
        sys.exit("challenge_reference: --only tabor: no Tabor sweep with its runs under "
                 f"{_rel(a.results)}/challenge-tabor-sweep/ (scripts/tabor_sweep.sh makes them)")
    write_curves(a.cmc, curves, a.out)
    kept = kept_curves(a.out, curves)
    if next((c for c in kept if c["item"] == 9), None) is None:
        sys.exit("challenge_reference: --only tabor: the stored reference-load curves are missing; "
                 "regenerate everything (without --only)")
    # The README's reference-load paragraph and hard-wall table come from their runs; without
    # them, the stored README's paragraphs are kept as they are and only the parts that depend
    # on the curves are rewritten.
    write_atomically(os.path.join(a.out, "README.md"),
                     readme(kept + curves, a.out, hw, None, None, keep_from=os.path.join(a.out, "README.md")))
    print(f"challenge_reference: {_rel(os.path.join(a.out, 'README.md'))} (the other curves kept)")


def regenerate(a, runs, members, hw, notes):
    """Every curve of both problems from the runs (with --only reference-load items 1, 3, 4, 5 and
    9 alone, the other stored curves kept and read back for the READMEs) and the READMEs."""
    only = a.only == "reference-load"
    written = {}
    for adhesive in (True, False):
        out = a.out if adhesive else os.path.join(a.out, "adhesionless")
        pair = _reference_load_runs(runs, adhesive)
        dist = distribution_pair(runs + members, adhesive)
        curves, ref_step = [], None
        if dist:
            curves, ref_step = reference_load_curves(dist[-1][0], hw, notes, dist[0] if len(dist) > 1 else None)
        if not only:
            curves += load_sweep_curves(runs, hw, adhesive, pair)
            curves += tabor_curves([r for r in runs if r.name.startswith("challenge-tabor")], hw) if adhesive else []
        written[adhesive] = curves
        if only and not curves:
            continue
        write_curves(a.cmc, curves, out)
        path = os.path.join(out, "README.md")
        shown = kept_curves(out, curves) + curves if only else curves
        coarser = dist[0] if len(dist) > 1 else None
        write_atomically(path, readme(shown, out, hw, dist[-1][0] if dist else None, ref_step,
                                      keep_from=path if only else None, keep_bands=only, coarser=coarser)
                         if adhesive else readme_adhesionless(shown, pair, dist))
        print(f"challenge_reference: {_rel(path)}" + (" (the other curves kept)" if only else ""))
    for n in notes:
        print("challenge_reference: note: " + str(n), file=sys.stderr)
    if only and not (written[True] or written[False]):
        sys.exit(f"challenge_reference: --only reference-load: no run at 250 kPa with observables under {_rel(a.results)}")
    if not only and not written[True]:
        sys.exit("challenge_reference: no curves: no adhesive challenge run with observables found")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", choices=["tabor", "reference-load"], default=None,
                    help="tabor: recompute items 6 and 7 (the Tabor sweep: its runs and the family's stores) only; "
                         "reference-load: items 1, 3, 4, 5 and 9 (the runs at 250 kPa with observables) of both "
                         "problems only. The other stored curves are kept as they are and read back for the README, "
                         "so that their runs need not be at hand (e.g. after the family was run at another mu_T)")
    ap.add_argument("--results", default=os.path.join(ROOT, "results"))
    ap.add_argument("--hardwall-refine", default=None, help="default: RESULTS/refine/reference-load-hardwall")
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--cmc", default=os.path.join(ROOT, "build", "cmc"), help="the cmc that formats the curves")
    a = ap.parse_args()
    hw = hardwall_refinement(a.hardwall_refine or os.path.join(a.results, "refine", "reference-load-hardwall"))
    notes = []
    # The report's discovery: every results/**/summary.json of a challenge case (not the scaled family).
    runs = []
    for r in _find_runs(a.results, notes):
        # A load sweep whose last steps did not converge still gives its converged steps (the
        # sweep curves keep only those and say how many); a single run must converge.
        if r.status == "converged" or (r.status == "not_converged" and r.is_load_sweep()):
            runs.append(r)
    if a.only == "tabor":
        only_tabor(a, runs, hw)
    else:
        regenerate(a, runs, member_runs(a.results), hw, notes)
    apply_best(a.out, a.cmc)


def apply_best(out, cmc):
    """The best estimates (OUT/best_estimates.json, scripts/best_estimates.py) put into the curves
    they decide (scripts/apply_best_estimates.py), after the curves were written from the runs."""
    path = os.path.join(out, "best_estimates.json")
    if not os.path.exists(path):
        print(f"challenge_reference: no {_rel(path)}: the curves keep their runs' values "
              "(scripts/best_estimates.py makes it)", file=sys.stderr)
        return
    import apply_best_estimates  # noqa: E402 (imports this module)
    with open(path) as f:
        for p in apply_best_estimates.apply(json.load(f), out, cmc):
            print(f"challenge_reference: {_rel(p)} (best estimates)")


if __name__ == "__main__":
    main()
