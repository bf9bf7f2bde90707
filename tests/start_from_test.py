#!/usr/bin/python3
"""Tests of `cmc run --start-from` (a start from a coarser run of the same case,
solver/cmc/output/CoarseStart.hpp).

usage: tests/start_from_test.py CMC WORKDIR TEST

The case: the scaled challenge family at s = 128 (lambda_s = 12.8 um, w = 6.4 J/m^2,
mu_T = 3; rho = 223 nm): 128^2 points (dx = 3.5 rho), 256^2 (1.75 rho), each run a second.

TEST is one of
  same_state   256^2 started from the 128^2 answer ends in the cold start's state: the same
               contact and repulsive fractions to 2 points of 65536 and the mean gap to 1e-6
               relative. Measured: identical fractions, mean gap 4e-9 relative,
               31 outer steps and 488 FFT pairs against 37 and 658 cold, although the 128^2
               answer itself is far off (a_r 0.146 against 0.160). The bounds: the outer
               tolerance (1e-3 of the peak tension) leaves single points unresolved (1 point
               of 262144 at 512^2, QuasiStaticAdhesion.hpp), and moves gaps by about
               tolerance x rho (the quasi-static tests), 1e-6 of this mean gap. Also: the
               summary records the start (folder, grid, factor 2, gap lift = rho), and the
               run says where it started from.
  resume       the started run killed between two outer steps (--checkpoint-every 0) and
               resumed without --start-from equals the uninterrupted started run bit for bit
               (scripts/compare_runs.py), its start record included
  bad_input    each refused with exit 2, a message naming what to change, and an earlier
               run's results in --out left as they were: a folder without a finished run, a
               run without fields, a grid that does not divide, another surface (seed), a
               larger load, the adhesive CG solver
Exits 0 on success, 1 with the reasons on failure.
"""
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
from resume_test import COMPARE, FAMILY_CASE, check, env, failures, summary  # noqa: E402

S128 = ["--set", "case.name=challenge-scaled-s128", "--set", "surface.cutoff_wavelength=1.28e-05",
        "--set", "interaction.work_of_adhesion=6.4"]


def run(cmc, out, n, *args, fields=False, quiet=True, **extra):
    cmd = [cmc, "run", FAMILY_CASE, "--out", out, *S128, "--set", f"grid.n={n}", *args]
    cmd += ["--set", "output.fields=true"] if fields else []
    cmd += ["--quiet"] if quiet else []
    return subprocess.run(cmd, env=env(**extra), capture_output=True, text=True)


def ok_run(p, label):
    return check(p.returncode == 0, f"{label}: exit {p.returncode}:\n{p.stderr}")


def coarse(cmc, work, fields=True):
    """The 128^2 run the tests start from (with its fields, or without)."""
    out = os.path.join(work, "coarse-128" + ("" if fields else "-nofields"))
    if not os.path.exists(os.path.join(out, "summary.json")):
        shutil.rmtree(out, ignore_errors=True)
        if not ok_run(run(cmc, out, 128, fields=fields), "the 128^2 run"):
            raise SystemExit(1)
    return out


def test_same_state(cmc, work):
    start = coarse(cmc, work)
    cold = os.path.join(work, "cold-256")
    shutil.rmtree(cold, ignore_errors=True)
    if not ok_run(run(cmc, cold, 256), "the cold 256^2 run"):
        return
    out = os.path.join(work, "start-256")
    shutil.rmtree(out, ignore_errors=True)
    p = run(cmc, out, 256, "--start-from", start, quiet=False)
    if not ok_run(p, "the started 256^2 run"):
        return
    check(f"from {start} (128 x 128 points, prolonged by 2" in p.stderr,
          f"the started run did not say where it started from:\n{p.stderr}")
    a, b = summary(cold), summary(out)
    sa, sb = a["steps"][0], b["steps"][0]
    points = 256 * 256
    for key in ("contact_fraction", "repulsive_fraction"):
        va = sa["observables"][key]
        vb = sb["observables"][key]
        check(abs(va - vb) * points <= 2.0, f"{key}: started {vb} against cold {va} ({abs(va - vb) * points:.0f} points)")
    rel = abs(sb["mean_gap"] - sa["mean_gap"]) / sa["mean_gap"]
    check(rel <= 1e-6, f"mean gap: started {sb['mean_gap']} against cold {sa['mean_gap']} ({rel:.2e} relative)")
    check(sb["converged"] and b["status"] == "converged", f"the started run did not converge: {b['status']}")
    rec = b.get("start_from", {})
    rho = a["surface_facts"].get("interaction_range")
    check(rec.get("folder") == start and rec.get("grid") == [128, 128] and rec.get("factor") == 2,
          f"summary.json start_from: {rec}")
    check(rho is not None and abs(rec.get("gap_lift", 0.0) - rho) <= 1e-9 * rho,
          f"start_from.gap_lift {rec.get('gap_lift')} is not the range {rho}")
    check("start_from" not in a, "the cold run's summary has a start_from record")
    print(f"cold: {sa['diagnostics']['outer_iterations']} outer steps, {sa['fft_pairs']} FFT pairs; started: "
          f"{sb['diagnostics']['outer_iterations']} outer steps, {sb['fft_pairs']} FFT pairs; a_r {sa['contact_fraction']}"
          f" / {sb['contact_fraction']}, mean gap {rel:.2e} relative")


