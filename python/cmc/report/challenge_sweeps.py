"""The challenge report's sweeps: the load sweep (items 2 and 8) and the Tabor sweep (items 6
and 7), drawn with their bands and written as data/*.csv, with the lines of index.md on them."""
import os

import numpy as np

from cmc.analysis import bands
from cmc.analysis.conditions import load_bands
from cmc.analysis.refinement import REFINEMENT_BISTABILITY
from .best import draw_point, draw_realisation, draw_tabor
from .challenge_runs import (P0, _band, _hint, _merged_sweeps, _problem, _reference_load_runs, _stopped, _stored,
                             finer_sweep, hardwall_sweep_band, method_link, refinement_grids, sweep_band,
                             sweep_end_note)
from .common import CHALLENGE, fmt, get, label_axes, md_table, plt, rel, savefig, write_csv


def _pm(v, relerr, digits=4, scale=1.0):
    """A table cell: the value, with ± its error where there is one."""
    if v is None:
        return fmt(None)
    return fmt(v * scale, digits) + (f" ± {fmt(bands.absolute_band([relerr], [v])[0] * scale, 2)}" if relerr else "")


# ------------------------------------------------------------------------ figures
def _secondary_pressure_axis(ax, Estar):
    sec = ax.secondary_xaxis("top", functions=(lambda x: x * Estar / 1e6, lambda x: x * 1e6 / Estar))
    sec.set_xlabel("mean pressure (MPa)", fontsize=8)


def _stored_label(ref, adhesive):
    return f"{'with' if adhesive else 'without'} adhesion: stored reference ({ref['meta'].get('grid', '?').split(',')[0]})"


def _stored_note(ref):
    m = ref["meta"]
    return (f"`{ref['path']}`: computed by `{m.get('command', '?')}` on {m.get('date', '?')} "
            f"({m.get('sampling', '')}); not rerun here")


def _sweep_band_maker(res, sweeps, hw_pair):
    """band_of(r, pts, key, short) for the load sweeps: (absolute band per point or None, legend
    text); notes on how each band was made go into res."""
    def band_of(r, pts, key, short):
        """The strategy's relative error for adhesive runs; for the hard wall hardwall_sweep_band."""
        if r.adhesive:
            b, words = load_bands(r.s, short, [st["p"] for st in pts])
            if not b:
                return None, ""
            note = f"Adhesive {r.nx}² sweep, {short}: band per load, {words}."
            if words and note not in res["notes"]:
                res["notes"].append(note)
            return (bands.absolute_band(b, [st[key] for st in pts]),
                    f"± {100 * b[0]:.3g} % … {100 * b[-1]:.3g} %, strategy error, scaled family" if words
                    else f"± {100 * b[0]:.3g} %, strategy error, scaled family")
        finer = finer_sweep(sweeps, r)
        band, how = hardwall_sweep_band(hw_pair, r, pts, key, finer)
        if not band:
            return None, ""
        res.setdefault("hw_how", {})[key] = f"{r.nx}²: {how}"
        if finer and how.startswith("the change from"):
            return band, f"grid change {r.nx}² → {finer[0].nx}², measured at the loads both ran"
        return band, f"grid change {hw_pair[0][0].nx}² → {hw_pair[1][0].nx}² at 250 kPa, scaled"
    return band_of


def _draw_area_sweep(a1, a2, r, pts, band_of):
    """One sweep's a_r (with its band and the perimeter-corrected a_r) and 1 - a_r; returns
    (band of a_r, band of the mean gap, the corrected points)."""
    pt = np.array([s["p"] / r.Estar for s in pts])
    ar = np.array([s["ar"] for s in pts])
    (band_ar, what_ar) = band_of(r, pts, "ar", "a_r")
    band_gap = band_of(r, pts, "gap", "mean_gap")[0] if all(s["gap"] is not None for s in pts) else None
    lab = f"{_problem(r)}: {r.label}"
    line, = a1.loglog(pt, ar, "o-", ms=4, label=lab)
    if band_ar:
        a1.fill_between(pt, ar - np.array(band_ar), np.minimum(ar + np.array(band_ar), 1.0), color=line.get_color(),
                        alpha=0.2,
                        lw=0, label=what_ar)
    corr = [(s["p"] / r.Estar, s["ar_corr"]) for s in pts if s["ar_corr"] is not None]
    if corr:
        a1.loglog([c[0] for c in corr], [c[1] for c in corr], "s--", ms=3, mfc="none", color=line.get_color(),
                  lw=0.8, label=f"{_problem(r)}: perimeter-corrected")
    m = ar < 1
    a2.loglog(pt[m], 1 - ar[m], "o-", ms=4, color=line.get_color(), label=lab)
    return band_ar, band_gap, corr


