"""The command scripts/scaled_family.py: runs the scaled challenge family's members (runs) and
merges them into its store (store); --reestimate recomputes the store's estimates only."""
from __future__ import annotations
import argparse
import datetime
import json
import math
import os
import sys

from ..analysis.family import adhesionless, challenge_estimates, member_reference, seed_members
from ..analysis.runs import REPO as ROOT
from ..analysis.s_route import s_extrapolation
from .runs import (CASE, CASE_HW, L, LAMBDA_S1, STRATEGY, W1, condition_name, condition_sets, condition_words,
                   grids, job, job_folder, record, rho_of, run_jobs)
from .store import write_store
from cmc._types import Json


def arguments(argv: list[str] | None, doc: str) -> argparse.Namespace:
    """The command's options (scripts/scaled_family.py, whose usage text is `doc`)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--s", type=int, nargs="+", default=[32, 16])
    ap.add_argument("--coarse", type=float, nargs="*", default=[2.0, 4.0],
                    help="coarse spacings dx = k rho(s) to run plain and with the strategy (default 2 4)")
    ap.add_argument("--grids", type=int, nargs="*", default=[], help="explicit grids, plain and with the strategies")
    ap.add_argument("--strategies", nargs="*", default=list(STRATEGY), choices=list(STRATEGY),
                    help="the coarse-grainings to run beside the plain runs (default: all)")
    ap.add_argument("--no-resolved", action="store_true", help="skip the resolved and refinement grids")
    ap.add_argument("--refinement-only", action="store_true",
                    help="of the resolved and refinement grids, run only the refinement grid (and the hard wall on it "
                         "and on half of it): a member whose resolved run takes too long for one sitting (s = 8)")
    ap.add_argument("--start-resolved", action="store_true",
                    help="start the resolved grid's run from the refinement grid's answer (cmc run --start-from; "
                         "the refinement run then writes its fields, into nN-fields): the resolved run takes about "
                         "0.6 of a cold start's FFT pairs")
    ap.add_argument("--max-outer-resolved", type=int, default=None, metavar="N",
                    help="the resolved run's cap on outer steps (solver.max_outer_steps): a resumed run may lower it "
                         "to just above where it stands, and stops there unconverged "
                         "(docs/user-guide/command-line.md)")
    ap.add_argument("--no-plain", action="store_true",
                    help="skip the plain runs of --coarse and --grids (e.g. to store a strategy's run on a grid whose "
                         "plain run is not made yet; --store keeps the stored plain runs)")
    ap.add_argument("--no-hardwall", action="store_true",
                    help="skip the hard-wall runs (the resolved and refinement grids, or the two finest --grids)")
    ap.add_argument("--results", default="results/scaled-family")
    ap.add_argument("--store", default=None, help="write scaled_family.json and README.md here")
    ap.add_argument("--cmc", default="build/cmc")
    ap.add_argument("--set", action="append", default=[],
                    help="extra cmc --set override for every adhesive run (not the hard-wall ones)")
    ap.add_argument("--seed", type=int, default=None,
                    help="another realization of the surface (surface.seed; the case file's is 28): set on every run, "
                         "the hard-wall ones included, and recorded in the store, which refuses to merge members of "
                         "different seeds. Store each seed apart (e.g. reference/challenge-scaled/seeds/seedN)")
    ap.add_argument("--tabor", type=float, default=None, metavar="MU",
                    help="another Tabor parameter than the case's 3 (interaction.tabor): a condition of the challenge's "
                         "Tabor sweep; its runs go to RESULTS/conditions/<condition>/, its store holds that condition only")
    ap.add_argument("--pressure", type=float, default=None, metavar="PA",
                    help="another load than 250 kPa (loading.values, Pa): a point of the challenge's load sweep; "
                         "as --tabor, the hard-wall runs included")
    ap.add_argument("--dry-run", action="store_true", help="print the runs, run nothing")
    ap.add_argument("--reestimate", action="store_true",
                    help="run nothing: recompute the challenge's error bars in --store from the members stored there "
                         "and the other realizations in STORE/seeds/ (after storing a new realization), and rewrite "
                         "its scaled_family.json and README.md")
    return ap.parse_args(argv)


def reestimate(a: argparse.Namespace) -> None:
    """--reestimate: the challenge's error bars in --store recomputed from the members stored there."""
    if not a.store:
        sys.exit("scaled_family: --reestimate needs --store (the family store whose estimates to recompute)")
    path = os.path.join(ROOT, a.store, "scaled_family.json")
    if not os.path.isfile(path):
        sys.exit(f"scaled_family: --reestimate: no {path} (expected a store written with --store)")
    with open(path, encoding="utf-8") as f:
        data = json.load(f)
    challenge_estimates(data["members"], seed_members(os.path.join(ROOT, a.store)))
    write_store(a.store, data)
    print(f"scaled_family: recomputed the estimates of {a.store}", file=sys.stderr)


