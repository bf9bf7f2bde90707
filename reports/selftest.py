#!/usr/bin/python3
"""Self-test of the report scripts on synthetic inputs (no cmc run needed).

usage: /usr/bin/python3 reports/selftest.py [--keep DIR]

Writes small synthetic inputs that follow the output contracts (summary.json and
result.h5 of validation and challenge runs, results/performance/*.json, Google
Benchmark JSON) into a temporary folder, runs make_reports.py on them, and checks
that every figure is drawn and that an empty input tree gives "not computed yet"
lines instead of a crash. Exit 0 when all is well, 1 with the failures listed,
3 when numpy/matplotlib/h5py are missing.
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def write_json(path, obj):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(obj, f, indent=1)


def challenge_case(name, interaction=None, x0=50e-6):
    return {"case": {"name": name}, "material": {"contact_modulus": 25e6},
            "interaction": interaction or {"kind": "hard_wall"},
            "observables": {"enabled": True, "cross_section_x": x0}}


def grid(n):
    dx = 1e-4 / n
    return {"nx": n, "ny": n, "size_x": 1e-4, "size_y": 1e-4, "dx": dx, "dy": dx, "boundary": "periodic"}


def _reference_inputs(res, np, h5py):
    """A load sweep and a run at the reference load with result.h5 observables."""
    # --- a load sweep (summary only) -------------------------------------------------
    steps = []
    for k, p in enumerate([12.5e3, 25e3, 50e3, 125e3, 250e3, 500e3, 1.25e6, 2.5e6, 5e6, 10e6, 17.5e6, 25e6]):
        t = p / 25e6
        ar = 1 - math.exp(-2.2 * t * (1 + 3 * t) / 0.9) if t < 1 else 0.999
        gap = 0.43e-6 * math.log(0.4 / t) if t < 0.4 else 1e-9 / t
        obs = {"contact_fraction": ar, "contact_fraction_corrected": ar * 0.97, "repulsive_fraction": ar,
               "attractive_fraction": 0.0, "mean_gap": gap, "mean_pressure": p, "n_patches": int(500 * ar + 3)}
        steps.append({"index": k, "branch": "loading", "mean_pressure": p, "contact_fraction": ar, "mean_gap": gap,
                      "converged": True, "iterations": 100, "observables": obs})
    write_json(os.path.join(res, "challenge-load-sweep-test", "summary.json"),
               {"case": challenge_case("challenge-load-sweep-test"), "grid": grid(256), "status": "converged",
                "timing": {"wall_s": 12.0, "fft_pairs": 1000}, "steps": steps})
    # --- a reference-load run with result.h5 observables -------------------------------
    folder = os.path.join(res, "challenge-reference-test")
    write_json(os.path.join(folder, "summary.json"),
               {"case": challenge_case("challenge-reference-test"), "grid": grid(256), "status": "converged",
                "surface_facts": {"dx_over_cutoff_wavelength": 3.906, "dx_over_range": 188.6},
                "timing": {"wall_s": 3.0, "fft_pairs": 300},
                "steps": [{"index": 0, "mean_pressure": 250e3, "contact_fraction": 0.03, "mean_gap": 1.1e-6,
                           "converged": True,
                           "observables": {"contact_fraction": 0.03, "mean_gap": 1.1e-6, "mean_pressure": 250e3,
                                           "n_patches": 40}}]})
    rng = np.random.default_rng(1)
    with h5py.File(os.path.join(folder, "result.h5"), "w") as f:
        f["heights"] = rng.random((8, 8)) * 1e-6
        o = f.create_group("step_0000/observables")
        ge = np.logspace(-10, -5.5, 46)
        gc = np.sqrt(ge[:-1] * ge[1:])
        o["gap_hist_edges"] = ge
        o["gap_hist_density"] = np.where(gc < 3e-6, 0.97 * np.sqrt(gc) / (2 / 3 * (3e-6) ** 1.5), 0.0)
        se = np.linspace(-24e6, 60e6, 101)
        sc = 0.5 * (se[:-1] + se[1:])
        o["stress_hist_edges"] = se
        o["stress_hist_density"] = 0.03 * np.exp(-np.abs(sc) / 5e6) / 1e7
        ae = np.logspace(-16, -10, 31)
        ac = np.sqrt(ae[:-1] * ae[1:])
        o["patch_area_edges"] = ae
        o["patch_area_density"] = 1e14 * (ac / 1e-16) ** -1.9
        q = np.logspace(4.5, 7.8, 80)
        o["stress_spectrum_q"] = q
        o["stress_spectrum_C"] = 1e-2 * (q / 3e5) ** -1.0
        y = np.arange(2048) * 1e-4 / 2048
        gsec = np.clip(1e-6 * np.sin(2 * np.pi * y / 2e-5) ** 2 - 1e-7, 0, None)
        o["cross_section_y"] = y
        o["cross_section_gap"] = gsec
        o["cross_section_pressure"] = np.where(gsec == 0, 2e6, 0.0) - np.where((gsec > 0) & (gsec < 5e-9), 1e6, 0.0)


def _sweep_and_stray_inputs(res):
    """Tabor sweeps (one refined, one stopped), a stopped finer run, and runs the report must
    ignore or survive: another project's, a cluster measurement, the family's, a malformed one."""
    # --- a Tabor sweep: one run per Tabor value (run-level), plus one run with a "tabor" per step
    for mu in (0.5, 1.0, 2.0, 3.0):
        write_json(os.path.join(res, f"challenge-tabor-{mu}", "summary.json"),
                   {"case": challenge_case(f"challenge-tabor-{mu}", {"kind": "exponential", "tabor": mu}),
                    "grid": grid(256), "status": "converged", "timing": {"wall_s": 5.0, "fft_pairs": 500},
                    "steps": [{"index": 0, "mean_pressure": 250e3, "contact_fraction": 0.03 + 0.01 * math.log(1 + mu),
                               "mean_gap": 1.0e-6 - 2e-8 * mu, "converged": True}]})
    write_json(os.path.join(res, "challenge-tabor-steps", "summary.json"),
               {"case": challenge_case("challenge-tabor-steps", {"kind": "exponential"}), "grid": grid(512),
                "status": "converged", "timing": {"wall_s": 9.0, "fft_pairs": 900},
                "steps": [{"index": k, "tabor": mu, "mean_pressure": 250e3, "converged": True,
                           "observables": {"contact_fraction": 0.031 + 0.01 * math.log(1 + mu),
                                           "mean_gap": 0.99e-6 - 2e-8 * mu, "mean_pressure": 250e3}}
                          for k, mu in enumerate([0.3, 1.0, 3.0, 10.0])]})
    # A Tabor point refined on the challenge itself (scripts/tabor_sweep.sh --grid N): one case on 256²
    # and 512², first order in dx, the cohesive zone resolved (bistability number below 1.49).
    for n in (256, 512):
        write_json(os.path.join(res, f"challenge-tabor-refined-n{n}", "summary.json"),
                   {"case": challenge_case("challenge-tabor-refined", {"kind": "exponential", "tabor": 0.1}),
                    "grid": grid(n), "status": "converged", "timing": {"wall_s": 5.0, "fft_pairs": 500},
                    "surface_facts": {"dx_over_range": 0.4 * 2048 / n, "bistability_number": 0.013 * 2048 / n},
                    "steps": [{"index": 0, "mean_pressure": 250e3, "converged": True,
                               "observables": {"contact_fraction": 0.02 * (1 + 0.14 * 2048 / n),
                                               "mean_gap": 1.0e-6 * (1 + 1e-4 * (2048 / n) ** 4),
                                               "mean_pressure": 250e3}}]})
    # A Tabor run that stopped before its tolerance: listed as such, not drawn, not in the CSVs.
    write_json(os.path.join(res, "challenge-tabor-stopped", "summary.json"),
               {"case": challenge_case("challenge-tabor-stopped", {"kind": "exponential", "tabor": 0.7}),
                "grid": grid(256), "status": "not_converged", "timing": {"wall_s": 5.0, "fft_pairs": 500},
                "steps": [{"index": 0, "mean_pressure": 250e3, "contact_fraction": 0.05, "mean_gap": 1.0e-6,
                           "converged": False, "iterations": 1000}]})
    # The reference-load case on a finer grid that stopped before its tolerance: not the headline's
    # grid error (its last state is not a result); the headline says that it stopped.
    write_json(os.path.join(res, "challenge-reference-test-n512", "summary.json"),
               {"case": challenge_case("challenge-reference-test"), "grid": grid(512), "status": "not_converged",
                "steps": [{"index": 0, "mean_pressure": 250e3, "contact_fraction": 0.9, "mean_gap": 1e-8,
                           "converged": False, "iterations": 5000,
                           "observables": {"contact_fraction": 0.9, "mean_gap": 1e-8, "mean_pressure": 250e3}}]})
    # A run of another project in the same folder must be ignored.
    write_json(os.path.join(res, "challenge-not", "summary.json"),
               {"case": {"case": {"name": "hertz-free"}}, "grid": grid(64), "steps": []})
    # A cluster cost measurement (scripts/cluster/measure.py) of the same case on a coarser grid
    # is not a result: the headline must not show it.
    write_json(os.path.join(res, "cluster-measure", "baseline", "summary.json"),
               {"case": challenge_case("challenge-reference-test"), "grid": grid(64), "status": "converged",
                "steps": [{"index": 0, "mean_pressure": 250e3, "contact_fraction": 0.5, "mean_gap": 9e-6,
                           "converged": True, "observables": {"contact_fraction": 0.5, "mean_gap": 9e-6,
                                                               "mean_pressure": 250e3}}]})
    # The scaled family's runs written outside results/scaled-family/ (scripts/scaled_family.py
    # --results results/seeds/seedN): three grids of a member at 250 kPa must not become the
    # reference-load runs (their group has the most grids).
    for n in (64, 128, 270):
        write_json(os.path.join(res, "seeds", "seed29", "s32", f"n{n}", "summary.json"),
                   {"case": challenge_case("challenge-scaled-hardwall-s32"), "grid": grid(n), "status": "converged",
                    "steps": [{"index": 0, "mean_pressure": 250e3, "contact_fraction": 0.05, "mean_gap": 3e-6,
                               "converged": True, "observables": {"contact_fraction": 0.05, "mean_gap": 3e-6,
                                                                   "mean_pressure": 250e3}}]})
    # A malformed summary must not crash the report.
    os.makedirs(os.path.join(res, "challenge-broken"), exist_ok=True)
    with open(os.path.join(res, "challenge-broken", "summary.json"), "w") as f:
        f.write("{ not json")


def _performance_inputs(root, res):
    """Performance records and Google Benchmark output."""
    # --- performance records and Google Benchmark output -------------------------------
    write_json(os.path.join(res, "performance", "pk.json"), {"records": [
        {"case": "challenge-hardwall", "grid": n, "tolerance": tol, "wall_s": 0.1 * (n / 256) ** 2 / tol ** 0.1,
         "iterations": 100, "fft_pairs": 110, "fft_pair_s": 1e-3 * (n / 256) ** 2,
         "error": {"contact_fraction": 0.1 * 256 / n + tol, "mean_gap": 0.02 * 256 / n + tol}}
        for n in (256, 512, 1024) for tol in (1e-4, 1e-8)]})
    benches = []
    for n in (256, 512, 1024, 2048):
        benches.append({"name": f"BM_FFTPair/{n}", "run_name": f"BM_FFTPair/{n}", "run_type": "iteration",
                        "real_time": 0.5 * (n / 256) ** 2, "time_unit": "ms", "items_per_second": 2000 / (n / 256) ** 2})
        benches.append({"name": f"BM_PolonskyKeerIteration/{n}", "run_name": f"BM_PolonskyKeerIteration/{n}",
                        "run_type": "iteration", "real_time": 0.62 * (n / 256) ** 2, "time_unit": "ms",
                        "items_per_second": 1000 / 0.62 / (n / 256) ** 2})
    # An iteration benchmark with the same-run counters (bench/bench_common.hpp): its loop's
    # iteration is 30 ms (ms_per_iteration), while its items/s say 40 ms (setup included).
    for n in (1024, 2048):
        benches.append({"name": f"BM_PolonskyKeerIteration_plain/{n}", "run_name": f"BM_PolonskyKeerIteration_plain/{n}",
                        "run_type": "iteration", "real_time": 1200.0, "time_unit": "ms", "items_per_second": 25.0,
                        "ms_per_iteration": 30.0, "fft_pairs_per_iteration": 1.5, "fft_pair_ms": 20.0,
                        "iteration_over_fft_pair": 1.5, "time_per_fft_pair": 1.0, "floor_pair_ms": 15.0,
                        "iteration_over_floor_pair": 2.0, "time_per_floor_pair": 30.0 / 1.5 / 15.0})
    write_json(os.path.join(root, "build", "bench.json"),
               {"context": {"date": "synthetic", "num_cpus": 2, "host_name": "selftest"}, "benchmarks": benches})


def _validation_inputs(root, np):
    """Validation summaries: a pass with a refinement study, a Hertz case with profiles, a failure."""
    # --- validation: one passing case with a refinement study, one failing check ---------
    v = os.path.join(root, "build", "validation")
    write_json(os.path.join(v, "synthetic-pass", "summary.json"),
               {"case": {"case": {"name": "synthetic-pass"}, "validation": {"reference": "none"}},
                "grid": {"nx": 128, "ny": 128, "size_x": 1e-3, "dx": 1e-3 / 128}, "status": "converged",
                "timing": {"wall_s": 0.1, "fft_pairs": 10},
                "validation": [{"reference": "none", "quantity": "penetration", "definition": "|d - d_ref| / d_ref",
                                "error": 1e-4, "tolerance": 1e-3, "pass": True},
                               {"reference": "none", "quantity": "order(penetration)", "grids": [64, 128, 256],
                                "errors": [4e-4, 1e-4, 2.5e-5], "observed_order": 2.0, "min_order": 1.2,
                                "fitted_errors": [4e-4, 1e-4, 2.5e-5],
                                "required_order_errors": [2.3e-4, 1e-4, 4.4e-5], "pass": True}]})
    # A Hertz case with the profiles.csv that `cmc validate --out` writes (columns of
    # validation/Profiles.cpp); the numbers are synthetic, the report only draws them.
    write_json(os.path.join(v, "synthetic-hertz", "summary.json"),
               {"case": {"case": {"name": "synthetic-hertz"}, "validation": {"reference": "hertz"}},
                "grid": {"nx": 16, "ny": 16, "boundary": "free"}, "status": "converged",
                "steps": [{"index": 0, "force": 1e-3}],
                "validation": [{"reference": "hertz", "quantity": "penetration", "definition": "d",
                                "error": 1e-4, "tolerance": 1e-3, "pass": True}]})
    with open(os.path.join(v, "synthetic-hertz", "profiles.csv"), "w") as f:
        f.write("# synthetic\nstep,a_over_dx,r_over_a,p_over_p0,p_hertz_over_p0,p_error_over_p0,gap_over_delta,"
                "gap_hertz_over_delta\n")
        for r in np.linspace(0, 2.9, 30):
            p = max(1 - r * r, 0)  # a synthetic dome, not Hertz
            f.write(f"0,8,{r},{p},{p},0,{max(r - 1, 0)},{max(r - 1, 0)}\n")
    write_json(os.path.join(v, "synthetic-fail", "summary.json"),
               {"case": {"case": {"name": "synthetic-fail"}}, "grid": {"nx": 64, "ny": 64}, "status": "converged",
                "validation": [{"reference": "none", "quantity": "mean_gap", "definition": "d", "error": 0.5,
                                "tolerance": 1e-3, "pass": False}]})


def make_inputs(root, np, h5py):
    """The synthetic inputs of every report under root."""
    res = os.path.join(root, "results")
    _reference_inputs(res, np, h5py)
    _sweep_and_stray_inputs(res)
    _performance_inputs(root, res)
    _validation_inputs(root, np)


def run_reports(root, out):
    cmd = [sys.executable, os.path.join(HERE, "make_reports.py"),
           "--validation", os.path.join(root, "build", "validation"), "--results", os.path.join(root, "results"),
           "--bench", os.path.join(root, "build", "bench.json"), "--reference", os.path.join(ROOT, "reference"),
           "--cases", os.path.join(ROOT, "cases", "challenge"), "--out", out]
    return subprocess.run(cmd, capture_output=True, text=True)


def profile_band_checks(np):
    """The cross-section band (cmc.report.challenge_figures profile_band, which reads the run for
    cmc.analysis.bands) holds the finer profile at every finer point when read as `cmc check`
    reads it (band and curve linear between points), with numbers worked by hand, and is never
    below its floor."""
    from cmc.report.challenge_figures import profile_band

    class R:  # the parts of a run that profile_band reads
        s = {"case": {"solver": {"tolerance": 1e-3}, "surface": {"rms_gradient": 1.0}},
             "surface_facts": {"rms_height": 2.0}}
        Estar = 10.0

    y, v = np.array([0.0, 1.0, 2.0, 3.0]), np.array([0.0, 0.0, 4.0, 4.0])
    yf = np.arange(0.0, 3.5, 0.5)
    vf = np.array([0.0, 0.0, 0.0, 3.0, 4.0, 4.0, 4.0])  # the step sits half a spacing earlier
    out = []
    b, floor = profile_band(R, "cross_section_gap", y, v, yf, vf)
    # |interp - fine| at the finer points: 0, 0, 0, 1 (y = 1.5: 2 vs 3), 0, 0, 0; floor 1e-3 x 2.
    if floor != 2e-3 or b is None or not np.allclose(b, [2e-3, 1.0, 1.0, 2e-3]):
        out.append(f"profile_band: gap band {b} floor {floor}, expected [0.002, 1, 1, 0.002] floor 0.002")
    else:
        held = np.abs(np.interp(yf, y, v) - vf) <= np.interp(yf, y, b) + 1e-15
        if not held.all():
            out.append("profile_band: the band does not hold the finer profile at every finer point")
    _, floor_p = profile_band(R, "cross_section_pressure", y, v, yf, vf)
    if floor_p != 1e-2:
        out.append(f"profile_band: stress floor {floor_p}, expected tolerance x E* x rms slope = 0.01")
    if profile_band(R, "cross_section_gap", y, v, yf[:3], vf[:3]) != (None, None):
        out.append("profile_band: a finer profile that covers only part of the line must give no band")
    return out


def sweep_end_checks():
    """cmc.report.challenge_runs sweep_end_note says why a load sweep's curve ends: full contact, a
    solver that stopped before its tolerance, or the case's last load."""
    from cmc.report.challenge_runs import sweep_end_note

    class R:  # the parts of a run that sweep_end_note reads
        s = {"case_file": "cases/x.toml", "case": {"interaction": {"kind": "exponential_adhesion"}}}
        nx, Estar, adhesive = 64, 25e6, True

    def step(ar, converged=True):
        return {"p": 25e6, "ar": ar, "converged": converged, "iterations": 121}

    out = []
    for pts, want in (([step(0.5), step(1.0)], "in full contact"),
                      ([step(0.988, converged=False)], "stopped before its tolerance"),
                      ([step(0.988)], "the last load the run was given (`loading.values`; case `cases/x.toml`), where the solver converged in 121 iterations")):
        note = sweep_end_note(R, pts)
        if want not in note or "25 MPa" not in note:
            out.append(f"sweep_end_note: {note!r} does not say '{want}' at 25 MPa")
    return out


