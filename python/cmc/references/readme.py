"""The README.md of reference/challenge/ and reference/challenge/adhesionless/: the table of
files, the reference load's runs, the accuracy of each curve and where its band comes from."""
from __future__ import annotations

from typing import Sequence
from cmc.analysis.conditions import condition_checks
from cmc.analysis.refinement import REFINEMENT_BISTABILITY
from cmc.analysis.runs import strategy_of
from cmc.report.common import STRATEGY_WORDS, condition_summary, read_reference_csv, roundoff_note, transfer_caveat
from .provenance import HW_LABELS, RHO, _bistable, _over_rho, _rel, provenance
from cmc._types import Json
from cmc.report.challenge_runs import Run


# ------------------------------------------------------------------ README
ALL = [("patch_size_distribution", 1), ("contact_area_vs_pressure", 2), ("gap_distribution", 3),
       ("stress_distribution", 4), ("stress_spectrum", 5), ("contact_area_vs_tabor", 6), ("mean_gap_vs_tabor", 7),
       ("mean_gap_vs_pressure", 8), ("cross_section_gap", 9), ("cross_section_pressure", 9)]
MISSING_HOW = {2: "`build/cmc run cases/challenge/load-sweep.toml --out results/challenge-load-sweep`",
               8: "`build/cmc run cases/challenge/load-sweep.toml --out results/challenge-load-sweep`",
               6: "`scripts/tabor_sweep.sh` (results/challenge-tabor-sweep/mu_T_*/)",
               7: "`scripts/tabor_sweep.sh` (results/challenge-tabor-sweep/mu_T_*/)"}

BEST_REGENERATE = [
    ". scripts/python_path.sh     # the package on PYTHONPATH for the Python commands below",
    "/usr/bin/python3 scripts/store_runs.py --commit C --origin WHY RUN ...   # a finished run into runs.json "
    "(the load and Tabor curves: each stored record names its command)",
    "/usr/bin/python3 scripts/best_estimates.py        # best_estimates.json: each row's best estimate from runs.json",
]


def files_table(curves: list[Json]) -> list[str]:
    """The README's table of stored files, one row per curve in the challenge's item order."""
    have = {c["quantity"]: c for c in curves}
    L = ["| file | item | columns (SI) | repr. | points | band | run | grid |", "|---|---|---|---|---|---|---|---|"]
    for q, item in ALL:
        c = have.get(q)
        if c is None:
            continue
        grid = dict(c["extra"])["grid"].split(" (")[0]
        run = " ; ".join(cmd.split("--out ")[-1].split(" --set ")[0] for cmd in dict(c["extra"])["command"].split(" ; "))
        L.append(f"| `{q}.csv` | {item} | `{c['columns'][0][0]}`, `{c['columns'][1][0]}` | {c['representation']} | "
                 f"{len(c['columns'][0][3])} | {'yes' if c.get('band') else 'no'} | `{run}` | {grid} |")
    return L + [""]


def _sweep_band_words(curves, pair):
    """The adhesionless README's sentence on the load sweep's bands."""
    sweep = {c["quantity"]: c for c in curves}.get("contact_area_vs_pressure")
    if sweep is None:
        return ""
    if "best estimates" in sweep.get("title", ""):
        return ("The load sweep's rows are best estimates (`../best_estimates.json`), each with the error of its own "
                "refinement sequence (the file's `estimated_error` and column `grid_n`).")
    if sweep.get("estimated_error", "").startswith("band per point: the change from"):
        how = ("the change to the same sweep on a grid twice as fine, measured at the loads both ran and interpolated "
               "in log p between them (each file's `estimated_error` says which loads and runs)")
    elif len(pair) >= 2:
        (r0, a), (r1, b) = pair[0], pair[1]
        how = (f"(only run on {r0.nx}²) the change at 250 kPa between {r0.nx}² and {r1.nx}² (contact fraction "
               f"{a['ar']:.5g} → {b['ar']:.5g}, mean gap {a['gap'] * 1e6:.6g} → {b['gap'] * 1e6:.6g} µm), for a_r "
               "scaled by each load's contact perimeter (the counted area's grid error is a boundary effect; at least "
               "one grid point), for the mean gap the same relative change at every load (assumed; at least the "
               "solver's tolerance times the rms height)")
    else:
        return ""
    return (f"The load sweep's band is {how}: a change under one refinement, a lower estimate of the grid error; the "
            "counted contact area converges as dx, its perimeter-corrected value much faster.")


