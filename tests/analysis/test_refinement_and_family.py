"""Unit tests of python/cmc/analysis: refinement and the family's transferred errors, each
against a case computed by hand."""
import math

import pytest

from cmc.analysis import bands, family, refinement


def test_observed_order_of_a_power_law():
    # v = 1 + 0.5 h^2 at h = 1, 1/2, 1/4: changes 0.375 and 0.09375, ratio 4: order 2
    assert refinement.observed_order(1.5, 1.125, 1.03125) == pytest.approx(2.0)
    assert refinement.observed_order(1.0, 1.1, 1.05) is None      # the changes differ in sign
    assert refinement.observed_order(1.0, 1.0, 1.05) is None      # no change


def test_richardson_recovers_the_limit():
    # v = 2 + 3 h at h = 1/2, 1/4: 3.5, 2.75 -> 2 with order 1
    assert refinement.richardson(3.5, 2.75, 1.0) == pytest.approx(2.0)
    # order 2, ratio 2: v = 1 + h^2 at h = 1, 1/2 -> 1.25 + 0.75/3 ... = 1
    assert refinement.richardson(2.0, 1.25, 2.0) == pytest.approx(1.0)


def test_sequence_error_methods():
    got = refinement.sequence_error([1.5, 1.125, 1.03125])  # order 2, limit 1
    assert got["method"] == "richardson" and got["order"] == pytest.approx(2.0)
    assert got["v_inf"] == pytest.approx(1.0) and got["error"] == pytest.approx(0.03125)
    # changes +0.1, -0.05: not asymptotic, the largest of the last two changes
    got = refinement.sequence_error([1.0, 1.1, 1.05])
    assert got["method"] == "largest change" and got["error"] == pytest.approx(0.1)
    # order 0.2 < MIN_ORDER: not asymptotic either
    got = refinement.sequence_error([1.0, 1.1, 1.1 + 0.1 * 2 ** -0.2])
    assert got["method"] == "largest change" and got["error"] == pytest.approx(0.1)
    # two grids: twice the change, the bound for any order down to 0.58
    got = refinement.sequence_error([3.0, 2.5])
    assert got["method"] == "first-order bound" and got["error"] == pytest.approx(1.0)
    assert refinement.sequence_error([1.0]) is None
    assert refinement.sequence_error([1.0, float("nan")]) is None


def member(s, ref_ar, ref_err, runs, seed=None):
    m = {"s": s, "reference": {"a_r": {"value": ref_ar, "refinement_error": ref_err}},
         "runs": [{"role": role, "dx_over_rho": k, "a_r": v, "n": 100} for role, k, v in runs]}
    if seed is not None:
        m["seed"] = seed
    return m


def test_member_error_near_interpolated_and_outside():
    m = member(8, 0.04, 0.0004, [("shape_2rho", 2.0, 0.0396), ("shape_4rho", 4.0, 0.0408)])
    # near 2 rho (within 1.3): |0.0396/0.04 - 1| + 0.0004/0.04 = 0.01 + 0.01
    err, used = family.member_error_at(m, "shape", 2.2, "a_r")
    assert err == pytest.approx(0.02) and used == [2.0]
    # at 2.83 rho (halfway in log between 2 and 4): (0.02 + (0.02 + 0.01)) / 2
    err, used = family.member_error_at(m, "shape", 2 * math.sqrt(2), "a_r")
    assert err == pytest.approx(0.025) and used == [2.0, 4.0]
    assert family.member_error_at(m, "shape", 8.0, "a_r") is None     # beyond the runs
    assert family.member_error_at(m, "range", 2.0, "a_r") is None     # no such strategy run


def test_transferred_error_takes_the_members_nearest_s_1():
    far = member(32, 0.05, 0.0, [("shape_2rho", 2.0, 0.045)])          # 10 %: left out
    near = [member(8, 0.04, 0.0, [("shape_2rho", 2.0, 0.0404)]),        # 1 %
            member(16, 0.045, 0.0, [("shape_2rho", 2.0, 0.0459)]),      # 2 %
            member(16, 0.045, 0.0, [("shape_2rho", 2.0, 0.04455)], seed=29)]  # 1 %
    got = family.transferred_error([far] + near, "shape", 2.0, "a_r")
    assert got["error"] == pytest.approx(0.02)
    assert sorted({s for s, _, _, _ in got["members"]}) == [8, 16] and len(got["members"]) == 3
    assert family.transferred_error([far] + near, "shape", 9.0, "a_r") is None


def test_refinement_matches_cmc_refine_on_its_unit_test_numbers():
    # tests/test_validate.cpp Refinement.ChangesAndOrder: v(n) = 1 + 8/n^2 on n = 16, 32, 64, 128;
    # `cmc refine` gives the change (v64 - v128) / v128 = (8/4096 - 8/16384) / (1 + 8/16384) and order 2.
    v = {n: 1 + 8.0 / (n * n) for n in (16, 32, 64, 128)}
    assert bands.relative_change(v[64], v[128]) == pytest.approx((8 / 4096 - 8 / 16384) / (1 + 8 / 16384), rel=1e-12)
    assert refinement.observed_order(v[16], v[32], v[64]) == pytest.approx(2.0)
    assert refinement.observed_order(v[32], v[64], v[128]) == pytest.approx(2.0)
    # Richardson with that order recovers the limit 1: 1 + 8/16384 + (8/16384 - 8/4096) / 3 = 1
    assert refinement.richardson(v[64], v[128], 2.0) == pytest.approx(1.0, abs=1e-15)