def transfer_checks():
    """cmc.analysis.transfer transfer_check compares strategy/plain a_r at s = 1 with every member
    s > 1 at the same dx/rho, a member without its resolved run included (the ratio needs no
    reference), for each strategy; common.transfer_caveat names the strategy and says whether the
    members approach s = 1."""
    from cmc.report.common import transfer_caveat
    from cmc.analysis.transfer import transfer_check

    def run(role, k, a_r):
        return {"role": role, "n": 100, "dx_over_rho": k, "a_r": a_r}

    members = [
        {"s": 1, "runs": [run("plain_n4096", 12.0, 1.0), run("range_n4096", 12.0, 1.02), run("shape_n4096", 12.0, 1.08)]},
        {"s": 8, "runs": [run("plain_12rho", 12.1, 1.0), run("range_12rho", 12.1, 1.06), run("shape_12rho", 12.1, 1.12)]},
        {"s": 16, "reference": {"a_r": {"value": 1.0}},
         "runs": [run("plain_12rho", 11.7, 1.0), run("range_12rho", 11.7, 1.11), run("shape_12rho", 11.7, 1.18)]},
        {"s": 32, "runs": [run("plain_6rho", 6.0, 1.0), run("range_6rho", 6.0, 1.3)]},  # no dx/rho near 12
    ]
    out = []
    for strategy, want in (("range", {8: 1.06, 16: 1.11}), ("shape", {8: 1.12, 16: 1.18})):
        rows = transfer_check(members, strategy)
        got = {s: round(b, 6) for _, _, _, s, b in rows}
        if got != want or any(abs(a - members[0]["runs"][1 if strategy == "range" else 2]["a_r"]) > 1e-12
                              for _, _, a, _, _ in rows):
            out.append(f"transfer_check({strategy}): {rows}, expected the ratios {want} against s = 1's")
        text = transfer_caveat(members, strategy)
        if f"a_r of the {strategy} run" not in text or "at s = 8" not in text or "approach" not in text:
            out.append(f"transfer_caveat({strategy}): {text!r} does not name the strategy, s = 8 and the approach")
    return out