def _sweep_csv_and_rows(r, pts, corr, band_ar, band_gap, data_dir):
    """data/load_sweep__<run>.csv and the table rows of one sweep; returns (csv path, rows)."""
    ar = np.array([s["ar"] for s in pts])
    cols = [("pressure_Pa", [s["p"] for s in pts]), ("contact_fraction", ar)]
    if corr and len(corr) == len(pts):
        cols.append(("contact_fraction_corrected", [s["ar_corr"] for s in pts]))
    gaps = [s["gap"] for s in pts]
    if all(g is not None for g in gaps):
        cols.append(("mean_gap_m", gaps))
    csv = os.path.join(data_dir, f"load_sweep__{r.tag()}.csv")
    write_csv(csv, cols, f"cmc challenge load sweep: {r.name}, grid {r.nx}x{r.ny}, from "
                         + ", ".join(sorted({s['run'].folder for s in pts})) + "\n"
                         "checkable with: cmc check FILE --quantity contact_area_vs_pressure | mean_gap_vs_pressure")

    def pm_abs(v, b, scale=1.0):
        return fmt(v * scale, 4) + (f" ± {fmt(b * scale, 2)}" if b else "") if v is not None else fmt(None)

    rows = [[fmt(s["p"] / 1e3, 4), fmt(s["p"] / r.Estar, 3), pm_abs(s["ar"], band_ar[k] if band_ar else None),
             fmt(s["ar_corr"], 4), pm_abs(s["gap"], band_gap[k] if band_gap else None, 1e6), fmt(s["n_patches"]),
             "yes" if s["converged"] else "**no**"] for k, s in enumerate(pts)]
    return csv, rows


def _sweep_notes(r, pts, shared):
    """The notes on one sweep: the runs it joins, why it ends, where it stopped early."""
    notes = []
    folders = sorted({s["run"].folder for s in pts})
    if len(folders) > 1:
        notes.append(f"The sweep {_problem(r)} on {r.nx}² joins {len(folders)} runs ("
                     + ", ".join(f"`{f}`" for f in folders) + ")"
                     + ("; where two share a load, the longer continuation is kept: "
                        + "; ".join(f"at {p / 1e6:.4g} MPa a_r {a['ar']:.4g} (kept, from `{a['run'].folder}`) "
                                    f"against {b['ar']:.4g} ({100 * (b['ar'] / a['ar'] - 1):+.2g} %), mean gap "
                                    f"{100 * (b['gap'] / a['gap'] - 1):+.2g} %"
                                    for p, a, b in shared if a['gap'] and b['gap'])
                        + " (the other run starts there from the undeformed solid: the difference is how "
                          "much the load path matters)" if shared else "") + ".")
    notes.append(sweep_end_note(r, pts))
    unconverged = [s for s in pts if not s["converged"]]
    if unconverged:
        notes.append(f"The sweep {_problem(r)} on {r.nx}²: the solver stopped before its tolerance at "
                     + ", ".join(f"{s['p'] / 1e6:.4g} MPa" for s in unconverged)
                     + " (those points are drawn but marked **no** in the table).")
    return notes