def checked_conditions(a: argparse.Namespace) -> tuple[str | None, list[str], list[str]]:
    """The realization and condition of this invocation, refused where --set gives them: returns
    (condition name or None, the adhesive runs' overrides, the hard-wall runs' overrides); with a
    condition, a.results becomes its own folder."""
    seed_set = [f"surface.seed={a.seed}"] if a.seed is not None else []
    if any(x.split("=")[0].strip() == "surface.seed" for x in a.set):
        sys.exit("scaled_family: give a realization with --seed N (it reaches the hard-wall runs and the store too), "
                 "not --set surface.seed=N")
    for key, opt in (("interaction.tabor", "--tabor MU"), ("loading.values", "--pressure PA")):
        if any(x.split("=")[0].strip() == key for x in a.set):
            sys.exit(f"scaled_family: give a condition with {opt} (it names the results folder and the store), "
                     f"not --set {key}=...")
    if a.tabor is not None and not (a.tabor > 0 and math.isfinite(a.tabor)):
        sys.exit(f"scaled_family: --tabor {a.tabor}: expected a positive Tabor parameter")
    if a.pressure is not None and not (a.pressure > 0 and math.isfinite(a.pressure)):
        sys.exit(f"scaled_family: --pressure {a.pressure}: expected a positive mean pressure in Pa")
    condition = condition_name(a.tabor, a.pressure)
    if condition:
        a.results = os.path.join(a.results, "conditions", condition)
    adhesive_set = seed_set + condition_sets(a.tabor, a.pressure)
    hardwall_set = seed_set + condition_sets(a.tabor, a.pressure, adhesion=False)
    return condition, adhesive_set, hardwall_set


