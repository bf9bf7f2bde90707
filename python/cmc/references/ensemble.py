"""The command scripts/ensemble_references.py: the ensemble and realisation references
(reference/challenge/ensemble/, realisation/) and their summary from the seed ensemble's store
and the best estimates (numbers from cmc.analysis.ensemble)."""
from __future__ import annotations
from typing import Iterable
import argparse
import json
import os
import sys

from cmc.analysis import ensemble, runs
from cmc.reference_files import CurveError, write_atomically, write_curve
from cmc.analysis.runs import REPO as ROOT
from cmc._types import Json

STORE = os.path.join(ROOT, "reference", "challenge", "ensemble", "runs.json")
BEST = os.path.join(ROOT, "reference", "challenge", "best_estimates.json")
# (file stem, x column, y column, record key, best-estimate quantity, x key, representation, y unit, words)
CURVES = {
    "contact_area_vs_pressure": ("pressure_Pa", "contact_fraction", "a_r", "a_r", "pressure_Pa", "log-log", "1",
                                 "relative contact area a_r"),
    "mean_gap_vs_pressure": ("pressure_Pa", "mean_gap_m", "mean_gap_m", "mean_gap", "pressure_Pa", "log-lin", "m",
                             "mean gap"),
    "contact_area_vs_tabor": ("tabor", "contact_fraction", "a_r", "a_r", "tabor", "log-lin", "1",
                              "relative contact area a_r"),
    "mean_gap_vs_tabor": ("tabor", "mean_gap_m", "mean_gap_m", "mean_gap", "tabor", "log-lin", "m", "mean gap"),
}
ITEMS = {"contact_area_vs_pressure": 2, "mean_gap_vs_pressure": 8, "contact_area_vs_tabor": 6, "mean_gap_vs_tabor": 7}
X_WORDS = {"pressure_Pa": ("Pa", "mean pressure"), "tabor": ("1", "Tabor coefficient mu_T")}


KINDS = {("hardwall", "load"): "hardwall_load", ("adhesive", "load"): "load", ("adhesive", "tabor"): "tabor"}


def sets_of(records: list[Json], n: int) -> dict[tuple[str, str], list[Json]]:
    """{(problem, curve kind): records on n² points}: the ensemble's sweeps by what they answer."""
    return {k: [r for r in records if r["tag"].startswith(f"ens-{kind}-") and r["n"] == n] for k, kind in KINDS.items()}


def transfers(records: list[Json], main_records: Iterable[Json], n: int, key: str, x_key: str, problem: str,
              kind: str) -> list[Json]:
    """ensemble.transfer_rows of one curve's quantity between n² and (2n)²: the other seeds' finer
    runs from the ensemble's store, seed 28's from the run store (the same case, plain)."""
    fine = [r for r in records if r["tag"].startswith(f"ens-{kind}-") and r["n"] == 2 * n]
    if not fine:
        return []
    case = {"hardwall_load": "challenge-load-sweep-hardwall", "load": "challenge-load-sweep",
            "reference": "challenge-reference", "reference_hardwall": "challenge-hardwall"}.get(kind)
    own = [dict(r, physics=dict(r.get("physics") or {}, **{"surface.seed": ensemble.OWN_SEED}))
           for r in main_records if r.get("case_name") == case and r["n"] == 2 * n and r.get("strategy") == "plain"]
    coarse = [r for r in records if r["tag"].startswith(f"ens-{kind}-") and r["n"] == n]
    return ensemble.transfer_rows(ensemble.table(coarse, key, x_key), ensemble.table(fine + own, key, x_key))


def best_points(best: Json, problem: str, x_key: str) -> list[tuple[float, Json]]:
    """[(x, {quantity: {value, error}})] of seed 28's best estimates for a curve."""
    pts = best["tabor"] if x_key == "tabor" else (best.get("load_sweep") or {}).get(problem) or []
    return [(p[x_key], p["quantities"]) for p in pts if p.get(x_key) is not None]