def realization_checks():
    """common.realization_rows (numbers from cmc.analysis.transfer realization_deviations): each
    run's a_r and mean gap against its own realization's reference, the strategies' targets (3 % /
    0.5 % at 2 rho, 6 % / 1 % at 4 rho) marked per cell and counted in the summary row, plain runs
    never marked."""
    from cmc.report.common import realization_rows

    def member(a_ref, g_ref, runs):
        return {"rho_m": 6e-8, "reference": {"a_r": {"value": a_ref, "refinement_error": 1e-4},
                                             "mean_gap": {"value": g_ref, "refinement_error": 1e-9}},
                "runs": [{"role": role, "a_r": a, "mean_gap": g} for role, a, g in runs]}

    members = [(28, member(0.05, 3e-6, [("plain_2rho", 0.047, 3.03e-6), ("shape_2rho", 0.0472, 3.02e-6),
                                         ("shape_4rho", 0.052, 2.99e-6)])),
               (29, member(0.06, 2.8e-6, [("shape_2rho", 0.0605, 2.801e-6), ("range_4rho", 0.06, 2.7e-6)]))]
    header, rows = realization_rows(members)
    out = []
    col = {h: i for i, h in enumerate(header)}
    if len(rows) != 3 or rows[0][0] != 28 or rows[1][0] != 29 or rows[2][0] != "largest":
        out.append(f"realization_rows: rows {rows}")
        return out
    want = {("plain, 2 ρ", 0): "-6.0 % / +1.00 %", ("shape, 2 ρ", 0): "-5.6 % / +0.67 % (not met)",
            ("shape, 2 ρ", 1): "+0.8 % / +0.04 % (met)", ("shape, 4 ρ", 0): "+4.0 % / -0.33 % (met)",
            ("range, 4 ρ", 1): "+0.0 % / -3.57 % (not met)", ("range, 2 ρ", 0): "–",
            ("shape, 2 ρ", 2): "5.6 % / 0.67 %; target met on 1 of 2", ("plain, 2 ρ", 2): "6.0 % / 1.00 %"}
    for (h, r), v in want.items():
        if rows[r][col[h]] != v:
            out.append(f"realization_rows: row {r}, column {h!r}: {rows[r][col[h]]!r}, expected {v!r}")
    return out