def member_jobs(a: argparse.Namespace, s: int, g: dict[str, int], adhesive_set: list[str],
                hardwall_set: list[str]) -> list[Json]:
    """The runs of member s on its grids g (role -> n), adhesive and hard-wall."""
    jobs = []
    for role in g:
        strategy = role.split("_")[0] if role.split("_")[0] in STRATEGY else None
        suffix = f"-{strategy}" if strategy else ""
        extra, options = adhesive_set + a.set + (STRATEGY[strategy] if strategy else []), []
        if a.start_resolved and role == "refinement":
            suffix, extra = suffix + "-fields", extra + ["output.fields=true"]
        if a.start_resolved and role == "resolved":  # from the refinement run's answer
            options = ["--start-from", os.path.join(a.results, f"s{s}", f"n{g['refinement']}-fields")]
        if a.max_outer_resolved is not None and role == "resolved":
            extra = extra + [f"solver.max_outer_steps={a.max_outer_resolved}"]
        jobs.append(job(role, g[role], suffix, extra, options=options))
    # The same surface under the hard wall on the two finest grids (the second route's
    # denominator; a hard-wall solve costs little beside the adhesive one).
    if not a.no_hardwall:
        hw_grids = ({"hardwall_refinement": g["refinement"], "hardwall_resolved": g["resolved"]}
                    if "resolved" in g else
                    {f"hardwall_n{g['refinement'] // 2}": g["refinement"] // 2, "hardwall_refinement": g["refinement"]}
                    if "refinement" in g else {f"hardwall_n{n}": n for n in sorted(a.grids)[-2:]})
        jobs += [job(role, n, "-hardwall", hardwall_set, case=CASE_HW) for role, n in hw_grids.items()]
    return jobs


def run_member(a: argparse.Namespace, s: int, adhesive_set: list[str], hardwall_set: list[str]) -> Json:
    """Runs member s (resumable) and returns its record: its runs and reference."""
    rho = rho_of(a.cmc, s, adhesive_set + a.set)
    g = grids(rho, a.coarse, a.grids, not a.no_resolved, a.strategies, lambda_s=s * LAMBDA_S1)
    if a.no_plain:
        g = {role: n for role, n in g.items() if not role.startswith("plain_")}
    if a.refinement_only:
        g.pop("resolved", None)
    print(f"scaled_family: s = {s}: rho = {rho * 1e9:.4g} nm, grids "
          + ", ".join(f"{k} {v}² (dx = {L / v / rho:.2f} rho)" for k, v in g.items()), file=sys.stderr)
    jobs = member_jobs(a, s, g, adhesive_set, hardwall_set)
    commands = run_jobs(a.cmc, a.results, s, jobs, a.dry_run)
    runs = [] if a.dry_run else [record(job_folder(a.results, s, j), j["role"], j["n"], rho, cmd)
                                 for j, cmd in zip(jobs, commands)]
    m = {"s": s, "lambda_s_m": s * LAMBDA_S1, "w_J_m2": s * W1, "rho_m": rho, "runs": runs, "reference": {},
         "adhesionless": adhesionless(runs)}
    if a.seed is not None:
        m["seed"] = a.seed
    if a.tabor is not None:
        m["tabor"] = a.tabor
    if a.pressure is not None:
        m["pressure_Pa"] = a.pressure
    by = {r["role"]: r for r in runs}
    if "resolved" in by and "refinement" in by:
        m["reference"] = member_reference(by["resolved"], by["refinement"])
    return m


def store_members(a: argparse.Namespace, members: list[Json], condition: str | None) -> None:
    """Merges this invocation's members into STORE/scaled_family.json and rewrites its README."""
    path = os.path.join(ROOT, a.store, "scaled_family.json")
    old = {}
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            old = {m["s"]: m for m in json.load(f).get("members", [])}
    for m in members:
        prev = old.get(m["s"])
        if prev and prev.get("seed") != m.get("seed"):
            sys.exit(f"scaled_family: {path} holds s = {m['s']} of surface seed {prev.get('seed', 'of the case file')}, "
                     f"this invocation seed {m.get('seed', 'of the case file')}: store each realization apart")
        if prev and (prev.get("tabor"), prev.get("pressure_Pa")) != (m.get("tabor"), m.get("pressure_Pa")):
            sys.exit(f"scaled_family: {path} holds s = {m['s']} at {condition_words(prev)}, this invocation "
                     f"{condition_words(m)}: store each condition apart (e.g. reference/challenge-scaled/conditions/"
                     f"{condition or 'NAME'})")
        if prev:  # keep the roles this invocation did not run
            roles = {r["role"] for r in m["runs"]}
            m["runs"] = [r for r in prev["runs"] if r["role"] not in roles] + m["runs"]
            if not m["reference"]:
                m["reference"] = prev.get("reference", {})
            m["adhesionless"] = adhesionless(m["runs"])
        old[m["s"]] = m
    merged = [old[s] for s in sorted(old, reverse=True)]
    for m in merged:
        m["runs"].sort(key=lambda r: (r["role"].split("_")[0] not in ("resolved", "refinement"), -r["n"], r["role"]))
    # A realization's or a condition's own store measures nothing for the challenge: only the
    # family store's estimates take the other realizations in.
    challenge_estimates(merged, seed_members(os.path.join(ROOT, a.store)) if a.seed is None and not condition else ())
    data = {"generator": "scripts/scaled_family.py", "case_file": CASE, "case_file_hardwall": CASE_HW,
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "load_Pa": a.pressure or 250e3, "members": merged, "s_extrapolation": s_extrapolation(merged)}
    write_store(a.store, data)
    print(f"scaled_family: wrote {a.store}/scaled_family.json and README.md", file=sys.stderr)


def main(argv: list[str] | None, doc: str) -> int:
    """scripts/scaled_family.py."""
    a = arguments(argv, doc)
    if a.reestimate:
        reestimate(a)
        return 0
    condition, adhesive_set, hardwall_set = checked_conditions(a)
    members = [run_member(a, s, adhesive_set, hardwall_set) for s in a.s]
    if a.store and not a.dry_run:
        store_members(a, members, condition)
    return 0
