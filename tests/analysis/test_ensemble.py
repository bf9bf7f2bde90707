"""Unit tests of python/cmc/analysis/ensemble.py, each against a case computed by hand."""
import math

import pytest

from cmc.analysis import ensemble  # noqa: E402


def test_t_quantile_matches_the_tables():
    # Student's t, 97.5 %: 2.5706 (5), 2.2281 (10), 2.0395 (31), 1.9840 (100); A&S table 26.10
    for df, t in ((5, 2.5706), (10, 2.2281), (31, 2.0395), (100, 1.9840)):
        assert ensemble.t975(df) == pytest.approx(t, abs=3e-4)
    with pytest.raises(ValueError):
        ensemble.t975(0)


def test_row_stats_by_hand():
    # values 1, 2, 3, 4: mean 2.5, s = sqrt(5/3), se = s/2, prediction t(3) s sqrt(5/4)
    s = ensemble.row_stats(7.0, {1: 1.0, 2: 2.0, 3: 3.0, 4: 4.0, 5: float("nan")})
    assert (s.m, s.mean, s.seeds) == (4, 2.5, (1, 2, 3, 4))
    assert s.std == pytest.approx(math.sqrt(5 / 3)) and s.stderr == pytest.approx(math.sqrt(5 / 3) / 2)
    assert s.prediction == pytest.approx(ensemble.t975(3) * math.sqrt(5 / 3) * math.sqrt(1.25))
    assert ensemble.row_stats(1.0, {1: 1.0, 2: 2.0}) is None  # fewer than three surfaces


def _sweep(seed, values, h=1e-6):
    steps = [{"pressure_Pa": p, "a_r": a, "a_rep": a, "mean_gap_m": g, "converged": True} for p, a, g in values]
    return {"physics": {"surface.seed": seed}, "steps": steps, "rms_height_m": h}


def test_table_takes_sweep_steps_and_single_runs_by_seed():
    recs = [_sweep(1, [(1e5, 0.01, 2e-6), (2.5e5, 0.02, 1e-6)]),
            _sweep(2, [(1.001e5, 0.011, 2.2e-6), (2.5e5, 0.021, 1.1e-6)], h=2e-6),
            {"physics": {"surface.seed": 3}, "pressure_Pa": 2.5e5, "a_r": 0.019, "mean_gap_m": 0.9e-6,
             "status": "converged", "rms_height_m": 1e-6},
            {"physics": {"surface.seed": 4}, "pressure_Pa": 2.5e5, "a_r": 0.5, "status": "not_converged"}]
    rows = ensemble.table(recs, "a_r", "pressure_Pa")
    assert [x for x, _ in rows] == [1e5, 2.5e5]  # 1.001e5 is the same row (within 1 %)
    assert rows[0][1] == {1: 0.01, 2: 0.011} and rows[1][1] == {1: 0.02, 2: 0.021, 3: 0.019}
    gaps = dict(ensemble.table(recs, "mean_gap_over_h_rms", "pressure_Pa"))
    assert gaps[2.5e5] == pytest.approx({1: 1.0, 2: 0.55, 3: 0.9})
    assert ensemble.table(recs, "a_r", "pressure_Pa", seeds=[2])[0][1] == {2: 0.011}


def test_reference_rows_carry_the_correction_and_combine_bands():
    s = ensemble.RowStats(x=2.5e5, m=32, mean=2.0, std=0.4, stderr=0.4 / math.sqrt(32), prediction=0.83, seeds=())
    c = ensemble.correction(2.5e5, own=1.9, best=1.71, best_error=0.0342)  # factor 0.9, 2 %
    assert c.factor == pytest.approx(0.9) and c.relative_error == pytest.approx(0.02)
    ens = ensemble.reference_rows([s], [c], "ensemble")[0]
    assert ens.value == pytest.approx(1.8)
    assert ens.band == pytest.approx(1.8 * math.hypot(0.02, 2 * 0.4 / math.sqrt(32) / 2.0))
    one = ensemble.reference_rows([s], [c], "realisation")[0]
    assert one.band == pytest.approx(1.8 * math.hypot(0.02, 0.83 / 2.0))
    assert ensemble.reference_rows([s], [], "ensemble") == []  # no correction at that load: no row
    with pytest.raises(ValueError):
        ensemble.reference_rows([s], [c], "surface")
    assert ensemble.correction(1.0, own=0.0, best=1.0, best_error=0.1) is None


def test_transfer_check_names_the_worst_seed():
    got = ensemble.transfer_check({28: 1.02, 1: 1.025, 2: 1.0})
    assert got["seed"] == 2 and got["largest"] == pytest.approx(abs(1.0 / 1.02 - 1))
    assert ensemble.transfer_check({1: 1.0, 2: 1.0}) is None


