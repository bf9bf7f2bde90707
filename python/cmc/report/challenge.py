"""reports/challenge/: the nine quantities of the Contact Mechanics Challenge, drawn as
the problem definition asks (section "Quantities to be predicted"), with index.md
giving the numbers behind them and the grid spacing of every run relative to
lambda_s = 0.1 um and rho = 2.071 nm.

Input: challenge runs under results/challenge*/ (summary.json, result.h5): a run is
one whose case name starts with "challenge". Per step, summary.json may carry
"observables" {contact_fraction, contact_fraction_corrected, repulsive_fraction,
attractive_fraction, mean_gap, mean_pressure, n_patches} and a "tabor" value; result.h5
step groups may carry an "observables" subgroup with gap_hist_*, stress_hist_*,
patch_area_*, stress_spectrum_*, cross_section_* (SI). What is missing is reported as
"not computed yet" with the command that computes it.

Also writes, next to each figure, the numbers as CSV in the column convention of
`cmc check` (data/*.csv), so a run can be checked against a reference directly.
"""
from __future__ import annotations
import os

from cmc.analysis.family import FAMILY_QUANTITIES, STRATEGIES
from cmc.analysis.s_route import route_difference, s_extrapolation
from . import speed as speed_report
from .best import headline, load_best
from .challenge_figures import _cross_section, _distribution_runs, _hist_figure, _spectrum
from .challenge_runs import (_condition_note, _find_runs, _hint, _reference_load_candidates, _reference_load_runs,
                             _stopped_reference_runs, method_link)
from .challenge_sweeps import _load_sweep, _tabor
from .common import (fmt, get, gpu_row_head, gpu_section, load_json, md_table, realization_members,
                     realization_rows, rel, roundoff_note, s_extrapolation_verdict, transfer_caveat)
from .surface import headline_surfaces, surface_section


# ------------------------------------------------------------------------ index
def _no_rows(content):
    """The same figure and data files, without repeating a table shown for another item."""
    if isinstance(content, str) or content is None:
        return content
    return (content[0], [], content[2] if len(content) > 2 else [])


def _grid_table(runs):
    """dx/λ_s and dx/ρ as cmc computed them (summary.json surface_facts)."""
    rows = []
    for r in runs:
        dx = r.dx
        rows.append([r.name, f"`{r.folder}`", f"{r.nx}×{r.ny}{r.gpu_mark}", fmt(dx * 1e9 if dx else None, 4),
                     fmt(get(r.s, "surface_facts", "dx_over_cutoff_wavelength"), 4),
                     fmt(get(r.s, "surface_facts", "dx_over_range"), 4),
                     len(r.steps), r.status, fmt(r.wall_s, 4),
                     fmt(r.run_tabor, 3) if r.run_tabor is not None else "–"])
    return md_table(["case", "folder", "grid", "dx (nm)", "dx/λ_s", "dx/ρ", "steps", "status", "wall (s)", "μ_T"], rows)


_FAMILY_LABEL = {"a_r": "a_r", "a_rep": "repulsive a_r", "mean_gap": "mean gap (µm)"}  # FAMILY_QUANTITIES' rows


