"""The best estimates (reference/challenge/best_estimates.json) put into the stored challenge
references without the runs at hand (scripts/apply_best_estimates.py; what it rewrites is
listed there). The challenge references' command (cmc.references.challenge) calls `apply`
after it rewrites the curves from the runs."""
from __future__ import annotations
import argparse
import json
import os
import sys
import tomllib

from ..analysis import best as best_mod
from ..analysis.runs import REPO as ROOT
from ..reference_files import CurveError, read_curve, write_atomically, write_curve
from .._types import Json

P0 = 250e3
BEGIN, END = "<!-- best-estimates:begin -->", "<!-- best-estimates:end -->"
QUANTITY = {"contact_fraction": ("a_r", "relative contact area a_r"), "mean_gap_m": ("mean_gap", "mean gap")}


def run_words(est: Json) -> str:
    return f"{est['run']} ({est['n']}^2, {est['strategy']}, {est['device']})"


def error_words(est: Json, short: str) -> str:
    """How the error of one estimated quantity was made, in a sentence."""
    q = est["quantities"][short]
    ref = q["refinement"]
    grids = ", ".join(f"{g['n']}^2" + ("" if g["status"] == "converged" else f" ({g['status']})") for g in est["grids"])
    order = "" if ref["order"] is None else f", order {ref['order']:.2g}"
    def pct(rel, err):  # a relative error in %, or the absolute one where the value is 0
        return f"{100 * rel:.3g} %" if rel is not None else f"{err:.3g} (absolute)"
    text = (f"+-{pct(q['relative_error'], q['error'])}: refinement over {grids} ({ref['method']}{order}: "
            f"{pct(ref['relative'], ref['error'])})")
    if q.get("strategy_error"):
        text += f" plus the {est['strategy']} strategy's error at dx = {est['dx_over_rho']:.3g} rho " \
                f"({100 * q['strategy_error']['error']:.2g} %, {q['strategy_error']['rule']})"
    if q.get("roundoff_floor"):
        text += "; at least the round-off spread between builds"
    return text


OTHER_ROWS = "the other rows: "


def sweep_words(estimated_error: str) -> str:
    """The sweep's own words of an estimated_error line, without what best estimates put before
    them (by an earlier application, once or several times)."""
    words = estimated_error.split(" || ")[-1]
    while words.startswith(OTHER_ROWS):
        words = words[len(OTHER_ROWS):]
    return words


def with_best_rows(curve: Json, ests: list[Json], short: str) -> Json:
    """The load-sweep curve with each row that has a best estimate at its load (ests, ascending in
    load) replaced by it, its error the band; a best estimate at 250 kPa is joined where the
    curve has no row there. The file's words say which rows come from where."""
    x, y = curve["columns"][0][3], curve["columns"][1][3]
    band = curve["columns"][2][3] if len(curve["columns"]) > 2 else None
    used = []
    for est in ests:
        q = est["quantities"].get(short)
        if not q or not q.get("error"):  # the format needs a band > 0
            continue
        p = est["pressure_Pa"]
        i = next((k for k, v in enumerate(x) if abs(v / p - 1) < best_mod.SAME_POINT), None)
        if i is None:
            if abs(p / P0 - 1) >= best_mod.SAME_POINT:
                continue
            i = sum(1 for v in x if v < p)
            x.insert(i, p), y.insert(i, q["value"])
            if band is not None:
                band.insert(i, q["error"])
        y[i] = q["value"]
        if band is not None:
            band[i] = q["error"]
        used.append((p, est))
    if not used:
        return curve
    old = sweep_words(curve["estimated_error"])
    per = "; ".join(f"{p / 1e3:g} kPa: {run_words(e)}, {error_words(e, short)}" for p, e in used)
    curve["estimated_error"] = (f"rows with a best estimate (reference/challenge/best_estimates.json): {per} || "
                                f"{OTHER_ROWS}{old}")
    curve["extra"] = [(k, v) for k, v in curve["extra"] if k != "best_estimate"] + [
        ("best_estimate", "rows at " + ", ".join(f"{p / 1e3:g} kPa" for p, _ in used)
         + ": the best estimates (estimated_error); the other rows: the sweep named in command")]
    curve["title"] = curve["title"].split(" [")[0] + " [best estimates at " + \
        ", ".join(f"{p / 1e3:g}" for p, _ in used) + " kPa]"
    return curve


