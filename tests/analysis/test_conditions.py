"""Unit tests of python/cmc/analysis/conditions.py: a run's band from the scaled family at its own
conditions, and the check of that band, each against a case computed by hand."""
import math

import pytest

from cmc.analysis import conditions


def member(run_a_r, tabor=None, pressure=None, role="plain_24rho", k=24.0):
    """s = 32 with a reference a_r 0.05, mean gap 3e-6 m (each 1 % refinement error) and one run at
    dx = k rho whose mean gap is the reference's: its error is |a_r / 0.05 - 1| + 1 % for a_r."""
    ref = {short: {"value": v, "refinement_error": 0.01 * v} for short, v in
           (("a_r", 0.05), ("a_rep", 0.04), ("mean_gap", 3e-6))}
    m = {"s": 32, "reference": ref,
         "runs": [{"role": role, "n": 64, "dx_over_rho": k, "a_r": run_a_r, "a_rep": 0.8 * run_a_r, "mean_gap": 3e-6}]}
    if tabor is not None:
        m["tabor"] = tabor
    if pressure is not None:
        m["pressure_Pa"] = pressure
    return m


FAM = [member(0.045)]                                      # 10 % low: 11 %
AT_P = member(0.06, pressure=2.5e6)                        # 20 % high at 2.5 MPa: 21 %
AT_MU = member(0.065, tabor=1.0)                           # 30 % high at mu_T = 1: 31 %
STORES = {"members": FAM, "conditions": [AT_P, AT_MU]}


def summary(tabor, kind="exponential", strategy=None):
    inter = {"kind": kind, "tabor": tabor}
    if strategy:
        inter["coarse_graining"] = strategy
    # dx = 48 over rho = 2: 24 rho
    return {"case": {"interaction": inter}, "surface_facts": {"specified_range": 2.0}, "grid": {"dx": 48.0}}


def test_run_strategy_error_at_the_runs_spacing():
    k, err, used = conditions.run_strategy_error(summary(3.0), "a_r", FAM)
    assert k == 24.0 and err == pytest.approx(0.11) and used == ["s = 32 at 64² (dx = 24.00 rho)"]
    assert conditions.run_strategy_error(summary(3.0, strategy="shape"), "a_r", FAM) == (24.0, None, [])
    assert conditions.run_strategy_error(summary(3.0, kind="hard_wall"), "a_r", FAM) is None


def test_own_tabor_is_none_at_the_challenges():
    assert conditions.own_tabor(summary(3.02)) is None      # within 1 % of 3
    assert conditions.own_tabor(summary(1.0)) == 1.0


def test_run_band_is_the_larger_of_the_two_conditions():
    _, band, at3, at, _ = conditions.run_band(summary(3.0), "a_r", **STORES)
    assert band == pytest.approx(0.11) and at is None
    # at mu_T = 1 the family measured 31 % > 11 %
    _, band, at3, at, _ = conditions.run_band(summary(1.0), "a_r", **STORES)
    assert at3 == pytest.approx(0.11) and at == pytest.approx(0.31) and band == at
    err, _ = conditions.condition_error("plain", 24.0, tabor=1.0, members=[AT_P, AT_MU])
    assert err["a_r"] == pytest.approx(0.31)
    assert conditions.condition_error("plain", 24.0, tabor=0.1, members=[AT_P, AT_MU]) == (None, [])


def test_load_bands_interpolate_in_log_p_and_hold_beyond():
    # 250 kPa: 11 %; 2.5 MPa: 21 %; halfway in log p (790.6 kPa) 16 %; held below and above
    ps = [12.5e3, 250e3, math.sqrt(250e3 * 2.5e6), 2.5e6, 1e8]
    got, words = conditions.load_bands(summary(3.0), "a_r", ps, **STORES)
    assert got == pytest.approx([0.11, 0.11, 0.16, 0.21, 0.21])
    assert "2500 kPa: 21 %" in words
    # without other loads: the band at every load, no words
    assert conditions.load_bands(summary(3.0), "a_r", ps[:2], members=FAM, conditions=[]) == ([pytest.approx(0.11)] * 2, "")


def test_condition_checks_and_the_worst_failure():
    rows = conditions.condition_checks(members=[AT_MU], reference=FAM)
    assert len(rows) == 1
    row = rows[0]
    # a_r: +30 % with 1 % refinement against the band 11 %: fails; mean gap: 0 + 1 % against 1 %: holds
    assert row["tabor"] == 1.0 and row["pressure_Pa"] == 250e3 and row["strategy"] == "plain"
    assert row["a_r"]["deviation"] == pytest.approx(0.3) and row["a_r"]["band"] == pytest.approx(0.11)
    assert conditions.quantity_holds(row["a_r"]) is False and conditions.quantity_holds(row["mean_gap"]) is True
    assert conditions.condition_holds(row) is False
    # excess (30 + 1) / 11 = 2.8 for a_r against 1 for the mean gap
    worst, short = conditions.worst_failure(rows)
    assert worst is row and short == "a_r"
    held = conditions.condition_checks(members=[member(0.052, tabor=1.0)], reference=FAM)  # 4 % + 1 % <= 11 %
    assert conditions.condition_holds(held[0]) is True and conditions.worst_failure(held) is None
    assert conditions.quantity_holds({"deviation": 0.0, "refinement": 0.0, "band": None}) is None