def _gpu_grids(reference_dir):
    """The challenge on grids run on a GPU (reference/challenge/runs.json), with where
    each ran; the shape run set beside the scaled-family store's CPU run of the same case."""
    recs, lines = gpu_section(reference_dir, "The challenge on finer grids, run on a GPU")
    if not recs:
        return lines
    lines += ["Runs of the CUDA backend (`reference/challenge/runs.json`: command, device, date of each). The "
              "adhesion rows are `cases/challenge/reference-load.toml` (ρ = 2.071 nm as the problem states), "
              "plain, on the loading branch; the shape row is the scaled family's s = 1 case (μ_T = 3, so ρ "
              "follows from the surface), stopped at 170 outer steps like its CPU run in the table above. "
              "Error bars: none here; the grid-to-grid change is the refinement error of the coarser grid.", ""]
    rows = []
    for r in recs:
        gap = r.get("mean_gap_m")
        rows.append(gpu_row_head(r) + [fmt(r.get("dx_over_rho"), 3),
                     f"{r['device']}, {r['date']}" if r.get("backend") == "cuda" else r.get("device", "?"),
                     r["iterations"], fmt(r["solve_s"], 4), fmt(r["a_r"], 6), fmt(r.get("a_rep"), 6),
                     fmt(gap * 1e6 if gap is not None else None, 8), r["status"]])
    lines += [md_table(["case", "grid", "dx/ρ", "ran on", "iterations", "solve (s)", "a_r", "repulsive a_r",
                        "mean gap (µm)", "status"], rows), ""]
    fam = load_json(os.path.join(reference_dir, "challenge-scaled", "scaled_family.json"))
    cpu = None
    for m in (fam or {}).get("members", []):
        for run in m.get("runs", []):
            if run.get("role") == "shape_n8192":
                cpu = run
    gpu = next((r for r in recs if r["kind"] == "shape" and r["n"] == 8192), None)
    if cpu and gpu:
        same_it = cpu["iterations"] == gpu["iterations"]
        lines += [f"The 8192² shape run on both: the CPU's ({fmt(cpu['wall_s'], 4)} s on 2 cores) and the GPU's "
                  f"({fmt(gpu['solve_s'], 4)} s) took {cpu['iterations']} and {gpu['iterations']} iterations"
                  + (" (the same)" if same_it else "") + f"; a_r {cpu['a_r']!r} and {gpu['a_r']!r}, repulsive a_r "
                  f"{cpu['a_rep']!r} and {gpu['a_rep']!r}, mean gap differing by "
                  f"{fmt(abs(cpu['mean_gap'] - gpu['mean_gap_m']) / cpu['mean_gap'], 2)} relative"
                  + (": the same contact set, and the backends agree to round-off on this grid." if same_it and
                     cpu["a_r"] == gpu["a_r"] and abs(cpu["mean_gap"] - gpu["mean_gap_m"]) < 1e-9 * cpu["mean_gap"]
                     else "."), ""]
    return lines


def _challenge_runs_table(ch, members, out_dir):
    """The challenge's own coarse runs (the family's member s = 1) with their strategies' error
    bars, and the transfer check's caveat per strategy."""
    rows = []
    est = {e["role"]: e for e in ch.get("estimates", [])}
    for r in ch["runs"]:
        e = est.get(r["role"])
        def cell(short, scale, digits):
            v = r[short] * scale
            if e and e[short]["error"] is not None:
                return f"{v:.{digits}g} ± {e[short]['error'] * scale:.2g}"
            return f"{v:.{digits}g}"
        stopped = r.get("status", "converged") != "converged"  # at its outer-step cap: the store says how far
        rows.append([r["role"].split("_")[0], f"{r['n']}²" + (" (stopped before its tolerance)" if stopped else ""),
                     fmt(r["dx_over_rho"], 3), cell("a_r", 1, 4),
                     cell("a_rep", 1, 4), cell("mean_gap", 1e6, 5), r["iterations"], fmt(r["wall_s"], 3),
                     "; ".join(e["measured_on"]) if e and e["measured_on"] else "–"])
    lines = [md_table(["run", "grid", "dx/ρ", "a_r", "repulsive a_r", "mean gap (µm)", "iterations",
                       "wall (s)", "strategy error measured on"], rows), ""]
    for strategy in STRATEGIES:
        caveat = transfer_caveat(list(members.values()), strategy, brief=True)
        if caveat:
            lines += ["**Caveat.** " + caveat.rstrip(".") + f" ({method_link(out_dir, 'the-transfer-check')}).", ""]
    return lines