def readme_adhesionless(curves: list[Json], pair: list[tuple[Run, Json]], dist: Sequence[tuple[Run, Json]] = (),
                        best: bool = False) -> str:
    """The README of reference/challenge/adhesionless/. pair: the hard-wall runs at 250 kPa, coarsest
    first (the load sweep's modelled band); dist: [(run, step) coarser, finest] behind items 1, 3, 4,
    5 and 9 (distribution_pair); best: the best estimates decide the load curves."""
    L = ["# Challenge reference curves without adhesion", "",
         "The challenge's surface pressed on the half-space with the hard wall alone (no adhesion): the adhesionless "
         "counterpart that the problem definition compares with (with adhesion, about half as much contact area "
         "again at a few per cent contact). `cmc check PRED.csv --quantity Q --adhesionless` scores against these files. Same "
         "format and provenance as [../README.md](../README.md); generated by the same command "
         "(`/usr/bin/python3 scripts/challenge_reference.py`). Items 6 and 7 (against the Tabor parameter) have no "
         "adhesionless counterpart.", "", "## Files", ""] + files_table(curves)
    sweep_words = _sweep_band_words(curves, pair)
    if len(dist) >= 2 or sweep_words:
        L += ["## Accuracy", "", "The hard-wall problem converges under refinement (no adhesion range to resolve)."
              + (f" Items 1, 3, 4, 5 and 9 come from {dist[1][0].nx}² (`{_rel(dist[1][0].folder)}`); their bands are "
                 f"twice the change of each curve from {dist[0][0].nx}² (`{_rel(dist[0][0].folder)}`) to "
                 f"{dist[1][0].nx}²: per point for the distributions and the spectrum (the coarser curve interpolated "
                 "in the representation), at the same y for the cross sections (there at least the solver's tolerance "
                 "in the problem's scale). That is the two-grid first-order bound (`python/cmc/analysis/bands.py`, "
                 "`refinement.py` `sequence_error`): it covers a power-law convergence of any order down to "
                 "log2(1.5) = 0.58, and the counted contact area and the patch statistics converge as dx." if len(dist) >= 2 else "")
              + (" " + sweep_words if sweep_words else ""), ""]
    commands = run_commands(dist[-1][0], dist[-1][1], dist[0] if len(dist) >= 2 else None) if dist else []
    sweeps = BEST_REGENERATE if best else [
        "build/cmc run cases/challenge/load-sweep-hardwall.toml --out results/challenge-load-sweep-hardwall",
        "build/cmc run cases/challenge/load-sweep-hardwall.toml --set grid.n=4096 "
        "--set 'loading.values=[12.5e3,250e3,2.5e6,10e6,25e6]' --out results/challenge-load-sweep-hardwall-n4096"]
    L += ["## Regenerate", "", "```"] + (commands or [
          "build/cmc run cases/challenge/reference-load-hardwall.toml --out results/challenge-hardwall",
          "build/cmc run cases/challenge/reference-load-hardwall.toml --set grid.n=4096 --out results/challenge-hardwall-n4096"]) + sweeps + [
          "/usr/bin/python3 scripts/challenge_reference.py", "```", ""]
    sweep = {c["quantity"]: c for c in curves}.get("contact_area_vs_pressure")
    joined = sweep is not None and " ; " in dict(sweep["extra"]).get("command", "")
    L += ["(all in `scripts/sweeps.sh`" + ("; the stored sweep joins several runs of the same case and grid: each "
                                          "file's `command` line names them" if joined else "") + ").", ""]
    return "\n".join(L)