def roundoff_checks(root):
    """scripts/roundoff_spread.py on hand-made runs: the largest relative difference per quantity
    over the steps, and a clear error (non-zero exit, nothing written) for runs of two cases;
    cmc.report.common roundoff_note states what it wrote."""
    from cmc.report.common import roundoff_note

    def run(folder, name, ar, gap):
        write_json(os.path.join(root, "roundoff", folder, "summary.json"),
                   {"case": {"case": {"name": name}}, "grid": {"nx": 64, "ny": 64, "threads": 2},
                    "steps": [{"index": k, "mean_pressure": 1e5 * (k + 1), "contact_fraction": a, "mean_gap": g,
                               "observables": {"repulsive_fraction": a}} for k, (a, g) in enumerate(zip(ar, gap))]})
        return os.path.join(root, "roundoff", folder)

    a = run("a", "challenge-x", [0.1, 0.2], [1e-6, 5e-7])
    b = run("b", "challenge-x", [0.1, 0.2002], [1e-6, 5.005e-7])
    c = run("c", "challenge-y", [0.1, 0.2], [1e-6, 5e-7])
    out = os.path.join(root, "roundoff", "spread.json")
    script = os.path.join(ROOT, "scripts", "roundoff_spread.py")
    got, fails = subprocess.run([sys.executable, script, "--out", out, f"two builds:{a}:{b}"],
                                capture_output=True, text=True), []
    doc = json.load(open(out)) if got.returncode == 0 and os.path.isfile(out) else {}
    big = doc.get("largest", {})
    want = {"contact_fraction": 1e-3, "repulsive_fraction": 1e-3, "mean_gap": 1e-3}
    if any(not math.isclose(big.get(k, {}).get("relative", -1), v, rel_tol=1e-9) for k, v in want.items()):
        fails.append(f"roundoff_spread.py: largest {big}, expected 1e-3 in each quantity (exit {got.returncode}: "
                     f"{got.stderr.strip()})")
    elif doc["comparisons"][0]["steps_identical"] != 1:
        fails.append("roundoff_spread.py: the first step is equal in every quantity and must count as identical")
    elif "0.001 in a_r" not in roundoff_note(out):
        fails.append(f"roundoff_note does not state the spread: {roundoff_note(out)!r}")
    os.remove(out)
    bad = subprocess.run([sys.executable, script, "--out", out, f"mixed:{a}:{c}"], capture_output=True, text=True)
    if bad.returncode == 0 or "expected the same case" not in bad.stderr or os.path.exists(out):
        fails.append(f"roundoff_spread.py on two cases: exit {bad.returncode}, {bad.stderr.strip()!r}, "
                     f"output {'written' if os.path.exists(out) else 'absent'}")
    return fails