def _family_values_table(fam):
    """The second route's table: each member's converged values as s falls toward 1."""
    rows = []
    for m in fam:
        ref = m["reference"]
        stopped = ref["a_r"].get("status", "converged") != "converged"  # stopped at a cap: a bound, see the store
        rows.append([m["s"], fmt(m["lambda_s_m"] * 1e6, 3), fmt(m["rho_m"] * 1e9, 4),
                     f"{ref['a_r']['grid']}²" + (" (stopped before its tolerance)" if stopped else ""),
                     f"{ref['a_r']['value']:.4g} ± {ref['a_r']['refinement_error']:.2g}",
                     f"{ref['a_rep']['value']:.4g} ± {ref['a_rep']['refinement_error']:.2g}",
                     f"{ref['mean_gap']['value'] * 1e6:.5g} ± {ref['mean_gap']['refinement_error'] * 1e6:.2g}"])
    lines = ["Second route: the family's converged values (the resolved grid, ± its refinement error) as s "
             "falls toward the challenge (s = 1):", "",
             md_table(["s", "λ_s (µm)", "ρ (nm)", "grid", "a_r", "repulsive a_r", "mean gap (µm)"], rows), ""]
    if len(fam) < 2:
        lines += ["One member is not enough to extrapolate in s: s = 16 and 8 (resolved on 4096² and 8192²) are "
                  "pending (`scripts/scaled_family.py --s 16 8`).", ""]
    return lines


def _s_extrapolation_lines(x, out_dir):
    """The extrapolation in s (cmc.analysis.s_route s_extrapolation's result x) as a table."""
    sa, sb = x["members"][:2]
    lines = [f"Extrapolated in s: R(s), each member's converged value over its hard-wall value, on two lines "
             f"through s = {sb} and {sa} (in log s and in s) to s = 1, times the challenge's own hard-wall value "
             f"({method_link(out_dir, 'second-route-extrapolation-in-s')}).", ""]
    rows = []
    for _, short, _ in FAMILY_QUANTITIES:
        q = x[short]
        scale, digits = (1e6, 5) if short == "mean_gap" else (1.0, 4)
        rows.append([_FAMILY_LABEL[short],
                     f"{q['ratios'][str(sb)]['value']:.4f}", f"{q['ratios'][str(sa)]['value']:.4f}",
                     f"{q['ratio_at_1_log_s']:.4f} / {q['ratio_at_1_linear_s']:.4f}",
                     f"{q['adhesionless_at_1']['value'] * scale:.{digits + 1}g}",
                     f"{q['value'] * scale:.{digits}g} ± {q['error'] * scale:.2g}"])
    lines += [md_table(["quantity", f"R(s = {sb})", f"R(s = {sa})", "R(1): line in log s / in s",
                        "hard wall, s = 1", "s = 1 by extrapolation"], rows), ""]
    verdict = s_extrapolation_verdict(x)
    if verdict:
        lines += [verdict, ""]
    return lines


def _routes_side_by_side(x, ch):
    """Per strategy, its finest run's estimate (route 1) beside the extrapolation in s (route 2)."""
    lines = []
    for strategy in STRATEGIES if ch else ():
        est = sorted(ch.get("estimates", []), key=lambda e: -e["n"])
        est = [e for e in est if e["role"].startswith(strategy + "_")]
        if est and est[0]["a_r"]["error"] is not None:
            e = est[0]
            rows = []
            for _, short, _ in FAMILY_QUANTITIES:
                scale, digits = (1e6, 5) if short == "mean_gap" else (1.0, 4)
                a, b = e[short], x[short]
                diff = route_difference(a, b)
                rows.append([_FAMILY_LABEL[short],
                             f"{a['value'] * scale:.{digits}g} ± {a['error'] * scale:.2g}",
                             f"{b['value'] * scale:.{digits}g} ± {b['error'] * scale:.2g}",
                             "–" if diff is None else f"{diff:.2f}"])
            lines += [f"Both routes side by side (route 1: the `{strategy}` run on {e['n']}² with the strategy's "
                      "error measured on the family; route 2: the extrapolation in s). A difference beyond the sum "
                      "of the two errors (last column above 1) is a finding, not noise.", "",
                      md_table(["quantity", f"route 1 ({e['n']}², {strategy})", "route 2 (in s)",
                                "difference / sum of errors"], rows), ""]
    return lines


