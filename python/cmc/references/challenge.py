"""The command scripts/challenge_reference.py: the challenge reference curves
reference/challenge/<quantity>.csv and their README.md from cmc's own challenge runs (curves,
readme), then the best estimates put into them (apply)."""
from __future__ import annotations
import argparse
import json
import os
import sys

from cmc.analysis.runs import REPO as ROOT
from cmc.report.challenge_runs import _find_runs, _reference_load_runs
from .apply import apply as apply_best_estimates
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


def only_tabor(a: argparse.Namespace, runs: list[Run], hw: Json | None) -> None:
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


def regenerate(a: argparse.Namespace, runs: list[Run], members: list[Run], hw: Json | None, notes: list[str]) -> None:
    """Every curve of both problems from the runs (with --only reference-load items 1, 3, 4, 5 and
    9 alone, the other stored curves kept and read back for the READMEs) and the READMEs."""
    only = a.only == "reference-load"
    written = {}
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
    """scripts/challenge_reference.py: the curves from the runs, then the best estimates put in."""
    a = arguments(argv, doc)
    hw = hardwall_refinement(a.hardwall_refine or os.path.join(a.results, "refine", "reference-load-hardwall"))
    notes: list[str] = []
    runs = usable_runs(a.results, notes)
    if a.only == "tabor":
        only_tabor(a, runs, hw)
    else:
        regenerate(a, runs, member_runs(a.results), hw, notes)
    apply_best(a.out, a.cmc)
    return 0


def apply_best(out: str, cmc: str) -> None:
    """The best estimates (OUT/best_estimates.json, scripts/best_estimates.py) put into the curves
    they decide (cmc.references.apply), after the curves were written from the runs."""
    path = os.path.join(out, "best_estimates.json")
    if not os.path.exists(path):
        print(f"challenge_reference: no {_rel(path)}: the curves keep their runs' values "
              "(scripts/best_estimates.py makes it)", file=sys.stderr)
        return
    with open(path) as f:
        for p in apply_best_estimates(json.load(f), out, cmc):
            print(f"challenge_reference: {_rel(p)} (best estimates)")
