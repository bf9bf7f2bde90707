"""The command scripts/best_estimates.py: the challenge's best estimates
(reference/challenge/best_estimates.json) from the run store and the scaled family's stores,
decided in cmc.analysis.best and cmc.analysis.challenge, and printed."""
from __future__ import annotations
import argparse
import json
import os
import sys

from cmc.analysis import challenge, family, plausibility, runs
from cmc.analysis.runs import REPO as ROOT
from cmc._types import Json

OUT = os.path.join(ROOT, "reference", "challenge", "best_estimates.json")


def _pm(q, scale=1.0, digits=4):
    if not q or q.get("error") is None:
        return "–"
    rel = "" if q.get("relative_error") is None else f" ({100 * q['relative_error']:.2g} %)"
    return f"{q['value'] * scale:.{digits}g} ± {q['error'] * scale:.2g}{rel}"


def describe(est: Json | None) -> list[str]:
    """Lines printed for one estimate."""
    if not est:
        return ["  none (no converged run at this point in the store)"]
    q = est["quantities"]
    return [f"  {est['run']} ({est['n']}², {est['strategy']}, {est['device']})",
            f"    a_r {_pm(q.get('a_r'))}   repulsive a_r {_pm(q.get('a_rep'))}   mean gap {_pm(q.get('mean_gap'), 1e6, 6)} µm"]


def stored_records(path: str) -> tuple[list[Json] | None, str | None]:
    """The store's records; (None, message) where the store cannot be read or holds a record
    with an impossible value (python/cmc/analysis/plausibility.py), which no estimate may use."""
    try:
        records = runs.load_store(path)
    except runs.StoreError as e:
        return None, f"best_estimates: {e}"
    bad = [f"  {r['tag']}: " + "; ".join(p) for r in records for p in [plausibility.record_problems(r)] if p]
    if bad:
        return None, f"best_estimates: {path}: records with impossible values (remove them):\n" + "\n".join(bad)
    return records, None


def main(argv: list[str] | None, doc: str | None = None) -> int:
    ap = argparse.ArgumentParser(description=(doc or __doc__), formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--store", default=runs.RUN_STORE, help="the run store (default: %(default)s)")
    ap.add_argument("--family", default=family.FAMILY_STORE, help="the scaled family's store (default: %(default)s)")
    ap.add_argument("--out", default=OUT, help="where to write (default: %(default)s)")
    ap.add_argument("--any-physics", action="store_true",
                    help="use every stored run, not only those of the challenge's physics (tests at scaled-down grids)")
    a = ap.parse_args(argv)
    if not os.path.isfile(a.store):
        print(f"best_estimates: {a.store}: no run store (store runs with scripts/store_runs.py or scripts/gpu/store.py)",
              file=sys.stderr)
        return 2
    store_dir = os.path.dirname(a.family)
    records, refused = stored_records(a.store)
    if refused or records is None:
        print(refused, file=sys.stderr)
        return 2
    data = challenge.build(records, family.measured_members(a.family),
                           family.condition_members(store_dir), physics=None if a.any_physics else challenge.PHYSICS)
    data = {"generator": "scripts/best_estimates.py (python/cmc/analysis/challenge.py)",
            "run_store": os.path.relpath(a.store, ROOT), "family_store": os.path.relpath(a.family, ROOT), **data}
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = f"{a.out}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, a.out)
    rl = data["reference_load"]
    lines = ["250 kPa with adhesion (mu_T = 3):"] + describe(rl["adhesive"]) + ["250 kPa, hard wall:"] + describe(rl["hardwall"])
    if rl.get("ratio"):
        lines.append(f"kappa {_pm(rl.get('kappa_adhesive'))} with adhesion, {_pm(rl.get('kappa_hardwall'))} without; "
                     f"ratio {_pm(rl['ratio'])}")
    lines.append(f"Tabor sweep: {len(data['tabor'])} points with a best estimate")
    ex = data["mean_gap_extremum"]
    lines.append("mean gap minimum: " + ("not bracketed by the stored points" if not ex else
                 f"mu_T* = {ex['mu']:.3g} ({ex['mu_range'][0]:.3g} .. {ex['mu_range'][1]:.3g}), "
                 f"mean gap {1e6 * ex['y']:.5f} ± {1e6 * ex['y_total_error']:.2g} µm"))
    print("\n".join(lines))
    print(f"best_estimates: wrote {os.path.relpath(a.out, ROOT)}", file=sys.stderr)
    return 0