def corrections(records: list[Json], best: Json, problem: str, x_key: str, key: str, short: str) -> list[ensemble.Correction]:
    """The grid correction of every row where seed 28 has a best estimate and an ensemble run."""
    own = dict(ensemble.table(records, key, x_key, seeds=[ensemble.OWN_SEED]))
    out = []
    for x, q in best_points(best, problem, x_key):
        mine = next((v.get(ensemble.OWN_SEED) for ox, v in own.items() if abs(ox / x - 1) <= 0.01), None)
        got = q.get(short) or {}
        c = ensemble.correction(x, mine, got.get("value"), got.get("error"))
        if c is not None:
            out.append(c)
    return out


def curve(stem: str, problem: str, question: str, rows: list[ensemble.Row], k: float | None, seeds: list[int], n_grid: int,
          date: str) -> Json:
    """The reference curve (cmc.reference_files' dict) of one question's rows."""
    xcol, ycol, _, _, _, rep, yunit, words = CURVES[stem]
    xunit, xwords = X_WORDS[xcol]
    ms = sorted({r.m for r in rows})
    stat = (f"k = {k:.3g} standard errors of the mean over the surfaces" if question == "ensemble" else
            f"k s sqrt(1 + 1/m), k = {k:.3g}, s the surfaces' standard deviation")
    stat += (" (k: the seeds' largest standardised deviation over the rows that 95 % of surfaces stay under, "
             "python/cmc/analysis/ensemble.py: the band holds a whole curve, not one row)")
    what = ("the mean over all surfaces of the challenge's spectrum (for a theory)" if question == "ensemble" else
            "any one surface of the challenge's spectrum, e.g. the organisers' (for a run on a surface of its own)")
    hw = " without adhesion" if problem == "hardwall" else ""
    return {
        "name": stem, "quantity": stem, "x": xcol, "y": ycol, "representation": rep, "band": ycol + "_err",
        "title": f"Challenge item {ITEMS[stem]}: {words} vs {xwords}{hw}, {question} of {ms[-1]} surfaces",
        "estimated_error": (f"band per row: the grid correction's relative error (cmc's own surface, seed "
                            f"{ensemble.OWN_SEED}: its best estimate over its value on {n_grid}^2; where other "
                            f"surfaces were also run on {2 * n_grid}^2, widened by twice the largest difference of "
                            "their refinement factor from seed 28's, ensemble/summary.json transfer) combined in "
                            f"quadrature with {stat}"),
        "columns": [[xcol, xunit, xwords, [r.x for r in rows]], [ycol, yunit, words, [r.value for r in rows]],
                    [ycol + "_err", yunit, "half-width of the error band: " + words, [r.band for r in rows]],
                    ["surfaces", "1", "surfaces behind the row", [r.m for r in rows]]],
        "extra": [("cmc_version", "0.1.0"), ("case_file", "cases/challenge/" + ("tabor-sweep.toml" if xcol == "tabor"
                                                                                else "load-sweep*.toml")),
                  ("grid", f"{n_grid}^2 on each surface, carried to the best estimates' grids by seed "
                           f"{ensemble.OWN_SEED}'s correction"),
                  ("solver_tolerance", "per run, in reference/challenge/ensemble/runs.json"), ("date", date),
                  ("command", "scripts/ensemble.py; scripts/ensemble_store.py; scripts/ensemble_references.py"),
                  ("question", f"{question}: {what}"),
                  ("seeds", f"{ms[0]}" + (f" to {ms[-1]}" if ms[-1] != ms[0] else "")
                            + f" surfaces per row (column surfaces), of surface.seed {seeds[0]}-{seeds[-1]}: "
                              "those run to a converged point there"),
                  ("generator", "scripts/ensemble_references.py (python/cmc/analysis/ensemble.py)")]}


def build(records: list[Json], best: Json, seeds: list[int], n: int, main_records: Iterable[Json] = (),
          ) -> tuple[dict[tuple[str, str, str], tuple[list[ensemble.Row], float | None]], dict[tuple[str, str], list[Json]]]:
    """{(question, problem, stem): (rows, k)} of every curve with two rows or more, and the
    transfer checks {(problem, stem): rows}."""
    out, checked = {}, {}
    for (problem, kind), recs in sets_of(records, n).items():
        for stem, (xcol, _, key, short, x_key, *_rest) in CURVES.items():
            if (x_key == "tabor") != (kind == "tabor"):
                continue
            table = ensemble.table(recs, key, x_key, seeds)
            stats = ensemble.stats(recs, key, x_key, seeds)
            moved = transfers(records, main_records, n, key, x_key, problem, KINDS[(problem, kind)])
            if moved:
                checked[(problem, stem)] = moved
            corr = [ensemble.with_transfer(c, moved) for c in corrections(recs, best, problem, x_key, key, short)]
            # The factor over the rows the reference keeps (those with a correction).
            kept = [s for s in stats if any(abs(c.x / s.x - 1) <= 0.01 for c in corr)]
            k = ensemble.simultaneous_factor(table, kept)
            for question in ("ensemble", "realisation"):
                rows = ensemble.reference_rows(kept, corr, question, k)
                if len(rows) >= 2:
                    out[(question, problem, stem)] = (rows, k)
    return out, checked