def _area_figure(sweeps, stored, Es, band_of, ctx, res):
    """Item 2: contact area vs pressure (and 1 - a_r); returns the table of each sweep."""
    out_dir, data_dir, reference_dir, ests = ctx
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    tables = []
    for r, pts, shared in sweeps:
        band_ar, band_gap, corr = _draw_area_sweep(a1, a2, r, pts, band_of)
        csv, rows = _sweep_csv_and_rows(r, pts, corr, band_ar, band_gap, data_dir)
        tables.append((r, csv, rows))
        res["notes"] += _sweep_notes(r, pts, shared)
    for ad, (ref_ar, _) in stored.items():
        x = ref_ar["x"] / Es
        line, = a1.loglog(x, ref_ar["y"], "d-" if ad else "d--", ms=4, lw=1.0, label=_stored_label(ref_ar, ad))
        if ref_ar["band"] is not None:
            a1.fill_between(x, ref_ar["y"] - ref_ar["band"], ref_ar["y"] + ref_ar["band"], color=line.get_color(),
                            alpha=0.2, lw=0, label="its error band")
        m = ref_ar["y"] < 1
        a2.loglog(x[m], 1 - ref_ar["y"][m], "d-", ms=4, color=line.get_color(), label=_stored_label(ref_ar, ad))
        res["notes"].append(f"Drawn from the stored reference ({'with' if ad else 'without'} adhesion): "
                            + _stored_note(ref_ar) + ".")
    for est in (ests.get("adhesive"), ests.get("hardwall")):
        draw_point(a1, est, "a_r", 1.0, x=P0 / Es)
    draw_realisation(a1, reference_dir, "contact_area_vs_pressure", 1.0, Es)
    a1.axhline(0.75, color="gray", ls=":", lw=0.8)
    label_axes(a1, "p / (E* ḡ)   (E* ḡ = 25 MPa)", "relative contact area a_r", "2. contact area vs pressure")
    _secondary_pressure_axis(a1, Es)
    label_axes(a2, "p / (E* ḡ)", "1 − a_r  (non-contact fraction)", "approach to full contact")
    path = os.path.join(out_dir, "contact_area_vs_pressure.png")
    savefig(fig, path)
    res["area"] = (path, tables)
    return tables


def _gap_figure(sweeps, stored, Es, band_of, ctx, tables, res):
    """Item 8: mean gap vs pressure (log abscissa)."""
    out_dir, data_dir, reference_dir, ests = ctx
    fig, ax = plt.subplots(figsize=(6, 4.4))
    any_gap = False
    for r, pts, _ in sweeps:
        pts = [s for s in pts if s["gap"] is not None]
        if pts:
            any_gap = True
            x, g = np.array([s["p"] / r.Estar for s in pts]), np.array([s["gap"] * 1e6 for s in pts])
            line, = ax.semilogx(x, g, "o-", ms=4, label=f"{_problem(r)}: {r.label}")
            band, what = band_of(r, pts, "gap", "mean_gap")
            if band:
                b = np.array(band) * 1e6
                ax.fill_between(x, g - b, g + b, color=line.get_color(), alpha=0.2, lw=0, label=what)
    for ad, (_, ref_gap) in stored.items():
        if ref_gap is None:
            continue
        any_gap = True
        x, g = ref_gap["x"] / Es, ref_gap["y"] * 1e6
        line, = ax.semilogx(x, g, "d-" if ad else "d--", ms=4, lw=1.0, label=_stored_label(ref_gap, ad))
        if ref_gap["band"] is not None:
            ax.fill_between(x, g - ref_gap["band"] * 1e6, g + ref_gap["band"] * 1e6, color=line.get_color(), alpha=0.2,
                            lw=0, label="its error band")
    if not any_gap:
        plt.close(fig)
        res["gap"] = "not computed yet — the load sweeps carry no mean gap."
        return
    for est in (ests.get("adhesive"), ests.get("hardwall")):
        draw_point(ax, est, "mean_gap", 1e6, x=P0 / Es)
    draw_realisation(ax, reference_dir, "mean_gap_vs_pressure", 1e6, Es)
    label_axes(ax, "p / (E* ḡ)   (E* ḡ = 25 MPa)", "mean gap ū (µm)", "8. mean gap vs pressure")
    _secondary_pressure_axis(ax, Es)
    path = os.path.join(out_dir, "mean_gap_vs_pressure.png")
    savefig(fig, path)
    res["gap"] = (path, tables)