def speed_and_hard_checks(root):
    """The challenge report's speed and hard-case sections (speed_report.py): the hard-case table
    reads build/hard/<case>/summary.json, counts an expected failure as one, and draws the
    residual histories; a FAIL is named."""
    from cmc.report import speed as speed_report
    hard = os.path.join(root, "hard")
    checks = [{"quantity": "iterations", "verdict": "pass"}, {"quantity": "gap", "verdict": "xfail"}]
    write_json(os.path.join(hard, "spike", "summary.json"),
               {"case": {"case": {"name": "hard-spike", "description": "one spike"}, "solver": {"kind": "polonsky_keer"}},
                "grid": {"nx": 64, "ny": 64}, "status": "converged", "timing": {"iterations": 43, "wall_s": 0.05},
                "validation": checks, "residual_history": {"solve": [0, 0, 1, 1], "iteration": [0, 5, 0, 3],
                                                            "residual": [1.0, 0.1, "inf", 1e-11]}})
    write_json(os.path.join(hard, "bad", "summary.json"),
               {"case": {"case": {"name": "hard-bad"}}, "grid": {"nx": 8, "ny": 8}, "status": "not_converged",
                "validation": [{"quantity": "threads", "verdict": "FAIL"}]})
    out = os.path.join(root, "hard-report")
    lines = "\n".join(speed_report.hard_lines([hard], out))
    failures = []
    if "| hard-spike | one spike | polonsky_keer | 64×64 | converged | 43 | 0.05 | 2 | pass (expected failure: gap) |" \
            not in lines:
        failures.append("hard-case table: the spike's row (an expected failure) is not as expected:\n" + lines)
    x, y = speed_report.history_curve({"solve": [0, 0, 1, 1], "iteration": [0, 5, 0, 3], "residual": [1.0, 0, "inf", 1e-11]})
    import math
    if x[:2].tolist() != [0, 5] or not math.isnan(x[2]) or x[3:].tolist() != [6, 9] \
            or not (math.isnan(y[1]) and math.isnan(y[3]) and y[4] == 1e-11):
        failures.append(f"history_curve: the solves are not laid one after the other, or 0 and inf drawn: {x}, {y}")
    if "FAIL: threads" not in lines or not os.path.isfile(os.path.join(out, "hard_residuals.png")):
        failures.append("hard-case table: a failing case is not named, or the residual figure is missing")
    return failures


