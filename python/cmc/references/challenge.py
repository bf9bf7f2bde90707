"""The command scripts/challenge_reference.py: the challenge reference curves
reference/challenge/<quantity>.csv and their README.md from cmc's own challenge runs (curves,
readme), then the best estimates put into them (apply)."""
from __future__ import annotations
import argparse
import json
import os
import sys
from dataclasses import dataclass, field

from cmc.analysis.runs import REPO as ROOT
from cmc.report.challenge_runs import _find_runs, _reference_load_runs
from .apply import apply as apply_best_estimates, update_readme
from .curves import distribution_pair, load_sweep_curves, member_runs, reference_load_curves, tabor_curves
from .provenance import _rel, hardwall_refinement, write_atomically, write_curve
from .readme import ALL, readme, readme_adhesionless, stored_curve
from cmc._types import Json
from cmc.report.challenge_runs import Run


def write_curves(cmc: str, curves: list[Json], out: str) -> None:
    """Has cmc write each curve to OUT/<quantity>.csv and says so."""
    for c in curves:
        path = os.path.join(out, c["quantity"] + ".csv")
        text = write_curve(cmc, c, path)
        print(f"challenge_reference: {_rel(path)}: {len(c['columns'][0][3])} points, {len(text)} bytes")


def kept_curves(out: str, curves: list[Json]) -> list[Json]:
    """The stored curves of `out` other than `curves`' quantities, read back (stored_curve)."""
    new = {c["quantity"] for c in curves}
    kept = [stored_curve(os.path.join(out, q + ".csv"), q, item) for q, item in ALL if q not in new]
    return [c for c in kept if c is not None]


# The quantities whose stored curves the best estimates rewrite (apply): with best_estimates.json
# the READMEs describe those curves as stored after that, not as the runs at hand made them.
DECIDED = ("contact_area_vs_pressure", "mean_gap_vs_pressure", "contact_area_vs_tabor", "mean_gap_vs_tabor")


@dataclass
class ReadmePlan:
    """What one README is written from once the curves are final: its problem, folder, the curves
    computed from the runs, and (adhesive) the run behind items 1, 3, 4, 5 and 9."""
    adhesive: bool
    out: str
    curves: list[Json]
    keep_from: str | None = None
    dist: list = field(default_factory=list)
    ref_step: Json | None = None
    pair: list = field(default_factory=list)


def only_tabor(a: argparse.Namespace, runs: list[Run], hw: Json | None) -> list[ReadmePlan]:
    """--only tabor: items 6 and 7 from the Tabor sweep's runs, the other stored curves kept."""
    curves = tabor_curves([r for r in runs if r.name.startswith("challenge-tabor")], hw)
    if len(curves) != 2:
        sys.exit("challenge_reference: --only tabor: no Tabor sweep with its runs under "
                 f"{_rel(a.results)}/challenge-tabor-sweep/ (scripts/tabor_sweep.sh makes them)")
    write_curves(a.cmc, curves, a.out)
    if next((c for c in kept_curves(a.out, curves) if c["item"] == 9), None) is None:
        sys.exit("challenge_reference: --only tabor: the stored reference-load curves are missing; "
                 "regenerate everything (without --only)")
    # The README's reference-load paragraph and hard-wall table come from their runs; without
    # them, the stored README's paragraphs are kept as they are and only the parts that depend
    # on the curves are rewritten.
    return [ReadmePlan(True, a.out, curves, keep_from=os.path.join(a.out, "README.md"))]


def regenerate(a: argparse.Namespace, runs: list[Run], members: list[Run], hw: Json | None,
               notes: list[str]) -> list[ReadmePlan]:
    """Every curve of both problems from the runs (with --only reference-load items 1, 3, 4, 5 and
    9 alone, the other stored curves kept); returns the READMEs to write."""
    only = a.only == "reference-load"
    plans: list[ReadmePlan] = []
    for adhesive in (True, False):
        out = a.out if adhesive else os.path.join(a.out, "adhesionless")
        pair = _reference_load_runs(runs, adhesive)
        dist = distribution_pair(runs + members, adhesive)
        curves: list[Json] = []
        ref_step: Json | None = None
        if dist:
            curves, ref_step = reference_load_curves(dist[-1][0], hw, notes, dist[0] if len(dist) > 1 else None)
        if not only:
            curves += load_sweep_curves(runs, hw, adhesive, pair)
            curves += tabor_curves([r for r in runs if r.name.startswith("challenge-tabor")], hw) if adhesive else []
        if only and not curves:
            continue
        write_curves(a.cmc, curves, out)
        plans.append(ReadmePlan(adhesive, out, curves, os.path.join(out, "README.md") if only else None,
                                dist, ref_step, pair))
    for n in notes:
        print("challenge_reference: note: " + str(n), file=sys.stderr)
    if only and not plans:
        sys.exit(f"challenge_reference: --only reference-load: no run at 250 kPa with observables under {_rel(a.results)}")
    if not only and not any(p.adhesive and p.curves for p in plans):
        sys.exit("challenge_reference: no curves: no adhesive challenge run with observables found")
    return plans


