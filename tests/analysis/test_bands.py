"""Unit tests of python/cmc/analysis/bands.py, each against a case computed by hand."""
import math

import numpy as np
import pytest

from cmc.analysis import bands


def test_relative_change_is_relative_to_the_finer_grid():
    # |3 - 2| / |2| = 0.5; a finer value of 0 or a missing value: no change
    assert bands.relative_change(3.0, 2.0) == 0.5
    assert bands.relative_change(-1.0, -2.0) == 0.5
    assert bands.relative_change(1.0, 0.0) is None and bands.relative_change(None, 1.0) is None


def test_absolute_band_and_its_floor():
    # 0.1 x |2| = 0.2, 0.2 x |-3| = 0.6; at least 0.5: 0.5, 0.6
    assert bands.absolute_band([0.1, 0.2], [2.0, -3.0]) == pytest.approx([0.2, 0.6])
    assert bands.absolute_band([0.1, 0.2], [2.0, -3.0], 0.5) == pytest.approx([0.5, 0.6])


def test_interp_curve_in_each_representation():
    # lin-lin through (1, 10), (3, 30): 20 at x = 2; outside the range NaN
    got = bands.interp_curve([2.0, 0.5, 4.0], [1.0, 3.0], [10.0, 30.0], False, False)
    assert got[0] == pytest.approx(20.0) and np.isnan(got[1:]).all()
    # log-log through (1, 1), (100, 10^4), y = x^2: 100 at x = 10 (linear would give 1010)
    assert bands.interp_curve([10.0], [1.0, 100.0], [1.0, 1e4], True, True)[0] == pytest.approx(100.0)
    # log y drops the non-positive point (2, -1): through (1, 1), (3, 9) exp((ln 1 + ln 9) / 2) = 3 at x = 2
    assert bands.interp_curve([2.0], [1.0, 2.0, 3.0], [1.0, -1.0, 9.0], False, True)[0] == pytest.approx(3.0)


def test_refinement_band_is_the_distance_to_the_finer_curve():
    # the finer curve through (1, 4), (3, 6) is 4 at 1 and 5 at 2: |5 - 4| = 1, |5 - 5| = 0
    assert list(bands.refinement_band([1.0, 2.0], [5.0, 5.0], [1.0, 3.0], [4.0, 6.0], False, False)) == [1.0, 0.0]


def test_profile_band_holds_the_finer_profile():
    y, v = [0.0, 1.0, 2.0, 3.0], [0.0, 0.0, 4.0, 4.0]
    yf = np.arange(0.0, 3.5, 0.5)
    vf = [0.0, 0.0, 0.0, 3.0, 4.0, 4.0, 4.0]  # the step half a spacing earlier
    # tolerance 1e-3 x rms height 2 = 2e-3 (gap); 1e-3 x E* 10 x rms slope 1 = 1e-2 (stress)
    floor = bands.profile_floor("cross_section_gap", 1e-3, 2.0, 10.0, 1.0)
    assert floor == pytest.approx(2e-3)
    assert bands.profile_floor("cross_section_pressure", 1e-3, 2.0, 10.0, 1.0) == pytest.approx(1e-2)
    # v read linearly at the finer points: 0, 0, 0, 2, 4, 4, 4; |difference| 1 at y = 1.5 only, which
    # lies between y = 1 and y = 2 and counts for both; elsewhere the floor
    b = bands.profile_band(y, v, yf, vf, floor)
    assert list(b) == pytest.approx([2e-3, 1.0, 1.0, 2e-3])
    assert (np.abs(np.interp(yf, y, v) - vf) <= np.interp(yf, y, b) + 1e-15).all()
    assert bands.profile_band(y, v, yf[:3], vf[:3], floor) is None  # the finer profile covers part of the line
    assert bands.profile_band(y, v, yf, vf, 0.0) is None


def test_finest_grid_band_is_twice_the_change_from_the_coarser_grid():
    # the coarser curve through (1, 4), (3, 6) is 4 at x = 1 and 5 at x = 2: 2 x |5 - 4| = 2, 2 x |5 - 5| = 0;
    # x = 4 lies beyond it: no band
    got = bands.finest_grid_band([1.0, 2.0, 4.0], [5.0, 5.0, 5.0], [1.0, 3.0], [4.0, 6.0], False, False)
    assert list(got[:2]) == [2.0, 0.0] and np.isnan(got[2])
    # log-log: the coarser density through (1, 1), (100, 10^4) is 100 at x = 10; the finer 90 there: 2 x 10 = 20
    assert bands.finest_grid_band([10.0], [90.0], [1.0, 100.0], [1.0, 1e4], True, True)[0] == pytest.approx(20.0)


