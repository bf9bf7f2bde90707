"""cmc.solve on numpy heights: Hertz against the analytic reference within the case file's
tolerance, bad arguments named, non-finite heights refused, Ctrl-C stops a solve."""
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from conftest import case_path


def paraboloid(n, size, radius):
    """h = r^2/(2R) about the box centre, minimum-image distances (as a periodic case's sphere)."""
    x = np.arange(n) * (size / n) - size / 2
    dx = x - size * np.round(x / size)
    return (dx[None, :] ** 2 + dx[:, None] ** 2) / (2 * radius)


def test_hertz_from_numpy_heights_within_the_case_tolerance(cmc):
    case = cmc.Case.load(case_path("validation/hertz-periodic.toml"))
    c = case.resolved
    n, size, E, R = c["grid"]["n"], c["grid"]["size"], c["material"]["contact_modulus"], c["surface"]["radius"]
    force = c["loading"]["values"][0]
    tolerance = next(k["tolerance"] for k in c["validation"]["check"] if k["quantity"] == "penetration")
    s = cmc.solve(paraboloid(n, size, R), size, E, force=force, tolerance=c["solver"]["tolerance"])
    assert s.converged, s.message
    assert s.force == pytest.approx(force, rel=1e-12)
    reference = cmc.analytic.hertz_periodic_penetration(E, R, force, size)
    error = abs(s.penetration - reference) / cmc.analytic.hertz(E, R, force=force).penetration
    assert error <= tolerance, f"penetration error {error:.3g} > the case's tolerance {tolerance}"
    # The pressure carries the load: mean pressure x area.
    assert s.pressure.mean() * size * size == pytest.approx(force, rel=1e-9)
    assert s.units["pressure"] == "Pa" and s.units["gap"] == "m"
    assert s.pressure.shape == (n, n) and not s.pressure.flags.owndata  # a view of the run's buffer


def test_solve_matches_the_same_case_run_from_a_file(cmc):
    """The numpy path and the case-file path give the same solve for the same heights (to
    round-off: the heights pass through metres, and h L / L is not always h's bits)."""
    case = cmc.Case.load(case_path("validation/hertz-periodic.toml"), set={"grid.n": 64})
    run = cmc.run(case)
    c = case.resolved
    s = cmc.solve(run.heights, c["grid"]["size"], c["material"]["contact_modulus"], force=c["loading"]["values"],
                  tolerance=c["solver"]["tolerance"])
    assert s.penetration == pytest.approx(run.steps[0]["penetration"], rel=1e-12)
    p = run.field("pressure")
    assert np.max(np.abs(s.pressure - p)) <= 1e-9 * np.max(p)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_heights_are_refused(cmc, bad):
    h = np.zeros((32, 32))
    h[5, 7] = bad
    with pytest.raises(cmc.CaseError, match=r"heights: 1 of 1024 values are not finite .* row 5, column 7"):
        cmc.solve(h, 1e-4, 25e6, pressure=1e5)


@pytest.mark.parametrize("change, argument", [
    ({"size": -1.0}, "size"),
    ({"size": "big"}, "size"),
    ({"modulus": 0.0}, "modulus"),
    ({"strategy": "fastest"}, "strategy"),
    ({"tolerance": -1e-8}, "tolerance"),
    ({"max_iterations": 0}, "max_iterations"),
    ({"boundary": "open"}, "boundary"),
    ({"pressure": -5.0}, "pressure"),
    ({"pressure": None}, "give exactly one of pressure=, penetration="),
    ({"penetration": 1e-6}, "give exactly one of pressure=, penetration="),
    ({"interaction": "sticky"}, "interaction"),
    ({"interaction": "EXP"}, "interaction"),
])
def test_bad_arguments_are_named(cmc, change, argument):
    args = {"size": 1e-4, "modulus": 25e6, "pressure": 1e5}
    args.update(change)
    if change.get("interaction") == "EXP":
        args["interaction"] = cmc.Exponential(0.05, -1e-9)  # a negative range
    with pytest.raises(cmc.CaseError) as e:
        cmc.solve(np.zeros((16, 16)), **args)
    assert f"cmc.solve(): {argument}" in str(e.value), str(e.value)


@pytest.mark.parametrize("heights", [np.zeros((2, 3, 4)), np.zeros((0, 4)), [["a", "b"]]])
def test_heights_of_the_wrong_shape_or_type_are_named(cmc, heights):
    with pytest.raises(cmc.CaseError, match=r"cmc.solve\(\): heights: expected"):
        cmc.solve(heights, 1e-4, 25e6, pressure=1e5)


def test_a_progress_callback_that_raises_stops_the_solve(cmc):
    calls = []

    def progress(point):
        calls.append(point)
        if len(calls) == 2:
            raise RuntimeError("enough")

    h = cmc.self_affine(128, 1e-4, cutoff_wavelength=1e-6)
    with pytest.raises(RuntimeError, match="enough"):
        cmc.solve(h, 1e-4, 25e6, pressure=1e5, strategy="adhesive_cg", tolerance=1e-300, max_iterations=10 ** 8,
                  progress=progress)
    assert [sorted(p) for p in calls] == [["inner", "iteration", "outer", "residual", "step"]] * 2
    assert calls[1]["iteration"] > calls[0]["iteration"]


def test_ctrl_c_stops_a_solve_cleanly():
    """SIGINT during a solve: KeyboardInterrupt from cmc.solve within a second or so, and
    the process goes on (here: prints and exits 0)."""
    code = """
import sys, time, cmc
h = cmc.self_affine(256, 1e-4, cutoff_wavelength=1e-6)
started = []
def progress(point):
    if not started:
        started.append(time.monotonic())
        print("solving", flush=True)
try:
    cmc.solve(h, 1e-4, 25e6, pressure=1e5, strategy="adhesive_cg", tolerance=1e-300, max_iterations=10**8,
              progress=progress)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    p = subprocess.Popen(["/usr/bin/python3", "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=env)
    try:
        assert p.stdout.readline().strip() == "solving"
        time.sleep(0.3)
        sent = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
    finally:
        p.kill()
    assert p.returncode == 0, err
    assert out.strip() == "interrupted", (out, err)
    assert time.monotonic() - sent < 30


def test_the_gil_is_released_during_a_solve(cmc):
    """Another Python thread runs while a solve computes (a fixed 300 iterations)."""
    import threading
    h = cmc.self_affine(256, 1e-4, cutoff_wavelength=1e-6)
    ticks, done = [], threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.002)

    t = threading.Thread(target=tick)
    t.start()
    try:
        start = time.monotonic()
        s = cmc.solve(h, 1e-4, 25e6, pressure=1e5, strategy="adhesive_cg", tolerance=1e-300, max_iterations=300)
        end = time.monotonic()
    finally:
        done.set()
        t.join()
    assert s.iterations == 300
    inside = [x for x in ticks if start < x < end]
    # With the GIL held the ticker would not run until the solve returned.
    assert len(inside) >= 10, f"{len(inside)} ticks in {end - start:.2f} s of solving"
