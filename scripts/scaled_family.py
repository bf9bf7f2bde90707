#!/usr/bin/python3
"""The scaled challenge family: converged adhesive references where they are
affordable, and plain coarse runs beside them.

    /usr/bin/python3 scripts/scaled_family.py [--s 32 16] [--coarse 2 4] [--grids N ...] [--no-resolved]
                                              [--start-resolved] [--refinement-only] [--max-outer-resolved N]
                                              [--no-plain] [--no-hardwall]
                                              [--strategies range shape]
                                              [--results results/scaled-family] [--store reference/challenge-scaled]
                                              [--cmc build/cmc] [--set KEY=VALUE ...] [--dry-run]
                                              [--seed N] [--tabor MU] [--pressure PA]

Member s of the family is cases/challenge/scaled-family.toml with
surface.cutoff_wavelength = s x 0.1 µm and interaction.work_of_adhesion = s x 0.05 J/m²
(mu_T = 3, so rho(s) follows from the surface's R_c). For each s it runs, on the loading
branch at 250 kPa:
  resolved     the smallest power-of-two grid with dx <= 0.8 rho(s)   -> the reference value
               (and dx <= lambda_s/64, which only a lower mu_T than 3 makes the finer bound)
  refinement   half that grid (dx <= 1.6 rho(s))                        -> its refinement error
  plain_<k>rho the FFT-friendly grid (factors 2, 3, 5) nearest dx = k rho(s), for each k of
               --coarse (default 2 and 4, the spacings the resolution strategy targets; 6, 12
               and 24 match the challenge's own 8192², 4096² and 2048² in dx/rho AND dx/lambda_s,
               since rho/lambda_s is the same for every s)
  range_<k>rho, shape_<k>rho   the same grids with interaction.coarse_graining = "range" or "shape"
               (the two resolution strategies; --strategies picks)
  plain_n<N>, range_n<N>, shape_n<N>   explicit grids of --grids (the challenge itself, s = 1, which no
               grid here resolves: use --s 1 --no-resolved --grids 2048 4096)
--start-resolved starts the resolved run from the refinement run's answer (cmc run
--start-from, solver/cmc/output/CoarseStart.hpp; the refinement run then writes its fields
into n<N>-fields/): about 0.6 of a cold start's FFT pairs, with the same a_r where measured
(s = 32 at 2048²; s = 16 at 4096²); its record says so ("start_from"). The s = 8 member's
8192² run needs it, and still takes hours on 2 cores (1503 iterations in 73 outer steps and
2.4 h, unconverged); it resumes from its checkpoint.
--max-outer-resolved N caps the resolved run's outer steps (solver.max_outer_steps; cmc's
default 1000). A resumed run may lower the cap to just above the outer steps it has made
(docs/user-guide/command-line.md): it then stops there, status not_converged, and the
stored reference says so (its status and last tension change), for a run that creeps for
hours towards its tension tolerance (s = 8).
rho(s) is read from `cmc surface` (dx_over_range), never assumed. Runs go to
RESULTS/s<S>/n<N>/ through `cmc sweep`, one per case and set of overrides over its grids (its
table RESULTS/s<S>/sweep-<first role>.json): a finished run is kept, an interrupted one resumes.

--tabor MU and --pressure PA run the family at another condition than the challenge's
(mu_T = 3, 250 kPa): the Tabor sweep's and the load sweep's points (challenge items 2, 6, 7
and 8), whose error bands are the family's error measured at mu_T = 3 and 250 kPa. A
condition's runs go to RESULTS/conditions/<condition>/ and its store holds that condition
only (e.g. --store reference/challenge-scaled/conditions/mu_T1): it measures whether the
bands hold there (cmc.analysis.conditions, condition_checks), and the sweeps' references take the
larger of the two errors (run_band, load_bands); the challenge's own error bars (s = 1 at
250 kPa) take nothing from it. The hard-wall runs get the pressure too (mu_T is adhesion's).

--store merges into STORE/scaled_family.json (members and runs of this invocation replace
those with the same s and role; others are kept) and rewrites STORE/README.md from it:
STORE/scaled_family.json (every run: command, grid, dx/rho, tolerance,
iterations, FFT pairs, wall time, a_r, repulsive a_r, mean gap; per s the reference with
its refinement error) and STORE/README.md, each atomically. The reference of a quantity
is its value on the resolved grid; its refinement error is |resolved - refinement|, which
bounds the resolved grid's own error if the error falls at least linearly with dx (for
order p it is |difference| / (2^p - 1)); the README states it as such. Numbers come from
the runs' summary.json only.
"""
import argparse
import datetime
import json
import math
import os
import subprocess
import sys
import tempfile