# The bands the challenge's load curves aim at (relative, up to a load), and the GPU stage of
# scripts/gpu/reference_plan.py that narrows a row still wider.
TARGETS = {("hardwall", "a_r"): (0.02, 10e6), ("hardwall", "mean_gap"): (0.002, 10e6),
           ("adhesive", "a_r"): (0.05, 2.5e6), ("adhesive", "mean_gap"): (0.01, 2.5e6)}
NARROWING = {"hardwall": "hardwall_load:16384 (priority 2)", "adhesive": "shape_load:8192 (priority 3)"}


def sweep_loads(problem: str) -> list[float]:
    """The loads of the challenge's load sweep (cases/challenge/load-sweep*.toml), Pa."""
    name = "load-sweep-hardwall.toml" if problem == "hardwall" else "load-sweep.toml"
    with open(os.path.join(ROOT, "cases", "challenge", name), "rb") as f:
        return [float(p) for p in tomllib.load(f)["loading"]["values"]]


def best_load_curve(old: Json, ests: list[Json], short: str, problem: str) -> Json:
    """A load curve made of best estimates alone (ests ascending in load): each row its estimate's
    value and error, a column with the grid of the run behind it; rows of the old curve without a
    best estimate are left out and named, and so are the rows wider than the targets, with the GPU
    stage that would narrow them."""
    rows = [(e["pressure_Pa"], e["quantities"][short], e) for e in ests
            if short in e["quantities"] and e["quantities"][short].get("error")]
    missing = [p for p in sweep_loads(problem) if not any(abs(p / r[0] - 1) < best_mod.SAME_POINT for r in rows)]
    cols = [list(c[:3]) for c in old["columns"][:3]]
    for c, vals in zip(cols, ([p for p, _, _ in rows], [q["value"] for _, q, _ in rows],
                              [q["error"] for _, q, _ in rows])):
        c.append(vals)
    cols.append(["grid_n", "1", "points a side of the finest grid behind the row", [e["n"] for _, _, e in rows]])
    target, upto = TARGETS[(problem, short)]
    wide = [p for p, q, _ in rows if p <= upto * (1 + best_mod.SAME_POINT) and (q["relative_error"] or 0) > target]
    per = "; ".join(f"{p / 1e3:g} kPa: {run_words(e)}, {error_words(e, short)}" for p, _, e in rows)
    notes = [("best_estimate", "every row is the best estimate at its load (reference/challenge/best_estimates.json); "
                               "column grid_n names its grid, estimated_error its run and band")]
    if missing:
        notes.append(("rows_left_out", "loads without a refinement sequence in the run store yet: "
                      + ", ".join(f"{p / 1e3:g} kPa" for p in missing)))
    if wide:
        notes.append(("still_wide", f"bands wider than {100 * target:g} % at " + ", ".join(f"{p / 1e3:g}" for p in wide)
                      + f" kPa; the GPU stage that narrows them: {NARROWING[problem]} of scripts/gpu/reference_plan.py"))
    kept = ("cmc_version", "case_file", "date")  # the rest described the sweep the rows no longer come from
    extra = [(k, v) for k, v in old["extra"] if k in kept]
    grids = sorted({e["n"] for _, _, e in rows})
    extra += [("grid", "per row, its best estimate's (column grid_n: " + ", ".join(f"{n}^2" for n in grids) + ")"),
              ("solver_tolerance", "per run, in reference/challenge/runs.json"),
              ("command", "scripts/best_estimates.py; scripts/apply_best_estimates.py"),
              ("sampling", f"{len(rows)} loads, each its own best estimate"),
              ("generator", "scripts/apply_best_estimates.py (python/cmc/analysis/best.py)")] + notes
    title = old["title"].split(", cmc ")[0].split(" [")[0].split(", best estimates")[0] + ", best estimates"
    return dict(old, title=title, columns=cols, extra=extra, estimated_error=f"band per row, its best estimate's error ({per})")


def _kept_date(curve):
    """The stored curve's date, kept where the estimates name none (else cmc writes the time of
    writing, and the same estimates would not give the same file twice)."""
    return dict(curve["extra"]).get("date", "") if curve else ""


