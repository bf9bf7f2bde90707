"""Property tests of the Python API (hypothesis; a fixed seed, a bounded number of examples):
cmc.solve takes any array and either solves it or raises cmc.CaseError naming the heights,
never another exception; it accepts exactly the real numbers of a 1-D or 2-D shape; at zero load
its answer does not depend on a constant added to the heights; yes/no arguments take only bools."""
import os
import tempfile

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st
from hypothesis.configuration import set_hypothesis_home_dir
from hypothesis.extra import numpy as hnp

set_hypothesis_home_dir(os.path.join(tempfile.gettempdir(), "cmc-hypothesis"))  # its caches, not in the tree

SETTINGS = dict(derandomize=True, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])  # cmc: the module
dtypes = st.one_of(hnp.floating_dtypes(), hnp.integer_dtypes(), hnp.unsigned_integer_dtypes(), hnp.boolean_dtypes(),
                   hnp.complex_number_dtypes(), hnp.datetime64_dtypes(), hnp.timedelta64_dtypes(),
                   hnp.unicode_string_dtypes(max_len=3))
shapes = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=6)


@settings(max_examples=60, **SETTINGS)
@given(hnp.arrays(dtypes, shapes))
def test_any_array_is_solved_or_refused_by_name(cmc, heights):
    real = heights.dtype.kind in "fiu"
    shaped = heights.ndim in (1, 2) and heights.size > 0
    finite = real and np.all(np.isfinite(heights.astype(np.float64)))
    try:
        s = cmc.solve(heights * 1e-9 if real else heights, 1e-6, 25e6, pressure=1e3, max_iterations=200)
    except cmc.CaseError as e:
        assert "heights" in str(e), str(e)  # the only argument that varies
        return
    assert real and shaped and finite, f"accepted {heights.dtype} of shape {heights.shape}"
    assert s.status in ("converged", "not_converged")
    assert 0.0 <= s.contact_fraction <= 1.0


# Heights and offsets on binary grids (2^-30 m, 2^-20 m), so that h + offset is exact: heights
# that differ by less than the offset's last bit become one height, and touch together (hypothesis
# found [[0, 4e-31], [4e-31, 4e-31]] + 6e-5, all four points alike after the sum).
@settings(max_examples=20, **SETTINGS)
@given(hnp.arrays(np.int64, hnp.array_shapes(min_dims=2, max_dims=2, min_side=2, max_side=12),
                  elements=st.integers(-1000, 1000)),
       st.integers(-1000, 1000))
def test_zero_load_does_not_depend_on_an_offset(cmc, steps, shift):
    heights, offset = steps * 2.0 ** -30, shift * 2.0 ** -20
    a = cmc.solve(heights, 1e-5, 25e6, pressure=0.0)
    b = cmc.solve(heights + offset, 1e-5, 25e6, pressure=0.0)
    assert a.converged and b.converged
    assert a.contact_fraction == b.contact_fraction
    assert abs(a.mean_gap - b.mean_gap) <= 1e-12 * abs(a.mean_gap) + 1e-22  # the sums' round-off


@settings(max_examples=30, **SETTINGS)
@given(st.one_of(st.text(max_size=4), st.integers(), st.floats(), st.none(), st.lists(st.booleans(), max_size=2)))
def test_yes_no_arguments_refuse_all_but_bools(cmc, value):
    try:
        cmc.solve(np.zeros((4, 4)), 1e-6, 25e6, pressure=1e3, observables=value)
    except cmc.CaseError as e:
        assert "observables: expected True or False" in str(e)
    else:
        raise AssertionError(f"observables={value!r} was taken")
