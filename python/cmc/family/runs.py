"""The scaled challenge family's runs: member s's case overrides, its grids (resolved,
refinement, coarse), the cmc sweeps that run them (resumable), and each run's record."""
from __future__ import annotations
from typing import Any, Iterable, Sequence
import os
import subprocess
import sys

from ..analysis.family import FAMILY_QUANTITIES as QUANTITIES
from ..analysis.runs import REPO as ROOT
from cmc import run_folder
from cmc._types import Json


CASE = "cases/challenge/scaled-family.toml"
CASE_HW = "cases/challenge/scaled-family-hardwall.toml"  # the same surfaces under the hard wall alone
L = 1.0e-4                 # m, the case's grid.size
LAMBDA_S1, W1 = 0.1e-6, 0.05  # the challenge's cutoff (m) and work of adhesion (J/m²), s = 1
# The resolution strategies' runs: the coarse grids with the range or the shape coarse-graining
# (docs/user-guide/case-files.md, [interaction] coarse_graining; solver/cmc/contact/Interaction.hpp,
# coarse_grained_range and shape_coarse_grained).
STRATEGY = {"range": ['interaction.coarse_graining="range"'], "shape": ['interaction.coarse_graining="shape"']}


def member_sets(s: int, adhesion: bool = True) -> list[str]:
    """The --set overrides that make member s of a family case (the hard-wall case has no w)."""
    return ([f"surface.cutoff_wavelength={s * LAMBDA_S1:.6g}"]
            + ([f"interaction.work_of_adhesion={s * W1:.6g}"] if adhesion else []))


def condition_sets(tabor: float | None, pressure: float | None, adhesion: bool = True) -> list[str]:
    """The --set overrides of a condition (--tabor, --pressure); the hard-wall case has no mu_T."""
    return (([f"interaction.tabor={tabor:.6g}"] if tabor is not None and adhesion else [])
            + ([f"loading.values=[{pressure:.6g}]"] if pressure is not None else []))


def condition_name(tabor: float | None, pressure: float | None) -> str | None:
    """The folder name of a condition ("mu_T1", "p1e+06Pa", "mu_T0.316-p1e+06Pa"), or None for the
    challenge's own (mu_T = 3, 250 kPa)."""
    parts = ([f"mu_T{tabor:g}"] if tabor is not None else []) + ([f"p{pressure:g}Pa"] if pressure is not None else [])
    return "-".join(parts) or None


def condition_words(m: Json) -> str:
    """"μ_T = 3, at 250 kPa" or the member's own condition."""
    mu = m.get("tabor", 3)
    p = m.get("pressure_Pa", 250e3)
    return f"μ_T = {mu:g}" + ("" if "tabor" not in m else " (`--tabor`)") + f", at {p / 1e3:g} kPa" + (
        "" if "pressure_Pa" not in m else " (`--pressure`)")


def rho_of(cmc: str, s: int, extra: list[str]) -> float:
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


def fft_friendly(x: float) -> int:
    """The even integer with prime factors 2, 3, 5 only that is nearest to x."""
    best = None
    for n in range(max(2, int(x * 0.8)), int(x * 1.25) + 2):
        m = n
        for f in (2, 3, 5):
            while m % f == 0:
                m //= f
        if m == 1 and n % 2 == 0 and (best is None or abs(n - x) < abs(best - x)):
            best = n
    if best is None:
        raise ValueError(f"no even 2-3-5 grid size within a factor 1.25 of {x:g}")
    return best


def fmt_k(k: float) -> str:
    return f"{k:g}".replace(".", "p")


def grids(rho: float, coarse: Sequence[float], explicit: Sequence[int], resolved: bool,
          strategies: Sequence[str] = tuple(STRATEGY), lambda_s: float | None = None) -> dict[str, int]:
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


def summary_ok(path: str) -> bool:
    """A finished run (converged, or stopped at a cap: not_converged, which a rerun of the same case
    repeats bit for bit) is kept; a failed or missing one is (re)run."""
    try:
        return run_folder.read_summary(os.path.dirname(path)).status in ("converged", "not_converged")
    except run_folder.RunFolderError:
        return False


def job(role: str, n: int, suffix: str, extra: list[str], case: str = CASE, options: Iterable[str] = ()) -> Json:
    """One run: `case` as member s on the grid n into RESULTS/s<S>/n<N><suffix>, with the --set
    overrides `extra` and cmc run's `options` (--start-from)."""
    return {"role": role, "n": n, "suffix": suffix, "extra": extra, "case": case, "options": list(options)}


def job_folder(results: str, s: int, j: Json) -> str:
    return os.path.join(results, f"s{s}", f"n{j['n']}{j['suffix']}")


def job_sets(s: int, j: Json, grid: bool = True) -> list[str]:
    # The case files name the s = 32 member; each run is named for its own s.
    name = f"challenge-scaled-s{s}" if j["case"] == CASE else f"challenge-scaled-hardwall-s{s}"
    return ([f"case.name={name}"] + member_sets(s, adhesion=j["case"] == CASE) + ([f"grid.n={j['n']}"] if grid else [])
            + j["extra"])


def run_command(cmc: str, results: str, s: int, j: Json) -> list[str]:
    """The `cmc run` that makes the job's folder (as a cmc sweep point makes it, bit for bit)."""
    return ([cmc, "run", j["case"], "--out", job_folder(results, s, j), "--resume"]
            + sum((["--set", x] for x in job_sets(s, j)), []) + j["options"])


def shown(cmd: list[str]) -> str:
    return " ".join(["cmc"] + cmd[1:])


def finished(results: str, s: int, j: Json) -> bool:
    """Whether the job's folder holds a finished run (summary_ok); said on stderr."""
    out = job_folder(results, s, j)
    if not summary_ok(os.path.join(ROOT, out, "summary.json")):
        return False
    status = run_folder.read_summary(os.path.join(ROOT, out)).data["status"]
    print(f"scaled_family: s = {s}, {j['n']}²: done ({out}" + ("" if status == "converged" else f", {status}") + ")",
          file=sys.stderr)
    return True


def sweep_command(cmc: str, results: str, s: int, jobs: list[Json]) -> list[str]:
    """One `cmc sweep` over the grids of `jobs` (one case, one set of overrides, one folder suffix):
    RESULTS/s<S>/n<N><suffix> per grid, its table RESULTS/s<S>/sweep-<first role>.json and .md."""
    first = jobs[0]
    grids = [str(n) for n in sorted({j["n"] for j in jobs})]
    return ([cmc, "sweep", first["case"], "--out", os.path.join(results, f"s{s}"), "--grids", *grids,
             "--folder", "n{n}" + first["suffix"], "--table", "sweep-" + first["role"]]
            + sum((["--set", x] for x in job_sets(s, first, grid=False)), []))


def run_jobs(cmc: str, results: str, s: int, jobs: list[Json], dry: bool) -> list[str]:
    """Makes every job's folder, in the order of the jobs: those of one case and one set of
    overrides (not started from another run) as one `cmc sweep` over their grids, refinement and
    resolved grids apart from the coarse ones (cheapest first); a run started from another with
    `cmc run`. A sweep whose runs have all finished is not started (a finished run is kept, an
    interrupted one resumes). Returns each job's command as the store records it: the `cmc run`
    that makes its folder."""
    steps: dict[tuple[Any, ...], list[Json]] = {}
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


def record(out: str, role: str, n: int, rho: float, command: str) -> Json:
    d = run_folder.read_summary(os.path.join(ROOT, out)).data
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