def _adhesion_resolution(reference_dir, out_dir):
    """The challenge's adhesive numbers with error bars, from the scaled-family store
    (reference/challenge-scaled/scaled_family.json, written by scripts/scaled_family.py)."""
    path = os.path.join(reference_dir, "challenge-scaled", "scaled_family.json")
    cmd = "`/usr/bin/python3 scripts/scaled_family.py --s 1 --no-resolved --coarse --grids 2048 4096 8192 --store reference/challenge-scaled`"
    lines = ["## Adhesion: how the numbers move with the grid, and their error bars", ""]
    data = load_json(path) if os.path.exists(path) else None
    if not data:
        return lines + [f"Not computed yet: {cmd} (after the family's references, same script).", ""]
    members = {m["s"]: m for m in data.get("members", [])}
    ch = members.get(1)
    lines += ["No grid on one machine resolves ρ = 2.071 nm (the published solution used 65536², dx ≈ 0.75 ρ). Below: "
              "the challenge at 250 kPa on coarse grids, plain and with the two resolution strategies (`[interaction] "
              "coarse_graining = \"range\"` or `\"shape\"`); a strategy's error bar is its error measured on the scaled "
              "challenge family at the same dx/ρ, the plain runs carry none "
              f"({method_link(out_dir, 'adhesion-resolution-strategies-and-the-scaled-family')}; "
              f"`{rel(os.path.join(reference_dir, 'challenge-scaled', 'README.md'), '.')}`).", ""]
    if ch:
        lines += _challenge_runs_table(ch, members, out_dir)
    else:
        lines += [f"The challenge's own runs: not computed yet ({cmd}).", ""]
    fam = [m for s, m in sorted(members.items(), reverse=True) if m.get("reference", {}).get("a_r")]
    if fam:
        lines += _family_values_table(fam)
    x = s_extrapolation(list(members.values()))
    if x:
        lines += _s_extrapolation_lines(x, out_dir) + _routes_side_by_side(x, ch)
    return lines


def _case_seed(case_dir):
    """The surface seed of the family's case file (case_dir: cases/challenge), or None."""
    try:
        from cmc.case_files import read_case_file  # with its base, challenge-base.toml
        return read_case_file(os.path.join(case_dir, "scaled-family.toml"))["surface"]["seed"]
    except (OSError, KeyError, ValueError, ImportError):
        return None


def _realizations(reference_dir, case_dir, out_dir):
    """The strategies' coarse-grid errors on several realizations of the surface (the
    family's members stored with scripts/scaled_family.py --seed N), beside the case file's."""
    by_s = realization_members(reference_dir, _case_seed(case_dir))
    lines = []
    for s, members in sorted(by_s.items(), reverse=True):
        if len(members) < 2:
            continue
        if not lines:
            lines = ["## The strategies on other realizations of the surface", "",
                     "The family's member on surfaces that differ only in their random phases (`scripts/scaled_family.py "
                     "--seed N`), each against its own resolved reference. Each cell: the run's a_r and mean gap "
                     "relative to that reference, and for a strategy whether its target (±3 % / ±0.5 % at 2 ρ, ±6 % / "
                     "±1 % at 4 ρ) is met; the error bars above take the largest deviation over every realization "
                     f"({method_link(out_dir, 'other-realizations')}).", ""]
        header, rows = realization_rows(members)
        lines += [f"s = {s}, at the spacings the strategies have targets for (3 % / 0.5 % at 2 ρ, 6 % / 1 % at 4 ρ):", "", md_table(header, rows), ""]
        header, rows = realization_rows(members, spacings=(6, 12, 24))
        if any(c != "–" for row in rows[:-1] for c in row[4:]):
            lines += [f"s = {s}, at the challenge's own spacings (its 8192², 4096² and 2048²; these runs set its error "
                      "bars):", "", md_table(header, rows), ""]
    return lines