def _stored_block(path, first, last=None):
    """The paragraphs of a stored README from the one starting with `first` through the one
    starting with `last` (or the first alone), as lines; [] where it has none."""
    try:
        with open(path, encoding="utf-8") as f:
            paras = f.read().split("\n\n")
    except OSError:
        return []
    i = next((k for k, p in enumerate(paras) if p.startswith(first)), None)
    if i is None:
        return []
    j = i if last is None else next((k for k in range(i, len(paras)) if paras[k].startswith(last)), i)
    return "\n\n".join(paras[i:j + 1]).split("\n") + [""]


def _own_refinement_sentence(banded):
    """The README's words on the Tabor sweep's points whose band is the challenge's own refinement
    (tabor_curves' "own_refinement": their mu_T), one sentence per set of mu_T."""
    by = {}
    for c in banded:
        if c.get("own_refinement"):
            by.setdefault(tuple(c["own_refinement"]), []).append(f"`{c['quantity']}.csv`")
    return "".join(
        f"At μ_T = {', '.join(f'{m:.3g}' for m in mus)} the band{'s' if len(files) > 1 else ''} of "
        f"{' and '.join(files)} {'are' if len(files) > 1 else 'is'} instead the challenge's own grid error, measured "
        "by refining the sweep itself (`scripts/tabor_sweep.sh --grid N`) where the finer pair of grids resolves the "
        f"adhesion (bistability number w dx/(E\\* ρ²) ≤ {REFINEMENT_BISTABILITY:g} on its coarser grid, as on the "
        "family's refinement grids): Richardson extrapolation of order 1 plus the spread of "
        "the other estimates of the converged value (`python/cmc/analysis/refinement.py` `own_band`); it needs no transfer "
        "from the family. " for mus, files in by.items())


def run_commands(run: Run, step: Json, coarser: tuple[Run, Json] | None) -> list[str]:
    """The lines of the README's regenerate block that rerun the runs behind items 1, 3, 4, 5, 9
    (their provenance's command), [] without them."""
    if run is None or step is None:
        return []
    out = ["build/" + dict(provenance(run, [step]))["command"] + "   # items 1, 3, 4, 5, 9"]
    if coarser:
        out.append("build/" + dict(provenance(coarser[0], [coarser[1]]))["command"] + "   # their bands")
    return out


def accuracy_head(ref_run: Run | None) -> str:
    """The first paragraph of the README's accuracy section: the grids, against rho."""
    if ref_run is None:
        return ("The adhesive runs use the challenge's grid 2048² (dx = 48.8 nm = λ_s/2.05 ≈ 24 ρ, ρ = 2.071 nm), far "
                "coarser than the ≈ 0.75 ρ of the published solution (65536²). The adhesive neck is not resolved and "
                "every grid point is bistable, so these curves are **not converged**.")
    return (f"Items 1, 3, 4, 5 and 9 come from {ref_run.nx}² (dx = {ref_run.dx * 1e9:.3g} nm = {_over_rho(ref_run):.3g} ρ, "
            f"ρ = {RHO * 1e9:.4g} nm; {STRATEGY_WORDS[strategy_of(ref_run.s)]}), far coarser than the ≈ 0.75 ρ of the "
            "published solution (65536²): the adhesive neck is not resolved"
            + _bistable(ref_run).replace(" and every", ", every").replace("rho^2", "ρ²")
            + ", so these curves are **not converged** in ρ. The other files name their grids (the table above).")


