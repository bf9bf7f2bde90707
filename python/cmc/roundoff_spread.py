"""The command scripts/roundoff_spread.py: the round-off spread of the challenge's results from
pairs of runs of one case by two builds or at two thread counts (roundoff_spread.json)."""
from __future__ import annotations
from typing import Any, NoReturn
import argparse
import datetime
import json
import os
import sys

from . import run_folder
from .analysis.runs import REPO as ROOT
from ._types import Json

QUANTITIES = (("contact_fraction", "a_r"), ("repulsive_fraction", "repulsive a_r"), ("mean_gap", "mean gap"))


def fail(msg: str) -> NoReturn:
    sys.exit(f"roundoff_spread.py: {msg}")


def load(folder: str) -> Json:
    try:
        return run_folder.read_summary(folder).data
    except run_folder.RunFolderError as e:
        fail(f"{e} (expected a finished cmc run)")


def value(step: Json, key: str) -> float | None:
    ob = step.get("observables") or {}
    v = ob.get(key, step.get(key))
    return float(v) if isinstance(v, (int, float)) else None


def run_info(folder: str, s: Json) -> Json:
    g = s.get("grid") or {}
    return {"folder": os.path.relpath(os.path.abspath(folder), ROOT), "status": s.get("status"),
            "threads": g.get("threads"), "fft_plans": g.get("fft_plans"),
            "fft_wisdom_fingerprint": g.get("fft_wisdom_fingerprint"),
            "fft_pairs": (s.get("timing") or {}).get("fft_pairs")}


def compare(name: str, a_dir: str, b_dir: str) -> Json:
    a, b = load(a_dir), load(b_dir)
    name_a, name_b = (x.get("case", {}).get("case", {}).get("name") for x in (a, b))
    if name_a != name_b:
        fail(f"{name}: {a_dir} runs case '{name_a}', {b_dir} runs '{name_b}' (expected the same case)")
    ga, gb = a.get("grid") or {}, b.get("grid") or {}
    if (ga.get("nx"), ga.get("ny")) != (gb.get("nx"), gb.get("ny")):
        fail(f"{name}: grids {ga.get('nx')}² and {gb.get('nx')}² differ (expected the same grid)")
    steps = list(zip(a.get("steps") or [], b.get("steps") or []))
    if not steps:
        fail(f"{name}: no load step in common")
    rows: list[Json] = []
    largest: dict[str, dict[str, Any]] = {k: {"relative": 0.0, "step": None} for k, _ in QUANTITIES}
    for sa, sb in steps:
        pa, pb = value(sa, "mean_pressure"), value(sb, "mean_pressure")
        if pa is None or pb is None or abs(pa - pb) > 1e-6 * max(abs(pa), abs(pb)):
            fail(f"{name}: step {sa.get('index')} is at {pa} Pa in one run and {pb} Pa in the other "
                 "(expected the same loads)")
        row = {"step": sa.get("index"), "pressure_Pa": pa, "iterations": [sa.get("iterations"), sb.get("iterations")]}
        for key, _ in QUANTITIES:
            va, vb = value(sa, key), value(sb, key)
            if va is None or vb is None:
                continue
            rel = abs(va - vb) / abs(va) if va else abs(vb)
            row[key] = rel
            if rel > largest[key]["relative"]:
                largest[key] = {"relative": rel, "step": sa.get("index"), "pressure_Pa": pa}
        rows.append(row)
    same = sum(1 for r in rows if all(r.get(k, 0.0) == 0.0 for k, _ in QUANTITIES))
    return {"name": name, "runs": [run_info(a_dir, a), run_info(b_dir, b)], "steps_compared": len(rows),
            "steps_identical": same, "largest": largest, "per_step": rows}


def main(argv: list[str] | None = None, doc: str | None = None) -> None:
    ap = argparse.ArgumentParser(description=(doc or __doc__).split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge", "roundoff_spread.json"))
    ap.add_argument("pairs", nargs="+", metavar="NAME:RUN_A:RUN_B")
    a = ap.parse_args(argv)
    comparisons = []
    for p in a.pairs:
        parts = p.split(":")
        if len(parts) != 3 or not all(parts):
            fail(f"'{p}': expected NAME:RUN_A:RUN_B (a label and two run folders)")
        comparisons.append(compare(*parts))
    overall = {}
    for key, label in QUANTITIES:
        best = max(comparisons, key=lambda c: c["largest"][key]["relative"])
        overall[key] = {"label": label, "relative": best["largest"][key]["relative"], "from": best["name"],
                        "step": best["largest"][key].get("step"), "pressure_Pa": best["largest"][key].get("pressure_Pa")}
    record = {"what": "round-off spread of the challenge's results: the same case by two builds (each plans its FFTs "
                   "at build time) or at two thread counts; largest relative difference per quantity",
           "command": "scripts/roundoff_spread.py " + " ".join(a.pairs),
           "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
           "largest": overall, "comparisons": comparisons}
    tmp = a.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")
    os.replace(tmp, a.out)
    for c in comparisons:
        print(f"{c['name']}: {c['steps_identical']} of {c['steps_compared']} steps with all three to the last bit; largest "
              + ", ".join(f"{label} {c['largest'][k]['relative']:.2g}" for k, label in QUANTITIES), file=sys.stderr)
    print(f"roundoff_spread.py: wrote {a.out}", file=sys.stderr)