def test_resume(cmc, work):
    start = coarse(cmc, work)
    ref = os.path.join(work, "start-256-uninterrupted")
    shutil.rmtree(ref, ignore_errors=True)
    if not ok_run(run(cmc, ref, 256, "--start-from", start, "--checkpoint-every", "0", fields=True),
                  "the uninterrupted started run"):
        return
    out = os.path.join(work, "start-256-killed")
    shutil.rmtree(out, ignore_errors=True)
    p = run(cmc, out, 256, "--start-from", start, "--checkpoint-every", "0", fields=True, CMC_TEST_KILL_AT="outer:2")
    if not check(p.returncode == -9, f"kill at outer:2: expected SIGKILL, got exit {p.returncode}:\n{p.stderr}"):
        return
    p = run(cmc, out, 256, "--resume", "--checkpoint-every", "0", fields=True, quiet=False)
    if not ok_run(p, "the resumed run"):
        return
    check("inside" in p.stderr, f"the resumed run did not go on inside the step:\n{p.stderr}")
    c = subprocess.run(["/usr/bin/python3", COMPARE, ref, out], capture_output=True, text=True)
    check(c.returncode == 0, f"the resumed run differs from the uninterrupted one:\n{c.stdout}{c.stderr}")
    check(summary(out).get("start_from", {}).get("folder") == start, "the resumed run lost its start_from record")


def test_bad_input(cmc, work):
    start = coarse(cmc, work)
    nofields = coarse(cmc, work, fields=False)
    incomplete = os.path.join(work, "incomplete")
    os.makedirs(incomplete, exist_ok=True)
    open(os.path.join(incomplete, "INCOMPLETE"), "w").close()
    # An earlier run's results in --out must survive every refusal.
    out = os.path.join(work, "kept")
    if not os.path.exists(os.path.join(out, "summary.json")):
        shutil.rmtree(out, ignore_errors=True)
        if not ok_run(run(cmc, out, 64), "the 64^2 run whose results must be kept"):
            return
    before = open(os.path.join(out, "summary.json")).read()
    cases = [
        ("a folder without a finished run", 256, [incomplete], "no finished run"),
        ("a missing folder", 256, [os.path.join(work, "nowhere")], "no finished run"),
        ("a run without fields", 256, [nofields], "output.fields=true"),
        ("a grid that does not divide", 192, [start], "does not divide"),
        ("another surface", 256, [start, "--set", "surface.seed=29"], "not this case's"),
        ("a larger load", 256, [start, "--set", "loading.values=[1e5]"], "smaller load"),
        ("the adhesive CG", 256, [start, "--set", "solver.kind=\"adhesive_cg\""], "quasi-static and Polonsky-Keer"),
    ]
    for label, n, args, said in cases:
        p = run(cmc, out, n, "--start-from", *args)
        check(p.returncode == 2 and said in p.stderr and "--start-from" in p.stderr,
              f"{label}: exit {p.returncode} (expected 2 and a message with {said!r}):\n{p.stderr}")
        check(os.path.exists(os.path.join(out, "summary.json")) and
              open(os.path.join(out, "summary.json")).read() == before and
              not os.path.exists(os.path.join(out, "INCOMPLETE")),
              f"{label}: the earlier results in {out} were touched")


def main(argv):
    if len(argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    cmc, work, test = argv[1], argv[2], argv[3]
    os.makedirs(work, exist_ok=True)
    tests = {"same_state": test_same_state, "resume": test_resume, "bad_input": test_bad_input}
    if test not in tests:
        print(f"start_from_test: unknown test {test!r}; one of {', '.join(tests)}", file=sys.stderr)
        return 2
    tests[test](cmc, os.path.join(work, test))
    if failures:
        print(f"start_from_test {test}: {len(failures)} failure(s)")
        return 1
    print(f"start_from_test {test}: passed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
