"""The challenge reference curves from cmc's runs: the distributions, spectrum and cross sections
at the reference load (items 1, 3, 4, 5, 9), the load sweep (items 2, 8) and the Tabor sweep
(items 6, 7), each with its provenance and band."""
from __future__ import annotations
import os

import numpy as np

from cmc.analysis import bands
from cmc.analysis.conditions import run_band
from cmc.analysis.family import FAMILY_STORE
from cmc.analysis.refinement import REFINEMENT_BISTABILITY, own_refinement_words
from cmc.analysis.runs import strategy_of, tabor_of
from cmc.report.challenge_runs import (Run, _centers, _merged_sweeps, _observables, _reference_load_runs, _stopped,
                                       finer_sweep, grid_change, hardwall_sweep_band, sweep_band)
from cmc.report.common import case_name, get, roundoff_note, transfer_caveat
from .provenance import (GENERATOR, P0, RHO, _clean, _rel, _with_refinement_band, add_abs_band, add_band,
                         adhesive_error, provenance, strategy_band, with_band)
from cmc import run_folder
from cmc._types import Json


CONTEXT = ("run", "st", "obs", "fobs", "nc", "prov", "params", "conv", "base")


def _same_run_in_h5(run, st):
    """Stops where the summary and result.h5 do not belong to the same run (a run may be being
    rewritten): the step's mean pressure must agree."""
    got = run_folder.step_attribute(run.folder, run.step(st), "mean_pressure")
    p_h5 = float("nan") if got is None else got
    if not (abs(p_h5 - st["p"]) <= 1e-9 * abs(st["p"])):
        raise SystemExit(f"challenge_reference: {run.h5path} (p = {p_h5}) and its summary.json (p = {st['p']}) "
                         "differ: the run is being rewritten; retry when it has finished")


def _reference_load_context(run, st, hw, obs, fobs, nc):
    """What every curve at the reference load shares (CONTEXT): the run, its step and observables,
    the coarser run's and its grid, the provenance, the parameters line, and base(keys), the
    adhesive error words."""
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
    return dict(run=run, st=st, obs=obs, fobs=fobs, nc=nc, prov=prov, params=params, conv=conv, base=base)


def _hist_curve(ctx, q, item, title, ek, dk, log_x, log_y, xcol, ycol, rep, keys, what):
    """A distribution (item 1, 3 or 4) from the histogram edges ek and densities dk, or None."""
    run, st, obs, fobs, nc, prov, params, conv, base = (ctx[k] for k in CONTEXT)
    if ek not in obs or dk not in obs or len(obs[ek]) != len(obs[dk]) + 1:
        return None
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
    return c


def _distribution_curves(ctx):
    """Items 1, 3 and 4: patch sizes, gaps and stresses."""
    curves = [
        _hist_curve(ctx, "patch_size_distribution", 1, "Challenge item 1: contact patch size distribution",
                    "patch_area_edges", "patch_area_density", True, True,
                    ("patch_area_m2", "m^2", "contact patch area, bin centre"),
                    ("density_per_m2", "1/m^2", "probability density of the patch area, normalised over patches"),
                    "log-log", ["n_patches", "mean_patch_area", "largest_patch_area"],
                    "density normalised over patches"),
        _hist_curve(ctx, "gap_distribution", 3, "Challenge item 3: gap distribution", "gap_hist_edges",
                    "gap_hist_density", True, True, ("gap_m", "m", "gap g, bin centre"),
                    ("density_per_m", "1/m", "probability density of the gap, contact points excluded"),
                    "log-log", ["mean_gap", "max_gap", "contact_fraction"], "contact points excluded"),
        _hist_curve(ctx, "stress_distribution", 4, "Challenge item 4: interfacial stress distribution",
                    "stress_hist_edges", "stress_hist_density", False, True,
                    ("stress_Pa", "Pa", "interfacial stress, compressive > 0, bin centre"),
                    ("density_per_Pa", "1/Pa", "probability density of the stress, p = 0 excluded"), "lin-log",
                    ["max_pressure", "contact_fraction_corrected"], "p = 0 excluded")]
    return [c for c in curves if c is not None]


def _spectrum_curve(ctx):
    """Item 5: the stress spectrum, or None."""
    run, st, obs, fobs, nc, prov, params, conv, base = (ctx[k] for k in CONTEXT)
    q, C = obs.get("stress_spectrum_q"), obs.get("stress_spectrum_C")
    if not (q is not None and C is not None and len(q) == len(C) and len(q) > 1):
        return None
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
    return c


def _cross_section_curves(ctx):
    """Item 9: the gap and the stress along the cross section, each with its band where a coarser
    run has the same line."""
    run, st, obs, fobs, nc, prov, params, conv, base = (ctx[k] for k in CONTEXT)
    curves = []
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
    return curves