def _load_sweep(runs, out_dir, data_dir, case_dir, reference_dir, best=None):
    """Items 2 and 8 from the load sweeps among runs (or, without one, the stored references):
    {"area": ..., "gap": ..., "notes": [...]} with each item's figure and tables or what to run."""
    sweeps = _merged_sweeps(runs)
    stored = {ad: (_stored(reference_dir, "contact_area_vs_pressure", ad), _stored(reference_dir, "mean_gap_vs_pressure", ad))
              for ad in (True, False) if not any(r.adhesive == ad for r, _, _ in sweeps)}
    stored = {ad: v for ad, v in stored.items() if v[0] is not None}
    res = {"notes": []}
    if not sweeps and not stored:
        msg = _hint(case_dir, ["sweep"], "a load sweep: many mean pressures from ~0.1 % to above 75 % contact")
        res["area"] = res["gap"] = msg
        return res
    Es = sweeps[0][0].Estar if sweeps else CHALLENGE["Estar"]
    band_of = _sweep_band_maker(res, sweeps, _reference_load_runs(runs, False))
    ctx = (out_dir, data_dir, reference_dir, ((best or {}).get("reference_load") or {}))
    tables = _area_figure(sweeps, stored, Es, band_of, ctx, res)
    _gap_figure(sweeps, stored, Es, band_of, ctx, tables, res)
    return res