def test_simultaneous_factor_is_an_order_statistic_of_the_largest_deviations():
    # two rows, four seeds: row 1 values 1, 2, 3, 4 (mean 2.5, s = sqrt(5/3)); row 2 all equal but
    # seed 4 (mean 1.25, s = 0.5): z per seed = max over rows of |v - mean| / s
    rows = [(1.0, {1: 1.0, 2: 2.0, 3: 3.0, 4: 4.0}), (2.0, {1: 1.0, 2: 1.0, 3: 1.0, 4: 2.0})]
    stats = [ensemble.row_stats(x, v) for x, v in rows]
    s1 = math.sqrt(5 / 3)
    z = sorted([max(1.5 / s1, 0.5), max(0.5 / s1, 0.5), max(0.5 / s1, 0.5), max(1.5 / s1, 1.5)])
    # ceil(0.95 x 5) = 5 > 4 seeds: the largest; at 50 % coverage ceil(2.5) = 3: the third smallest
    assert ensemble.simultaneous_factor(rows, stats) == pytest.approx(z[-1])
    assert ensemble.simultaneous_factor(rows, stats, coverage=0.5) == pytest.approx(z[2])
    s = stats[0]
    c = ensemble.correction(1.0, own=2.5, best=2.5, best_error=0.0)
    one = ensemble.reference_rows([s], [c], "realisation", factor=3.0)[0]
    assert one.band == pytest.approx(3.0 * s.std * math.sqrt(1.25))
    assert ensemble.reference_rows([s], [c], "ensemble", factor=3.0)[0].band == pytest.approx(3.0 * s.stderr)


def test_reference_load_questions_by_hand():
    # seeds 1, 2, 28 at 250 kPa: a_r 0.02, 0.022, 0.021 on the ensemble's grid; seed 28's best
    # estimate 0.0231 +- 1 % (factor 1.1); rms heights 1 um (mean gap over h_rms: 1.0, 1.2, 1.1)
    recs = [{"physics": {"surface.seed": s}, "pressure_Pa": 2.5e5, "a_r": a, "a_rep": a, "mean_gap_m": 1e-6 * g,
             "status": "converged", "rms_height_m": 1e-6} for s, a, g in ((1, 0.02, 1.0), (2, 0.022, 1.2), (28, 0.021, 1.1))]
    est = {"quantities": {"a_r": {"value": 0.0231, "error": 0.000231, "relative_error": 0.01},
                          "mean_gap": {"value": 1.1e-6, "error": 1.1e-9, "relative_error": 0.001}}}
    got = ensemble.reference_load_questions(recs, est, [1, 2, 28], p_tilde=0.01)
    s = ensemble.row_stats(2.5e5, {1: 0.02, 2: 0.022, 28: 0.021})
    assert got["a_r"]["surface"] == {"value": 0.0231, "band": pytest.approx(0.000231)}
    assert got["a_r"]["ensemble"]["value"] == pytest.approx(0.021 * 1.1)
    assert got["a_r"]["ensemble"]["band"] == pytest.approx(0.0231 * math.hypot(0.01, 2 * s.stderr / 0.021))
    assert got["a_r"]["realisation"]["band"] == pytest.approx(0.0231 * math.hypot(0.01, s.prediction / 0.021))
    assert got["kappa"]["surface"]["value"] == pytest.approx(2.31) and got["kappa"]["ensemble"]["m"] == 3
    assert got["mean_gap_over_h_rms"]["surface"]["value"] == pytest.approx(1.1)
    assert "a_rep" not in got  # no best estimate of it given
    assert ensemble.reference_load_questions(recs, None, [1, 2, 28], 0.01) == {}
    # a transfer check at 250 kPa (seed 2's refinement factor 2 % off seed 28's) widens the
    # correction's 1 % to hypot(1 %, 2 x 2 %) in the ensemble's and realisation's bands (not seed
    # 28's own); a_r's alone
    moved = {"a_r": [{"x": 2.5e5, "largest": 0.02, "seed": 2}]}
    wide = ensemble.reference_load_questions(recs, est, [1, 2, 28], p_tilde=0.01, transfer=moved)
    assert wide["a_r"]["surface"] == got["a_r"]["surface"]
    assert wide["a_r"]["ensemble"]["band"] == pytest.approx(0.0231 * math.hypot(0.01, 0.04, 2 * s.stderr / 0.021))
    assert wide["mean_gap"] == got["mean_gap"]


def test_transfer_rows_and_the_correction_they_widen():
    # seed 28's factor 0.9/1.0 = 0.9; seed 1's 0.99/1.1 = 0.9 (same); seed 2's 0.88/1.0 = 0.88
    coarse = [(1e5, {28: 1.0, 1: 1.1, 2: 1.0})]
    fine = [(1.001e5, {28: 0.9, 1: 0.99, 2: 0.88})]
    rows = ensemble.transfer_rows(coarse, fine)
    assert len(rows) == 1 and rows[0]["seed"] == 2 and rows[0]["largest"] == pytest.approx(abs(0.88 / 0.9 - 1))
    c = ensemble.correction(1e5, own=1.0, best=0.85, best_error=0.0085)
    wide = ensemble.with_transfer(c, rows)
    assert wide.relative_error == pytest.approx(math.hypot(0.01, 2 * abs(0.88 / 0.9 - 1)))
    assert ensemble.with_transfer(ensemble.correction(2e5, 1.0, 0.85, 0.0085), rows).relative_error == pytest.approx(0.01)
    assert ensemble.transfer_rows(coarse, [(1e5, {1: 0.99, 2: 0.88})]) == []  # seed 28 missing