def distribution_paragraphs(curves: list[Json]) -> list[str]:
    """The README's paragraphs on the bands of items 1, 3, 4, 5 and 9."""
    L = []
    if any(c.get("band") for c in curves if c["item"] in (1, 3, 4, 5)):
        L += ["**Distributions and spectrum** (items 1, 3, 4, 5): the band is, per point, twice the change of the "
              "curve from the same case on the next coarser grid to this one (the coarser curve interpolated in the "
              "representation; points outside its range are left out): the two-grid first-order bound "
              "(`python/cmc/analysis/bands.py` `finest_grid_band`, `refinement.py` `sequence_error`), which covers "
              "a power-law convergence of any order down to log2(1.5) = 0.58. It bounds the grid error of the numerics at "
              "this dx/ρ only: both grids leave ρ unresolved, which the family measures for a_r and the mean gap "
              "only. Each file's `estimated_error` gives the median relative half-width.", ""]
    else:
        L += ["The distributions (items 1, 3, 4, 5) have **no error estimate**: no run of the reference-load case "
              "on a coarser grid with observables.", ""]
    if any(c.get("band") for c in curves if c["item"] == 9):
        L += ["**Cross sections** (item 9): the band is, per point, twice the change of the profile from the same "
              "case on the next coarser grid (linear between its points, periodic) to this one, at the same y "
              "(`bands.py` `finest_profile_band`); at least the solver's tolerance in the problem's scale (times the "
              "rms height for the gap, times E* times the rms slope for the stress), which is the band wherever both "
              "grids agree exactly. It is large at contact lines, which move by up to a grid spacing between the "
              "grids, so a prediction from another grid may fail there by many band widths; its median says more "
              "(`cmc check` prints both).", ""]
    else:
        L += ["The **cross sections** (item 9) have no error estimate: no run of the reference-load case on a "
              "coarser grid.", ""]
    return L


def _reference_load_paragraph(ref_run, ref_step, keep_from, coarser):
    """The paragraph on the run behind items 1, 3, 4, 5 and 9 (or the stored one)."""
    L = []
    if ref_run is not None and ref_step is not None:
        L += [f"Items 1, 3, 4, 5 and 9 are the step at p = {ref_step['p']:.6g} Pa (target 250 kPa) of "
              f"`{_rel(ref_run.folder)}` (case `{ref_run.s.get('case_file')}`, {ref_run.name}: the challenge's "
              f"problem, exponential adhesion with μ_T = {ref_run.run_tabor:.4g}); contact fraction "
              f"{ref_step['ar']:.4g} (perimeter-corrected {ref_step['ar_corr'] or float('nan'):.4g}), mean gap "
              f"{(ref_step['gap'] or float('nan')) * 1e9:.4g} nm, {int(ref_step['n_patches'] or 0)} patches"
              + (f"; their bands from the same case on {coarser[0].nx}² (`{_rel(coarser[0].folder)}`)" if coarser else "")
              + ". The extraction is the challenge report's (`python/cmc/report/challenge_runs.py`), except that empty bins "
              "are left out of log-scaled curves.", ""]
    elif keep_from:
        L += _stored_block(keep_from, "Items 1, 3, 4, 5 and 9 are the step")
    return L


def _missing_lines(have):
    """The quantities without a file yet, with the run that makes each."""
    L = []
    miss = [(q, item) for q, item in ALL if q not in have]
    if miss:
        L += ["## Not yet computed", "", "No file, because no adhesive run has the data yet:", ""]
        for q, item in miss:
            how = MISSING_HOW.get(item, "a run at the reference load with observables and fields "
                                        "(`cases/challenge/reference-load.toml`)")
            L.append(f"- `{q}` (item {item}): not yet computed, run {how}, then regenerate.")
        L.append("")
    return L


def _best_band_lines(banded):
    """The paragraph on the bands where the best estimates decide the load and Tabor curves."""
    return ["**Error bands.** " + ", ".join(f"`{c['quantity']}.csv`" for c in banded) + " carry the reference's "
            "own uncertainty as a column (`# band: <y>_err`, the half-width in y's unit), and `cmc check` scores a "
            "prediction against it (inside the band passes; outside, it says by how much in units of the band). "
            "The load and Tabor curves (items 2, 6, 7 and 8) are best estimates row by row (the block at the top, "
            "`python/cmc/analysis/best.py`): each row's band is the error of its own refinement sequence (twice "
            "the last change where only two grids exist, the first-order bound), plus, where its grid does not "
            "resolve ρ, its strategy's error measured on the scaled family at the same dx/ρ "
            "(`reference/challenge-scaled/`). Each file's `estimated_error` names the run, grid and rule of every "
            "row, and `still_wide` the rows whose bands stay above the targets. " + roundoff_note(rel=_rel), ""]