def _own_refinement_lines(refined, runs, band_of, out_dir):
    """Section 6's account of the Tabor sweep refined on the challenge itself (rows marked ‡): a
    table of each grid's a_r and mean gap with its own band and the family's, the converged values
    estimated, and a figure of the change between successive grids against dx (log-log: its slope
    is the observed order). refined: mu_T -> (a run of that point, own_band a_r, own_band mean gap);
    band_of: (id(run), short) -> sweep_band of every run of the sweep (_tabor)."""
    rows, est_rows = [], []
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for mu, (run, own_ar, own_gap) in sorted(refined.items()):
        grids = refinement_grids(run, runs)
        for q in grids:
            st = q.reference_step()
            cells = [fmt(mu, 4), f"{q.nx}²{q.gpu_mark}", fmt(get(q.s, "surface_facts", "dx_over_range"), 3),
                     fmt(get(q.s, "surface_facts", "bistability_number"), 2)]
            for short, key, scale, digits in (("a_r", "ar", 1.0, 5), ("mean_gap", "gap", 1e9, 7)):
                own = (band_of.get((id(q), short)) or sweep_band(q, short, runs))[1]
                fam = _band(q, short)
                cells += [fmt(st[key] * scale, digits), "–" if own is None else f"±{100 * own['band']:.3g} %",
                          "–" if fam is None else f"±{100 * fam:.3g} %"]
            rows.append(cells)
        for own, name, scale, unit, digits in ((own_ar, "a_r", 1.0, "", 5), (own_gap, "mean gap", 1e9, " nm", 7)):
            if own:
                pairs = [w for w, _ in own["estimates"] if "/" in w]  # the last: v_inf's (own_refinement)
                est_rows.append([fmt(mu, 4), name, fmt(own["order"], 3), f"{fmt(own['v_inf'] * scale, digits)}{unit}",
                                 "; ".join(f"{w}: {fmt(v * scale, digits)}" for w, v in own["estimates"] if w != pairs[-1])])
        for ax, key in zip(axes, ("ar", "gap")):
            vals = [(q.dx, q.reference_step()[key]) for q in grids]
            pts = [(a[0] * 1e9, bands.relative_change(a[1], b[1])) for a, b in zip(vals, vals[1:]) if a[1] != b[1]]
            if pts:
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=4, label=f"μ_T = {mu:g}")
    for ax, title, slope in zip(axes, ("a_r", "mean gap"), (1, 4)):
        x = np.array(ax.get_xlim())
        if ax.lines:  # a guide through the first point
            x0, y0 = ax.lines[0].get_data()
            ax.loglog(x, y0[0] * (x / x0[0]) ** slope, "k:", lw=0.8, label=f"slope {slope}")
        ax.set_xlabel("dx of the coarser grid (nm)")
        ax.set_ylabel("|change to the grid with twice the points| / value")
        ax.set_title(f"{title}: the Tabor sweep refined on the challenge", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    path = os.path.join(out_dir, "tabor_refinement.png")
    savefig(fig, path)
    return "\n".join([
        "‡ **The Tabor sweep refined on the challenge itself** (`scripts/tabor_sweep.sh --grid N`): at these μ_T the "
        "band is the challenge's own grid error, not the family's: the distance from the converged value that "
        "Richardson extrapolation of order 1 estimates from the finest pair of grids with w dx/(E\\* ρ²) ≤ "
        f"{REFINEMENT_BISTABILITY:g}, plus the spread of the other estimates "
        f"({method_link(out_dir, 'the-tabor-sweep-refined-on-the-challenge-itself')}). Grids marked (GPU) ran with "
        "`grid.backend = \"cuda\"`.", "",
        md_table(["μ_T", "grid", "dx/ρ", "w dx/(E\\* ρ²)", "a_r", "band (own)", "band (family)", "mean gap (nm)",
                  "band (own)", "band (family)"], rows), "",
        md_table(["μ_T", "quantity", "observed order", "converged (Richardson, order 1, finest pair)",
                  "other estimates"], est_rows), "",
        f"![the Tabor sweep refined on the challenge]({rel(path, out_dir)})", "",
        "The change between successive grids against the coarser grid's spacing, log-log: the slope is the "
        "observed order (dotted: guides of slope 1 and 4)."])


def _tabor_points(runs):
    """(run, step) of every Tabor-sweep point among runs: each step of a run with a "tabor" per
    step, else the run's step at the reference load."""
    pts = []
    for r in runs:
        with_tabor = [st for st in r.steps if st["tabor"] is not None]
        if not with_tabor:
            continue
        if len({st["tabor"] for st in with_tabor}) > 1:  # one run, a "tabor" per step
            use = with_tabor
        else:
            st = r.reference_step()
            use = [st] if st is not None and st["tabor"] is not None else []
        for st in use:
            if st["ar"] is not None or st["gap"] is not None:
                pts.append((r, st))
    return pts


def _tabor_group(key, items, runs, data_dir, band_of, refined, res):
    """One grid's points (key: nx, ny): data/tabor_sweep__<grid>.csv, their bands into band_of,
    the points refined on the challenge itself into refined; returns (csv path, table rows)."""
    items.sort(key=lambda t: t[1]["tabor"])
    cols = [("tabor", [st["tabor"] for _, st in items])]
    if all(st["ar"] is not None for _, st in items):
        cols.append(("contact_fraction", [st["ar"] for _, st in items]))
    if all(st["gap"] is not None for _, st in items):
        cols.append(("mean_gap_m", [st["gap"] for _, st in items]))
    if all(st["p"] is not None for _, st in items):
        cols.append(("pressure_Pa", [st["p"] for _, st in items]))
    csv = os.path.join(data_dir, f"tabor_sweep__{key[0]}x{key[1]}.csv")
    write_csv(csv, cols, "cmc challenge Tabor sweep at the reference load\n"
                         "checkable with: cmc check FILE --quantity contact_area_vs_tabor | mean_gap_vs_tabor")
    rows = []
    for r, st in items:
        for short in ("a_r", "mean_gap"):
            band_of[id(r), short] = sweep_band(r, short, runs)
        (b_ar, own_ar), (b_gap, own_gap) = band_of[id(r), "a_r"], band_of[id(r), "mean_gap"]
        rows.append([fmt(st["tabor"], 4), r.name,
                     f"{r.nx}²{r.gpu_mark}" + (" ‡" if own_ar or own_gap else ""),
                     fmt(st["p"] / 1e3 if st["p"] else None, 4),
                     _pm(st["ar"], b_ar), fmt(st["rep"], 4), _pm(st["gap"], b_gap, 5, 1e9)])
        if own_ar or own_gap:
            res["own_refined"] = True
            refined.setdefault(round(st["tabor"], 6), (r, own_ar, own_gap))
    return csv, rows


def _unconverged_tabor_rows(unconverged, res):
    """The table rows of the points that stopped before their tolerance, with a note on each."""
    rows = []
    for r, st in sorted(unconverged, key=lambda t: (t[0].nx, t[1]["tabor"])):
        rows.append([fmt(st["tabor"], 4), r.name, f"{r.nx}²{r.gpu_mark} (NOT CONVERGED)", fmt(st["p"] / 1e3 if st["p"] else None, 4),
                     fmt(st["ar"], 4), fmt(st["rep"], 4), fmt(st["gap"] * 1e9 if st["gap"] else None, 5)])
        res.setdefault("notes", []).append(
            f"NOT CONVERGED: μ_T = {st['tabor']:.3g} on {r.nx}² (`{r.folder}`) stopped before its tolerance "
            f"({st['iterations'] if st['iterations'] is not None else '?'} iterations; its `summary.json` says why). Its row is the "
            "last state, not a result: it is not drawn, not in the CSVs and has no band.")
    return rows


def _tabor_figure(what, groups, band_of, best, ax, scale):
    """Draws the best estimates and each grid's points of `what` (ar, gap) with error bars;
    returns whether anything was drawn."""
    drawn = draw_tabor(ax, best, what, scale)
    barred = False
    for key, items in sorted(groups.items()):
        use = [(r, st) for r, st in items if st[what] is not None and st["tabor"] > 0]
        xy = [(st["tabor"], st[what] * scale) for _, st in use]
        if xy:
            drawn = True
            line, = ax.semilogx([p[0] for p in xy], [p[1] for p in xy], "o-", ms=4, label=f"your runs, {key[0]}²")
            # Each mu_T has its own rho, so its own dx/rho and strategy error: error bars.
            rels = [band_of[id(r), "a_r" if what == "ar" else "mean_gap"][0] for r, _ in use]
            if any(rels):
                ax.errorbar([p[0] for p in xy], [p[1] for p in xy],
                            yerr=bands.absolute_band([b or 0 for b in rels], [p[1] for p in xy]),
                            fmt="none", ecolor=line.get_color(), capsize=3, lw=0.8,
                            label=None if barred else "error bars: own refinement where measured, else the scaled "
                                                      "family's")
                barred = True
    return drawn


def _tabor(runs, out_dir, data_dir, case_dir, reference_dir, best=None):
    """Items 6 and 7 from the Tabor sweeps among runs and the best estimates: {"area": ...,
    "gap": ..., "notes": [...]} with each item's figure, table rows and CSVs or what to run."""
    pts = _tabor_points(runs)
    if not pts and not (best or {}).get("tabor"):
        msg = _hint(case_dir, ["tabor"], "a Tabor sweep at the reference load: runs at several Tabor coefficients "
                                         "(one run each, or one run with a \"tabor\" value per step)")
        return {"area": msg, "gap": msg}
    groups = {}
    unconverged = []  # listed in the table as such; neither drawn, written to the CSVs, nor banded
    for r, st in pts:
        if _stopped(r, st):
            unconverged.append((r, st))
        else:
            groups.setdefault((r.nx, r.ny), []).append((r, st))
    res = {}
    rows = []
    csvs = []
    band_of = {}  # (id(run), short) -> sweep_band: for the table and the figures
    refined = {}  # mu_T -> (a run of it, own_band a_r, own_band mean gap): refined on the challenge itself
    for key, items in sorted(groups.items()):
        csv, group_rows = _tabor_group(key, items, runs, data_dir, band_of, refined, res)
        csvs.append(csv)
        rows += group_rows
    rows += _unconverged_tabor_rows(unconverged, res)
    if refined:
        res.setdefault("notes", []).append(_own_refinement_lines(refined, runs, band_of, out_dir))
    for what, ylabel, scale, fname, title in (("ar", "relative contact area a_r", 1.0, "contact_area_vs_tabor.png",
                                               "6. contact area vs Tabor coefficient"),
                                              ("gap", "mean gap ū (nm)", 1e9, "mean_gap_vs_tabor.png",
                                               "7. mean gap vs Tabor coefficient")):
        fig, ax = plt.subplots(figsize=(6, 4.4))
        if not _tabor_figure(what, groups, band_of, best, ax, scale):
            plt.close(fig)
            res["area" if what == "ar" else "gap"] = "not computed yet — the Tabor runs carry no " + \
                ("contact fraction." if what == "ar" else "mean gap.")
            continue
        ax.set_xscale("log")
        ax.axvline(CHALLENGE["tabor"], color="gray", ls=":", lw=0.8)
        label_axes(ax, "Tabor coefficient μ_T  (default 3)", ylabel, title + " at p = 250 kPa")
        path = os.path.join(out_dir, fname)
        savefig(fig, path)
        res["area" if what == "ar" else "gap"] = (path, rows, csvs)
    return res