def reference_load_curves(run: Run, hw: Json | None, notes: list[str], coarser: tuple[Run, Json] | None = None,
                          ) -> tuple[list[Json], Json | None]:
    """Items 1, 3, 4, 5, 9 from the finest run at the reference load; `coarser` = (run, step) of
    the same case on the next coarser grid gives them their bands."""
    obs, st = _observables(run, notes)
    if not obs:
        return [], st
    fobs = _observables(coarser[0], notes)[0] if coarser else {}
    nc = coarser[0].nx if coarser else None
    _same_run_in_h5(run, st)
    ctx = _reference_load_context(run, st, hw, obs, fobs, nc)
    curves = _distribution_curves(ctx)
    spectrum = _spectrum_curve(ctx)
    if spectrum is not None:
        curves.append(spectrum)
    return curves + _cross_section_curves(ctx), st


def finest_profile_band(run: Run, key: str, y: np.ndarray, v: np.ndarray, yc: np.ndarray, vc: np.ndarray,
                        ) -> tuple[np.ndarray | None, float | None]:
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


def member_runs(results: str) -> list[Run]:
    """The converged runs of case CHALLENGE_MEMBER under `results`, with mu_T the problem's
    (cmc.analysis.runs.tabor_of: the specified range, not a coarse-grained law's)."""
    out = []
    for summary in run_folder.read_summaries(run_folder.find(results)):
        s = summary.data
        if case_name(s) == CHALLENGE_MEMBER and s.get("status") == "converged":
            r = Run(s, summary.folder)
            r.run_tabor = tabor_of(s)
            out.append(r)
    return out


def distribution_pair(runs: list[Run], adhesive: bool) -> list[tuple[Run, Json]]:
    """The runs items 1, 3, 4, 5 and 9 come from: of every case and strategy at the reference load
    with result.h5 (the report's _reference_load_runs, one case at a time), the finest grid that
    has a coarser grid of the same case, and that coarser grid, as [(run, step) coarser, (run,
    step) finest]; on a tie the case with more grids, then the first by name. A case with one
    grid alone: [(run, step)] of the finest such; [] without any."""
    cases = sorted({(r.name, strategy_of(r.s)) for r in runs if r.has_result})
    seqs = [_reference_load_runs([r for r in runs if (r.name, strategy_of(r.s)) == c and r.has_result],
                                 adhesive) for c in cases]
    seqs = [q for q in seqs if q]
    if not seqs:
        return []
    best = max(seqs, key=lambda q: (len(q) >= 2, q[-1][0].nx, len(q)))
    return best[-2:]


def load_sweep_curves(runs: list[Run], hw: Json | None, adhesive: bool, ref_pair: list[tuple[Run, Json]],
                      ) -> list[Json]:
    """Items 2 and 8 of one problem from its load sweep with the most converged loads, on the
    finest grid among those (several runs of the same case and grid joined, as the report joins
    them: cmc.report.challenge_runs _merged_sweeps). Adhesive: the strategy's band;
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


def _tabor_band(c, items, mus, bands, short, runs):
    """Adds the Tabor curve's band per point: the larger of the family's errors at mu_T = 3 and at
    the point's own mu_T, or the challenge's own refinement where it applies; and its words."""
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


def _tabor_grid_items(runs):
    """The Tabor sweep's (run, step) per mu_T on the grid with the most mu_T (at least 2), the
    coarser where two have as many; [] where there is none."""
    by_grid = {}
    for r in runs:
        st = r.reference_step()
        # A run that stopped before its tolerance is no reference point (the report lists it as such).
        if r.run_tabor is not None and st is not None and not r.is_load_sweep() and not _stopped(r, st):
            by_grid.setdefault((r.nx, r.ny), {})[round(r.run_tabor, 9)] = (r, st)
    grids = [g for g in sorted(by_grid, key=lambda g: (-len(by_grid[g]), g[0] * g[1])) if len(by_grid[g]) >= 2]
    return [by_grid[grids[0]][k] for k in sorted(by_grid[grids[0]])] if grids else []


def tabor_curves(runs: list[Run], hw: Json | None) -> list[Json]:
    """Items 6 and 7 (adhesive Tabor sweep), when run."""
    curves: list[Json] = []
    # Tabor sweep: one run per mu_T (at the reference load) on the grid with the most mu_T (at least
    # 2), the coarser where two have as many: the sweep on a finer grid (scripts/tabor_sweep.sh
    # --grid N) measures that curve's error (sweep_band), as the reference load's 4096² run does.
    items = _tabor_grid_items(runs)
    if not items:
        return curves
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
        c: Json = dict(name=q, quantity=q, item=item,
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
            _tabor_band(c, items, mus, bands, short, runs)
        elif any(text for _, text in bands):
            missing = [f"{m:.3g}" for m, (rel, _) in zip(mus, bands) if rel is None]
            c["estimated_error"] = ("no error band: the scaled family has no run of this strategy "
                                    f"near the dx/rho of mu_T = {', '.join(missing)} (scripts/scaled_family.py "
                                    "--coarse K adds one). " + c["estimated_error"])
        curves.append(c)
    return curves
