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
import glob
import math
import os
import re

import numpy as np

from common import (CHALLENGE, condition_check_lines, condition_summary, realization_members, realization_rows,
                    case_name, finite, fmt, get, gpu_row_head, gpu_section, h5_open, load_json, md_table, plt,
                    read_reference_csv, rel, roundoff_note, s_extrapolation_verdict, savefig, step_groups,
                    transfer_caveat, write_csv)  # common puts python/ on the path for cmc.analysis

from best_report import draw_point, draw_realisation, draw_tabor, headline, load_best  # noqa: E402
import speed_report  # noqa: E402
from surface_report import headline_surfaces, surface_section  # noqa: E402
from stored_distributions import draw_stored_curve, draw_stored_profiles  # noqa: E402
from cmc.analysis import bands, refinement  # noqa: E402
from cmc.analysis.conditions import condition_checks, load_bands, run_band  # noqa: E402
from cmc.analysis.family import FAMILY_QUANTITIES, STRATEGIES  # noqa: E402
from cmc.analysis.refinement import REFINEMENT_BISTABILITY  # noqa: E402
from cmc.analysis.runs import strategy_of  # noqa: E402
from cmc.analysis.s_route import route_difference, s_extrapolation  # noqa: E402

P0 = CHALLENGE["p0"]
# How each band and number is made: the report keeps short captions that link here.
METHOD = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "challenge",
                      "report-method.md")


def method_link(out_dir, anchor, words="method"):
    """A Markdown link from the report in out_dir to a section of docs/challenge/report-method.md."""
    return f"[{words}]({rel(METHOD, out_dir)}#{anchor})"


def _band(run, short):
    """The relative error for `short` (a_r, mean_gap) that the run's strategy (range or shape
    coarse-graining, or plain) has on the scaled challenge family at this run's dx/rho, the larger
    of it and the error measured at the run's own mu_T where the family was run there too
    (cmc.analysis.conditions run_band), or None (no exponential adhesion, or no family run near
    its dx/rho)."""
    got = run_band(run.s, short)
    return got[1] if got else None