def test_finest_profile_band_is_twice_the_change_at_least_the_floor():
    # finer profile on spacing 0.5, the coarser on spacing 1 (its step half a spacing later), line length 4
    y, v = np.arange(0.0, 4.0, 0.5), [0.0, 0.0, 0.0, 4.0, 4.0, 4.0, 4.0, 0.0]
    yc, vc = [0.0, 1.0, 2.0, 3.0], [0.0, 0.0, 4.0, 4.0]
    # v_c linear: 0, 0, 0, 2, 4, 4, 4 at y = 0 ... 3; at y = 3.5, periodic, halfway between 4 (y = 3) and 0 (y = 4): 2.
    # Twice the differences: 0, 0, 0, 4, 0, 0, 0, 4; at least the floor 0.01
    b = bands.finest_profile_band(y, v, yc, vc, 0.01, period=4.0)
    assert list(b) == pytest.approx([0.01, 0.01, 0.01, 4.0, 0.01, 0.01, 0.01, 4.0])
    # without the period the coarser profile ends at y = 3 and does not cover y = 3.5: no band
    assert bands.finest_profile_band(y, v, yc, vc, 0.01) is None
    assert bands.finest_profile_band(y[:7], v[:7], yc, vc, 0.01)[3] == pytest.approx(4.0)
    assert bands.finest_profile_band(y, v, yc, vc, 0.0, period=4.0) is None


def test_sweep_floor():
    # one point of 64 x 64: 1/4096; tolerance 1e-3 x rms height 2e-6 m = 2e-9 m
    assert bands.sweep_floor("ar", 64, 64, 1e-3, 2e-6) == (1 / 4096, "one grid point (1/64^2)")
    assert bands.sweep_floor("gap", 64, 64, 1e-3, 2e-6)[0] == pytest.approx(2e-9)


def step(p, ar, gap=1e-6, perimeter=None, converged=True):
    return {"p": p, "ar": ar, "gap": gap, "perimeter": perimeter, "converged": converged}


def test_measured_sweep_band_interpolates_per_unit_perimeter():
    steps = [step(1e5, 0.1, perimeter=0.5), step(1e6, 0.3, perimeter=1.0), step(1e7, 0.9, perimeter=0.2)]
    finer = [step(1e5, 0.095), step(1e7, 0.896)]
    # per unit perimeter: |0.1 - 0.095| / 0.5 = 0.01 at 0.1 MPa, |0.9 - 0.896| / 0.2 = 0.02 at 10 MPa;
    # 1 MPa lies halfway in log p: 0.015. Band = that x the step's perimeter: 0.005, 0.015, 0.004
    band, words = bands.measured_sweep_band(steps, finer, "ar", 64, 128)
    assert band == pytest.approx([0.005, 0.015, 0.004])
    assert words.startswith("the change from 64^2 to 128^2 measured at 2 loads (0.1, 10 MPa)")
    # the mean gap scales with itself: |2 - 1.9| / 2 = 5 % at both loads, held: 5 % of 4 = 0.2 at 1 MPa
    gaps = [step(1e5, 0.1, 2.0), step(1e6, 0.3, 4.0), step(1e7, 0.9, 1.0)]
    band, _ = bands.measured_sweep_band(gaps, [step(1e5, 0, 1.9), step(1e7, 0, 0.95)], "gap", 64, 128)
    assert band == pytest.approx([0.1, 0.2, 0.05])
    assert bands.measured_sweep_band(steps, finer[:1], "ar", 64, 128) == (None, "")  # one shared load


def test_hardwall_sweep_band_modelled_from_the_reference_load():
    steps = [step(1e5, 0.05, 1.0, perimeter=0.25), step(1e6, 0.3, 0.0, perimeter=1.0)]
    ref = (step(2.5e5, 0.10, 2.0, perimeter=0.5), step(2.5e5, 0.098, 2.5), 64, 128)
    # a_r: the change 0.002 at 250 kPa times perimeter / 0.5: 0.001, 0.004 (floor 1e-4 below both)
    band, how = bands.hardwall_sweep_band(steps, "ar", 64, (1e-4, "w"), reference=ref)
    assert band == pytest.approx([0.001, 0.004]) and "from 64^2 to 128^2 (0.002)" in how
    # mean gap: |2 - 2.5| / 2.5 = 20 % of each gap: 0.2, and 0 raised to the floor 0.01
    band, how = bands.hardwall_sweep_band(steps, "gap", 64, (0.01, "w"), reference=ref)
    assert band == pytest.approx([0.2, 0.01]) and "(20 %)" in how
    # the reference pair on other grids than the sweep's, or none: no band
    assert bands.hardwall_sweep_band(steps, "ar", 256, (1e-4, "w"), reference=ref) == (None, "")
    assert bands.hardwall_sweep_band(steps, "ar", 64, (1e-4, "w")) == (None, "")
    # a finer sweep measures it instead: |0.05 - 0.045| = |0.3 - 0.295| = 0.005, raised to the floor 0.01
    finer = (128, [step(1e5, 0.045), step(1e6, 0.295)])
    band, how = bands.hardwall_sweep_band(steps, "ar", 64, (0.01, "one point"), finer=finer, reference=ref)
    assert band == pytest.approx([0.01, 0.01]) and how.endswith("at least one point")
    assert math.isclose(bands.hardwall_sweep_band(steps, "ar", 64, (0.0, ""), finer=finer)[0][1], 0.005)
