"""The scaled family's store: STORE/scaled_family.json and its README.md, each written
atomically; the README says what every member's runs measured and how far to trust it."""
from __future__ import annotations
import json
import os
import tempfile

from ..analysis.conditions import condition_checks
from ..analysis.family import (FAMILY_QUANTITIES as QUANTITIES, condition_members, deviation, seed_members,
                               strategy_run_near)
from ..analysis.runs import REPO as ROOT
from ..analysis.transfer import STRATEGY_TARGETS, meets_target
from ..report.common import condition_check_lines, condition_summary, s_extrapolation_verdict
from .runs import CASE_HW, STRATEGY, condition_words
from cmc._types import Json


def atomic_write(path: str, text: str) -> None:
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".tmp-")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def write_store(store: str, data: Json) -> None:
    """STORE/scaled_family.json and the README.md made from it, each written atomically."""
    atomic_write(os.path.join(ROOT, store, "scaled_family.json"), json.dumps(data, indent=1) + "\n")
    atomic_write(os.path.join(ROOT, store, "README.md"), readme(data, os.path.join(ROOT, store)))


def _member_lines(m):
    """One member's section: its reference, and every run with its deviation from it."""
    lines = []
    ref = m["reference"]
    lines += [f"## s = {m['s']}: λ_s = {m['lambda_s_m'] * 1e6:.3g} µm, w = {m['w_J_m2']:.3g} J/m², "
              f"ρ = {m['rho_m'] * 1e9:.4g} nm"
              + (f", surface seed {m['seed']} (another realization: every run has --set surface.seed={m['seed']})"
                 if "seed" in m else ""), "",
              "| quantity | reference | refinement error | relative |", "|---|---|---|---|"]
    for _, short, unit in QUANTITIES:
        q = ref.get(short)
        if q:
            rel = q["refinement_error"] / abs(q["value"]) if q["value"] else float("nan")
            lines.append(f"| {short} ({unit}) | {q['value']:.6g} | {q['refinement_error']:.3g} | {100 * rel:.2f} % |")
    res = next((r for r in m["runs"] if r["role"] == "resolved"), None)
    if ref and res and res["status"] != "converged":
        lines += ["", f"**The resolved run did not reach its tolerance**: {res['status']}, "
                      f"\"{res.get('message') or 'no message'}\". The loading-branch iteration is monotone (gaps "
                      "only fall, points only join the contact), so the converged a_r is at least the stored one and "
                      "the converged mean gap at most; how far the creep would still move them is not known from "
                      "the run (docs/theory/coarse-graining.md gives what its checkpoints showed)."]
    lines += ["", "| run | grid | dx/ρ | a_r | repulsive a_r | mean gap (m) | iterations | FFT pairs | wall (s) | status |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in m["runs"]:
        dev = ""
        if r["role"].split("_")[0] in ("plain",) + tuple(STRATEGY) and ref.get("a_r"):
            da, dg = deviation(r, ref, "a_r"), deviation(r, ref, "mean_gap")
            dev = f" ({100 * da:+.1f} %, gap {100 * dg:+.2f} %)"
            for k, (ta, tg) in STRATEGY_TARGETS.items():
                if any(strategy_run_near(r, st, k) for st in STRATEGY):
                    dev += (" target " + ("met" if meets_target(k, da, dg) else "NOT met")
                            + f" (±{100 * ta:g} %, ±{100 * tg:g} %)")
        lines.append(f"| {r['role']}{dev} | {r['n']}² | {r['dx_over_rho']:.2f} | {r['a_r']:.6g} | {r['a_rep']:.6g} | "
                     f"{r['mean_gap']:.7g} | {r['iterations']} | {r['fft_pairs']:.0f} | {r['wall_s']:.0f} | {r['status']} |")
    lines.append("")
    return lines


def _estimate_lines(m):
    """One member's strategy runs with the strategy's error measured on the family."""
    lines = []
    if m.get("estimates"):
        lines += [("No grid here resolves this member" if m["s"] == 1 else
                   "This member's resolved run is not stored yet (it is computed on a grid with dx ≤ 0.8 ρ, "
                   "like the others)") + "; the strategy's runs with the strategy's error measured on the "
                  "family at the same dx/ρ (largest |deviation| from a member's reference plus that reference's "
                  "refinement error, over the members here and those of the other realizations in `seeds/`; `—`: "
                  "no member has a run at that dx/ρ):", "",
                  "| grid | dx/ρ | a_r | repulsive a_r | mean gap (m) | error measured on |", "|---|---|---|---|---|---|"]
        for e in m["estimates"]:
            cells = []
            for _, short, _ in QUANTITIES:
                q = e[short]
                cells.append(f"{q['value']:.4g}" + (f" ± {q['error']:.2g}" if q["error"] is not None else " ± —"))
            lines.append(f"| {e['n']}² ({e['role']}) | {e['dx_over_rho']:.1f} | " + " | ".join(cells)
                         + f" | {'; '.join(e['measured_on']) or '—'} |")
        lines.append("")
    return lines


def readme(data: Json, store_dir: str) -> str:
    """STORE/README.md's text from the store's data."""
    lines = ["# Scaled challenge family: converged adhesive references", "",
             "Generated by `/usr/bin/python3 scripts/scaled_family.py --store reference/challenge-scaled` "
             "from the runs' `summary.json`; do not edit by hand. Every run, with its command, is in "
             "`scaled_family.json`.", "",
             "Member s of the family is the challenge (`cases/challenge/scaled-family.toml`) with the short "
             "cutoff λ_s = s × 0.1 µm and the work of adhesion w = s × 50 mJ/m², "
             + (condition_words(data["members"][0]) if data["members"] else "μ_T = 3, at 250 kPa")
             + " (ρ(s) from the surface's R_c), on the loading branch (solver `quasi_static`). ρ/λ_s, w/(E\\*ρ) and "
             "μ_T are the challenge's at that condition; only the bandwidth shrinks.", ""]
    if data["members"] and ("tabor" in data["members"][0] or "pressure_Pa" in data["members"][0]):
        lines += ["**Another condition than the challenge's** (μ_T = 3, 250 kPa): a point of the challenge's "
                  "Tabor sweep or load sweep, whose error bands are the family's error measured at μ_T = 3 and "
                  "250 kPa. This store checks whether they hold here (`python/cmc/analysis/conditions.py`, "
                  "`condition_checks`; the family's README and the challenge report print the check); where it "
                  "measures a larger error, the "
                  "sweep's reference takes that as its band (`run_band`, `load_bands`).", ""]
    lines += [
             "**Reference** = the run on the resolved grid (dx ≤ 0.8 ρ(s)). **Refinement error** = |resolved − "
             "refinement| (the same case on half the points): it bounds the resolved grid's own error if the error "
             "falls at least linearly with dx (for order p it is |difference| / (2^p − 1)). The plain coarse runs "
             "(dx ≈ 2 ρ and 4 ρ, the unmodified exponential law sampled at grid points) show what a coarse grid "
             "gives without a resolution strategy; their deviation is from the reference. The `range` and `shape` "
             "runs use the two resolution strategies, `[interaction] coarse_graining`: `\"range\"` lengthens ρ to "
             "√(2w/K_ii) where a grid point would be bistable, keeping w (so the peak tension and the Tabor parameter "
             "fall); `\"shape\"` keeps w and the peak tension w/ρ (so μ_T) and gives the law the least curvature "
             "that leaves no point bistable, a linear head of slope K_ii/2 joined to an exponential tail, or where "
             "even that is bistable the triangle with a lower peak. Both with a margin of 2 in stiffness; "
             "derivations and citations in `solver/cmc/contact/Interaction.hpp`. "
             "The targets for a strategy: a_r within 3 % and 6 %, mean gap within 0.5 % and 1 % of the "
             "reference at dx = 2 ρ and 4 ρ; the table below says which each meets.", ""]
    for m in data["members"]:
        lines += _member_lines(m) + _estimate_lines(m)
    main_store = not any(k in m for m in data["members"] for k in ("seed", "tabor", "pressure_Pa"))
    if main_store:
        lines += condition_lines(store_dir, data["members"])
    lines += s_route_lines(data.get("s_extrapolation"))
    return "\n".join(lines)


def condition_lines(store_dir: str, members: list[Json]) -> list[str]:
    """The family store's section on the bands at other conditions (the stores of --tabor and
    --pressure in STORE/conditions/): measured deviation against the band taken at mu_T = 3 from
    this store's members and its other realizations (STORE/seeds/)."""
    rows = condition_checks(condition_members(store_dir), reference=list(members) + seed_members(store_dir))
    lines = ["## The bands at other conditions", ""]
    if not rows:
        return lines + ["Not measured yet: the challenge's Tabor sweep and load sweep take their bands from the "
                        "family at μ_T = 3 and 250 kPa; `--tabor MU` and `--pressure PA` (with "
                        "`--store reference/challenge-scaled/conditions/NAME`) measure them at other points.", ""]
    lines += ["The challenge's Tabor sweep and load sweep (items 2, 6, 7, 8) take their error bands from the family "
              "at μ_T = 3 and 250 kPa, at each point's dx/ρ. The same member run at another μ_T or load "
              "(`scripts/scaled_family.py --s 32 --tabor MU` or `--pressure PA`, each with its own resolved reference, "
              "stores in `conditions/`) measures whether that band holds there. Each row: a coarse run's deviation "
              "from that condition's reference (in brackets the reference's own refinement error) against the band "
              "the references take at that dx/ρ; \"band holds\" when |deviation| plus the refinement error is "
              "within it. The coarse grids are the challenge's 2048² and 4096² at that condition in dx/ρ (and "
              "dx/λ_s), and 2 ρ and 4 ρ where μ_T ≥ 1.", ""]
    lines += condition_check_lines(rows, ("plain",) + tuple(STRATEGY))
    summary = condition_summary(rows)
    lines += ([summary, ""] if summary else []) + [
        "The sweeps' references (`reference/challenge/`, `scripts/challenge_reference.py`) take the larger of the "
        "two errors as their band: the Tabor sweep's at each μ_T measured here, the load sweep's per load "
        "(interpolated in log p between the loads measured here and 250 kPa, held beyond them; "
        "`python/cmc/analysis/conditions.py`, `load_bands`).", ""]
    return lines


def s_route_lines(x: Json | None) -> list[str]:
    """README lines for the second route (cmc.analysis.s_route s_extrapolation)."""
    lines = ["## Second route to the challenge: extrapolation in s", ""]
    if not x:
        return lines + ["Not computed: it needs two members with a reference and a hard-wall value "
                        "(`--s 32 16`) and the challenge's hard-wall runs (`--s 1 --no-resolved --grids 2048 4096`).", ""]
    sa, sb = x["members"][:2]
    members = sorted(x["members"], reverse=True)
    lines += [f"Each member's adhesive reference over its adhesionless value (the same surface under the hard wall, "
              f"`{CASE_HW}`: a_r perimeter-corrected, on the two finest grids), R(s), extrapolated to s = 1 on two "
              f"lines through s = {sa} and {sb}, one in log s and one in s, times the challenge's hard-wall value. "
              "Along the family only the bandwidth λ_r/λ_s changes; the ratio carries what adhesion adds. Value: the "
              "midpoint of the two lines; error: the model error (half their distance where a third member's held-out "
              "check finds them bracketing the curve, else their whole distance), the members' refinement errors "
              "through the lines, and the hard-wall value's refinement error (`python/cmc/analysis/s_route.py`, `s_extrapolation`).",
              "", "| quantity | " + " | ".join(f"R(s = {m})" for m in members)
              + " | R(1), line in log s | R(1), line in s | hard wall at s = 1 | value at s = 1 |",
              "|---|" + "---|" * (len(members) + 4)]
    for _, short, unit in QUANTITIES:
        q = x[short]
        hw = q["adhesionless_at_1"]
        cells = [f"{q['ratios'][str(m)]['value']:.4f} ± {q['ratios'][str(m)]['error']:.2g}" for m in members]
        lines.append(f"| {short} ({unit}) | " + " | ".join(cells) + " | "
                     f"{q['ratio_at_1_log_s']:.4f} | {q['ratio_at_1_linear_s']:.4f} | "
                     f"{hw['value']:.5g} ± {hw['refinement_error']:.2g} ({hw['grid']}²) | "
                     f"**{q['value']:.4g} ± {q['error']:.2g}** |")
    verdict = s_extrapolation_verdict(x)
    return lines + [""] + ([verdict, ""] if verdict else [])