def summary(records: list[Json], seeds: list[int], n: int) -> Json:
    """Per curve and row: the ensemble's statistics of the raw values and of the quantities that
    transfer best across surfaces (the mean gap over the rms height)."""
    out = {}
    for (problem, kind), recs in sets_of(records, n).items():
        x_key = "tabor" if kind == "tabor" else "pressure_Pa"
        for key in ("a_r", "a_rep", "mean_gap_m", "mean_gap_over_h_rms"):
            out[f"{problem}/{kind}/{key}"] = [vars(s) for s in ensemble.stats(recs, key, x_key, seeds)]
    return out


def main(argv: list[str] | None, doc: str | None = None) -> int:
    ap = argparse.ArgumentParser(description=(doc or __doc__), formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--store", default=STORE)
    ap.add_argument("--best", default=BEST)
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--seeds", default="1-32", help="the ensemble's seeds (default %(default)s)")
    ap.add_argument("--cmc", default=os.path.join(ROOT, "build", "cmc"))
    ap.add_argument("--runs", default=runs.RUN_STORE, help="the run store, for seed 28's finer grid (default %(default)s)")
    a = ap.parse_args(argv)
    try:
        lo, _, hi = a.seeds.partition("-")
        seeds = list(range(int(lo), int(hi or lo) + 1))
        records = runs.load_store(a.store)
        with open(a.best) as f:
            best = json.load(f)
    except (ValueError, OSError) as e:
        print(f"ensemble_references: {e} (--seeds takes A-B; the store and best estimates must be readable)",
              file=sys.stderr)
        return 2
    grids = [r["n"] for r in records]
    n_grid = max(set(grids), key=grids.count) if grids else 0  # the ensemble's grid: most of its runs
    main_records = runs.load_store(a.runs) if os.path.exists(a.runs) else []
    date = max((r.get("date") or "" for r in records), default="")
    got, checked = build(records, best, seeds, n_grid, main_records)
    try:
        for (question, problem, stem), (rows, k) in sorted(got.items()):
            path = os.path.join(a.out, question, "adhesionless" if problem == "hardwall" else "", stem + ".csv")
            write_curve(a.cmc, curve(stem, problem, question, rows, k, seeds, n_grid, date), path)
            print(f"ensemble_references: {os.path.relpath(path, ROOT)} ({len(rows)} rows)")
    except CurveError as e:
        print(f"ensemble_references: {e}", file=sys.stderr)
        return 1
    rl = best["reference_load"]
    at_p0 = {}
    for problem, kind in (("hardwall", "reference_hardwall"), ("adhesive", "reference")):
        moved = {key: transfers(records, main_records, n_grid, key, "pressure_Pa", problem, kind)
                 for _, key, _ in ensemble.HEADLINE}
        checked.update({(problem, "reference_load/" + key): t for key, t in moved.items() if t})
        at_p0[problem] = ensemble.reference_load_questions(
            [r for r in records if r["tag"].startswith(f"ens-{kind}-") and r["n"] == n_grid], rl.get(problem), seeds,
            rl["p_tilde"], moved)
    write_atomically(os.path.join(a.out, "ensemble", "summary.json"),
                     json.dumps({"generator": "scripts/ensemble_references.py", "seeds": seeds, "reference_load": at_p0,
                                 "grid": n_grid, "rows": summary(records, seeds, n_grid),
                                 "transfer": {f"{p}/{q}": t for (p, q), t in sorted(checked.items())}},
                                indent=1, sort_keys=True) + "\n")
    return 0

