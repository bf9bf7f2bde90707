"""The challenge report's runs: discovery of the challenge runs under a results folder (Run),
the step at the reference load, the observables of a step, the bands of a run's numbers, and
the hints that say what to run where something is missing."""
from __future__ import annotations
from typing import Any
import glob
import math
import os
import re

import numpy as np

from cmc.analysis import bands, refinement
from cmc.analysis.conditions import condition_checks, run_band
from cmc.analysis.runs import REPO, strategy_of
from .common import (CHALLENGE, case_name, condition_check_lines, condition_summary, finite, get,
                     read_reference_csv, rel)
from cmc import run_folder
from cmc._types import Json


P0 = CHALLENGE["p0"]
# How each band and number is made: the report keeps short captions that link here.
METHOD = os.path.join(REPO, "docs", "challenge",
                      "report-method.md")


def method_link(out_dir: str, anchor: str, words: str = "method") -> str:
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


def refinement_grids(run: Run, runs: list[Run]) -> list[Run]:
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


def own_band(run: Run, short: str, runs: list[Run]) -> Json | None:
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
        assert st is not None  # refinement_grids keeps the runs with one
        rows.append({"nx": q.nx, "dx_over_rho": get(q.s, "surface_facts", "dx_over_range"),
                     "bistability": get(q.s, "surface_facts", "bistability_number"), "value": st[key],
                     "corrected": st["ar_corr"] if short == "a_r" else None})
    return refinement.own_band(rows, grids.index(run))


def sweep_band(run: Run, short: str, runs: list[Run]) -> tuple[float | None, Json | None]:
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


class Run:
    """A challenge run as the report reads it: its summary (`s`, parsed; `record`, its steps as
    cmc.run_folder reads them) and per step the numbers the report uses (`steps`, dicts)."""

    def __init__(self, summary: Json, folder: str) -> None:
        self.s = summary
        self.record = run_folder.summary_of(folder, summary)
        self.folder = folder
        self.name = case_name(summary) or os.path.basename(folder)
        self.Estar = get(summary, "case", "material", "contact_modulus") or CHALLENGE["Estar"]
        g: Any = summary.get("grid") or {}
        self.nx, self.ny = g.get("nx"), g.get("ny")
        self.dx = g.get("dx")
        self.size = g.get("size_x")
        # Where it ran: the tables mark the grids that ran on a GPU (grid.backend = "cuda")
        self.gpu_mark = " (GPU)" if g.get("backend") == "cuda" else ""
        self.status = summary.get("status", "?")
        self.wall_s = get(summary, "timing", "wall_s")
        self.h5path = run_folder.result_path(folder)
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
        self.steps: list[Json] = []
        for step in self.record.steps:
            k, st, ob = step.position, step.record, step.scalar_observables

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
    def has_result(self) -> bool:
        """Whether the run's folder holds a result.h5."""
        return run_folder.has_result(self.folder)

    def step(self, st: Json) -> run_folder.Step:
        """The run_folder.Step of one of `steps`."""
        return next(s for s in self.record.steps if s.position == st["k"])

    @property
    def label(self) -> str:
        return f"{self.name} ({self.nx}²)" if self.nx == self.ny else f"{self.name} ({self.nx}×{self.ny})"

    def tag(self) -> str:
        return re.sub(r"[^A-Za-z0-9_.-]", "_", f"{self.name}_{self.nx}")

    def pressures(self) -> list[float]:
        return [st["p"] for st in self.steps if st["p"] is not None]

    def is_load_sweep(self) -> bool:
        ps = {round(p, 9) for p in self.pressures() if p > 0}
        taborss = {st["tabor"] for st in self.steps if st["tabor"] is not None}
        return len(ps) >= 3 and len(taborss) <= 1

    def reference_step(self) -> Json | None:
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
    skip = tuple(os.path.join(results_dir, d) + os.sep
                 for d in ("validation", "performance", "scaled-family", "bench", "cluster-measure", "roundoff",
                           "surfaces"))
    runs = []
    for summary in run_folder.read_summaries([d for d in run_folder.find(results_dir)
                                              if not run_folder.summary_path(d).startswith(skip)], notes):
        s, f = summary.data, summary.path
        name = case_name(s)
        in_challenge_dir = os.path.relpath(f, results_dir).startswith("challenge")
        if not (name.startswith("challenge") if name is not None else in_challenge_dir):
            continue
        # The family's runs wherever they were written (scripts/scaled_family.py --results, e.g.
        # results/seeds/seedN/ for other realizations): by case name, not only by folder. Left in,
        # a realization's many coarse grids won the reference-load group (the most grids).
        if name is not None and name.startswith("challenge-scaled"):
            continue
        runs.append(Run(s, summary.folder))
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
                                  any(r.has_result for r, _ in item[1].values())))
    return [by[n] for n in sorted(by)]


def grid_change(pair: list[tuple[Run, Json]], key: str) -> tuple[float, Run, Run] | None:
    """(bands.relative_change of step quantity `key`, coarse run, finer run) between the first two
    of [(run, step)] (coarsest first); None with fewer than two grids or without the change."""
    if len(pair) < 2:
        return None
    (r0, a), (r1, b) = pair[0], pair[1]
    change = bands.relative_change(a.get(key), b.get(key))
    return None if change is None else (change, r0, r1)


def finer_sweep(sweeps: list[tuple[Run, list[Json], Any]], r: Run) -> tuple[Run, list[Json]] | None:
    """The load sweep of r's case on the next finer grid, (run, steps), among _merged_sweeps'
    entries; None if there is none."""
    cands = [(rf, pf) for rf, pf, _ in sweeps if rf.name == r.name and rf.adhesive == r.adhesive and rf.nx > r.nx]
    return min(cands, key=lambda c: c[0].nx) if cands else None


def band_floor(r: Run, key: str) -> tuple[float, str]:
    """(least band, its words) of a load-sweep point of run r, for key "ar" or "gap"
    (bands.sweep_floor, from the run's grid, solver tolerance and rms height)."""
    return bands.sweep_floor(key, r.nx, r.ny, get(r.s, "case", "solver", "tolerance") or 0.0,
                             get(r.s, "surface_facts", "rms_height") or 0.0)


def hardwall_sweep_band(pair: list[tuple[Run, Json]], r: Run, steps: list[Json], key: str,
                        finer: tuple[Run, list[Json]] | None = None) -> tuple[list[float] | None, str]:
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
    if st is None or not run.has_result:
        return {}, st
    try:
        return run_folder.observables(run.folder, run.step(st)).arrays, st
    except ImportError:
        notes.append("h5py is missing (install python3-h5py): fields in result.h5 were not read")
    except run_folder.RunFolderError as e:
        notes.append(f"{e}; its observables were not read")
    return {}, st


def _centers(edges, log):
    e = np.asarray(edges, dtype=float)
    if log and np.all(e > 0):
        return np.sqrt(e[:-1] * e[1:])
    return 0.5 * (e[:-1] + e[1:])


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


def sweep_end_note(r: Run, pts: list[Json]) -> str:
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


def _problem(r):
    return "with adhesion" if r.adhesive else "without adhesion"