from cmc.analysis.conditions import condition_checks  # noqa: E402
from cmc.analysis.family import (FAMILY_QUANTITIES as QUANTITIES, adhesionless, challenge_estimates,  # noqa: E402
                                 condition_members, deviation, member_reference, seed_members, strategy_run_near)
from cmc.analysis.s_route import s_extrapolation  # noqa: E402
from cmc.analysis.transfer import STRATEGY_TARGETS, meets_target  # noqa: E402
from cmc.report.common import condition_check_lines, condition_summary, s_extrapolation_verdict  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
CASE = "cases/challenge/scaled-family.toml"
CASE_HW = "cases/challenge/scaled-family-hardwall.toml"  # the same surfaces under the hard wall alone
L = 1.0e-4                 # m, the case's grid.size
LAMBDA_S1, W1 = 0.1e-6, 0.05  # the challenge's cutoff (m) and work of adhesion (J/m²), s = 1
# The resolution strategies' runs: the coarse grids with the range or the shape coarse-graining
# (docs/user-guide/case-files.md, [interaction] coarse_graining; solver/cmc/contact/Interaction.hpp,
# coarse_grained_range and shape_coarse_grained).
STRATEGY = {"range": ['interaction.coarse_graining="range"'], "shape": ['interaction.coarse_graining="shape"']}


def member_sets(s, adhesion=True):
    """The --set overrides that make member s of a family case (the hard-wall case has no w)."""
    return ([f"surface.cutoff_wavelength={s * LAMBDA_S1:.6g}"]
            + ([f"interaction.work_of_adhesion={s * W1:.6g}"] if adhesion else []))


def condition_sets(tabor, pressure, adhesion=True):
    """The --set overrides of a condition (--tabor, --pressure); the hard-wall case has no mu_T."""
    return (([f"interaction.tabor={tabor:.6g}"] if tabor is not None and adhesion else [])
            + ([f"loading.values=[{pressure:.6g}]"] if pressure is not None else []))


def condition_name(tabor, pressure):
    """The folder name of a condition ("mu_T1", "p1e+06Pa", "mu_T0.316-p1e+06Pa"), or None for the
    challenge's own (mu_T = 3, 250 kPa)."""
    parts = ([f"mu_T{tabor:g}"] if tabor is not None else []) + ([f"p{pressure:g}Pa"] if pressure is not None else [])
    return "-".join(parts) or None


def condition_words(m):
    """"μ_T = 3, at 250 kPa" or the member's own condition."""
    mu = m.get("tabor", 3)
    p = m.get("pressure_Pa", 250e3)
    return f"μ_T = {mu:g}" + ("" if "tabor" not in m else " (`--tabor`)") + f", at {p / 1e3:g} kPa" + (
        "" if "pressure_Pa" not in m else " (`--pressure`)")


def rho_of(cmc, s, extra):
    """rho(s) in m from `cmc surface` at the case's own grid (dx / dx_over_range)."""
    args = [cmc, "surface", CASE] + sum((["--set", x] for x in member_sets(s) + extra), [])
    out = subprocess.run(args, capture_output=True, text=True, cwd=ROOT)
    if out.returncode != 0:
        sys.exit(f"scaled_family: {' '.join(args)} failed:\n{out.stderr}")
    facts = {}
    for line in out.stdout.splitlines():
        parts = line.split()
        if len(parts) >= 2:
            facts[parts[0]] = parts[1]
        if line.strip().startswith("grid"):
            facts["dx"] = line.split("dx =")[1].split()[0]
    return float(facts["dx"]) / float(facts["dx_over_range"])


def fft_friendly(x):
    """The even integer with prime factors 2, 3, 5 only that is nearest to x."""
    best = None
    for n in range(max(2, int(x * 0.8)), int(x * 1.25) + 2):
        m = n
        for f in (2, 3, 5):
            while m % f == 0:
                m //= f
        if m == 1 and n % 2 == 0 and (best is None or abs(n - x) < abs(best - x)):
            best = n
    return best


def fmt_k(k):
    return f"{k:g}".replace(".", "p")


