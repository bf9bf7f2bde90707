"""Unit tests of python/cmc/analysis: the choice of best estimates, the extremum and run records."""
import math

import numpy as np
import pytest

from cmc.analysis import best, challenge, extremum, runs


def rec(tag, n, a_r, gap, strategy="plain", status="converged", problem="adhesive", case="c", k=None, b=None, tabor=3.0):
    return {"tag": tag, "n": n, "a_r": a_r, "a_rep": a_r, "mean_gap_m": gap, "strategy": strategy,
            "status": status, "problem": problem, "case_name": case, "tabor": tabor if problem == "adhesive" else None,
            "pressure_Pa": 250e3, "dx_over_rho": k, "bistability_number": b, "tolerance": 1e-6, "date": "x",
            "device": "d", "backend": "cpu"}


FAMILY = [{"s": 8, "reference": {"a_r": {"value": 0.04, "refinement_error": 0.0},
                                 "a_rep": {"value": 0.04, "refinement_error": 0.0},
                                 "mean_gap": {"value": 1e-6, "refinement_error": 0.0}},
           "runs": [{"role": "shape_2rho", "dx_over_rho": 2.0, "a_r": 0.0404, "a_rep": 0.0404, "mean_gap": 1.001e-6, "n": 1},
                    {"role": "plain_2rho", "dx_over_rho": 2.0, "a_r": 0.036, "a_rep": 0.036, "mean_gap": 1.01e-6, "n": 1}]}]


def test_hardwall_best_is_the_finest_with_its_richardson_error():
    rs = [rec("h1", 1024, 0.024, 1.0, problem="hardwall"), rec("h2", 2048, 0.022, 1.0, problem="hardwall"),
          rec("h3", 4096, 0.021, 1.0, problem="hardwall")]
    got = best.best_at(rs, "hardwall", 250e3, None, FAMILY, [])
    q = got["quantities"]["a_r"]
    # changes -0.002, -0.001: order 1, v_inf = 0.020, error 0.001
    assert got["run"] == "h3" and q["value"] == 0.021 and q["error"] == pytest.approx(0.001)
    assert "strategy_error" not in q


def test_an_unconverged_finest_run_is_not_the_estimate():
    rs = [rec("h1", 1024, 0.024, 1.0, problem="hardwall"), rec("h2", 2048, 0.022, 1.0, problem="hardwall"),
          rec("h3", 4096, 0.021, 1.0, problem="hardwall", status="not_converged")]
    assert best.best_at(rs, "hardwall", 250e3, None, FAMILY, [])["run"] == "h2"


def test_a_finest_run_without_its_coarser_grid_gives_way():
    # 8192² with 4096² missing cannot make its error: the 1024²/2048² pair does, twice its change
    rs = [rec("h1", 1024, 0.024, 1.0, problem="hardwall"), rec("h2", 2048, 0.022, 1.0, problem="hardwall"),
          rec("h4", 8192, 0.0205, 1.0, problem="hardwall")]
    got = best.best_at(rs, "hardwall", 250e3, None, FAMILY, [])
    assert got["run"] == "h2" and got["quantities"]["a_r"]["error"] == pytest.approx(0.004)


def test_the_smaller_total_error_wins_and_strategy_errors_add():
    rs = [rec("p1", 1024, 0.030, 1.0, k=4.0, b=4.0), rec("p2", 2048, 0.034, 1.0, k=2.0, b=2.0),
          rec("s1", 1024, 0.0398, 1.0, strategy="shape", case="s", k=4.0, b=4.0),
          rec("s2", 2048, 0.0400, 1.0, strategy="shape", case="s", k=2.0, b=2.0)]
    got = best.best_at(rs, "adhesive", 250e3, 3.0, FAMILY, [])
    q = got["quantities"]["a_r"]
    # shape at 2 rho: refinement 2 x 0.0002/0.04 = 1 %, family 1 %: 2 %; plain: 2 x 0.004/0.034 + 10 %
    assert got["run"] == "s2" and q["relative_error"] == pytest.approx(0.02)
    assert q["strategy_error"]["error"] == pytest.approx(0.01)
    assert [o["run"] for o in got["passed_over"]] == ["p2"]


def test_a_resolved_run_needs_no_family_and_an_unmeasured_spacing_is_not_usable():
    rs = [rec("r1", 1024, 0.030, 1.0, k=0.8, b=0.5, tabor=0.1), rec("r2", 2048, 0.029, 1.0, k=0.4, b=0.25, tabor=0.1)]
    got = best.best_at(rs, "adhesive", 250e3, 0.1, FAMILY, [])
    assert got["run"] == "r2" and "strategy_error" not in got["quantities"]["a_r"]
    rs = [rec("u1", 1024, 0.030, 1.0, k=16.0, b=16.0), rec("u2", 2048, 0.029, 1.0, k=8.0, b=8.0)]
    assert best.best_at(rs, "adhesive", 250e3, 3.0, FAMILY, []) is None


def test_roundoff_is_a_floor():
    rs = [rec("h1", 1024, 0.024, 1.0, problem="hardwall"), rec("h2", 2048, 0.024, 1.0, problem="hardwall")]
    got = best.best_at(rs, "hardwall", 250e3, None, FAMILY, [], {"a_r": 1e-5})
    assert got["quantities"]["a_r"]["relative_error"] == 1e-5 and got["quantities"]["a_r"]["roundoff_floor"]


