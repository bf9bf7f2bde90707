#!/usr/bin/python3
"""The scaled challenge family (issue 13): converged adhesive references where they are
affordable, and plain coarse runs beside them.

    /usr/bin/python3 scripts/scaled_family.py [--s 32 16] [--roles resolved refinement plain_2rho plain_4rho]
                                              [--results results/scaled-family] [--store reference/challenge-scaled]
                                              [--cmc build/cmc] [--set KEY=VALUE ...] [--dry-run]

Member s of the family is cases/challenge/scaled-family.toml with
surface.cutoff_wavelength = s x 0.1 µm and interaction.work_of_adhesion = s x 0.05 J/m²
(mu_T = 3, so rho(s) follows from the surface's R_c). For each s it runs, on the loading
branch at 250 kPa:
  resolved     the smallest power-of-two grid with dx <= 0.8 rho(s)   -> the reference value
  refinement   half that grid (dx <= 1.6 rho(s))                        -> its refinement error
  plain_2rho   the FFT-friendly grid (factors 2, 3, 5) nearest dx = 2 rho(s)  } the coarse grids the
  plain_4rho   the same for dx = 4 rho(s)                                    } resolution strategy targets
  range_2rho, range_4rho   the same grids with interaction.coarse_graining = "range"
rho(s) is read from `cmc surface` (dx_over_range), never assumed. Runs go to
RESULTS/s<S>/n<N>/ with --resume: a finished run is kept, an interrupted one resumes.

--store writes STORE/scaled_family.json (every run: command, grid, dx/rho, tolerance,
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

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
CASE = "cases/challenge/scaled-family.toml"
L = 1.0e-4                 # m, the case's grid.size
LAMBDA_S1, W1 = 0.1e-6, 0.05  # the challenge's cutoff (m) and work of adhesion (J/m²), s = 1
ROLES = ("resolved", "refinement", "plain_2rho", "plain_4rho", "range_2rho", "range_4rho")
# The resolution strategy's runs: the coarse grids with the range coarse-graining
# (cases/README.md, [interaction] coarse_graining; solver/cmc/scene/Scene.cpp).
STRATEGY = {"range": ['interaction.coarse_graining="range"']}
QUANTITIES = (("contact_fraction", "a_r", "1"), ("repulsive_fraction", "a_rep", "1"), ("mean_gap", "mean_gap", "m"))


def member_sets(s):
    return [f"surface.cutoff_wavelength={s * LAMBDA_S1:.6g}", f"interaction.work_of_adhesion={s * W1:.6g}"]


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


def grids(rho):
    n_res = 2
    while L / n_res > 0.8 * rho:
        n_res *= 2
    n2, n4 = fft_friendly(L / (2 * rho)), fft_friendly(L / (4 * rho))
    return {"resolved": n_res, "refinement": n_res // 2, "plain_2rho": n2, "plain_4rho": n4,
            "range_2rho": n2, "range_4rho": n4}


def summary_ok(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f).get("status") == "converged"
    except (OSError, ValueError):
        return False


def run(cmc, s, n, out, extra, dry):
    sets = member_sets(s) + [f"grid.n={n}"] + extra
    cmd = [cmc, "run", CASE, "--out", out, "--resume"] + sum((["--set", x] for x in sets), [])
    shown = " ".join(["cmc"] + cmd[1:])
    if summary_ok(os.path.join(ROOT, out, "summary.json")):
        print(f"scaled_family: s = {s}, {n}²: done ({out})", file=sys.stderr)
        return shown
    print(f"scaled_family: s = {s}, {n}²: {shown}", file=sys.stderr, flush=True)
    if not dry:
        rc = subprocess.run(cmd, cwd=ROOT).returncode
        if rc not in (0, 3):  # 3: not converged, stated in the summary
            sys.exit(f"scaled_family: cmc run exited {rc} (s = {s}, n = {n}); rerun to resume")
    return shown


def record(out, role, n, rho, command):
    with open(os.path.join(ROOT, out, "summary.json"), encoding="utf-8") as f:
        d = json.load(f)
    st = d["steps"][-1]
    r = {"role": role, "n": n, "dx_m": L / n, "dx_over_rho": (L / n) / rho, "status": d["status"],
         "command": command, "output": out, "cmc_version": d.get("cmc_version"),
         "solver": d["case"]["solver"], "range_used_m": d["surface_facts"]["interaction_range"],
         "tabor_used": d["surface_facts"].get("tabor_parameter"),
         "iterations": st["iterations"], "fft_pairs": st.get("fft_pairs"), "wall_s": d["timing"]["wall_s"],
         "residual": st["residual"], "mean_pressure_Pa": st["mean_pressure"],
         "bistability_number": d["surface_facts"]["bistability_number"]}
    obs = st.get("observables", {})
    for key, short, _ in QUANTITIES:
        r[short] = obs.get(key, st.get(key))
    return r


def atomic_write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".tmp-")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def readme(data):
    lines = ["# Scaled challenge family: converged adhesive references", "",
             "Generated by `/usr/bin/python3 scripts/scaled_family.py --store reference/challenge-scaled` "
             "from the runs' `summary.json`; do not edit by hand. Every run, with its command, is in "
             "`scaled_family.json`.", "",
             "Member s of the family is the challenge (`cases/challenge/scaled-family.toml`) with the short "
             "cutoff λ_s = s × 0.1 µm and the work of adhesion w = s × 50 mJ/m², μ_T = 3 (ρ(s) from the "
             "surface's R_c), at 250 kPa on the loading branch (solver `quasi_static`). ρ/λ_s, w/(E\\*ρ) and "
             "μ_T are the challenge's; only the bandwidth shrinks.", "",
             "**Reference** = the run on the resolved grid (dx ≤ 0.8 ρ(s)). **Refinement error** = |resolved − "
             "refinement| (the same case on half the points): it bounds the resolved grid's own error if the error "
             "falls at least linearly with dx (for order p it is |difference| / (2^p − 1)). The plain coarse runs "
             "(dx ≈ 2 ρ and 4 ρ, the unmodified exponential law sampled at grid points) show what a coarse grid "
             "gives without a resolution strategy; their deviation is from the reference.", ""]
    for m in data["members"]:
        ref = m["reference"]
        lines += [f"## s = {m['s']}: λ_s = {m['lambda_s_m'] * 1e6:.3g} µm, w = {m['w_J_m2']:.3g} J/m², "
                  f"ρ = {m['rho_m'] * 1e9:.4g} nm", "",
                  "| quantity | reference | refinement error | relative |", "|---|---|---|---|"]
        for _, short, unit in QUANTITIES:
            q = ref.get(short)
            if q:
                rel = q["refinement_error"] / abs(q["value"]) if q["value"] else float("nan")
                lines.append(f"| {short} ({unit}) | {q['value']:.6g} | {q['refinement_error']:.3g} | {100 * rel:.2f} % |")
        lines += ["", "| run | grid | dx/ρ | a_r | repulsive a_r | mean gap (m) | iterations | FFT pairs | wall (s) | status |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for r in m["runs"]:
            dev = ""
            if r["role"].split("_")[0] in ("plain",) + tuple(STRATEGY) and ref.get("a_r"):
                dev = (f" ({100 * (r['a_r'] / ref['a_r']['value'] - 1):+.1f} %, gap "
                       f"{100 * (r['mean_gap'] / ref['mean_gap']['value'] - 1):+.2f} %)")
            lines.append(f"| {r['role']}{dev} | {r['n']}² | {r['dx_over_rho']:.2f} | {r['a_r']:.6g} | {r['a_rep']:.6g} | "
                         f"{r['mean_gap']:.7g} | {r['iterations']} | {r['fft_pairs']} | {r['wall_s']:.0f} | {r['status']} |")
        lines.append("")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--s", type=int, nargs="+", default=[32, 16])
    ap.add_argument("--roles", nargs="+", default=list(ROLES), choices=ROLES)
    ap.add_argument("--results", default="results/scaled-family")
    ap.add_argument("--store", default=None, help="write scaled_family.json and README.md here")
    ap.add_argument("--cmc", default="build/cmc")
    ap.add_argument("--set", action="append", default=[], help="extra cmc --set override for every run")
    ap.add_argument("--dry-run", action="store_true", help="print the runs, run nothing")
    a = ap.parse_args()

    members = []
    for s in a.s:
        rho = rho_of(a.cmc, s, a.set)
        g = grids(rho)
        print(f"scaled_family: s = {s}: rho = {rho * 1e9:.4g} nm, grids "
              + ", ".join(f"{k} {v}² (dx = {L / v / rho:.2f} rho)" for k, v in g.items()), file=sys.stderr)
        runs = []
        for role in a.roles:
            strategy = role.split("_")[0] if role.split("_")[0] in STRATEGY else None
            out = os.path.join(a.results, f"s{s}", f"n{g[role]}" + (f"-{strategy}" if strategy else ""))
            cmd = run(a.cmc, s, g[role], out, a.set + (STRATEGY[strategy] if strategy else []), a.dry_run)
            if not a.dry_run:
                runs.append(record(out, role, g[role], rho, cmd))
        m = {"s": s, "lambda_s_m": s * LAMBDA_S1, "w_J_m2": s * W1, "rho_m": rho, "runs": runs, "reference": {}}
        by = {r["role"]: r for r in runs}
        if "resolved" in by and "refinement" in by:
            for _, short, unit in QUANTITIES:
                m["reference"][short] = {"value": by["resolved"][short], "unit": unit,
                                         "refinement_error": abs(by["resolved"][short] - by["refinement"][short]),
                                         "grid": by["resolved"]["n"], "coarser_grid": by["refinement"]["n"]}
        members.append(m)
    if a.store and not a.dry_run:
        data = {"generator": "scripts/scaled_family.py", "case_file": CASE,
                "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
                "load_Pa": 250e3, "members": members}
        atomic_write(os.path.join(ROOT, a.store, "scaled_family.json"), json.dumps(data, indent=1) + "\n")
        atomic_write(os.path.join(ROOT, a.store, "README.md"), readme(data))
        print(f"scaled_family: wrote {a.store}/scaled_family.json and README.md", file=sys.stderr)


if __name__ == "__main__":
    main()