def _band_lines(have, keep_from, keep_bands, best=False):
    """The paragraph on the error bands (or the stored one); best: the best estimates decide the
    load and Tabor curves, so the strategies' bands those curves had before are not described."""
    L = []
    banded = [have[q] for q, _ in ALL if q in have and have[q].get("band")]  # the files table's order
    if banded and best:
        L += _best_band_lines(banded)
    elif banded and keep_bands and keep_from:
        L += _stored_block(keep_from, "**Error bands.**", "**Caveat.**")
    elif banded:
        checks = condition_checks()
        L += ["**Error bands.** " + ", ".join(f"`{c['quantity']}.csv`" for c in banded) + " carry the reference's "
              "own uncertainty as a column (`# band: <y>_err`, the half-width in y's unit), and `cmc check` scores a "
              "prediction against it (inside the band passes; outside, it says by how much in units of the band). "
              "The band is the error that the run's strategy (the plain interaction, or the range coarse-graining) "
              "has on the scaled challenge family (`reference/challenge-scaled/`: converged at s = 32, "
              "dx = 0.8 ρ(s)) at the same dx/ρ: its deviation from the family's converged value plus that value's "
              "refinement error. It was measured at μ_T = 3 and 250 kPa. Where the family was also run at a sweep's "
              "other points (`reference/challenge-scaled/conditions/`, `scripts/scaled_family.py --tabor` and "
              "`--pressure`) the band is the larger of the two measured errors: per μ_T for the Tabor sweep, per "
              "load for the load sweep (interpolated in log p between the measured loads and held beyond them); "
              "at the points not measured the band is **assumed** (each file's `estimated_error` says which). "
              + _own_refinement_sentence(banded)
              + (condition_summary(checks) + " (`reference/challenge-scaled/README.md`, \"The bands at "
                 "other conditions\".) " if checks else "")
              + roundoff_note(rel=_rel), "",
              "**Caveat.** " + (transfer_caveat() or "No transfer check possible (the store lacks the runs)."), ""]
    return L


def _hardwall_lines(hw, keep_from):
    """The hard-wall refinement table, for context (or the stored one)."""
    L = []
    if hw:
        n1, n2 = hw["grids"]
        L += [f"For context only, the **hard-wall** problem at the same load (`{hw['folder']}`"
              + (", `refinement.md`" if hw["table"] else "") + f") changes between {n1}² and {n2}² by:", "",
              f"| observable | {n1}² | {n2}² | relative change |", "|---|---|---|---|"]
        for k, (a, b, d) in hw["changes"].items():
            L.append(f"| {HW_LABELS[k]} | {a:.6g} | {b:.6g} | {100 * d:.2g} % |")
        L += ["", f"(SI units; relative change = |value at {n2}² − value at {n1}²| / |value at {n2}²|, from "
              "`cmc refine`'s refinement.json. The raw contact "
              "fraction converges slowly, the perimeter-corrected one much faster.) The hard-wall curves are in "
              "[adhesionless/](adhesionless/README.md).", ""]
    elif keep_from:
        L += _stored_block(keep_from, "For context only, the **hard-wall**", "(SI units;")
    return L


