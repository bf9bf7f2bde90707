"""cmc.self_affine, cmc.read_heights, cmc.analytic and cmc.check: the library's surfaces,
readers, references and checker, with numpy in and out."""
import os
import warnings

import h5py
import numpy as np
import pytest

from conftest import SOURCE, case_path


def test_self_affine_is_the_case_files_surface(cmc):
    case = cmc.Case.load(case_path("challenge/reference-load-hardwall.toml"),
                         set={"grid.n": 64, "surface.seed": 7, "surface.cutoff_wavelength": 4e-6,
                              "observables.enabled": False})
    c = case.resolved
    from_case = cmc.run(case).heights
    s = c["surface"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 64 points per side hold this band: no warning
        h = cmc.self_affine(64, c["grid"]["size"], hurst=s["hurst"], rolloff_wavelength=s["rolloff_wavelength"],
                            cutoff_wavelength=s["cutoff_wavelength"], rms_gradient=s["rms_gradient"], seed=7)
    assert h.shape == (64, 64) and h.min() == 0.0
    assert np.array_equal(h, from_case)


def test_self_affine_warns_on_a_low_passed_grid_and_names_bad_arguments(cmc):
    with pytest.warns(UserWarning, match="low-passed"):
        cmc.self_affine(32, 1e-4)
    with pytest.raises(cmc.CaseError, match=r"cmc.self_affine\(\): hurst \(\[surface\] hurst\): expected"):
        cmc.self_affine(32, 1e-4, hurst=1.5)
    with pytest.raises(cmc.CaseError, match=r"cmc.self_affine\(\): n \(\[grid\] n\): expected"):
        cmc.self_affine(0, 1e-4)


def test_read_heights_reads_the_challenge_formats(cmc, tmp_path):
    h = np.random.default_rng(3).random((16, 16)) * 1e-6  # metres
    L = 1e-4
    with h5py.File(tmp_path / "s.h5", "w") as f:
        f["surface"] = h / L  # the challenge's HDF5: heights in units of L
    np.savetxt(tmp_path / "s.txt", h / L, fmt="%.17g")
    assert np.array_equal(cmc.read_heights(tmp_path / "s.h5", L), h / L * L)
    assert np.array_equal(cmc.read_heights(tmp_path / "s.txt", L, "challenge_ascii"), h / L * L)
    with pytest.raises(cmc.SurfaceFileError, match="missing.h5"):
        cmc.read_heights(tmp_path / "missing.h5", L)
    with pytest.raises(cmc.CaseError, match=r"cmc.read_heights\(\): format: expected one of"):
        cmc.read_heights(tmp_path / "s.h5", L, "tiff")
    with pytest.raises(cmc.CaseError, match=r"cmc.read_heights\(\): size: expected"):
        cmc.read_heights(tmp_path / "s.h5", -L)


def test_analytic_functions_take_numbers_and_arrays(cmc):
    a = cmc.analytic
    H = a.hertz(1e6, 1e-2, force=1e-3)
    assert H.radius == pytest.approx((3 * 1e-3 * 1e-2 / (4 * 1e6)) ** (1 / 3), rel=1e-12)
    assert a.hertz(1e6, 1e-2, radius=H.radius).force == pytest.approx(1e-3, rel=1e-12)
    r = np.linspace(0, 2 * H.radius, 9)
    p = a.hertz_pressure(1e6, 1e-2, H.radius, r)
    assert p.shape == (9,) and p[0] == pytest.approx(H.max_pressure, rel=1e-12) and p[-1] == 0.0
    assert isinstance(a.hertz_pressure(1e6, 1e-2, H.radius, 0.0), float)
    assert a.jkr_pulloff_load_controlled(1e6, 1e-2, 0.05).force == pytest.approx(-1.5 * np.pi * 0.05 * 1e-2)
    with pytest.raises(ValueError):
        a.hertz(1e6, -1.0, force=1.0)
    with pytest.raises(ValueError, match="exactly one of"):
        a.hertz(1e6, 1e-2)


def reference_curve(quantity):
    path = os.path.join(SOURCE, "reference", "challenge", quantity + ".csv")
    rows = [line for line in open(path) if not line.startswith("#")]
    return np.loadtxt(rows[1:], delimiter=",", usecols=(0, 1))


def test_check_scores_data_as_it_scores_a_file(cmc, tmp_path):
    ref = reference_curve("contact_area_vs_pressure")
    pred = np.column_stack([ref[:, 0], ref[:, 1] * 1.03])
    # scored against the file it was made from (seed 28's, `surface`), not the default realisation
    from_data = cmc.check((pred[:, 0], pred[:, 1]), "contact_area_vs_pressure", against="surface")
    path = tmp_path / "p.csv"
    np.savetxt(path, pred, fmt="%.17g", delimiter=",", header="mean_pressure_Pa,contact_fraction", comments="")
    from_file = cmc.check(path, "contact_area_vs_pressure", against="surface")
    assert from_data.metrics == from_file.metrics and from_data.verdict == from_file.verdict
    assert from_data.metrics["max_rel"] == pytest.approx(0.03, rel=1e-9)
    assert from_data.report["prediction_file"] == "(array)"
    assert isinstance(from_data.passed, bool)


def test_check_names_bad_predictions(cmc):
    with pytest.raises(cmc.InputError, match="prediction row 1: .*strictly increasing"):
        cmc.check(np.array([[1e5, 0.1], [5e4, 0.2], [3e5, 0.3]]), "contact_area_vs_pressure")
    with pytest.raises(cmc.InputError, match="unknown quantity 'area'"):
        cmc.check(np.array([[1e5, 0.1], [2e5, 0.2]]), "area")
    with pytest.raises(cmc.InputError, match="expected an \\(N, 2\\) array"):
        cmc.check(np.zeros((3, 3)), "contact_area_vs_pressure")
    with pytest.raises(cmc.InputError, match="name its quantity"):
        cmc.check(np.zeros((3, 2)))