def _file_checks(out):
    """Every report's files exist; the performance table has the floor pair's row."""
    failures = []
    expect = {
        "validation": ["index.md", "refinement_synthetic-pass.png", "profiles_synthetic-hertz.png"],
        "performance": ["index.md", "iteration_vs_fft.png", "speed_vs_error_contact_fraction.png",
                        "speed_vs_error_mean_gap.png"],
        "challenge": ["index.md", "patch_size_distribution.png", "contact_area_vs_pressure.png",
                      "gap_distribution.png", "stress_distribution.png", "stress_spectrum.png",
                      "contact_area_vs_tabor.png", "mean_gap_vs_tabor.png", "mean_gap_vs_pressure.png",
                      "cross_section.png", "tabor_refinement.png", "speed_vs_error.png"],
    }
    for sub, files in expect.items():
        for f in files:
            if not os.path.isfile(os.path.join(out, sub, f)):
                failures.append(f"missing {sub}/{f}")
    perf = open(os.path.join(out, "performance", "index.md")).read() if os.path.isfile(
        os.path.join(out, "performance", "index.md")) else ""
    row = "| BM_PolonskyKeerIteration_plain | 2048 | 20 | 15 | 30 | 1.5 | 1.5 | 1 | 1.33 |"
    if row not in perf:
        failures.append("performance/index.md lacks the plain iteration's row against the floor pair, "
                        f"expected {row!r}:\n" + "\n".join(l for l in perf.splitlines() if "Iteration_plain" in l))
    return failures


