"""Unit tests of python/cmc/analysis/plausibility.py (what may enter the run store, and when a new
best estimate is an outlier) and of best.ratio at a value of 0."""
import os

import pytest

from cmc.analysis import best, plausibility, runs  # noqa: E402


def record(**kw):
    r = {"tag": "cuda-hardwall-64", "kind": "hardwall", "backend": "cuda", "n": 64, "problem": "hardwall",
         "pressure_Pa": 250e3, "a_r": 0.02, "a_rep": 0.02, "a_r_corrected": None, "mean_gap_m": 1e-6, "steps": None}
    r.update(kw)
    return r


def test_a_possible_record_has_no_problem():
    assert plausibility.record_problems(record()) == []
    assert plausibility.record_problems(record(a_r=0.0, a_rep=0.0)) == []
    assert plausibility.record_problems(record(a_r=1.0, a_rep=1.0, mean_gap_m=0.0)) == []


@pytest.mark.parametrize("change, words", [
    ({"a_r": 1.5}, "a_r = 1.5 lies outside [0, 1]"), ({"a_rep": -0.02}, "a_rep = -0.02 lies outside [0, 1]"),
    ({"a_r": float("nan")}, "a_r is not finite"), ({"run_s": float("inf")}, "run_s is not finite"),
    ({"mean_gap_m": -1e-9}, "negative under a hard wall"), ({"n": 0}, "not a grid size"),
    ({"n": True}, "not a grid size"), ({"a_r": None}, "a_r is missing"), ({"pressure_Pa": "250e3"}, "missing"),
    ({"steps": [{"a_r": 0.1, "a_rep": 1.2, "mean_gap_m": 1e-6}]}, "a_rep = 1.2 at step 0"),
])
def test_impossible_or_incomplete_records(change, words):
    problems = plausibility.record_problems(record(**change))
    assert any(words in p for p in problems), problems


def test_negative_mean_gap_is_possible_only_with_adhesion_in_the_record_check():
    assert plausibility.record_problems(record(problem="adhesive", mean_gap_m=-1e-9)) == []


def summary(p, force=None, want=250e3, tol=1e-8, **interaction):
    return {"grid": {"size_x": 1e-4, "size_y": 1e-4},
            "case": {"loading": {"control": "mean_pressure", "values": [want]}, "solver": {"tolerance": tol},
                     "material": {"contact_modulus": 25e6}, "surface": {"rms_gradient": 1.0},
                     "interaction": interaction},
            "steps": [{"index": 0, "mean_pressure": p, "force": p * 1e-8 if force is None else force}]}


def test_balance():
    assert plausibility.balance_problems(summary(250e3)) == []
    # The adhesive solvers' own promise, 10 x tolerance x E* rms slope = 2.5 Pa here, is no imbalance.
    assert plausibility.balance_problems(summary(250e3 + 2.5)) == []
    assert "asked for" in plausibility.balance_problems(summary(251e3))[0]
    assert "times the area" in plausibility.balance_problems(summary(250e3, force=2.6e-3))[0]
    # At a loose tolerance the solver may stop further from the load: 20 x 1e-4 x 25 MPa = 50 kPa.
    assert plausibility.balance_problems(summary(280e3, tol=1e-4)) == []
    assert plausibility.balance_problems({"steps": [{"mean_pressure": 1.0}]}) == []  # nothing to tell by


def estimate(run, n, a_r, err, gap=1e-6, gap_err=1e-9):
    return {"run": run, "n": n, "quantities": {"a_r": {"value": a_r, "error": err},
                                               "mean_gap": {"value": gap, "error": gap_err}}}


def test_outliers_are_finer_grids_far_outside_the_previous_band():
    old = {"reference_load": {"hardwall": estimate("h-16384", 16384, 0.0205, 0.0003)}}
    inside = {"reference_load": {"hardwall": estimate("h-32768", 32768, 0.0205 + 3.9 * 0.0003, 0.01)}}
    assert plausibility.outliers(old, inside) == []
    for a_r in (0.5, 0.03, 0.0205 - 4.1 * 0.0003):
        far = {"reference_load": {"hardwall": estimate("h-32768", 32768, a_r, 0.01)}}
        got = plausibility.outliers(old, far)
        assert [(p, q) for p, q, _, _ in got] == [("250 kPa, hardwall", "a_r")], got
    same_grid = {"reference_load": {"hardwall": estimate("other-16384", 16384, 0.5, 0.01)}}
    assert plausibility.outliers(old, same_grid) == []


def test_outliers_at_tabor_and_load_points_and_in_the_mean_gap():
    old = {"tabor": [dict(estimate("t-4096", 4096, 0.03, 0.001), tabor=0.1)],
           "load_sweep": {"hardwall": [dict(estimate("l-2048", 2048, 0.01, 0.001), pressure_Pa=1e5)]}}
    new = {"tabor": [dict(estimate("t-8192", 8192, 0.03, 0.001, gap=1.1e-6), tabor=0.1)],
           "load_sweep": {"hardwall": [dict(estimate("l-4096", 4096, 0.2, 0.001), pressure_Pa=1e5)]}}
    got = {(p, q) for p, q, _, _ in plausibility.outliers(old, new)}
    assert got == {("mu_T = 0.1", "mean_gap"), ("hardwall at 100 kPa", "a_r")}


def test_ratio_has_no_value_at_a_zero_denominator():
    a = {"value": 0.03, "relative_error": 0.01, "error": 0.0003}
    assert best.ratio(a, {"value": 0.0, "relative_error": None, "error": 1e-8}) is None
    assert best.ratio({"value": 0.0, "relative_error": None, "error": 1e-8}, a) is None
    r = best.ratio(a, {"value": 0.02, "relative_error": 0.02, "error": 0.0004})
    assert r["value"] == pytest.approx(1.5) and r["relative_error"] == pytest.approx(0.03)


def test_store_refuses_to_write_what_json_cannot_hold(tmp_path):
    path = os.path.join(str(tmp_path), "runs.json")
    with pytest.raises(ValueError):
        runs.save_store([record(a_r=float("nan"))], path)
    assert not os.listdir(str(tmp_path))


def test_changed_tags_are_replacements_not_repeats():
    old = [record()]
    assert runs.changed_tags(old, [record()]) == []
    assert runs.changed_tags(old, [record(a_r=0.03)]) == ["cuda-hardwall-64"]
    assert runs.changed_tags(old, [record(tag="cuda-hardwall-128")]) == []