INTRO = ["# Contact Mechanics Challenge: cmc's results", "",
         "The nine quantities of the problem definition (Müser & Dapp, section \"Quantities to be predicted\"), "
         "with and without adhesion, drawn in the representations it asks for. Default parameters: E* = 25 MPa, "
         "ḡ = 1, L = 0.1 mm, λ_r = 20 µm, λ_s = 0.1 µm, H = 0.8, γ0 = 50 mJ/m², ρ = 2.071 nm (μ_T = 3), reference "
         "pressure p = 250 kPa = 0.01 E*ḡ. Numbers behind every figure are in `data/*.csv` (columns as `cmc check` "
         "reads them). The last section says how each number was obtained and how far to trust it.", ""]
DIST_COLS = ["problem", "run", "p (kPa)", "bins", "range ({})", "band"]
SWEEP_COLS = ["run", "p (kPa)", "p/(E*ḡ)", "a_r", "a_r corrected", "mean gap (µm)", "patches", "converged"]
TABOR_COLS = ["μ_T", "run", "grid", "p (kPa)", "a_r", "repulsive fraction", "mean gap (nm)"]


def _trust_section(runs, results_dir, reference_dir, case_dir, out_dir):
    """The report's last section: how the numbers were obtained, and how far to trust them."""
    tail = ["## How the numbers were obtained, and how far to trust them", ""]
    if not runs:
        tail += [f"No challenge runs found under `{results_dir}/` (a summary.json whose case name starts with "
                 f"\"challenge\"; by convention in `{results_dir}/challenge-*/`).", ""]
    tail += ["### Runs and grid spacing", ""]
    if runs:
        tail += ["Grid spacing relative to the shortest wavelength λ_s = 0.1 µm and to the adhesion range "
                 "ρ = 2.071 nm. The challenge's reference solution used dx ≈ λ_s/64 = 1.56 nm ≈ 0.75 ρ "
                 "(65536² points). Figures show the coarsest grid of each problem; a finer run of the same case "
                 "gives the band (its change to the finer grid).", "", _grid_table(runs), ""]
    else:
        tail += ["(none yet)", ""]
    tail += ["#" + ln if ln.startswith("## ") else ln for ln in _adhesion_resolution(reference_dir, out_dir)]
    tail += ["#" + ln if ln.startswith("## ") else ln for ln in _realizations(reference_dir, case_dir, out_dir)]
    tail += ["#" + ln if ln.startswith("## ") else ln for ln in _gpu_grids(reference_dir)]
    return tail


def _reference_hint(runs, dists, case_dir):
    """What an item at the reference load says when it has nothing to draw."""
    ref_hint = _hint(case_dir, ["reference"], "a run at the reference load 250 kPa with observables and fields "
                                              "(result.h5 step_*/observables)")
    stopped = " ".join(t for t in (_stopped_reference_runs(runs, a) for a in (True, False)) if t)
    if not dists and stopped:
        ref_hint = stopped
    elif not dists and runs and any(r.reference_step() for r in runs):
        ref_hint = ("not computed yet — runs at 250 kPa exist but their result.h5 has no step_*/observables "
                    "group (enable [observables] and fields in the case). " + ref_hint)
    return ref_hint


def _section(lines, ref_hint, out_dir, num, title, content, cols, extra_lines=()):
    """Appends one item to lines: its figure, extra lines, table and data files, or what is missing."""
    lines.append(f"## {num}. {title}")
    lines.append("")
    if isinstance(content, str) or content is None:
        lines.append(content or ref_hint)
        lines.append("")
        return
    path, rows = content[0], content[1]
    csvs = content[2] if len(content) > 2 else []
    lines.append(f"![{title}]({rel(path, out_dir)})")
    lines.append("")
    lines.extend(extra_lines)
    if rows:
        lines.append(md_table(cols, rows))
        lines.append("")
    if csvs:
        lines.append("Data: " + ", ".join(f"[{os.path.basename(c)}]({rel(c, out_dir)})" for c in csvs))
        lines.append("")


