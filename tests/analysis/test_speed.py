"""Unit tests of python/cmc/analysis/speed.py: which runs are at the reference load, their method,
their error from the best estimate, and the Pareto front, each against a case worked by hand."""

from cmc.analysis import speed  # noqa: E402

# Best estimates: hard wall a_r 0.020 (1.5 % error), mean gap 1.0 um; adhesion a_r 0.032 from run "best".
BEST = {"reference_load": {
    "hardwall": {"run": "hw-16384", "quantities": {"a_r": {"value": 0.020, "relative_error": 0.015},
                                                   "mean_gap": {"value": 1.0e-6, "relative_error": 2e-4}}},
    "adhesive": {"run": "best", "quantities": {"a_r": {"value": 0.032, "relative_error": 0.016},
                                               "mean_gap": {"value": 1.0e-6, "relative_error": 2.5e-3}}}}}


def rec(tag, problem, n, a_r, gap, run_s, command="cmc run x.toml", strategy="plain", p=250e3, tabor=3.0, **kw):
    r = {"tag": tag, "problem": problem, "n": n, "a_r": a_r, "mean_gap_m": gap, "run_s": run_s, "command": command,
         "strategy": strategy, "pressure_Pa": p, "tabor": tabor if problem == "adhesive" else None,
         "backend": "cpu", "device": "2-core CPU", "status": "converged", "fft_pairs": 100.0}
    r.update(kw)
    return r


def test_reference_load_selection():
    assert speed.at_reference_load(rec("a", "hardwall", 2048, 0.02, 1e-6, 1.0))
    # load within 1e-6 relative: round-off of load control
    assert speed.at_reference_load(rec("a", "hardwall", 2048, 0.02, 1e-6, 1.0, p=250e3 * (1 + 1e-9)))
    assert not speed.at_reference_load(rec("a", "hardwall", 2048, 0.02, 1e-6, 1.0, p=251e3))
    # adhesion at another mu_T, or a load sweep, is another problem
    assert not speed.at_reference_load(rec("a", "adhesive", 2048, 0.03, 1e-6, 1.0, tabor=1.0))
    assert speed.at_reference_load(rec("a", "adhesive", 2048, 0.03, 1e-6, 1.0, tabor=3.002))
    assert not speed.at_reference_load(rec("a", "hardwall", 2048, 0.02, 1e-6, 1.0, steps=[{}, {}]))


def test_method_from_the_command():
    assert speed.method_of(rec("a", "hardwall", 64, 0, 0, 1)) == "Polonsky-Keer, preconditioned"
    assert speed.method_of(rec("a", "hardwall", 64, 0, 0, 1, command="cmc run x --set solver.precondition=false")) \
        == "Polonsky-Keer, plain"
    assert speed.method_of(rec("a", "adhesive", 64, 0, 0, 1, strategy="shape")) == "quasi-static, shape"
    assert speed.method_of(rec("a", "adhesive", 64, 0, 0, 1, command="cmc run x --set solver.kind=adhesive_cg")) \
        == "adhesive CG, plain"


def test_errors_against_the_best_estimate():
    # a_r 0.021 against 0.020: 5 %; gap 1.01 um against 1.0: 1 %.
    p = speed.speed_point(rec("a", "hardwall", 2048, 0.021, 1.01e-6, 3.0, gpu_peak_mib=800), BEST)
    assert abs(p.error_a_r - 0.05) < 1e-12 and abs(p.error_mean_gap - 0.01) < 1e-12
    assert p.method == "Polonsky-Keer, preconditioned" and not p.is_best
    assert p.peak_mib == 800 and p.peak_what == "GPU, measured"
    # The best estimate's own run: its error bars, marked.
    b = speed.speed_point(rec("best", "adhesive", 16384, 0.032, 1e-6, 70.0), BEST)
    assert b.is_best and b.error_a_r == 0.016 and b.error_mean_gap == 2.5e-3
    # A user's run of the same tag is not the stored best.
    u = speed.speed_point(rec("best", "adhesive", 2048, 0.030, 1e-6, 70.0, field_bytes_peak=2**21), BEST, "user")
    assert not u.is_best and abs(u.error_a_r - 0.0625) < 1e-12 and u.peak_mib == 2.0


def test_no_best_estimate_means_no_error():
    p = speed.speed_point(rec("a", "hardwall", 64, 0.02, 1e-6, 1.0), {})
    assert p.error_a_r is None and p.error_mean_gap is None


def test_pareto_front():
    # (time, error): A (1, 0.10), B (2, 0.05), C (3, 0.07) is beaten by B, D (4, 0.01), E (no time).
    pts = [speed.speed_point(rec(t, "hardwall", 64, 0.02 * (1 + e), 1e-6, w), BEST)
           for t, w, e in (("A", 1.0, 0.10), ("B", 2.0, 0.05), ("C", 3.0, 0.07), ("D", 4.0, 0.01), ("E", None, 0.0))]
    assert [p.tag for p in speed.pareto_front(pts)] == ["A", "B", "D"]
    # equal in both: both stay (neither is better in one)
    twin = pts[:1] + [speed.speed_point(rec("A2", "hardwall", 64, 0.02 * (1 + 0.10), 1e-6, 1.0), BEST)]
    assert sorted(p.tag for p in speed.pareto_front(twin)) == ["A", "A2"]
    # a run stopped before its tolerance is not a result: D stopped leaves B the most accurate
    stopped = pts[:3] + [speed.speed_point(rec("D", "hardwall", 64, 0.02 * 1.01, 1e-6, 4.0, status="not_converged"),
                                           BEST)]
    assert [p.tag for p in speed.pareto_front(stopped)] == ["A", "B"]


def test_missing_methods_are_named():
    pts = speed.speed_points([rec("a", "hardwall", 64, 0.02, 1e-6, 1.0), rec("b", "adhesive", 64, 0.03, 1e-6, 1.0)],
                             BEST)
    missing = speed.missing_methods(pts, speed.EXPECTED_METHODS)
    assert ("hardwall", "Polonsky-Keer, preconditioned") not in missing
    assert ("adhesive", "adhesive CG, plain") in missing and ("hardwall", "Polonsky-Keer, plain") in missing