def _challenge_index_checks(out):
    """What challenge/index.md must and must not say of the synthetic runs."""
    failures = []
    idx = open(os.path.join(out, "challenge", "index.md")).read() if os.path.isfile(
        os.path.join(out, "challenge", "index.md")) else ""
    if "not computed yet" in idx:
        failures.append("challenge/index.md says 'not computed yet' although every input exists")
    # The refined Tabor point: its band is its own refinement (v_inf = 2 v_512 - v_256 = 0.02), in the table.
    if "The Tabor sweep refined on the challenge itself" not in idx or "| 0.1 | 256² | 3.2 | 0.1 | 0.0424 |" not in idx:
        failures.append("challenge/index.md lacks the table of the Tabor point refined on the challenge itself")
    head = idx.split("## 1.")[0]
    if "NOT CONVERGED: challenge-reference-test (512²)" not in head or "without adhesion (± the larger of the " \
            "sources): relative contact area a_r: grid change" in head:
        failures.append("challenge/index.md uses the reference-load run that did not converge, or does not say so")
    if "| 0.7 | challenge-tabor-stopped | 256² (NOT CONVERGED) |" not in idx:
        failures.append("challenge/index.md does not mark the Tabor run that stopped before its tolerance")
    tabor_csv = os.path.join(out, "challenge", "data", "tabor_sweep__256x256.csv")
    if not os.path.isfile(tabor_csv) or any(ln.startswith("7.0") for ln in open(tabor_csv)):
        failures.append("challenge/data/tabor_sweep__256x256.csv is missing or holds the run that did not converge")
    # Items 1, 3, 4, 5 and 9 draw the stored references beside the runs, their grids and bands as stored.
    for num in ("1", "3", "4", "5", "9"):
        part = idx.split(f"## {num}.")[-1].split("\n## ")[0]
        if not re.search(r"\| stored reference \(\d+²\)[^|]*\|.*\| as stored \(", part):
            failures.append(f"challenge/index.md, item {num}: no row of the stored reference with its grid and band")
    if "cluster-measure" in idx:
        failures.append("challenge/index.md uses a run of results/cluster-measure/ (cost measurements)")
    if "challenge-scaled-hardwall-s32" in idx or "seeds/seed29" in idx:
        failures.append("challenge/index.md uses a scaled-family run found outside results/scaled-family/")
    if "hertz-free" in idx:
        failures.append("challenge/index.md lists a run whose case name does not start with 'challenge'")
    # dx/λ_s and dx/ρ are cmc's (surface_facts), not recomputed by the report.
    if "| dx/λ_s | dx/ρ |" not in idx or "| 3.906 | 188.6 |" not in idx:
        failures.append("challenge/index.md lacks the grid-spacing table with cmc's surface_facts")
    # Speed against error: the store's GPU runs are on it, with errors from the best estimates.
    if "## Speed against error" not in idx or "| hard wall | Polonsky-Keer, preconditioned | GPU: " not in idx:
        failures.append("challenge/index.md lacks the speed-against-error section or the stored GPU runs")
    return failures