def refinement_grids(run, runs):
    """The converged runs of run's case, strategy and mu_T on n/2, n, 2n, ... points a side (run's n
    among them) with a step at the reference load (the sweep refined on the challenge itself,
    scripts/tabor_sweep.sh --grid N), coarsest first."""
    def same(q, nx, ny):
        return (q.name == run.name and q.nx == nx and q.ny == ny and q.status == "converged"
                and strategy_of(q.s) == strategy_of(run.s) and q.run_tabor and run.run_tabor
                and abs(q.run_tabor / run.run_tabor - 1) < 1e-6 and q.reference_step() is not None)
    out = [run]
    while True:
        nxt = [q for q in runs if same(q, 2 * out[-1].nx, 2 * out[-1].ny)]
        if not nxt:
            break
        out.append(nxt[0])
    while out[0].nx % 2 == 0 and out[0].ny % 2 == 0:
        prev = [q for q in runs if same(q, out[0].nx // 2, out[0].ny // 2)]
        if not prev:
            break
        out.insert(0, prev[0])
    return out


def own_band(run, short, runs):
    """cmc.analysis.refinement own_band of a plain, converged run from the other grids of its
    point among `runs` (refinement_grids), for short = a_r or mean_gap: the band of this run's
    value from the challenge's own refinement. None where it does not apply."""
    grids = refinement_grids(run, runs)
    if len(grids) < 2 or run.status != "converged" or strategy_of(run.s) != "plain":
        return None
    key = {"a_r": "ar", "mean_gap": "gap"}[short]
    rows = []
    for q in grids:
        st = q.reference_step()
        rows.append({"nx": q.nx, "dx_over_rho": get(q.s, "surface_facts", "dx_over_range"),
                     "bistability": get(q.s, "surface_facts", "bistability_number"), "value": st[key],
                     "corrected": st["ar_corr"] if short == "a_r" else None})
    return refinement.own_band(rows, grids.index(run))


def sweep_band(run, short, runs):
    """The band of a Tabor-sweep point: the challenge's own refinement where its finer grids resolve
    the adhesion (own_band), which needs no transfer from the family and replaces the family's bands there;
    else the family's (_band). Returns (relative band or None, own_refinement's result or None)."""
    own = own_band(run, short, runs)
    return (own["band"], own) if own else (_band(run, short), None)


def _condition_note(kind, out_dir, own=False):
    """The Tabor section's (kind "tabor") or the load sweep's ("load") lines on the bands at the
    sweep's other points (cmc.analysis.conditions condition_checks): the family's member run at the
    point's own mu_T or load against the band measured at mu_T = 3 and 250 kPa."""
    rows = [r for r in condition_checks()
            if (r["pressure_Pa"] == 250e3 if kind == "tabor" else r["tabor"] == 3.0)]  # condition_checks' defaults
    if not rows:
        return []
    head = ("**Does the band measured at μ_T = 3 hold at the sweep's other μ_T?** Each row: the family's s = 32 "
            "member run at that μ_T (`scripts/scaled_family.py --tabor MU`)" if kind == "tabor" else
            "**Does the band measured at 250 kPa hold at the sweep's other loads?** Each row: the family's s = 32 "
            "member run at that load (`scripts/scaled_family.py --pressure PA`)")
    return [head + ", its deviation from its own resolved reference (refinement error in brackets) against the band "
            "taken at μ_T = 3 and 250 kPa. Where measured, the error bars above are the larger of the two"
            + ((", at the points marked ‡ the challenge's own grid error" if own else "") if kind == "tabor" else
               ", per load") + f" ({method_link(out_dir, 'the-bands-at-other-conditions')}).", ""] \
        + condition_check_lines(rows) + [condition_summary(rows), ""]


def _pm(v, relerr, digits=4, scale=1.0):
    """A table cell: the value, with ± its error where there is one."""
    if v is None:
        return fmt(None)
    return fmt(v * scale, digits) + (f" ± {fmt(bands.absolute_band([relerr], [v])[0] * scale, 2)}" if relerr else "")


class Run:
    def __init__(self, summary, folder):
        self.s = summary
        self.folder = folder
        self.name = case_name(summary) or os.path.basename(folder)
        self.Estar = get(summary, "case", "material", "contact_modulus") or CHALLENGE["Estar"]
        g = summary.get("grid") or {}
        self.nx, self.ny = g.get("nx"), g.get("ny")
        self.dx = g.get("dx")
        self.size = g.get("size_x")
        # Where it ran: the tables mark the grids that ran on a GPU (grid.backend = "cuda")
        self.gpu_mark = " (GPU)" if g.get("backend") == "cuda" else ""
        self.status = summary.get("status", "?")
        self.wall_s = get(summary, "timing", "wall_s")
        self.h5path = os.path.join(folder, "result.h5")
        kind = get(summary, "case", "interaction", "kind")
        # The problem: the challenge's (adhesion) or its adhesionless counterpart (hard wall).
        self.adhesive = kind not in (None, "hard_wall")
        run_tabor = None
        for keys in (("tabor",), ("surface_facts", "tabor_parameter"), ("case", "interaction", "tabor"),
                     ("case", "interaction", "tabor_parameter"),
                     ("case", "interaction", "tabor_coefficient"), ("case", "interaction", "mu_T"),
                     ("interaction", "tabor")):
            v = get(summary, *keys)
            if finite(v):
                run_tabor = float(v)
                break
        self.run_tabor = run_tabor
        self.steps = []
        for k, st in enumerate(summary.get("steps") or []):
            if not isinstance(st, dict):
                continue
            ob = st.get("observables") if isinstance(st.get("observables"), dict) else {}

            def pick(key, default=None):
                v = ob.get(key)
                if finite(v):
                    return float(v)
                v = st.get(key)
                return float(v) if finite(v) else default

            tabor = st.get("tabor", ob.get("tabor"))
            self.steps.append({
                "k": k, "index": st.get("index", k),
                "p": pick("mean_pressure"), "ar": pick("contact_fraction"),
                "ar_corr": pick("contact_fraction_corrected"), "rep": pick("repulsive_fraction"),
                "att": pick("attractive_fraction"), "gap": pick("mean_gap"), "n_patches": pick("n_patches"),
                "perimeter": pick("contact_perimeter"),
                "tabor": float(tabor) if finite(tabor) else run_tabor,
                "converged": st.get("converged", True), "branch": st.get("branch", ""),
                "iterations": st.get("iterations"), "has_observables": bool(ob),
            })

    @property
    def label(self):
        return f"{self.name} ({self.nx}²)" if self.nx == self.ny else f"{self.name} ({self.nx}×{self.ny})"

    def tag(self):
        return re.sub(r"[^A-Za-z0-9_.-]", "_", f"{self.name}_{self.nx}")

    def pressures(self):
        return [st["p"] for st in self.steps if st["p"] is not None]

    def is_load_sweep(self):
        ps = {round(p, 9) for p in self.pressures() if p > 0}
        taborss = {st["tabor"] for st in self.steps if st["tabor"] is not None}
        return len(ps) >= 3 and len(taborss) <= 1

    def reference_step(self):
        """The step nearest the reference pressure 250 kPa (within 5 %), else None."""
        best = None
        for st in self.steps:
            if st["p"] and st["p"] > 0:
                ratio = max(st["p"] / P0, P0 / st["p"])  # >= 1; a selection rule, not physics
                if ratio < 1.05 and (best is None or ratio < best[0]):
                    best = (ratio, st)
        return best[1] if best else None


def _find_runs(results_dir, notes):
    """Challenge runs: every results/**/summary.json whose case name starts with
    "challenge" (results/challenge*/ by convention; also e.g. results/refine/<run>/),
    except the validation, performance and bench folders, the scaled family's runs (other
    problems, s != 1, or the challenge with other settings: the family's own section reads
    them from its store; by folder and by case name, challenge-scaled-*), the cluster cost measurements (scripts/cluster/measure.py: the
    challenge's cases on small grids, at several rank counts, some stopped after a fixed number
    of iterations; not results) and the round-off runs (results/roundoff/: the same cases by
    another build or thread count, for scripts/roundoff_spread.py; duplicates, not results) and the runs on
    users' surface files (results/surfaces/: scripts/main.sh --surface, a report of their own)."""
    files = set(glob.glob(os.path.join(results_dir, "**", "summary.json"), recursive=True))
    skip = tuple(os.path.join(results_dir, d) + os.sep
                 for d in ("validation", "performance", "scaled-family", "bench", "cluster-measure", "roundoff",
                           "surfaces"))
    runs = []
    for f in sorted(files):
        if f.startswith(skip):
            continue
        s = load_json(f, notes)
        if not isinstance(s, dict):
            continue
        name = case_name(s)
        in_challenge_dir = os.path.relpath(f, results_dir).startswith("challenge")
        if not (name.startswith("challenge") if name is not None else in_challenge_dir):
            continue
        # The family's runs wherever they were written (scripts/scaled_family.py --results, e.g.
        # results/seeds/seedN/ for other realizations): by case name, not only by folder. Left in,
        # a realization's many coarse grids won the reference-load group (the most grids).
        if name is not None and name.startswith("challenge-scaled"):
            continue
        runs.append(Run(s, os.path.dirname(f)))
    return runs


def _stopped(run, step):
    """Whether a run (or its step) stopped before its tolerance: its numbers are a last state, not a result."""
    return run.status == "not_converged" or step["converged"] is False


def _reference_load_candidates(runs, adhesive):
    """[(run, step at 250 kPa)] of one problem (adhesive: the challenge's, mu_T = 3; else the hard wall),
    load sweeps left out."""
    out = []
    for r in runs:
        if r.adhesive != adhesive or r.is_load_sweep():
            continue
        st = r.reference_step()
        if st is None or (adhesive and not (r.run_tabor and abs(r.run_tabor / CHALLENGE["tabor"] - 1) < 0.01)):
            continue
        out.append((r, st))
    return out


def _stopped_reference_runs(runs, adhesive):
    """The runs at the reference load that stopped before their tolerance (_reference_load_runs leaves
    them out): one line saying so, or ""."""
    stopped = [r for r, st in _reference_load_candidates(runs, adhesive) if _stopped(r, st)]
    if not stopped:
        return ""
    return ("NOT CONVERGED: " + ", ".join(f"{r.label} (`{r.folder}`)" for r in stopped)
            + f" at 250 kPa {'with' if adhesive else 'without'} adhesion stopped before "
            + ("its" if len(stopped) == 1 else "their") + " tolerance (`summary.json` says why): a last state, not a "
            "result, so nothing here is drawn from " + ("it" if len(stopped) == 1 else "them")
            + ". A quasi-static run stopped at `solver.max_outer_steps` keeps its checkpoint: the same `cmc run` "
            "command with `--resume --set solver.max_outer_steps=N` and a larger N continues it (`summary.json`, "
            "key `continue`).")


def _reference_load_runs(runs, adhesive):
    """The runs of one problem (adhesive: the challenge's, mu_T = 3; else the hard wall) at the
    reference load that the headline and the distributions use: converged runs with a step within
    5 % of 250 kPa that are not load sweeps, grouped by case name; the group with the most grids (then
    with result.h5, then the first by name). Returns [(run, step)], one per grid, coarsest first:
    the first is the one shown, the next finer one measures its grid error."""
    groups = {}
    for r, st in _reference_load_candidates(runs, adhesive):
        if _stopped(r, st):  # not a result: _stopped_reference_runs lists it
            continue
        groups.setdefault(r.name, {}).setdefault(r.nx, (r, st))
    if not groups:
        return []
    # Not the Tabor sweep's mu_T = 3 runs (the same problem, but their own sweep's; refined with
    # scripts/tabor_sweep.sh --grid N they would tie with the reference-load runs).
    _, by = max(sorted(groups.items()),
                key=lambda item: (not item[0].startswith("challenge-tabor"), len(item[1]),
                                  any(os.path.isfile(r.h5path) for r, _ in item[1].values())))
    return [by[n] for n in sorted(by)]


def grid_change(pair, key):
    """(bands.relative_change of step quantity `key`, coarse run, finer run) between the first two
    of [(run, step)] (coarsest first); None with fewer than two grids or without the change."""
    if len(pair) < 2:
        return None
    (r0, a), (r1, b) = pair[0], pair[1]
    change = bands.relative_change(a.get(key), b.get(key))
    return None if change is None else (change, r0, r1)


def finer_sweep(sweeps, r):
    """The load sweep of r's case on the next finer grid, (run, steps), among _merged_sweeps'
    entries; None if there is none."""
    cands = [(rf, pf) for rf, pf, _ in sweeps if rf.name == r.name and rf.adhesive == r.adhesive and rf.nx > r.nx]
    return min(cands, key=lambda c: c[0].nx) if cands else None


def band_floor(r, key):
    """(least band, its words) of a load-sweep point of run r, for key "ar" or "gap"
    (bands.sweep_floor, from the run's grid, solver tolerance and rms height)."""
    return bands.sweep_floor(key, r.nx, r.ny, get(r.s, "case", "solver", "tolerance") or 0.0,
                             get(r.s, "surface_facts", "rms_height") or 0.0)


def hardwall_sweep_band(pair, r, steps, key, finer=None):
    """Per-step band of a hard-wall load sweep (run r) for key "ar" or "gap", with a sentence saying
    how (bands.hardwall_sweep_band); (None, "") without one. finer = (run, steps) of the same sweep
    on a finer grid (finer_sweep); pair: the runs at 250 kPa, [(run, step)] coarsest first."""
    reference = (pair[0][1], pair[1][1], pair[0][0].nx, pair[1][0].nx) if len(pair) >= 2 else None
    return bands.hardwall_sweep_band(steps, key, r.nx, band_floor(r, key),
                                     finer=None if finer is None else (finer[0].nx, finer[1]), reference=reference)


def _cases_hint(case_dir, words):
    files = sorted(glob.glob(os.path.join(case_dir, "*.toml")))
    hits = [f for f in files if any(w in os.path.basename(f) for w in words)]
    return hits


def _run_cmd(case_file):
    stem = os.path.splitext(os.path.basename(case_file))[0]
    return f"`build/cmc run {case_file} --out results/challenge-{stem}`"


def _hint(case_dir, words, what):
    hits = _cases_hint(case_dir, words)
    if hits:
        return "not computed yet — run " + " and ".join(_run_cmd(h) for h in hits) + f" ({what}), then `scripts/report.sh`."
    return (f"not computed yet — needs {what}; no matching case file in `{case_dir}/` yet "
            "(add one and run `build/cmc run CASE --out results/challenge-NAME`).")


# ------------------------------------------------------------------------ h5 observables
def _observables(run, notes):
    """{dataset name: array} of the reference step's observables subgroup, or {}."""
    st = run.reference_step()
    if st is None or not os.path.isfile(run.h5path):
        return {}, st
    h5 = h5_open(run.h5path, notes)
    if h5 is None:
        return {}, st
    out = {}
    with h5:
        groups = step_groups(h5)
        gname = f"step_{int(st['index']):04d}"
        if gname not in h5 and st["k"] < len(groups):
            gname = groups[st["k"]]
        if gname in h5 and "observables" in h5[gname]:
            for k, v in h5[gname]["observables"].items():
                try:
                    out[k] = np.asarray(v[()], dtype=float).ravel()
                except (TypeError, ValueError):
                    pass
    return out, st


def _centers(edges, log):
    e = np.asarray(edges, dtype=float)
    if log and np.all(e > 0):
        return np.sqrt(e[:-1] * e[1:])
    return 0.5 * (e[:-1] + e[1:])


# ------------------------------------------------------------------------ figures
def _secondary_pressure_axis(ax, Estar):
    sec = ax.secondary_xaxis("top", functions=(lambda x: x * Estar / 1e6, lambda x: x * 1e6 / Estar))
    sec.set_xlabel("mean pressure (MPa)", fontsize=8)


def _stored(reference_dir, quantity, adhesive):
    """A stored challenge reference curve (reference/challenge/[adhesionless/]<quantity>.csv) as
    {path, meta, x, y, band (or None)}, or None where there is none."""
    path = os.path.join(reference_dir, "challenge", *([] if adhesive else ["adhesionless"]), quantity + ".csv")
    got = read_reference_csv(path) if os.path.isfile(path) else None
    if not got:
        return None
    meta, names, a = got
    col = {n: a[:, i] for i, n in enumerate(names)}
    if meta.get("x") not in col or meta.get("y") not in col:
        return None
    return {"path": path, "meta": meta, "x": col[meta["x"]], "y": col[meta["y"]], "band": col.get(meta.get("band"))}


def sweep_end_note(r, pts):
    """Where a load sweep's curve ends and why (as far as the solver goes, stating where and
    why it stops): at full contact, at a load its solver did not converge at, or
    at the last load the run was given."""
    last = pts[-1]
    where = f"The sweep {_problem(r)} on {r.nx}² ends at {last['p'] / 1e6:.4g} MPa (p/(E*ḡ) = {last['p'] / r.Estar:.3g})"
    if last["ar"] is not None and last["ar"] >= 1.0:
        return where + ", in full contact (a_r = 1)."
    if not last["converged"]:
        return where + f", a_r = {last['ar']:.4g}, where its solver stopped before its tolerance."
    case_file = r.s.get("case_file") or "its case file"
    its = f" in {last['iterations']} iterations" if isinstance(last.get("iterations"), int) else ""
    return (where + f", a_r = {last['ar']:.4g}: the last load the run was given "
            f"(`loading.values`; case `{case_file}`), where the solver converged{its}. "
            "The curve stops there by the case's choice, not the solver's; a_r = 1 is not reached at this load.")


def _stored_label(ref, adhesive):
    return f"{'with' if adhesive else 'without'} adhesion: stored reference ({ref['meta'].get('grid', '?').split(',')[0]})"


def _stored_note(ref):
    m = ref["meta"]
    return (f"`{ref['path']}`: computed by `{m.get('command', '?')}` on {m.get('date', '?')} "
            f"({m.get('sampling', '')}); not rerun here")


def _merged_sweeps(runs):
    """Load sweeps grouped by (case name, grid): one curve each, from several runs where a sweep was
    continued in another run (e.g. the high loads). At a pressure that two runs share, the step of
    the run that starts at the lowest load (the longest continuation) is kept unless only the
    other one converged, and the pair is returned for the note. [(run, steps sorted by p, [(p, kept step, other step)])]."""
    groups = {}
    sweeps = {(r.name, r.nx) for r in runs if r.is_load_sweep()}
    for r in runs:  # a continuation may hold only one or two loads
        if (r.name, r.nx) in sweeps:
            groups.setdefault((r.name, r.nx), []).append(r)
    out = []
    for _, rs in sorted(groups.items()):
        rs.sort(key=lambda r: min(r.pressures() or [math.inf]))
        steps, shared = {}, []
        for r in rs:
            for st in r.steps:
                if not (st["p"] and st["p"] > 0 and st["ar"] is not None):
                    continue
                key = round(st["p"], 6)
                if key in steps and st["converged"] and not steps[key]["converged"]:
                    shared.append((st["p"], dict(st, run=r), steps[key]))  # a converged step replaces one that is not
                    steps[key] = dict(st, run=r)
                elif key in steps:
                    shared.append((st["p"], steps[key], dict(st, run=r)))
                else:
                    steps[key] = dict(st, run=r)
        out.append((rs[0], [steps[k] for k in sorted(steps)], shared))
    return out


def _load_sweep(runs, out_dir, data_dir, case_dir, reference_dir, best=None):
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
    hw_pair = _reference_load_runs(runs, False)

    def band_of(r, pts, key, short):
        """(absolute band per point or None, legend text) of a sweep: the strategy's relative error
        for adhesive runs; for the hard wall hardwall_sweep_band."""
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

    # Item 2: contact area vs pressure.
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    tables = []
    for r, pts, shared in sweeps:
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
        tables.append((r, csv, rows))
        folders = sorted({s["run"].folder for s in pts})
        if len(folders) > 1:
            res["notes"].append(f"The sweep {_problem(r)} on {r.nx}² joins {len(folders)} runs ("
                                + ", ".join(f"`{f}`" for f in folders) + ")"
                                + ("; where two share a load, the longer continuation is kept: "
                                   + "; ".join(f"at {p / 1e6:.4g} MPa a_r {a['ar']:.4g} (kept, from `{a['run'].folder}`) "
                                               f"against {b['ar']:.4g} ({100 * (b['ar'] / a['ar'] - 1):+.2g} %), mean gap "
                                               f"{100 * (b['gap'] / a['gap'] - 1):+.2g} %"
                                               for p, a, b in shared if a['gap'] and b['gap'])
                                   + " (the other run starts there from the undeformed solid: the difference is how "
                                     "much the load path matters)" if shared else "") + ".")
        res["notes"].append(sweep_end_note(r, pts))
        unconverged = [s for s in pts if not s["converged"]]
        if unconverged:
            res["notes"].append(f"The sweep {_problem(r)} on {r.nx}²: the solver stopped before its tolerance at "
                                + ", ".join(f"{s['p'] / 1e6:.4g} MPa" for s in unconverged)
                                + " (those points are drawn but marked **no** in the table).")
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
    ests = ((best or {}).get("reference_load") or {})
    for est in (ests.get("adhesive"), ests.get("hardwall")):
        draw_point(a1, est, "a_r", 1.0, x=P0 / Es)
    draw_realisation(a1, reference_dir, "contact_area_vs_pressure", 1.0, Es)
    a1.axhline(0.75, color="gray", ls=":", lw=0.8)
    a1.set_xlabel("p / (E* ḡ)   (E* ḡ = 25 MPa)")
    a1.set_ylabel("relative contact area a_r")
    a1.set_title("2. contact area vs pressure", fontsize=10)
    a1.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=7)
    _secondary_pressure_axis(a1, Es)
    a2.set_xlabel("p / (E* ḡ)")
    a2.set_ylabel("1 − a_r  (non-contact fraction)")
    a2.set_title("approach to full contact", fontsize=10)
    a2.grid(True, which="both", alpha=0.3)
    a2.legend(fontsize=7)
    path = os.path.join(out_dir, "contact_area_vs_pressure.png")
    savefig(fig, path)
    res["area"] = (path, tables)
    # Item 8: mean gap vs pressure (log abscissa).
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
    if any_gap:
        for est in (ests.get("adhesive"), ests.get("hardwall")):
            draw_point(ax, est, "mean_gap", 1e6, x=P0 / Es)
        draw_realisation(ax, reference_dir, "mean_gap_vs_pressure", 1e6, Es)
        ax.set_xlabel("p / (E* ḡ)   (E* ḡ = 25 MPa)")
        ax.set_ylabel("mean gap ū (µm)")
        ax.set_title("8. mean gap vs pressure", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        _secondary_pressure_axis(ax, Es)
        path = os.path.join(out_dir, "mean_gap_vs_pressure.png")
        savefig(fig, path)
        res["gap"] = (path, tables)
    else:
        plt.close(fig)
        res["gap"] = "not computed yet — the load sweeps carry no mean gap."
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


def _tabor(runs, out_dir, data_dir, case_dir, reference_dir, best=None):
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
        csvs.append(csv)
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
    for r, st in sorted(unconverged, key=lambda t: (t[0].nx, t[1]["tabor"])):
        rows.append([fmt(st["tabor"], 4), r.name, f"{r.nx}²{r.gpu_mark} (NOT CONVERGED)", fmt(st["p"] / 1e3 if st["p"] else None, 4),
                     fmt(st["ar"], 4), fmt(st["rep"], 4), fmt(st["gap"] * 1e9 if st["gap"] else None, 5)])
        res.setdefault("notes", []).append(
            f"NOT CONVERGED: μ_T = {st['tabor']:.3g} on {r.nx}² (`{r.folder}`) stopped before its tolerance "
            f"({st['iterations'] if st['iterations'] is not None else '?'} iterations; its `summary.json` says why). Its row is the "
            "last state, not a result: it is not drawn, not in the CSVs and has no band.")
    if refined:
        res.setdefault("notes", []).append(_own_refinement_lines(refined, runs, band_of, out_dir))
    for what, ylabel, scale, fname, title in (("ar", "relative contact area a_r", 1.0, "contact_area_vs_tabor.png",
                                               "6. contact area vs Tabor coefficient"),
                                              ("gap", "mean gap ū (nm)", 1e9, "mean_gap_vs_tabor.png",
                                               "7. mean gap vs Tabor coefficient")):
        fig, ax = plt.subplots(figsize=(6, 4.4))
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
        if not drawn:
            plt.close(fig)
            res["area" if what == "ar" else "gap"] = "not computed yet — the Tabor runs carry no " + \
                ("contact fraction." if what == "ar" else "mean gap.")
            continue
        ax.set_xscale("log")
        ax.axvline(CHALLENGE["tabor"], color="gray", ls=":", lw=0.8)
        ax.set_xlabel("Tabor coefficient μ_T  (default 3)")
        ax.set_ylabel(ylabel)
        ax.set_title(title + " at p = 250 kPa", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        path = os.path.join(out_dir, fname)
        savefig(fig, path)
        res["area" if what == "ar" else "gap"] = (path, rows, csvs)
    return res


def _distribution_runs(runs, notes):
    """Per problem (with adhesion first), the run shown at the reference load with its observables,
    and the next finer grid's observables for the band: [(run, obs, step, finer)], finer = (run,
    obs, step) or None."""
    out = []
    for adhesive in (True, False):
        got = []
        for r, _ in _reference_load_runs(runs, adhesive):
            obs, st = _observables(r, notes)
            if obs:
                got.append((r, obs, st))
        if got:
            out.append(got[0] + (got[1] if len(got) > 1 else None,))
    return out


def profile_band(run, key, y, v, yf, vf):
    """(band, floor) of a cross-section profile v(y) (key cross_section_gap or _pressure) against the
    same case's profile (yf, vf) on the next finer grid: bands.profile_band, at least
    bands.profile_floor from the run's solver tolerance, rms height, E* and rms slope. (None, None)
    where the finer profile does not cover the line."""
    floor = bands.profile_floor(key, get(run.s, "case", "solver", "tolerance") or 0.0,
                                get(run.s, "surface_facts", "rms_height") or 0.0, run.Estar,
                                get(run.s, "case", "surface", "rms_gradient") or 1.0)
    b = bands.profile_band(y, v, yf, vf, floor)
    return (None, None) if b is None else (b, floor)


def _problem(r):
    return "with adhesion" if r.adhesive else "without adhesion"


def _band_or_stored(c, d, finer_curve, finer_nx, logx, logy, reference_dir, quantity, adhesive):
    """(band, legend text, table text) of a curve (c, d) at the reference load: its change to the
    same case on the next finer grid when that run is here; (None, ...) otherwise (the stored
    reference is drawn beside it with its own band, draw_stored_curve)."""
    if finer_curve is not None:
        b = bands.refinement_band(c, d, finer_curve[0], finer_curve[1], logx, logy)
        if np.isfinite(b).any():
            return b, f"band: change to {finer_nx}²", f"|this − {finer_nx}²| at {int(np.isfinite(b).sum())} of {len(c)} points"
    return None, "", "– (no finer run of this case here)"


def _hist_figure(dists, key_edges, key_density, xscale, yscale, xunit, yunit, xlabel, ylabel, title, path,
                 data_dir, csv_names, csv_stem, reference_dir, extra=None):
    fig, ax = plt.subplots(figsize=(6, 4.4))
    rows, csvs = [], []

    def curve(obs):
        e, d = obs.get(key_edges), obs.get(key_density)
        if e is None or d is None or len(e) != len(d) + 1 or len(d) == 0:
            return None
        return _centers(e, xscale == "log"), d

    for r, obs, st, finer in dists:
        got = curve(obs)
        if got is None:
            continue
        c, d = got
        m = np.isfinite(d) & (d > 0 if yscale == "log" else np.isfinite(d)) & (c > 0 if xscale == "log" else True)
        line, = ax.plot(c[m] * xunit, d[m] * yunit, ".-", ms=3, lw=0.8,
                        label=f"{_problem(r)}: {r.label}, p = {st['p'] / 1e3:.4g} kPa")
        cols = [(csv_names[0], c[m]), (csv_names[1], d[m])]
        fc = curve(finer[1]) if finer else None
        b, legend, band_from = _band_or_stored(c[m], d[m], fc, finer[0].nx if finer else None, xscale == "log",
                                               yscale == "log", reference_dir, csv_stem, r.adhesive)
        if b is not None:
            ok = np.isfinite(b)
            lo = d[m] - np.where(ok, b, 0)
            if yscale == "log":
                lo = np.maximum(lo, d[m] * 1e-3)
            ax.fill_between(c[m] * xunit, lo * yunit, (d[m] + np.where(ok, b, 0)) * yunit, where=ok,
                            color=line.get_color(), alpha=0.2, lw=0, label=legend)
            cols.append((csv_names[1] + "_err", b))
        csv = os.path.join(data_dir, f"{csv_stem}__{r.tag()}.csv")
        write_csv(csv, cols, f"cmc challenge {csv_stem}: {r.name}, grid {r.nx}x{r.ny}, step at p = {st['p']:.6g} Pa\n"
                             "bin centres (geometric for log bins) and probability densities, SI"
                             + (f"; *_err: the band ({band_from}; nan: none there)" if len(cols) > 2 else ""))
        csvs.append(csv)
        e = obs[key_edges]
        rows.append([_problem(r), r.label, fmt(st["p"] / 1e3, 4), len(d), f"{fmt(e[0] * xunit, 3)} – {fmt(e[-1] * xunit, 3)}",
                     band_from])
    for ad in (True, False):
        rows += draw_stored_curve(ax, _stored(reference_dir, csv_stem, ad), ad, xunit, yunit, yscale == "log")
    if not rows:
        plt.close(fig)
        return None
    ax.set_xscale(xscale)
    ax.set_yscale(yscale)
    if extra:
        extra(ax)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    savefig(fig, path)
    return path, rows, csvs


def _spectrum(dists, out_dir, data_dir, reference_dir):
    fig, ax = plt.subplots(figsize=(6, 4.4))
    rows, csvs = [], []

    def curve(obs):
        q, C = obs.get("stress_spectrum_q"), obs.get("stress_spectrum_C")
        if q is None or C is None or len(q) != len(C) or len(q) == 0:
            return None
        m = (q > 0) & (C > 0) & np.isfinite(C)
        return q[m], C[m]

    for r, obs, st, finer in dists:
        got = curve(obs)
        if got is None:
            continue
        q, C = got
        line, = ax.loglog(q, C, ".-", ms=3, lw=0.8, label=f"{_problem(r)}: {r.label}, p = {st['p'] / 1e3:.4g} kPa")
        cols = [("q_per_m", q), ("C_Pa2m2", C)]
        fc = curve(finer[1]) if finer else None
        b, legend, band_from = _band_or_stored(q, C, fc, finer[0].nx if finer else None, True, True, reference_dir,
                                               "stress_spectrum", r.adhesive)
        if b is not None:
            ok = np.isfinite(b)
            ax.fill_between(q, np.maximum(C - np.where(ok, b, 0), C * 1e-3), C + np.where(ok, b, 0), where=ok,
                            color=line.get_color(), alpha=0.2, lw=0, label=legend)
            cols.append(("C_Pa2m2_err", b))
        csv = os.path.join(data_dir, f"stress_spectrum__{r.tag()}.csv")
        write_csv(csv, cols, f"cmc challenge stress spectrum: {r.name}, grid {r.nx}x{r.ny}, step at p = {st['p']:.6g} Pa\n"
                             "isotropic spectral density of the interfacial stress, integral d^2q C(q) = variance")
        csvs.append(csv)
        rows.append([_problem(r), r.label, fmt(st["p"] / 1e3, 4), len(q), f"{fmt(q.min(), 3)} – {fmt(q.max(), 3)}",
                     band_from])
    for ad in (True, False):
        rows += draw_stored_curve(ax, _stored(reference_dir, "stress_spectrum", ad), ad, 1.0, 1.0, True)
    if not rows:
        plt.close(fig)
        return None
    qr, qs = 2 * np.pi / CHALLENGE["lambda_r"], 2 * np.pi / CHALLENGE["lambda_s"]
    ax.axvline(qr, color="gray", ls=":", lw=0.8)
    ax.axvline(qs, color="gray", ls="--", lw=0.8)
    ax.text(qr, ax.get_ylim()[0], " q_r", fontsize=7, va="bottom")
    ax.text(qs, ax.get_ylim()[0], " q_s", fontsize=7, va="bottom")
    ax.set_xlabel("wavenumber q (1/m)")
    ax.set_ylabel("stress spectrum C_σ(q) (Pa² m²)")
    ax.set_title("5. interfacial stress spectrum", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    path = os.path.join(out_dir, "stress_spectrum.png")
    savefig(fig, path)
    return path, rows, csvs


def _zoom_centre(y, g, p):
    """Where the cross-section zoom is centred: at the largest tension (the adhesive neck at a
    contact line) if there is tension, else at the contact edge nearest the largest stress."""
    okg = g is not None and len(g) == len(y)
    okp = p is not None and len(p) == len(y)
    if okp and np.min(p) < 0:
        return y[int(np.argmin(p))]
    if not (okp or okg):
        return None
    i_max = int(np.argmax(p)) if okp else int(np.argmin(g))
    inside = (g <= 0) if okg else (p > 0)
    edges = np.nonzero(inside[1:] != inside[:-1])[0]
    return y[int(edges[np.argmin(np.abs(edges - i_max))])] if len(edges) else y[i_max]


def _cross_section(dists, out_dir, data_dir, reference_dir):
    have = [(r, o, st, f) for r, o, st, f in dists if "cross_section_y" in o and
            ("cross_section_gap" in o or "cross_section_pressure" in o)]
    if not have:
        return None
    # One zoom window for every run (the first run's, the adhesive one where there is one), so
    # that the panels compare the same 2 µm of the section.
    r0, o0 = have[0][0], have[0][1]
    yc = _zoom_centre(o0["cross_section_y"], o0.get("cross_section_gap"), o0.get("cross_section_pressure"))
    if yc is None:
        return None
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5))
    rows, csvs = [], []
    # Drawn adhesive first, then the hard wall on top, dashed and thinner, so that neither hides the other.
    styles = [dict(ls="-", lw=0.9, alpha=0.85, zorder=2), dict(ls="--", lw=0.7, color="k", zorder=3)]
    for k, (r, o, st, finer) in enumerate(have):
        y = o["cross_section_y"]
        lab = f"{_problem(r)}: {r.label}, p = {st['p'] / 1e3:.4g} kPa"
        sty = styles[min(k, 1)] if len(have) > 1 else styles[0]
        zoom = np.abs(y - yc) <= 1e-6
        cols, how = [("y_m", y)], []
        for row, key, col, scale in ((0, "cross_section_gap", "gap_m", (1e6, 1e9)),
                                     (1, "cross_section_pressure", "pressure_Pa", (1e-6, 1e-6))):
            v = o.get(key)
            if v is None or len(v) != len(y):
                continue
            line, = axes[row, 0].plot(y * 1e6, v * scale[0], label=lab, **sty)
            axes[row, 1].plot(y[zoom] * 1e6, v[zoom] * scale[1], marker=".", ms=2, **sty)
            cols.append((col, v))
            fo = finer[1] if finer else {}
            b, floor = (profile_band(r, key, y, v, fo["cross_section_y"], fo[key])
                        if "cross_section_y" in fo and key in fo else (None, None))
            if b is None:
                continue
            # The band is drawn in the zoom only: on the whole line it is a grid spacing wide.
            axes[row, 1].fill_between(y[zoom] * 1e6, (v - b)[zoom] * scale[1], (v + b)[zoom] * scale[1],
                                      color=line.get_color(), alpha=0.2, lw=0, step="mid",
                                      label=f"band: change to {finer[0].nx}²")
            cols.append((col + "_err", b))
            how.append(f"{col}: median {fmt(float(np.median(b)), 3)}, largest {fmt(float(np.max(b)), 3)}, "
                       f"floor {fmt(floor, 3)}")
        csv = os.path.join(data_dir, f"cross_section__{r.tag()}.csv")
        x0 = get(r.s, "case", "observables", "cross_section_x")
        write_csv(csv, cols, f"cmc challenge cross section x = {x0} m: {r.name}, grid {r.nx}x{r.ny}, "
                             f"step at p = {st['p']:.6g} Pa\n"
                             "checkable with: cmc check FILE --quantity cross_section_gap | cross_section_pressure"
                             + (f"\n*_err: the band, the largest |this - the same case on {finer[0].nx}^2| at the finer "
                                "points nearest each point, at least the solver's tolerance in the problem's scale" if how else ""))
        csvs.append(csv)
        rows.append([_problem(r), r.label, fmt(x0 * 1e6 if finite(x0) else None, 4), len(y),
                     "; ".join(how) if how else "– (no run of this case on a finer grid)"])
    for ad in (True, False):
        rows += draw_stored_profiles(axes[:, 1], [_stored(reference_dir, q, ad) for q in ("cross_section_gap",
                                                                                           "cross_section_pressure")], ad, yc)
    for a in axes[:, 1]:
        a.set_xlim((yc - 1e-6) * 1e6, (yc + 1e-6) * 1e6)
    axes[0, 0].set_ylabel("gap (µm)")
    axes[0, 1].set_ylabel("gap (nm)")
    axes[1, 0].set_ylabel("interfacial stress p (MPa, compressive > 0)")
    axes[1, 1].set_ylabel("p (MPa)")
    axes[0, 0].set_title("9. gap and stress along the cross section x = 50 µm", fontsize=10)
    axes[0, 1].set_title(f"zoom: y = {(yc - 1e-6) * 1e6:.4g} – {(yc + 1e-6) * 1e6:.4g} µm (one window for all runs)",
                         fontsize=9)
    for a in axes.ravel():
        a.set_xlabel("y (µm)")
        a.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    axes[1, 0].legend(fontsize=7)
    path = os.path.join(out_dir, "cross_section.png")
    savefig(fig, path)
    return path, rows, csvs


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
        lines += [md_table(["run", "grid", "dx/ρ", "a_r", "repulsive a_r", "mean gap (µm)", "iterations",
                            "wall (s)", "strategy error measured on"], rows), ""]
        for strategy in STRATEGIES:
            caveat = transfer_caveat(list(members.values()), strategy, brief=True)
            if caveat:
                lines += ["**Caveat.** " + caveat.rstrip(".") + f" ({method_link(out_dir, 'the-transfer-check')}).", ""]
    else:
        lines += [f"The challenge's own runs: not computed yet ({cmd}).", ""]
    fam = [m for s, m in sorted(members.items(), reverse=True) if m.get("reference", {}).get("a_r")]
    if fam:
        rows = []
        for m in fam:
            ref = m["reference"]
            stopped = ref["a_r"].get("status", "converged") != "converged"  # stopped at a cap: a bound, see the store
            rows.append([m["s"], fmt(m["lambda_s_m"] * 1e6, 3), fmt(m["rho_m"] * 1e9, 4),
                         f"{ref['a_r']['grid']}²" + (" (stopped before its tolerance)" if stopped else ""),
                         f"{ref['a_r']['value']:.4g} ± {ref['a_r']['refinement_error']:.2g}",
                         f"{ref['a_rep']['value']:.4g} ± {ref['a_rep']['refinement_error']:.2g}",
                         f"{ref['mean_gap']['value'] * 1e6:.5g} ± {ref['mean_gap']['refinement_error'] * 1e6:.2g}"])
        lines += ["Second route: the family's converged values (the resolved grid, ± its refinement error) as s "
                  "falls toward the challenge (s = 1):", "",
                  md_table(["s", "λ_s (µm)", "ρ (nm)", "grid", "a_r", "repulsive a_r", "mean gap (µm)"], rows), ""]
        if len(fam) < 2:
            lines += ["One member is not enough to extrapolate in s: s = 16 and 8 (resolved on 4096² and 8192²) are "
                      "pending (`scripts/scaled_family.py --s 16 8`).", ""]
    x = s_extrapolation(list(members.values()))
    if x:
        sa, sb = x["members"][:2]
        lines += [f"Extrapolated in s: R(s), each member's converged value over its hard-wall value, on two lines "
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


def build(results_dir, case_dir, out_dir, notes, reference_dir="reference"):
    os.makedirs(out_dir, exist_ok=True)
    data_dir = os.path.join(out_dir, "data")
    runs = _find_runs(results_dir, notes)
    lines = ["# Contact Mechanics Challenge: cmc's results", "",
             "The nine quantities of the problem definition (Müser & Dapp, section \"Quantities to be predicted\"), "
             "with and without adhesion, drawn in the representations it asks for. Default parameters: E* = 25 MPa, "
             "ḡ = 1, L = 0.1 mm, λ_r = 20 µm, λ_s = 0.1 µm, H = 0.8, γ0 = 50 mJ/m², ρ = 2.071 nm (μ_T = 3), reference "
             "pressure p = 250 kPa = 0.01 E*ḡ. Numbers behind every figure are in `data/*.csv` (columns as `cmc check` "
             "reads them). The last section says how each number was obtained and how far to trust it.", ""]
    best = load_best(reference_dir)
    user = {a: (pair[0] if pair else None) for a, pair in ((a, _reference_load_runs(runs, a)) for a in (True, False))}
    lines += headline(best, user, reference_dir, surfaces=headline_surfaces(results_dir, runs, reference_dir))
    lines += surface_section(results_dir, runs, reference_dir, user)
    for a in (True, False):
        stopped_run = _stopped_reference_runs(runs, a)
        if stopped_run:
            lines += [stopped_run, ""]
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

    sweep = _load_sweep(runs, out_dir, data_dir, case_dir, reference_dir, best)
    tabor = _tabor(runs, out_dir, data_dir, case_dir, reference_dir, best)
    dists = _distribution_runs(runs, notes)
    ref_hint = _hint(case_dir, ["reference"], "a run at the reference load 250 kPa with observables and fields "
                                              "(result.h5 step_*/observables)")
    stopped = " ".join(t for t in (_stopped_reference_runs(runs, a) for a in (True, False)) if t)
    if not dists and stopped:
        ref_hint = stopped
    elif not dists and runs and any(r.reference_step() for r in runs):
        ref_hint = ("not computed yet — runs at 250 kPa exist but their result.h5 has no step_*/observables "
                    "group (enable [observables] and fields in the case). " + ref_hint)

    def section(num, title, content, cols, extra_lines=()):
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

    patch = _hist_figure(dists, "patch_area_edges", "patch_area_density", "log", "log", 1e12, 1e-12,
                         "contact patch area A (µm²)", "probability density of A (1/µm²)",
                         "1. contact patch size distribution", os.path.join(out_dir, "patch_size_distribution.png"),
                         data_dir, ("patch_area_m2", "density_per_m2"), "patch_size_distribution", reference_dir)
    dist_cols = ["problem", "run", "p (kPa)", "bins", "range ({})", "band"]
    dist_note = ["Band (shaded): per point, the change of the curve to the same case on the next finer grid, "
                 "interpolated in the figure's axes; the stored references (dashed, their grids named) with their bands "
                 f"as stored ({method_link(out_dir, 'distributions-and-spectrum')}).", ""]
    section(1, "Distribution of contact patch size (log-log)", patch, [c.format("µm²") for c in dist_cols], dist_note)

    def area_rows(content):
        if isinstance(content, str):
            return content
        path, tables = content
        rows = []
        for r, csv, rws in tables:
            rows += [[r.label] + row for row in rws]
        return (path, rows, [t[1] for t in tables])

    sweep_cols = ["run", "p (kPa)", "p/(E*ḡ)", "a_r", "a_r corrected", "mean gap (µm)", "patches", "converged"]
    band_note = ["Error bands (shaded, and ± in the tables): for adhesive runs, the error that the run's strategy "
                 "(plain, range or shape) has on the scaled challenge family at the run's dx/ρ, measured at μ_T = 3 "
                 "and 250 kPa (assumed elsewhere unless measured there, below); for the hard wall, its change to a "
                 "finer grid: "
                 + ("; ".join(f"{'a_r' if k == 'ar' else 'mean gap'} on {v}" for k, v in sorted(sweep["hw_how"].items()))
                    if isinstance(sweep, dict) and sweep.get("hw_how") else "at 250 kPa, scaled to each load")
                 + f" ({method_link(out_dir, 'error-bands-of-the-sweeps')}). " + roundoff_note() + " "
                 + transfer_caveat(brief=True), ""]
    section(2, "Contact area as a function of pressure (log-log; 1 − a_r for the approach to full contact)",
            area_rows(sweep["area"]), sweep_cols,
            band_note + _condition_note("load", out_dir) + [n + "\n" for n in sweep["notes"]])
    gap = _hist_figure(dists, "gap_hist_edges", "gap_hist_density", "log", "log", 1e6, 1e-6,
                       "gap g (µm)", "probability density P(g) (1/µm)", "3. gap distribution (contact points excluded)",
                       os.path.join(out_dir, "gap_distribution.png"), data_dir, ("gap_m", "density_per_m"),
                       "gap_distribution", reference_dir)
    section(3, "Gap distribution function (log-log)", gap, [c.format("µm") for c in dist_cols], ["Band: as in item 1.", ""])
    stress = _hist_figure(dists, "stress_hist_edges", "stress_hist_density", "linear", "log", 1e-6, 1e6,
                          "interfacial stress p (MPa, compressive > 0)", "probability density P(p) (1/MPa)",
                          "4. interfacial stress distribution", os.path.join(out_dir, "stress_distribution.png"),
                          data_dir, ("stress_Pa", "density_per_Pa"), "stress_distribution", reference_dir,
                          extra=lambda ax: ax.axvline(0, color="gray", lw=0.8))
    section(4, "Interfacial stress distribution (stress linear, probability logarithmic)", stress,
            [c.format("MPa") for c in dist_cols], ["Band: as in item 1.", ""])
    section(5, "Interfacial stress spectrum (log-log)", _spectrum(dists, out_dir, data_dir, reference_dir),
            ["problem", "run", "p (kPa)", "q points", "q range (1/m)", "band"], ["Band: as in item 1.", ""])
    tabor_cols = ["μ_T", "run", "grid", "p (kPa)", "a_r", "repulsive fraction", "mean gap (nm)"]
    section(6, "Contact area as a function of the Tabor coefficient (log μ_T)", tabor["area"], tabor_cols,
            band_note[:1] + ["Each μ_T has its own ρ, hence its own dx/ρ and its own error bar.", ""]
            + _condition_note("tabor", out_dir, own=tabor.get("own_refined", False))
            + [n + "\n" for n in dict.fromkeys(tabor.get("notes", []))])
    section(7, "Mean gap as a function of the Tabor coefficient (log μ_T)", _no_rows(tabor["gap"]), tabor_cols,
            ["Numbers: the table of item 6.", ""])
    section(8, "Mean gap as a function of pressure (log pressure)", _no_rows(area_rows(sweep["gap"])), sweep_cols,
            ["Numbers: the table of item 2.", ""])
    section(9, "Gap and stress along the cross section x = 50 µm", _cross_section(dists, out_dir, data_dir, reference_dir),
            ["problem", "run", "x (µm)", "points", "band"],
            ["Band (shaded in the zooms): per point, the largest change of the profile to the same case on the next "
             "finer grid near it, at least the solver's tolerance in the problem's scale; large at contact lines, "
             "which move by up to a grid spacing between the grids. With adhesion both grids leave ρ unresolved "
             f"({method_link(out_dir, 'cross-section')}).", ""])
    lines += speed_report.section([(r.s, r.folder) for a in (True, False) for r, _ in _reference_load_candidates(runs, a)],
                                  reference_dir, out_dir)
    lines += tail
    return "\n".join(lines) + "\n"
