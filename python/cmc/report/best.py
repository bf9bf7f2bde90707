"""The challenge report's best-estimate parts: the headline (the best estimates with their errors
and provenance, the user's own run beside them), the mean gap's extremum in mu_T, and the best
estimates drawn first into the figures. Reads reference/challenge/best_estimates.json
(scripts/best_estimates.py); computes nothing but deviations for display.
"""
from __future__ import annotations
from typing import Any
import json
import os

import numpy as np
from cmc._types import Json

P0 = 250e3
ROWS = (("a_r", "relative contact area a_r", 1.0, 4), ("a_rep", "repulsive contact area (p > 0)", 1.0, 4),
        ("mean_gap", "mean gap ū (µm)", 1e6, 6))


def load_best(reference_dir: str) -> Json | None:
    """best_estimates.json, or None where it is missing or unreadable."""
    try:
        with open(os.path.join(reference_dir, "challenge", "best_estimates.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def _pm(q, scale, digits):
    return f"{q['value'] * scale:.{digits}g} ± {q['error'] * scale:.2g}"


def _beside(value, q, scale, digits):
    """The user's value with its deviation from the best estimate, in % and in units of its error."""
    if value is None:
        return "–"
    d = value / q["value"] - 1
    z = (value - q["value"]) / q["error"] if q["error"] else float("nan")
    return f"{value * scale:.{digits}g} ({100 * d:+.2g} %, {z:+.2g} σ)"


def provenance(est: Json) -> str:
    """Where an estimate comes from, in a few words."""
    return f"`{est['run']}`: {est['n']}², {est['strategy']}, {est['device']}"


def error_source(est: Json, short: str) -> str:
    q = est["quantities"][short]
    ref = q["refinement"]
    grids = "→".join(f"{g['n']}²" for g in est["grids"])
    text = f"refinement {grids} {100 * ref['relative']:.2g} % ({ref['method']})"
    if q.get("strategy_error"):
        text += f" + {est['strategy']} at dx = {est['dx_over_rho']:.3g} ρ {100 * q['strategy_error']['error']:.2g} % (scaled family)"
    if q.get("roundoff_floor"):
        text += f"; raised to the round-off spread between builds, {100 * q['relative_error']:.2g} %"
    return text


DISTRIBUTIONS = (("patch_size_distribution", 1), ("gap_distribution", 3), ("stress_distribution", 4),
                 ("stress_spectrum", 5), ("cross_section_gap", 9))


def stored_grids(reference_dir: str) -> dict[str, list[int]]:
    """{grid text: [items]} of the stored references of items 1, 3, 4, 5, 9 (their `grid` line)."""
    out: dict[str, list[int]] = {}
    for q, item in DISTRIBUTIONS:
        try:
            with open(os.path.join(reference_dir, "challenge", q + ".csv"), encoding="utf-8") as f:
                grid = next((ln.split(":", 1)[1].strip() for ln in f if ln.startswith("# grid:")), None)
        except OSError:
            continue
        if grid:
            out.setdefault(grid.split(" (")[0], []).append(item)
    return out


def still_wide(reference_dir: str) -> list[str]:
    """A bullet per stored load curve whose rows are left out or wider than the targets (their
    `rows_left_out` and `still_wide` lines, written by scripts/apply_best_estimates.py)."""
    out = []
    for sub, words in (("", "with adhesion"), ("adhesionless", "without adhesion")):
        for q in ("contact_area_vs_pressure", "mean_gap_vs_pressure"):
            try:
                with open(os.path.join(reference_dir, "challenge", sub, q + ".csv"), encoding="utf-8") as f:
                    meta = {k.strip(): v for k, v in (ln[1:].split(":", 1) for ln in f if ln.startswith("#") and ":" in ln)}
            except OSError:
                continue
            notes = [meta[k].strip() for k in ("rows_left_out", "still_wide") if k in meta]
            if notes:
                out.append(f"- `{q}` {words}: " + "; ".join(notes) + ".")
    return out


def headline(best: Json | None, user: dict[bool, Any], reference_dir: str = "reference",
             surfaces: tuple[str, str] | None = None) -> list[str]:
    """The report's opening section. user: {True: (run, step) or None, False: ...} (with and without
    adhesion, the user's runs at 250 kPa, as the report finds them). surfaces: words naming the surface
    of the best estimates and of the user's runs where the two differ (surface_report.py), or None."""
    L = ["## Headline: the best estimates at p = 250 kPa (p̃ = p/(E*ḡ) = 0.01)", ""]
    if not best:
        return L + ["No best estimates stored (`reference/challenge/best_estimates.json`; `scripts/best_estimates.py`).", ""]
    rl = best["reference_load"]
    ests = {True: rl.get("adhesive"), False: rl.get("hardwall")}
    label = {True: "with adhesion (μ_T = 3)", False: "without adhesion"}
    head = ["quantity"]
    for a in (True, False):
        got = user.get(a)
        best_on, yours_on = surfaces or ("", "")
        head += [f"{label[a]}: best estimate{best_on}", f"your run{yours_on} ({got[0].nx}²)" if got else f"your run{yours_on}"]
    rows = []
    for short, name, scale, digits in ROWS + (("kappa", "κ = a_r / p̃", 1.0, 4),):
        row = [name]
        for a in (True, False):
            est, got = ests[a], user.get(a)
            q = rl.get(f"kappa_{'adhesive' if a else 'hardwall'}") if short == "kappa" else (est or {}).get("quantities", {}).get(short)
            if not q or q.get("error") is None:
                row += ["–", "–"]
                continue
            key = {"a_r": "ar", "a_rep": "rep", "mean_gap": "gap", "kappa": "ar"}[short]
            mine = got[1].get(key) if got else None
            if short == "kappa" and mine is not None:
                mine = mine / rl["p_tilde"]
            row += [_pm(q, scale, digits), _beside(mine, q, scale, digits) if got else "not run (`scripts/main.sh`)"]
        rows.append(row)
    L += [_table(head, rows), ""]
    for a in (True, False):
        if ests[a]:
            L.append(f"- Best estimate {label[a]}: {provenance(ests[a])}; error of a_r: {error_source(ests[a], 'a_r')}; "
                     f"of the mean gap: {error_source(ests[a], 'mean_gap')}.")
    L += cross_check(ests[True])
    L += ["- Your run: the step at 250 kPa of your `results/` run, its deviation in % and in units of the best "
          "estimate's error (σ here is that error, not a standard deviation)."]
    L += still_wide(reference_dir)
    for grid, items in stored_grids(reference_dir).items():
        L.append(f"- Items {', '.join(str(i) for i in items)} (distributions, spectrum, cross sections): the finest "
                 f"stored run with these observables is still {grid}; their references carry that grid's band.")
    L.append("")
    L += questions_table(reference_dir)
    L += [statement_sentence(rl), ""]
    ex = best.get("mean_gap_extremum")
    if ex:
        L += [extremum_sentence(ex, best), ""]
    mono = monotonicity_sentence(best.get("a_r_monotonicity"))
    if mono:
        L += [mono, ""]
    return L


QUESTIONS = (("a_r", "a_r", 1.0, 4), ("a_rep", "repulsive a_r", 1.0, 4), ("mean_gap", "mean gap ū (µm)", 1e6, 5),
             ("kappa", "κ = a_r / p̃", 1.0, 4), ("mean_gap_over_h_rms", "ū / h_rms", 1.0, 4))


def questions_table(reference_dir: str) -> list[str]:
    """The headline's numbers for the three questions a prediction can answer (cmc check --against):
    cmc's own surface, the mean over surfaces, one surface of the spectrum; from
    reference/challenge/ensemble/summary.json (scripts/ensemble_references.py)."""
    try:
        with open(os.path.join(reference_dir, "challenge", "ensemble", "summary.json")) as f:
            data = json.load(f)
    except (OSError, ValueError):
        return []
    rl = data.get("reference_load") or {}
    rows = []
    for problem, words in (("adhesive", "with adhesion"), ("hardwall", "without adhesion")):
        for key, name, scale, digits in QUESTIONS:
            e = (rl.get(problem) or {}).get(key)
            if e:
                rows.append([f"{name}, {words}"] + [f"{e[q]['value'] * scale:.{digits}g} ± {e[q]['band'] * scale:.2g}"
                                                    for q in ("surface", "ensemble", "realisation")])
    if not rows:
        return []
    m = len(data.get("seeds") or [])
    head = ["at 250 kPa", "this surface (seed 28): best estimate", f"ensemble mean ({m} surfaces)",
            "one realisation (95 % of surfaces)"]
    return ["**Which surface a prediction answers** (`cmc check --against surface|ensemble|realisation`): the best "
            "estimates are for cmc's own surface; a theory predicts the ensemble mean (band: twice its standard error "
            "and the grid correction's error); a run on another surface, the organisers' included, falls inside the "
            "realisation band (95 % of surfaces). ū / h_rms is the mean gap that transfers best between surfaces.",
            "", _table(head, rows), ""]


def monotonicity_sentence(m: Json | None) -> str:
    """Whether a_r(mu_T) of the best estimates is monotonic, as the problem definition says, and
    where not, why (the falls, their grids, the bars; each grid's own sweep where it resolves rho)."""
    if not m:
        return ""
    grids = sorted((m.get("grids") or {}).items(), key=lambda x: int(x[0]))
    per = "; ".join(f"{n}²: " + ("rises" if g["rises"] else
                                 (f"rises over the μ_T where it resolves ρ (up to {g['resolved_up_to']:g}), not over all its points"
                                  if g["rises_where_resolved"] and g["resolved_up_to"] else "does not rise"))
                    for n, g in grids)
    if m["monotonic"]:
        return f"**a_r(μ_T) is monotonic** on the best estimates, as the problem definition says (each grid's own sweep: {per})."
    falls = "; ".join(f"from μ_T = {f['from']:g} ({f['grids'][0]}²) to {f['to']:g} ({f['grids'][1]}²) by {f['fall']:.2g}, "
                      + ("inside" if f["inside_bars"] else "**outside**") + " their error bars" for f in m["falls"])
    return (f"**a_r(μ_T) is not monotonic on the best estimates** where neighbouring points come from different grids: "
            f"{falls}. Each grid's counted area errs by a band of pixels along the contact lines, so a join of two grids "
            f"steps. On each grid's own sweep: {per}.")


def cross_check(est: Json) -> list[str]:
    """A bullet on the challenge's own check of the chosen estimate: each finest run of another
    strategy at the point, its a_r against the estimate and the way its refinement still moves."""
    if not est:
        return []
    q = est["quantities"]["a_r"]
    parts = [f"{o['strategy']} on {o['n']}² gives a_r {o['a_r']:.5g} ({100 * (o['a_r'] / q['value'] - 1):+.2g} %)"
             + (f", still moving by {100 * o['a_r_last_change']:+.2g} % from the grid before" if o.get("a_r_last_change")
                else "")
             for o in est.get("passed_over", []) if o.get("a_r")]
    return [f"- Checks on the challenge itself (runs the choice passed over): {'; '.join(parts)}."] if parts else []


def statement_sentence(rl: Json) -> str:
    """kappa and the ratio with/without adhesion against the problem definition, in one sentence."""
    ka, k0, r = rl.get("kappa_adhesive"), rl.get("kappa_hardwall"), rl.get("ratio")
    if not (ka and k0 and r):
        return ""
    return (f"**Against the problem definition:** κ = {ka['value']:.3f} ± {ka['error']:.2g} with adhesion (it gives "
            f"a little above 3) and {k0['value']:.3f} ± {k0['error']:.2g} without, a ratio of "
            f"{r['value']:.3f} ± {r['error']:.2g} where it gives about 1.5; nothing in cmc was "
            "tuned toward these statements.")


def extremum_sentence(ex: Json, best: Json) -> str:
    """Where the mean gap has its minimum in mu_T, with its errors, and how a_r behaves around it."""
    hw = (best["reference_load"].get("hardwall") or {}).get("quantities", {}).get("mean_gap")
    slope = ex.get("a_r_log_slope") or []
    text = (f"**The mean gap's extremum in μ_T** (\"a challenge in the challenge\"): a minimum at μ_T* = {ex['mu']:.3g} "
            f"(between {ex['mu_range'][0]:.3g} and {ex['mu_range'][1]:.3g}: the parabolas through the samples around it, "
            f"{ex['bracket'][0]:g} < μ_T < {ex['bracket'][1]:g}"
            + (f", and its change between the {ex['grids'][0]}² and {ex['grids'][1]}² sweeps" if len(ex.get("grids", [])) == 2 else "")
            + f"), where ū = {ex['y'] * 1e6:.5f} ± {ex['y_total_error'] * 1e6:.2g} µm")
    if hw:
        text += f", against {hw['value'] * 1e6:.5f} µm without adhesion, the limit μ_T → 0"
    text += "."
    if slope:
        text += a_r_slope_sentence(ex["mu"], slope, ex.get("a_r_log_slope_grid", "?"),
                                   ex.get("a_r_log_slope_resolved_up_to"))
    return text


def a_r_slope_sentence(mu_star: float, slope: list[Json], grid: int | str, resolved_up_to: float | None) -> str:
    """How a_r's slope against log10 mu_T behaves around mu_star on one grid's sweep (slope: the
    extremum's a_r_log_slope, mu_T ascending)."""
    flat = min(slope, key=lambda s: s["slope"])
    below = [x for x in slope if x["tabor"] < flat["tabor"]]
    above = [x for x in slope if x["tabor"] > flat["tabor"]]
    where = "just above it" if flat["tabor"] > mu_star else "just below it"
    if not below or not above:
        return f" a_r's slope against log10 μ_T is smallest ({flat['slope']:.3g}) near μ_T = {flat['tabor']:.3g}."
    peak = max(below, key=lambda x: x["slope"])
    return (f" Around it a_r(μ_T) flattens: on the {grid}² sweep its slope d a_r/d log10 μ_T falls from "
            f"{peak['slope']:.3g} near μ_T = {peak['tabor']:.3g} to {flat['slope']:.3g} near μ_T = {flat['tabor']:.3g}, "
            f"{where}, and rises again to {above[-1]['slope']:.3g} near μ_T = {above[-1]['tabor']:.3g}"
            + (f" (the sweep's points resolve ρ up to μ_T = {resolved_up_to:.3g})" if resolved_up_to else "")
            + ": the \"interesting\" behaviour the problem definition points to (figure 6).")


def _table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    return "\n".join(out + ["| " + " | ".join(str(c) for c in r) + " |" for r in rows])


def tabor_series(best: Json | None, short: str) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(mu, value, error) arrays of the best-estimate curve against mu_T, or None."""
    pts = [p for p in (best or {}).get("tabor", []) if short in p["quantities"] and p["quantities"][short]["error"]]
    if not pts:
        return None
    return (np.array([p["tabor"] for p in pts]), np.array([p["quantities"][short]["value"] for p in pts]),
            np.array([p["quantities"][short]["error"] for p in pts]))


def draw_tabor(ax: Any, best: Json | None, what: str, scale: float) -> bool:
    """The best estimates against mu_T, drawn first: a shaded band and the line, and the mean gap's
    extremum. Returns whether anything was drawn."""
    got = tabor_series(best, "a_r" if what == "ar" else "mean_gap")
    if got is None or best is None:
        return False
    mu, v, e = got
    ax.fill_between(mu, (v - e) * scale, (v + e) * scale, color="0.75", alpha=0.6, lw=0, zorder=1)
    ax.semilogx(mu, v * scale, "s-", color="k", ms=3.5, lw=1.0, zorder=2,
                label="best estimate ± its error (reference/challenge/)")
    ex = best.get("mean_gap_extremum")
    if what == "gap" and ex:
        ax.axvspan(ex["mu_range"][0], ex["mu_range"][1], color="tab:red", alpha=0.12, lw=0, zorder=0)
        ax.plot([ex["mu"]], [ex["y"] * scale], "*", color="tab:red", ms=10, zorder=3,
                label=f"minimum: μ_T* = {ex['mu']:.3g}")
    return True


def draw_point(ax: Any, est: Json | None, short: str, scale: float, x: float = P0) -> None:
    """A best estimate at the reference load, drawn with its error bar (the load-sweep figures)."""
    q = (est or {}).get("quantities", {}).get(short)
    if not q or q.get("error") is None or est is None:
        return
    ax.errorbar([x], [q["value"] * scale], yerr=[q["error"] * scale], fmt="*", color="k", ms=9, capsize=4, zorder=5,
                label=f"best estimate at 250 kPa ({est['n']}², {est['strategy']})")


def draw_realisation(ax: Any, reference_dir: str, quantity: str, scale: float, x_scale: float) -> None:
    """The realisation band of a load curve (reference/challenge/realisation/[adhesionless/]Q.csv:
    where 95 % of surfaces of the spectrum lie), hatched, for each interaction that has one."""
    for sub, words in (("", "with adhesion"), ("adhesionless", "without adhesion")):
        path = os.path.join(reference_dir, "challenge", "realisation", sub, quantity + ".csv")
        try:
            rows = np.array([[float(v) for v in line.split(",")[:3]] for line in open(path, encoding="utf-8")
                             if line[:1].isdigit()])
        except (OSError, ValueError):
            continue
        if rows.ndim != 2 or len(rows) < 2:
            continue
        x, y, b = rows[:, 0] / x_scale, rows[:, 1] * scale, rows[:, 2] * scale
        ax.fill_between(x, y - b, y + b, facecolor="none", edgecolor="0.45", hatch="///", lw=0.0, zorder=0,
                        label=f"one realisation, {words} (95 % of surfaces)")