def _validation_checks(out):
    """validation/index.md counts the checks and shows the failing one; the CSVs exist."""
    failures = []
    vidx = open(os.path.join(out, "validation", "index.md")).read()
    # The synthetic inputs hold four checks: synthetic-pass has two that pass (penetration
    # and its refinement study), synthetic-hertz one that passes, synthetic-fail one that
    # fails (mean_gap).
    if "**3 checks pass, 1 fail**" not in vidx:
        failures.append("validation/index.md does not count 3 passing and 1 failing check")
    if "| synthetic-fail | mean_gap | d | 0.5 | 0.001 | **FAIL** |" not in vidx:
        failures.append("validation/index.md does not show the failing check's row")
    # The challenge CSVs are readable by `cmc check` conventions (header row + numbers).
    data = os.path.join(out, "challenge", "data")
    if not os.path.isdir(data) or not any(f.startswith("load_sweep__") for f in os.listdir(data)):
        failures.append("challenge/data/load_sweep__*.csv missing")
    return failures


def _empty_input_checks(root):
    """Empty inputs: no crash, and lines saying what to run."""
    failures = []
    # Empty inputs: no crash, and lines saying what to run.
    empty = os.path.join(root, "empty")
    os.makedirs(empty, exist_ok=True)
    r2 = subprocess.run([sys.executable, os.path.join(HERE, "make_reports.py"), "--validation",
                         os.path.join(empty, "v"), "--results", os.path.join(empty, "r"), "--bench",
                         os.path.join(empty, "b.json"), "--reference", os.path.join(ROOT, "reference"),
                         "--cases", os.path.join(empty, "cases"), "--out", os.path.join(empty, "out")],
                        capture_output=True, text=True)
    if r2.returncode != 0:
        failures.append(f"empty inputs: make_reports.py exited {r2.returncode}: {r2.stderr}")
    else:
        for sub, phrase in (("challenge", "not computed yet"), ("validation", "No validation results"),
                            ("performance", "No records"), ("performance", "No Google Benchmark")):
            text = open(os.path.join(empty, "out", sub, "index.md")).read()
            if phrase not in text:
                failures.append(f"empty inputs: {sub}/index.md lacks '{phrase}'")
    return failures


def main(argv):
    try:
        import numpy as np
        import h5py
        import matplotlib  # noqa: F401
    except ImportError as e:
        print(f"selftest.py: {e}: install python3-numpy, python3-matplotlib, python3-h5py", file=sys.stderr)
        return 3
    keep = argv[argv.index("--keep") + 1] if "--keep" in argv else None
    root = keep or tempfile.mkdtemp(prefix="cmc_reports_selftest_")
    failures = []
    try:
        make_inputs(root, np, h5py)
        out = os.path.join(root, "reports")
        r = run_reports(root, out)
        if r.returncode != 0:
            failures.append(f"make_reports.py exited {r.returncode}:\n{r.stdout}\n{r.stderr}")
        failures += _file_checks(out) + _challenge_index_checks(out) + _validation_checks(out)
        failures += profile_band_checks(np)
        failures += sweep_end_checks()
        failures += roundoff_checks(root)
        failures += transfer_checks()
        failures += realization_checks()
        failures += speed_and_hard_checks(root)
        failures += _empty_input_checks(root)
    finally:
        if not keep:
            shutil.rmtree(root, ignore_errors=True)
    if failures:
        print("reports selftest FAILED:\n  " + "\n  ".join(failures))
        return 1
    print("reports selftest: ok" + (f" (inputs and reports kept in {root})" if keep else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