def tabor_curve(old: Json, points: list[Json], ycol: str, short: str) -> Json:
    """Item 6 or 7 as the best estimates at every mu_T, keeping the stored file's columns and words."""
    pts = [p for p in points if short in p["quantities"] and p["quantities"][short]["error"]]
    cols = [list(c[:3]) for c in old["columns"]] if old else [
        ["tabor", "1", "Tabor coefficient mu_T"], [ycol, "1" if short == "a_r" else "m", QUANTITY[ycol][1]],
        [ycol + "_err", "1" if short == "a_r" else "m", "half-width of the error band: " + QUANTITY[ycol][1]]]
    cols[0].append([p["tabor"] for p in pts])
    cols[1].append([p["quantities"][short]["value"] for p in pts])
    cols[2].append([p["quantities"][short]["error"] for p in pts])
    grids = sorted({p["n"] for p in pts})
    per = "; ".join(f"mu_T = {p['tabor']:.3g}: {run_words(p)}, {error_words(p, short)}" for p in pts)
    item = 6 if short == "a_r" else 7
    return {"name": f"{'contact_area' if item == 6 else 'mean_gap'}_vs_tabor",
            "quantity": f"{'contact_area' if item == 6 else 'mean_gap'}_vs_tabor",
            "title": f"Challenge item {item}: {QUANTITY[ycol][1]} vs Tabor coefficient at 250 kPa, best estimates "
                     f"(grids {', '.join(f'{n}^2' for n in grids)})",
            "x": "tabor", "y": ycol, "representation": "log-lin", "band": ycol + "_err", "columns": cols,
            "estimated_error": f"band per point, the best estimate's error ({per})",
            "extra": [("cmc_version", "0.1.0"), ("case_file", "cases/challenge/tabor-sweep.toml and the reference load's"),
                      ("grid", "per point, its best estimate's (estimated_error)"),
                      ("solver_tolerance", "per run, in reference/challenge/runs.json"),
                      ("date", (max(p.get("date") or "" for p in pts) if pts else "") or _kept_date(old)),
                      ("command", "scripts/best_estimates.py; scripts/apply_best_estimates.py"),
                      ("sampling", f"{len(pts)} mu_T, each from its own finest converged run"),
                      ("generator", "scripts/apply_best_estimates.py (python/cmc/analysis/best.py)")]}


DISTRIBUTIONS = ("patch_size_distribution", "gap_distribution", "stress_distribution", "stress_spectrum",
                 "cross_section_gap", "cross_section_pressure")


def with_finest_note(curve: Json, best: Json) -> Json:
    """A distribution's curve (items 1, 3, 4, 5, 9) with a line saying that its grid is still the
    finest run with these observables, while the best estimates reach further for a_r and the
    mean gap."""
    grid = dict(curve["extra"]).get("grid", "?").split(" (")[0]
    ests = [e for e in best["reference_load"].values() if isinstance(e, dict) and e.get("run")]
    finest = max((e["n"] for e in ests), default=None)
    note = (f"this quantity's finest stored run is {grid}" + (
        f"; the best estimates of a_r, the repulsive a_r and the mean gap come from {finest}^2 "
        "(best_estimates.json), whose runs were stored without these observables" if finest else ""))
    curve["extra"] = [(k, v) for k, v in curve["extra"] if k != "finest_run"] + [("finest_run", note)]
    return curve


def _other_rows(best, name):
    """How the load curves' other rows are made: best estimates at their own loads where the sweep
    has two or more (apply builds the curve from them alone), else the coarse sweep's."""
    problem = "hardwall" if name.startswith("without") else "adhesive"
    ests = (best.get("load_sweep") or {}).get(problem) or []
    grids = sorted({e["n"] for e in ests if e.get("n")})
    if len(ests) >= 2:
        return (f"; every other row is the best estimate at its own load (grids {', '.join(f'{n}²' for n in grids)},"
                " column `grid_n`).")
    return "; their other rows are still the 2048² load sweep's."


