"""The Python API is strict where a user would expect it to be: heights of real numbers only
(float or integer, converted), yes/no arguments as bools, paths without NUL, a mean gap that
can exist; a broadcast view too large for memory is refused before it is copied."""
import numpy as np
import pytest

from conftest import case_path


def rough(n=32, seed=3):
    """A small random surface (m), zero mean, rms about 1 µm."""
    h = np.random.default_rng(seed).normal(0.0, 1e-6, (n, n))
    return h - h.mean()


@pytest.mark.parametrize("heights, words", [
    (None, "got NoneType"),
    (np.zeros((8, 8), dtype=complex), "array of complex128"),
    (np.zeros((8, 8), dtype=bool), "array of bool"),
    (np.zeros((8, 8), dtype="datetime64[s]"), "array of datetime64"),
    (np.array([["a", "b"], ["c", "d"]]), "array of <U1"),
    (np.array(1e-6), "shape ()"),
    ([[0.0, None], [0.0, 0.0]], "array of object"),
])
def test_heights_that_are_not_real_numbers_are_refused(cmc, heights, words):
    with pytest.raises(cmc.CaseError, match="heights: expected") as e:
        cmc.solve(heights, 1e-4, 25e6, pressure=1e5)
    assert words in str(e.value)


def test_integer_heights_are_converted(cmc):
    h = np.round(rough(16) * 1e6).astype(np.int64)  # whole metres on a 1 km box
    s = cmc.solve(h, 1e3, 25e6, pressure=1e5)
    t = cmc.solve(h.astype(np.float64), 1e3, 25e6, pressure=1e5)
    assert s.converged and t.converged
    assert s.contact_fraction == t.contact_fraction and s.mean_gap == t.mean_gap


@pytest.mark.parametrize("value", ["no", "false", 1, 0, None, np.array([True])])
def test_yes_no_arguments_take_only_bools(cmc, value):
    with pytest.raises(cmc.CaseError, match="observables: expected True or False"):
        cmc.solve(rough(8), 1e-4, 25e6, pressure=1e5, observables=value)
    with pytest.raises(cmc.CaseError, match="adhesionless: expected True or False"):
        cmc.check([[1e5, 0.01], [2e5, 0.02]], "contact_area_vs_pressure", adhesionless=value)
    assert cmc.solve(rough(8), 1e-4, 25e6, pressure=1e5, observables=np.bool_(False)).converged


def test_path_with_a_nul_character_is_refused(cmc):
    real = case_path("validation/hertz-periodic.toml")
    for call in (lambda: cmc.Case.load(real + "\0ignored"), lambda: cmc.check(real + "\0x", "contact_area_vs_pressure"),
                 lambda: cmc.read_heights("h.h5\0", 1e-4)):
        with pytest.raises(cmc.CaseError, match="NUL character"):
            call()


def test_negative_mean_gap_is_refused_before_a_solve(cmc):
    with pytest.raises(cmc.CaseError, match="non-negative mean gaps"):
        cmc.solve(rough(8), 1e-4, 25e6, mean_gap=-1e-7)


def test_broadcast_view_too_large_is_refused_before_it_is_copied(cmc):
    big = np.broadcast_to(np.float64(0.0), (1 << 20, 1 << 20))  # 8 TiB as an array, 8 bytes as a view
    with pytest.raises(cmc.CaseError, match="memory"):
        cmc.solve(big, 1e-4, 25e6, pressure=1e5)


def test_check_on_arrays_names_no_row_that_does_not_exist(cmc):
    with pytest.raises(cmc.InputError) as e:
        cmc.check(np.zeros((0, 2)), "contact_area_vs_pressure")
    assert "row -" not in str(e.value), str(e.value)