def _area_rows(content):
    """The load sweep's tables joined into one, each row led by its run."""
    if isinstance(content, str):
        return content
    path, tables = content
    rows = []
    for r, csv, rws in tables:
        rows += [[r.label] + row for row in rws]
    return (path, rows, [t[1] for t in tables])


def _sweep_band_note(sweep, out_dir):
    """The lines that say how the sweeps' error bands are made."""
    return ["Error bands (shaded, and ± in the tables): for adhesive runs, the error that the run's strategy "
            "(plain, range or shape) has on the scaled challenge family at the run's dx/ρ, measured at μ_T = 3 "
            "and 250 kPa (assumed elsewhere unless measured there, below); for the hard wall, its change to a "
            "finer grid: "
            + ("; ".join(f"{'a_r' if k == 'ar' else 'mean gap'} on {v}" for k, v in sorted(sweep["hw_how"].items()))
               if isinstance(sweep, dict) and sweep.get("hw_how") else "at 250 kPa, scaled to each load")
            + f" ({method_link(out_dir, 'error-bands-of-the-sweeps')}). " + roundoff_note() + " "
            + transfer_caveat(brief=True), ""]


def _items_1_to_5(add, ctx, sweep, band_note):
    """Items 1 to 5: patch sizes, the load sweep's contact area, gaps, stresses and the spectrum."""
    dists, out_dir, data_dir, reference_dir = ctx
    patch = _hist_figure(dists, "patch_area_edges", "patch_area_density", "log", "log", 1e12, 1e-12,
                         "contact patch area A (µm²)", "probability density of A (1/µm²)",
                         "1. contact patch size distribution", os.path.join(out_dir, "patch_size_distribution.png"),
                         data_dir, ("patch_area_m2", "density_per_m2"), "patch_size_distribution", reference_dir)
    dist_note = ["Band (shaded): per point, the change of the curve to the same case on the next finer grid, "
                 "interpolated in the figure's axes; the stored references (dashed, their grids named) with their bands "
                 f"as stored ({method_link(out_dir, 'distributions-and-spectrum')}).", ""]
    add(1, "Distribution of contact patch size (log-log)", patch, [c.format("µm²") for c in DIST_COLS], dist_note)
    add(2, "Contact area as a function of pressure (log-log; 1 − a_r for the approach to full contact)",
        _area_rows(sweep["area"]), SWEEP_COLS,
        band_note + _condition_note("load", out_dir) + [n + "\n" for n in sweep["notes"]])
    gap = _hist_figure(dists, "gap_hist_edges", "gap_hist_density", "log", "log", 1e6, 1e-6,
                       "gap g (µm)", "probability density P(g) (1/µm)", "3. gap distribution (contact points excluded)",
                       os.path.join(out_dir, "gap_distribution.png"), data_dir, ("gap_m", "density_per_m"),
                       "gap_distribution", reference_dir)
    add(3, "Gap distribution function (log-log)", gap, [c.format("µm") for c in DIST_COLS], ["Band: as in item 1.", ""])
    stress = _hist_figure(dists, "stress_hist_edges", "stress_hist_density", "linear", "log", 1e-6, 1e6,
                          "interfacial stress p (MPa, compressive > 0)", "probability density P(p) (1/MPa)",
                          "4. interfacial stress distribution", os.path.join(out_dir, "stress_distribution.png"),
                          data_dir, ("stress_Pa", "density_per_Pa"), "stress_distribution", reference_dir,
                          extra=lambda ax: ax.axvline(0, color="gray", lw=0.8))
    add(4, "Interfacial stress distribution (stress linear, probability logarithmic)", stress,
        [c.format("MPa") for c in DIST_COLS], ["Band: as in item 1.", ""])
    add(5, "Interfacial stress spectrum (log-log)", _spectrum(dists, out_dir, data_dir, reference_dir),
        ["problem", "run", "p (kPa)", "q points", "q range (1/m)", "band"], ["Band: as in item 1.", ""])


