"""Unit tests of python/cmc/analysis: refinement and the family's transferred errors, each
against a case computed by hand."""
import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from cmc.analysis import family, refinement  # noqa: E402


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
    got = refinement.sequence_error([3.0, 2.5])
    assert got["method"] == "last change" and got["error"] == pytest.approx(0.5)
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