def grids(rho, coarse, explicit, resolved, strategies=tuple(STRATEGY), lambda_s=None):
    """role -> grid size, in the order the runs are made (cheapest first). The resolved grid is
    the smallest power of two with dx <= 0.8 rho and dx <= lambda_s / 64: at mu_T = 3 the first
    implies the second (rho/lambda_s = 0.019, so dx = 0.8 rho is lambda_s / 65.5 for every s); at
    a lower mu_T (--tabor) rho grows and the surface's short cutoff, resolved as finely as at
    mu_T = 3, sets the grid."""
    g = {}
    for k in sorted(coarse, reverse=True):
        n = fft_friendly(L / (k * rho))
        g[f"plain_{fmt_k(k)}rho"] = n
        for st in strategies:
            g[f"{st}_{fmt_k(k)}rho"] = n
    for n in sorted(explicit):
        g[f"plain_n{n}"] = n
        for st in strategies:
            g[f"{st}_n{n}"] = n
    if resolved:
        n_res = 2
        while L / n_res > 0.8 * rho or (lambda_s is not None and L / n_res > lambda_s / 64):
            n_res *= 2
        g["refinement"] = n_res // 2
        g["resolved"] = n_res
    return g


def summary_ok(path):
    """A finished run (converged, or stopped at a cap: not_converged, which a rerun of the same case
    repeats bit for bit) is kept; a failed or missing one is (re)run."""
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f).get("status") in ("converged", "not_converged")
    except (OSError, ValueError):
        return False


def job(role, n, suffix, extra, case=CASE, options=()):
    """One run: `case` as member s on the grid n into RESULTS/s<S>/n<N><suffix>, with the --set
    overrides `extra` and cmc run's `options` (--start-from)."""
    return {"role": role, "n": n, "suffix": suffix, "extra": extra, "case": case, "options": list(options)}


def job_folder(results, s, j):
    return os.path.join(results, f"s{s}", f"n{j['n']}{j['suffix']}")


def job_sets(s, j, grid=True):
    # The case files name the s = 32 member; each run is named for its own s.
    name = f"challenge-scaled-s{s}" if j["case"] == CASE else f"challenge-scaled-hardwall-s{s}"
    return ([f"case.name={name}"] + member_sets(s, adhesion=j["case"] == CASE) + ([f"grid.n={j['n']}"] if grid else [])
            + j["extra"])


def run_command(cmc, results, s, j):
    """The `cmc run` that makes the job's folder (as a cmc sweep point makes it, bit for bit)."""
    return ([cmc, "run", j["case"], "--out", job_folder(results, s, j), "--resume"]
            + sum((["--set", x] for x in job_sets(s, j)), []) + j["options"])


def shown(cmd):
    return " ".join(["cmc"] + cmd[1:])


def finished(results, s, j):
    """Whether the job's folder holds a finished run (summary_ok); said on stderr."""
    out = job_folder(results, s, j)
    if not summary_ok(os.path.join(ROOT, out, "summary.json")):
        return False
    with open(os.path.join(ROOT, out, "summary.json"), encoding="utf-8") as f:
        status = json.load(f)["status"]
    print(f"scaled_family: s = {s}, {j['n']}²: done ({out}" + ("" if status == "converged" else f", {status}") + ")",
          file=sys.stderr)
    return True


def sweep_command(cmc, results, s, jobs):
    """One `cmc sweep` over the grids of `jobs` (one case, one set of overrides, one folder suffix):
    RESULTS/s<S>/n<N><suffix> per grid, its table RESULTS/s<S>/sweep-<first role>.json and .md."""
    first = jobs[0]
    grids = [str(n) for n in sorted({j["n"] for j in jobs})]
    return ([cmc, "sweep", first["case"], "--out", os.path.join(results, f"s{s}"), "--grids", *grids,
             "--folder", "n{n}" + first["suffix"], "--table", "sweep-" + first["role"]]
            + sum((["--set", x] for x in job_sets(s, first, grid=False)), []))