def _items_6_to_9(add, ctx, sweep, tabor, band_note):
    """Items 6 to 9: the Tabor sweep's contact area and mean gap, the load sweep's mean gap, the
    cross section."""
    dists, out_dir, data_dir, reference_dir = ctx
    add(6, "Contact area as a function of the Tabor coefficient (log μ_T)", tabor["area"], TABOR_COLS,
        band_note[:1] + ["Each μ_T has its own ρ, hence its own dx/ρ and its own error bar.", ""]
        + _condition_note("tabor", out_dir, own=tabor.get("own_refined", False))
        + [n + "\n" for n in dict.fromkeys(tabor.get("notes", []))])
    add(7, "Mean gap as a function of the Tabor coefficient (log μ_T)", _no_rows(tabor["gap"]), TABOR_COLS,
        ["Numbers: the table of item 6.", ""])
    add(8, "Mean gap as a function of pressure (log pressure)", _no_rows(_area_rows(sweep["gap"])), SWEEP_COLS,
        ["Numbers: the table of item 2.", ""])
    add(9, "Gap and stress along the cross section x = 50 µm", _cross_section(dists, out_dir, data_dir, reference_dir),
        ["problem", "run", "x (µm)", "points", "band"],
        ["Band (shaded in the zooms): per point, the largest change of the profile to the same case on the next "
         "finer grid near it, at least the solver's tolerance in the problem's scale; large at contact lines, "
         "which move by up to a grid spacing between the grids. With adhesion both grids leave ρ unresolved "
         f"({method_link(out_dir, 'cross-section')}).", ""])


def build(results_dir: str, case_dir: str, out_dir: str, notes: list[str], reference_dir: str = "reference") -> str:
    """reports/challenge/index.md's text, with its figures and data/*.csv written beside it."""
    os.makedirs(out_dir, exist_ok=True)
    data_dir = os.path.join(out_dir, "data")
    runs = _find_runs(results_dir, notes)
    lines = list(INTRO)
    best = load_best(reference_dir)
    user = {a: (pair[0] if pair else None) for a, pair in ((a, _reference_load_runs(runs, a)) for a in (True, False))}
    lines += headline(best, user, reference_dir, surfaces=headline_surfaces(results_dir, runs, reference_dir))
    lines += surface_section(results_dir, runs, reference_dir, user)
    for a in (True, False):
        stopped_run = _stopped_reference_runs(runs, a)
        if stopped_run:
            lines += [stopped_run, ""]
    tail = _trust_section(runs, results_dir, reference_dir, case_dir, out_dir)
    sweep = _load_sweep(runs, out_dir, data_dir, case_dir, reference_dir, best)
    tabor = _tabor(runs, out_dir, data_dir, case_dir, reference_dir, best)
    dists = _distribution_runs(runs, notes)
    ref_hint = _reference_hint(runs, dists, case_dir)

    def add(num, title, content, cols, extra_lines=()):
        _section(lines, ref_hint, out_dir, num, title, content, cols, extra_lines)

    band_note = _sweep_band_note(sweep, out_dir)
    ctx = (dists, out_dir, data_dir, reference_dir)
    _items_1_to_5(add, ctx, sweep, band_note)
    _items_6_to_9(add, ctx, sweep, tabor, band_note)
    lines += speed_report.section([(r.s, r.folder) for a in (True, False) for r, _ in _reference_load_candidates(runs, a)],
                                  reference_dir, out_dir)
    lines += tail
    return "\n".join(lines) + "\n"