def test_own_band_of_any_grid_of_the_sequence():
    # v = 0.02 (1 + 0.14 x 2048 / n): first order, limit 0.02, every estimate 0.02 (spread 0); the band
    # of the 4096² value is |v - 0.02| / v = 0.07 / 1.07, of the 2048² value 0.14 / 1.14
    grids = [{"nx": n, "dx_over_rho": 0.44 * 2048 / n, "bistability": 0.44 * 2048 / n,
              "value": 0.02 * (1 + 0.14 * 2048 / n), "corrected": None} for n in (2048, 4096, 8192)]
    got = refinement.own_band(grids, 1)
    assert got["v_inf"] == pytest.approx(0.02) and got["band"] == pytest.approx(0.07 / 1.07) and got["nx"] == 4096
    assert refinement.own_band(grids, 0)["band"] == pytest.approx(0.14 / 1.14)
    grids[2]["bistability"] = None
    assert refinement.own_band(grids, 1) is None


def full_member(s, a_r, gap, refinement_error=0.0, runs=()):
    """A member with a reference of a_r (also a_rep) and the mean gap, or none where a_r is None."""
    ref = {} if a_r is None else {q: {"value": v, "refinement_error": refinement_error * v}
                                  for q, v in (("a_r", a_r), ("a_rep", a_r), ("mean_gap", gap))}
    return {"s": s, "reference": ref, "runs": list(runs)}


def test_member_reference_adhesionless_and_deviation():
    res = {"a_r": 0.05, "a_rep": 0.04, "mean_gap": 3e-6, "n": 2048, "status": "converged"}
    fine = {"a_r": 0.049, "a_rep": 0.0395, "mean_gap": 3.01e-6, "n": 1024}
    ref = family.member_reference(res, fine)
    # |0.05 - 0.049| = 0.001, |3e-6 - 3.01e-6| = 1e-8
    assert ref["a_r"]["refinement_error"] == pytest.approx(0.001) and ref["mean_gap"]["refinement_error"] == pytest.approx(1e-8)
    assert (ref["a_r"]["grid"], ref["a_r"]["coarser_grid"], ref["a_r"]["unit"]) == (2048, 1024, "1")
    # 0.0475 / 0.05 - 1 = -5 %
    assert family.deviation({"a_r": 0.0475}, ref, "a_r") == pytest.approx(-0.05)
    hw = [{"role": "hardwall_resolved", "n": 2048, "status": "converged", "a_r_corrected": 0.03, "mean_gap": 2e-6},
          {"role": "hardwall_refinement", "n": 1024, "status": "converged", "a_r_corrected": 0.0305, "mean_gap": 2.01e-6},
          {"role": "plain_2rho", "n": 4096, "status": "converged", "a_r_corrected": None, "mean_gap": 1e-6}]
    got = family.adhesionless(hw)
    # the finest hard wall's corrected a_r 0.03 with |0.03 - 0.0305| = 0.0005, for a_r and a_rep alike
    assert got["a_r"] == got["a_rep"] and got["a_r"]["value"] == 0.03
    assert got["a_r"]["refinement_error"] == pytest.approx(0.0005) and got["mean_gap"]["refinement_error"] == pytest.approx(1e-8)
    assert family.adhesionless(hw[:1]) == {}


def test_challenge_estimates_take_the_family_error_at_the_same_spacing():
    # s = 32's shape run at 12.5 rho is 5 % high, its reference 1 % uncertain: 6 % of s = 1's 0.030 = 0.0018
    fam = full_member(32, 0.05, 3e-6, 0.01, [{"role": "shape_12rho", "n": 128, "dx_over_rho": 12.5, "a_r": 0.0525,
                                              "a_rep": 0.0525, "mean_gap": 3e-6}])
    fam["estimates"] = ["stale"]
    challenge = full_member(1, None, None, runs=[{"role": "shape_n4096", "n": 4096, "dx_over_rho": 12.0, "a_r": 0.030,
                                                  "a_rep": 0.030, "mean_gap": 1e-6},
                                                 {"role": "plain_n4096", "n": 4096, "dx_over_rho": 12.0, "a_r": 0.029,
                                                  "a_rep": 0.029, "mean_gap": 1e-6}])
    family.challenge_estimates([fam, challenge])
    assert "estimates" not in fam and len(challenge["estimates"]) == 1
    est = challenge["estimates"][0]
    assert est["role"] == "shape_n4096" and est["a_r"]["error"] == pytest.approx(0.0018)
    assert est["measured_on"] == ["s = 32 at 128² (dx = 12.50 rho)"]
