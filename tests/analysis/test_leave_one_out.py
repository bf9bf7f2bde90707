"""The band rules of python/cmc/analysis/best.py tested on the stored runs: every best estimate
made without its sequence's finest grid must hold that grid's value inside its band, for every
point and quantity of reference/challenge/runs.json where a finer grid exists. A failure means
the rule is wrong (change the rule, not this test)."""

from cmc.analysis import best, challenge, family, runs  # noqa: E402


def _rows():
    records = runs.expand_steps(challenge.of_physics(runs.load_store()))
    return best.leave_one_out(records, family.measured_members(), family.condition_members(), challenge.roundoff())


def test_every_band_holds_the_finer_grid():
    rows = _rows()
    # The store holds refinement sequences of three grids or more at 10 loads of the hard wall and
    # at 8 points with adhesion (19 sequences, 57 rows): the test must see them, or it tests nothing.
    assert len({(r["problem"], r["pressure_Pa"]) for r in rows if r["problem"] == "hardwall"}) >= 10
    assert len(rows) >= 50
    out = [f"{r['problem']} p = {r['pressure_Pa']:.4g} Pa mu_T = {r['tabor']} {r['sequence']} {r['quantity']}: "
           f"{r['n']}² gives {r['value']:.6g} +- {r['error']:.3g}, {r['finest_n']}² has {r['finest']:.6g} "
           f"({r['deviation']:.2f} bands)" for r in rows if not r["inside"]]
    assert not out, "bands that miss the finer grid:\n" + "\n".join(out)


def test_a_two_grid_band_is_the_first_order_bound():
    # 2048² and 4096² of the hard-wall sweep: the finer value's error is twice the change, and
    # for the counted area (first order) the 8192² value lies near half of it.
    rows = [r for r in _rows() if r["problem"] == "hardwall" and r["quantity"] == "a_r" and r["n"] == 4096]
    assert rows and all(0.1 < r["deviation"] < 0.5 for r in rows)
