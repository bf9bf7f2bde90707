"""The command scripts/headline_table.py: the README's headline block from the best estimates."""
from __future__ import annotations
import json
import os
import sys

from cmc.analysis.runs import REPO as ROOT
from cmc._types import Json

BEST = os.path.join(ROOT, "reference", "challenge", "best_estimates.json")
BEGIN, END = "<!-- headline:begin -->", "<!-- headline:end -->"


def cell(q: Json | None, scale: float = 1.0, digits: int = 4) -> str:
    if not q or q.get("error") is None:
        return "–"
    return f"{q['value'] * scale:.{digits}g} ± {q['error'] * scale:.2g}"


def block(best: Json) -> list[str]:
    """The block's lines (markers included)."""
    rl = best["reference_load"]
    adh, hw = rl.get("adhesive") or {}, rl.get("hardwall") or {}
    qa, qh = adh.get("quantities", {}), hw.get("quantities", {})
    rows = [("relative contact area a_r", cell(qa.get("a_r")), cell(qh.get("a_r"))),
            ("repulsive contact area", cell(qa.get("a_rep")), "= a_r"),
            ("mean gap (µm)", cell(qa.get("mean_gap"), 1e6, 6), cell(qh.get("mean_gap"), 1e6, 6)),
            ("κ = a_r / p̃", cell(rl.get("kappa_adhesive")), cell(rl.get("kappa_hardwall"))),
            ("grid, strategy, device", f"{adh.get('n')}², {adh.get('strategy')}, {adh.get('device')}",
             f"{hw.get('n')}², {hw.get('strategy')}, {hw.get('device')}")]
    L = [BEGIN, "| at 250 kPa (p̃ = 0.01) | with adhesion (μ_T = 3) | without adhesion |", "|---|---|---|"]
    L += [f"| {a} | {b} | {c} |" for a, b, c in rows]
    r = rl.get("ratio")
    if r:
        L += ["", f"With/without adhesion a_r grows by a factor {r['value']:.3f} ± {r['error']:.2g} (the problem "
                  "definition: κ a little above 3, about 1.5 times the adhesionless one)."]
    ex = best.get("mean_gap_extremum")
    if ex:
        L += [f"The mean gap is smallest at μ_T* = {ex['mu']:.3g} ({ex['mu_range'][0]:.3g} … {ex['mu_range'][1]:.3g}), "
              f"where it is {ex['y'] * 1e6:.5f} ± {ex['y_total_error'] * 1e6:.2g} µm."]
    L += ["", "Generated from `reference/challenge/best_estimates.json` by `scripts/headline_table.py`; errors, runs "
              "and method in `reports/challenge/index.md` after `scripts/main.sh`.", END]
    return L


def main(argv: list[str], doc: str | None = None) -> int:
    check = "--check" in argv
    args = [a for a in argv if a != "--check"]
    path = args[0] if args else os.path.join(ROOT, "README.md")
    text = open(path, encoding="utf-8").read()
    if BEGIN not in text or END not in text:
        print(f"headline_table: {path}: no {BEGIN} ... {END} block", file=sys.stderr)
        return 2
    with open(BEST) as f:
        new = "\n".join(block(json.load(f)))
    i, j = text.index(BEGIN), text.index(END) + len(END)
    if check:
        if text[i:j] != new:
            print(f"headline_table: {path}: the headline block is out of date: run scripts/headline_table.py",
                  file=sys.stderr)
            return 1
        return 0
    out = text[:i] + new + text[j:]
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(out)
    os.replace(tmp, path)
    return 0