def shown_curves(plan: ReadmePlan, best: Json | None) -> list[Json]:
    """The curves a README describes: those computed here, the ones the best estimates decided
    (best) and, with --only, the other stored ones, as stored (read back)."""
    decided = set(DECIDED) if best else set()
    own = [c for c in plan.curves if c["quantity"] not in decided]
    if plan.keep_from:
        return kept_curves(plan.out, own) + own
    back = [stored_curve(os.path.join(plan.out, q + ".csv"), q, item) for q, item in ALL if q in decided]
    return own + [c for c in back if c is not None]


def write_readme(plan: ReadmePlan, hw: Json | None, best: Json | None) -> None:
    """One README from its plan, once the curves are final (after the best estimates went in)."""
    path = os.path.join(plan.out, "README.md")
    shown = shown_curves(plan, best)
    dist = plan.dist
    if plan.adhesive:
        ref = dist[-1][0] if dist else None
        text = readme(shown, plan.out, hw, ref, plan.ref_step, keep_from=plan.keep_from,
                      keep_bands=plan.keep_from is not None, coarser=dist[0] if len(dist) > 1 else None,
                      best=best is not None)
    else:
        text = readme_adhesionless(shown, plan.pair, dist, best=best is not None)
    write_atomically(path, text)
    if plan.adhesive and best is not None:
        update_readme(path, best)
    print(f"challenge_reference: {_rel(path)}" + (" (the other curves kept)" if plan.keep_from else ""))


def arguments(argv: list[str] | None, doc: str) -> argparse.Namespace:
    """The command's options (scripts/challenge_reference.py, whose usage text is `doc`)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", choices=["tabor", "reference-load"], default=None,
                    help="tabor: recompute items 6 and 7 (the Tabor sweep: its runs and the family's stores) only; "
                         "reference-load: items 1, 3, 4, 5 and 9 (the runs at 250 kPa with observables) of both "
                         "problems only. The other stored curves are kept as they are and read back for the README, "
                         "so that their runs need not be at hand (e.g. after the family was run at another mu_T)")
    ap.add_argument("--results", default=os.path.join(ROOT, "results"))
    ap.add_argument("--hardwall-refine", default=None, help="default: RESULTS/refine/reference-load-hardwall")
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--cmc", default=os.path.join(ROOT, "build", "cmc"), help="the cmc that formats the curves")
    return ap.parse_args(argv)


def usable_runs(results: str, notes: list[str]) -> list[Run]:
    """The report's discovery: every RESULTS/**/summary.json of a challenge case (not the scaled
    family). A load sweep whose last steps did not converge still gives its converged steps (the
    sweep curves keep only those and say how many); a single run must converge."""
    return [r for r in _find_runs(results, notes)
            if r.status == "converged" or (r.status == "not_converged" and r.is_load_sweep())]


def main(argv: list[str] | None, doc: str) -> int:
    """scripts/challenge_reference.py: the curves from the runs, the best estimates put in, then
    the READMEs describing the curves as stored."""
    a = arguments(argv, doc)
    hw = hardwall_refinement(a.hardwall_refine or os.path.join(a.results, "refine", "reference-load-hardwall"))
    notes: list[str] = []
    runs = usable_runs(a.results, notes)
    if a.only == "tabor":
        plans = only_tabor(a, runs, hw)
    else:
        plans = regenerate(a, runs, member_runs(a.results), hw, notes)
    best = apply_best(a.out, a.cmc)
    for plan in plans:
        write_readme(plan, hw, best)
    return 0


def apply_best(out: str, cmc: str) -> Json | None:
    """The best estimates (OUT/best_estimates.json, scripts/best_estimates.py) put into the curves
    they decide (cmc.references.apply), after the curves were written from the runs; returns
    them, or None where there are none."""
    path = os.path.join(out, "best_estimates.json")
    if not os.path.exists(path):
        print(f"challenge_reference: no {_rel(path)}: the curves keep their runs' values "
              "(scripts/best_estimates.py makes it)", file=sys.stderr)
        return None
    with open(path) as f:
        best = json.load(f)
    for p in apply_best_estimates(best, out, cmc):
        print(f"challenge_reference: {_rel(p)} (best estimates)")
    return best