def test_extremum_of_a_parabola_in_log_mu():
    mu = 10 ** np.arange(-3, 0.01, 0.25)
    y = 1.0 + 0.01 * (np.log10(mu) + 1.9) ** 2          # minimum at mu = 10^-1.9, y = 1
    got = extremum.locate(mu, y, "min")
    assert math.log10(got["mu"]) == pytest.approx(-1.9, abs=1e-9) and got["y"] == pytest.approx(1.0)
    assert got["bracket"][0] < got["mu"] < got["bracket"][1]
    assert extremum.locate(mu, np.log10(mu), "min") is None   # monotone: not bracketed
    # a neighbour a decade away does not bracket it: the samples between are missing
    assert extremum.locate([0.001, 0.00316, 0.00562, 3.0], [1.0, 0.99, 0.98, 1.01], "min") is None
    m, s = extremum.log_slope([1, 10, 100], [0.0, 1.0, 3.0])
    assert list(s) == [1.0, 2.0] and m[0] == pytest.approx(math.sqrt(10))


def test_extremum_grid_error_is_the_change_between_the_finest_grids():
    a = {"mu": 0.01, "y": 1.0, "log10_mu_error": 0.05, "y_error": 0.001, "bracket": [0.005, 0.02]}
    grids = [(1024, {"mu": 0.02, "y": 1.1}), (2048, {"mu": 0.0125, "y": 1.01}), (4096, None)]
    got = extremum.combine(a, grids)
    assert got["log10_mu_grid_error"] == pytest.approx(math.log10(0.02 / 0.0125))
    assert got["y_total_error"] == pytest.approx(0.001 + 0.09) and got["grids"] == [1024, 2048]


def test_record_from_a_summary():
    s = {"status": "converged", "case_file": "cases/x.toml", "grid": {"nx": 64, "dx": 2e-9, "backend": "cpu", "threads": 1},
         "case": {"case": {"name": "challenge-tabor-sweep"}, "interaction": {"kind": "exponential", "tabor": 0.1},
                  "solver": {"tolerance": 1e-6}},
         "surface_facts": {"specified_range": 1e-9, "bistability_number": 0.5},
         "timing": {"iterations": 7}, "steps": [{"contact_fraction": 0.02, "mean_gap": 1e-6, "mean_pressure": 250e3,
                                                 "wall_s": 1.5, "observables": {"repulsive_fraction": 0.01}}]}
    r = runs.record(s, tag="t", command="c", device="d", date="x", commit="abc", origin="o")
    assert r["kind"] == "tabor_mu0.1" and r["problem"] == "adhesive" and r["strategy"] == "plain"
    assert r["dx_over_rho"] == pytest.approx(2.0) and r["a_rep"] == 0.01 and r["commit"] == "abc"
    assert r["solve_s"] == 1.5 and r["iterations"] == 7


def test_tabor_values_group_points_within_one_percent():
    rs = [rec("a", 64, 0.1, 1.0, tabor=3.0), rec("b", 64, 0.1, 1.0, tabor=3.0017), rec("c", 64, 0.1, 1.0, tabor=0.1)]
    assert challenge.tabor_values(rs) == [0.1, 3.0]


def test_monotonicity_names_falls_and_checks_each_grid():
    q = lambda v, e: {"a_r": {"value": v, "error": e}}
    curve = [{"tabor": 0.01, "n": 4096, "quantities": q(0.0238, 0.0015)},
             {"tabor": 0.1, "n": 16384, "quantities": q(0.0236, 0.0003)},
             {"tabor": 1.0, "n": 16384, "quantities": q(0.0300, 0.0004)}]
    rs = [rec(f"g{k}", 2048, v, 1.0, case="challenge-tabor-sweep", tabor=mu, k=k_, b=k_)
          for k, (mu, v, k_) in enumerate([(0.01, 0.025, 0.1), (0.1, 0.026, 0.5), (1.0, 0.033, 3.0), (3.0, 0.030, 9.0)])]
    got = challenge.monotonicity(curve, rs)
    assert not got["monotonic"] and len(got["falls"]) == 1
    f = got["falls"][0]
    assert f["from"] == 0.01 and f["grids"] == [4096, 16384] and f["inside_bars"]  # 0.0002 <= 0.0018
    # on 2048² a_r falls at mu_T = 3, where that grid no longer resolves rho; it rises where it does
    assert got["grids"] == {2048: {"rises": False, "rises_where_resolved": True, "resolved_up_to": 0.1}}


def test_a_r_slope_around_the_extremum_uses_only_points_that_resolve_rho():
    # a_r rises in log mu_T on the points that resolve rho; the last point (dx = 3 rho) falls, as a
    # coarse grid's counted area does, and must not enter the slope
    pts = [(0.001, 0.020, 0.1), (0.003, 0.021, 0.1), (0.01, 0.0215, 0.2), (0.03, 0.0217, 0.3),
           (0.1, 0.023, 0.5), (3.0, 0.022, 3.0)]
    rs = [rec(f"g{k}", 4096, v, 1.0, case="challenge-tabor-sweep", tabor=mu, k=k_, b=k_)
          for k, (mu, v, k_) in enumerate(pts)]
    got = challenge.a_r_log_slope_around(0.008, rs)
    assert got["a_r_log_slope_grid"] == 4096 and got["a_r_log_slope_resolved_up_to"] == 0.1
    slopes = [s["slope"] for s in got["a_r_log_slope"]]
    assert len(slopes) == 4 and min(slopes) > 0
    assert slopes[2] == pytest.approx(0.0002 / math.log10(3.0))
    # no grid's resolved points bracket mu_T = 0.5
    assert challenge.a_r_log_slope_around(0.5, rs) == {}