def readme_block(best: Json) -> list[str]:
    """The README's best-estimate block: what each rewritten file takes from which run."""
    rl = best["reference_load"]
    L = [BEGIN, "## Best estimates", "",
         "The files below take the **best estimates** (`best_estimates.json`, `scripts/best_estimates.py`): at each "
         "point the finest converged run the project has stored (`runs.json`), with the error from its own refinement "
         "sequence plus, where it does not resolve ρ, its strategy's error measured on the scaled family at its dx/ρ "
         "(`python/cmc/analysis/best.py`).", ""]
    for name, est in (("with adhesion", rl.get("adhesive")), ("without adhesion", rl.get("hardwall"))):
        if est:
            q = est["quantities"]
            L.append(f"- 250 kPa {name}: {run_words(est)}: a_r {q['a_r']['value']:.5g} ± {q['a_r']['error']:.2g}, "
                     f"mean gap {q['mean_gap']['value'] * 1e6:.6g} ± {q['mean_gap']['error'] * 1e6:.2g} µm: the 250 kPa "
                     "rows of `contact_area_vs_pressure.csv` and `mean_gap_vs_pressure.csv`"
                     + (" (in `adhesionless/`)" if name.startswith("without") else "") + _other_rows(best, name))
    grids = sorted({p["n"] for p in best["tabor"]})
    L += [f"- `contact_area_vs_tabor.csv`, `mean_gap_vs_tabor.csv`: {len(best['tabor'])} values of μ_T, each its own "
          f"best estimate (grids {', '.join(f'{n}²' for n in grids)}).",
          "- Items 1, 3, 4, 5 and 9 (distributions, spectrum, cross sections) come from the finest stored run with "
          "those observables that has a coarser grid of the same case (each file's `grid`), with bands from that "
          "coarser grid.", ""]
    ex = best.get("mean_gap_extremum")
    if ex:
        L += [f"The mean gap's minimum in μ_T: μ_T* = {ex['mu']:.3g} (between {ex['mu_range'][0]:.3g} and "
              f"{ex['mu_range'][1]:.3g}), mean gap there {ex['y'] * 1e6:.5f} ± {ex['y_total_error'] * 1e6:.2g} µm.", ""]
    return L + [END]


def update_readme(path: str, best: Json) -> None:
    """Replace (or add, after the title) the best-estimate block of the README."""
    text = open(path, encoding="utf-8").read() if os.path.exists(path) else "# Challenge reference curves\n"
    block = "\n".join(readme_block(best))
    if BEGIN in text and END in text:
        text = text[:text.index(BEGIN)] + block + text[text.index(END) + len(END):]
    else:
        head, _, rest = text.partition("\n\n")
        text = head + "\n\n" + block + "\n\n" + rest
    write_atomically(path, text)


def apply(best: Json, out_dir: str, cmc: str) -> list[str]:
    """Rewrite the stored curves the best estimates decide; returns the paths written."""
    done = []
    rl, sweeps = best["reference_load"], best.get("load_sweep") or {}
    for problem, folder in (("adhesive", out_dir), ("hardwall", os.path.join(out_dir, "adhesionless"))):
        ests = sweeps.get(problem) or [e for e in (rl.get(problem),) if e]
        for q, short in (("contact_area_vs_pressure", "a_r"), ("mean_gap_vs_pressure", "mean_gap")):
            path = os.path.join(folder, q + ".csv")
            old = read_curve(path)
            if not (ests and old):
                continue
            with_errors = [e for e in ests if short in e["quantities"] and e["quantities"][short].get("error")]
            # Two rows or more: the curve is made of best estimates alone; one (250 kPa): joined to the sweep.
            curve = (best_load_curve(old, ests, short, problem) if len(with_errors) >= 2
                     else with_best_rows(old, ests, short))
            write_curve(cmc, curve, path)
            done.append(path)
    for q, ycol, short in (("contact_area_vs_tabor", "contact_fraction", "a_r"), ("mean_gap_vs_tabor", "mean_gap_m", "mean_gap")):
        path = os.path.join(out_dir, q + ".csv")
        old = read_curve(path)
        if best["tabor"] and old:
            write_curve(cmc, tabor_curve(old, best["tabor"], ycol, short), path)
            done.append(path)
    for folder in (out_dir, os.path.join(out_dir, "adhesionless")):
        for q in DISTRIBUTIONS:
            path = os.path.join(folder, q + ".csv")
            old = read_curve(path)
            if old:
                write_curve(cmc, with_finest_note(old, best), path)
                done.append(path)
    update_readme(os.path.join(out_dir, "README.md"), best)
    return done + [os.path.join(out_dir, "README.md")]


def main(argv: list[str] | None, doc: str) -> int:
    """scripts/apply_best_estimates.py, whose usage text is `doc`."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--best", default=os.path.join(ROOT, "reference", "challenge", "best_estimates.json"))
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--cmc", default=os.path.join(ROOT, "build", "cmc"), help="the cmc that formats the curves")
    a = ap.parse_args(argv)
    try:
        with open(a.best) as f:
            best = json.load(f)
    except (OSError, ValueError) as e:
        print(f"apply_best_estimates: {a.best}: {e} (scripts/best_estimates.py writes it)", file=sys.stderr)
        return 2
    try:
        written = apply(best, a.out, a.cmc)
    except CurveError as e:
        print(f"apply_best_estimates: {e}", file=sys.stderr)
        return 1
    for p in written:
        print(f"apply_best_estimates: {os.path.relpath(p, ROOT)}")
    return 0