def run_jobs(cmc, results, s, jobs, dry):
    """Makes every job's folder, in the order of the jobs: those of one case and one set of
    overrides (not started from another run) as one `cmc sweep` over their grids, refinement and
    resolved grids apart from the coarse ones (cheapest first); a run started from another with
    `cmc run`. A sweep whose runs have all finished is not started (a finished run is kept, an
    interrupted one resumes). Returns each job's command as the store records it: the `cmc run`
    that makes its folder."""
    steps = {}
    for i, j in enumerate(jobs):
        fine = j["role"] in ("refinement", "resolved")
        key = ("run", i) if j["options"] else ("sweep", j["case"], tuple(j["extra"]), j["suffix"], fine)
        steps.setdefault(key, []).append(j)
    for key, group in steps.items():
        todo = [j for j in group if not finished(results, s, j)]
        for j in todo:
            print(f"scaled_family: s = {s}, {j['n']}²: {shown(run_command(cmc, results, s, j))}", file=sys.stderr)
        if not todo:
            continue
        cmd = run_command(cmc, results, s, group[0]) if key[0] == "run" else sweep_command(cmc, results, s, group)
        print(f"scaled_family: s = {s}: {shown(cmd)}", file=sys.stderr, flush=True)
        if not dry:
            rc = subprocess.run(cmd, cwd=ROOT, stdout=sys.stderr).returncode  # a sweep's table: a log line
            if rc not in (0, 3):  # 3: not converged, stated in the summary
                sys.exit(f"scaled_family: cmc {cmd[1]} exited {rc} (s = {s}); rerun to resume")
    return [shown(run_command(cmc, results, s, j)) for j in jobs]


def record(out, role, n, rho, command):
    with open(os.path.join(ROOT, out, "summary.json"), encoding="utf-8") as f:
        d = json.load(f)
    st = d["steps"][-1]
    facts = d["surface_facts"]
    r = {"role": role, "n": n, "dx_m": L / n, "dx_over_rho": (L / n) / rho, "status": d["status"],
         "command": command, "output": out, "cmc_version": d.get("cmc_version"),
         "solver": d["case"]["solver"], "range_used_m": facts.get("interaction_range"),
         "tabor_used": facts.get("tabor_parameter"),
         "iterations": st["iterations"], "fft_pairs": st.get("fft_pairs"),
         # A resumed run's timing is its last process's; its steps' wall_s count every process's solve.
         "wall_s": max(d["timing"]["wall_s"], sum(x.get("wall_s", 0.0) for x in d["steps"])),
         "residual": st["residual"], "message": st.get("message", ""), "mean_pressure_Pa": st["mean_pressure"],
         "bistability_number": facts.get("bistability_number")}
    if "start_from" in d:  # started from a coarser run's answer (cmc run --start-from)
        r["start_from"] = {k: d["start_from"][k] for k in ("folder", "grid", "factor", "gap_lift")}
    obs = st.get("observables", {})
    for key, short, _ in QUANTITIES:
        r[short] = obs.get(key, st.get(key))
    if role.startswith("hardwall"):
        # The hard wall's counted area converges as dx (a boundary effect); its perimeter-
        # corrected value (Observables) much faster: that one is the adhesionless a_r.
        r["a_r_corrected"] = obs.get("contact_fraction_corrected")
    return r


def atomic_write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".tmp-")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def write_store(store, data):
    """STORE/scaled_family.json and the README.md made from it, each written atomically."""
    atomic_write(os.path.join(ROOT, store, "scaled_family.json"), json.dumps(data, indent=1) + "\n")
    atomic_write(os.path.join(ROOT, store, "README.md"), readme(data, os.path.join(ROOT, store)))


def readme(data, store_dir):
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
    main_store = not any(k in m for m in data["members"] for k in ("seed", "tabor", "pressure_Pa"))
    if main_store:
        lines += condition_lines(store_dir, data["members"])
    lines += s_route_lines(data.get("s_extrapolation"))
    return "\n".join(lines)


def condition_lines(store_dir, members):
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


def s_route_lines(x):
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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
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
    a = ap.parse_args()
    if a.reestimate:
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
        return
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

    members = []
    for s in a.s:
        rho = rho_of(a.cmc, s, adhesive_set + a.set)
        g = grids(rho, a.coarse, a.grids, not a.no_resolved, a.strategies, lambda_s=s * LAMBDA_S1)
        if a.no_plain:
            g = {role: n for role, n in g.items() if not role.startswith("plain_")}
        if a.refinement_only:
            g.pop("resolved", None)
        print(f"scaled_family: s = {s}: rho = {rho * 1e9:.4g} nm, grids "
              + ", ".join(f"{k} {v}² (dx = {L / v / rho:.2f} rho)" for k, v in g.items()), file=sys.stderr)
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
        members.append(m)
    if a.store and not a.dry_run:
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

if __name__ == "__main__":
    main()