def _regenerate_lines(ref_run, ref_step, coarser, best=False):
    """The commands that regenerate the files; best: the load and Tabor curves come from the
    stored runs' best estimates, not from one sweep each."""
    sweeps = BEST_REGENERATE if best else [
        "build/cmc run cases/challenge/load-sweep.toml --out results/challenge-load-sweep     # items 2, 8",
        "scripts/tabor_sweep.sh                                                                 # items 6, 7"]
    L = []
    L += ["## Regenerate", "",
          "One command runs everything behind these files (and `adhesionless/`), resumable, then rewrites them: "
          "`scripts/sweeps.sh` (hours on 2 cores; the commands it runs, with their `--set` options, are also in "
          "each file's `command` line). Its parts:", "",
          "```"] + (run_commands(ref_run, ref_step, coarser) or [
          "build/cmc run cases/challenge/reference-load.toml --out results/challenge-reference   # items 1, 3, 4, 5, 9",
          "build/cmc run cases/challenge/reference-load.toml --set grid.n=4096 --out results/challenge-reference-n4096"
          "   # their bands"]) + [
          ] + sweeps + [
          "/usr/bin/python3 scripts/roundoff_spread.py NAME:RUN_A:RUN_B ...  # round-off spread: one case by two "
          "builds or thread counts (roundoff_spread.json, its command line)",
          "/usr/bin/python3 scripts/scaled_family.py --s 32 --coarse 2 4 6 8 12 24 --store reference/challenge-scaled"
          "   # the strategy bands",
          "/usr/bin/python3 scripts/challenge_reference.py        # rewrites reference/challenge/*.csv and this README",
          "build/cmc check PRED.csv --quantity gap_distribution   # score a prediction against gap_distribution.csv",
          "```", "",
          "A finer grid of the same case (`--set grid.n=N`, twice the finest) becomes the source of items 1, 3, 4, 5 "
          "and 9 once its run is in `results/`, with its band from the grid before it; "
          "`scripts/challenge_reference.py --only reference-load` rewrites those alone.", ""]
    return L


def readme(curves: list[Json], out_dir: str, hw: Json | None, ref_run: Run | None, ref_step: Json | None,
           keep_from: str | None = None, keep_bands: bool = False, coarser: tuple[Run, Json] | None = None,
           best: bool = False) -> str:
    """The README of reference/challenge/. keep_from (--only): a stored README whose paragraphs
    on the reference-load run and the hard-wall refinement are kept where their runs are not at
    hand, and with keep_bands (--only reference-load) those on the bands of the curves not
    recomputed. coarser: (run, step) of the grid that gives ref_run's curves their bands. best: the
    best estimates (best_estimates.json) will decide the load and Tabor curves."""
    have = {c["quantity"]: c for c in curves}
    L = ["# Challenge reference curves", "",
         "`cmc check PRED.csv --quantity Q` compares a prediction with `reference/challenge/Q.csv` by default. "
         "These curves come from **cmc's own runs** (`source: cmc run`), not from the published solution of the "
         "Contact Mechanics Challenge, and are **not converged**: see *Accuracy* below. The format is described in "
         "[../README.md](../README.md); the provenance (cmc version, case file, grid, solver tolerance, date, "
         "command) is in each file's header.", "",
         "Generated by `/usr/bin/python3 scripts/challenge_reference.py` (deterministic given the runs; the "
         "`date` is the run's summary.json modification time). Do not edit the CSV files by hand.", "",
         "## Files", ""] + files_table(curves) + [
         "Without adhesion (the same surface under the hard wall alone): [adhesionless/](adhesionless/README.md), "
         "`cmc check --adhesionless`.", ""]
    L += _reference_load_paragraph(ref_run, ref_step, keep_from, coarser)
    L += _missing_lines(have)
    L += ["## Accuracy", "", accuracy_head(ref_run), ""]
    L += _band_lines(have, keep_from, keep_bands, best)
    L += distribution_paragraphs(curves)
    L += [] if best else _hardwall_lines(hw, keep_from)
    L += _regenerate_lines(ref_run, ref_step, coarser, best)
    return "\n".join(L)


def stored_curve(path: str, quantity: str, item: int) -> Json | None:
    """A stored reference CSV read back as the curve that wrote it (the fields the README uses),
    or None: what --only tabor keeps of the curves it does not recompute."""
    got = read_reference_csv(path)
    if got is None:
        return None
    meta, names, data = got
    cols = [(n, meta.get(f"unit.{n}", "").split(" (")[0], "", list(data[:, i])) for i, n in enumerate(names)]
    prov = [(k, meta[k]) for k in ("cmc_version", "case_file", "grid", "solver_tolerance", "date", "command") if k in meta]
    return dict(name=meta.get("name", quantity), quantity=quantity, item=item, title=meta.get("title", ""),
                columns=cols, representation=meta.get("representation", ""), band=meta.get("band"),
                extra=prov, estimated_error=meta.get("estimated_error", ""))
