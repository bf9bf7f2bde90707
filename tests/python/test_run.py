"""cmc.Case and cmc.run against the command line: the same checks and messages, and the
same numbers, bit for bit, as `cmc run` on the same case."""
import json
import os

import h5py
import numpy as np
import pytest

from conftest import case_path, cmc_cli

# Per-step numbers that depend on the clock, not on the solve.
TIMES = {"wall_s", "fft_s"}
CASES = [
    ("challenge/reference-load-hardwall.toml", ["grid.n=128"]),  # Polonsky-Keer, observables
    ("challenge/reference-load.toml", ["grid.n=64"]),            # quasi-static adhesion
    ("validation/maugis-dugdale-lambda1.toml", []),              # adhesive CG on a load path
]


def cli_run(case, overrides, out):
    args = ["run", case_path(case), "--out", str(out), "--quiet"]
    for o in overrides:
        args += ["--set", o]
    r = cmc_cli(*args)
    assert r.returncode == 0, r.stderr
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def same_steps(a, b):
    assert len(a) == len(b)
    for sa, sb in zip(a, b):
        assert {k: v for k, v in sa.items() if k not in TIMES} == {k: v for k, v in sb.items() if k not in TIMES}


@pytest.mark.parametrize("case, overrides", CASES)
def test_run_gives_the_numbers_of_cmc_run_bit_for_bit(cmc, tmp_path, case, overrides):
    cli = cli_run(case, overrides, tmp_path / "cli")
    r = cmc.run(cmc.Case.load(case_path(case), set=overrides))
    assert r.status == cli["status"]
    same_steps(r.steps, cli["steps"])  # == on floats: the same bits
    assert r.summary["case"] == cli["case"]
    assert r.summary["surface_facts"] == cli["surface_facts"]
    assert r.summary["timing"]["iterations"] == cli["timing"]["iterations"]
    assert r.summary.get("load_path", {}).get("pulloff_force") == cli.get("load_path", {}).get("pulloff_force")
    with h5py.File(tmp_path / "cli" / "result.h5") as f:
        assert np.array_equal(r.heights, f["heights"][()])
        for step, fields in zip(cli["steps"], r.fields):
            group = f[f"step_{step['index']:04d}"]
            for name in ("pressure", "displacement", "gap"):
                assert np.array_equal(fields[name], group[name][()]), name
                assert group[name].attrs["units"].decode() == r.units[name]
        assert len(r.observables) == (len(cli["steps"]) if cli["case"]["observables"]["enabled"] else 0)
        for step, observables in zip(cli["steps"], r.observables):
            group = f[f"step_{step['index']:04d}"]["observables"]
            assert sorted(observables) == sorted(group)
            for name, values in observables.items():
                assert np.array_equal(values, group[name][()]), name
                assert group[name].attrs["units"].decode() == r.units[name]


def test_run_writes_nothing_without_out(cmc, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cmc.run(cmc.Case.load(case_path("validation/hertz-periodic.toml"), set={"grid.n": 32}))
    assert os.listdir(tmp_path) == []


def test_run_with_out_writes_what_cmc_run_writes(cmc, tmp_path):
    case, overrides = CASES[0]
    cli = cli_run(case, overrides, tmp_path / "cli")
    r = cmc.run(cmc.Case.load(case_path(case), set=overrides), out=tmp_path / "py")
    assert sorted(os.listdir(tmp_path / "py")) == sorted(os.listdir(tmp_path / "cli"))
    with open(tmp_path / "py" / "summary.json") as f:
        assert r.summary == json.load(f)
    same_steps(r.steps, cli["steps"])
    assert set(r.summary) == set(cli)


def test_a_run_stopped_from_python_is_resumed_by_cmc_run(cmc, tmp_path):
    """Stopped in its third step (as Ctrl-C stops it), a run with out= says so in its
    summary.json and `cmc run --resume` finishes it with the numbers of a whole run."""
    overrides = ["grid.n=64", "loading.values=[1e5, 2e5, 3e5]", "observables.enabled=false"]
    case = cmc.Case.load(case_path("challenge/reference-load-hardwall.toml"), set=overrides)

    def stop_in_step_2(point):
        if point["step"] == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        cmc.run(case, out=tmp_path / "py", progress=stop_in_step_2)
    with open(tmp_path / "py" / "summary.json") as f:
        stopped = json.load(f)
    assert stopped["status"] == "failed" and stopped["message"].startswith("stopped from Python")
    assert os.path.exists(tmp_path / "py" / "INCOMPLETE")
    args = ["run", case.file, "--out", str(tmp_path / "py"), "--quiet", "--resume"]
    for o in overrides:
        args += ["--set", o]
    r = cmc_cli(*args)
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "py" / "summary.json") as f:
        same_steps(json.load(f)["steps"], cmc.run(case).steps)


def cli_error(case, *overrides):
    args = ["run", case, "--out", "/nonexistent/never-written", "--quiet"]
    for o in overrides:
        args += ["--set", o]
    r = cmc_cli(*args)
    assert r.returncode == 2, r.stderr
    assert r.stderr.startswith("cmc: error: ")
    return r.stderr[len("cmc: error: "):].strip()


PATH = case_path("challenge/reference-load-hardwall.toml")


@pytest.mark.parametrize("overrides, named", [
    (["grid.nn=3"], PATH + ": [grid] nn: unknown key"),
    (["grid.size=-1"], PATH + ": [grid] size: expected"),
    (["solver.kind=\"fast\""], PATH + ": [solver] kind: expected one of"),
    (["surface.hurst=1.5"], PATH + ": [surface] hurst: expected"),
    (["loading=3"], "--set loading=3: expected section.key=value"),
])
def test_case_errors_are_the_command_lines(cmc, overrides, named):
    with pytest.raises(cmc.CaseError) as e:
        cmc.Case.load(PATH, set=overrides)
    assert str(e.value) == cli_error(PATH, *overrides)
    assert str(e.value).startswith(named), str(e.value)


def test_set_takes_a_dict_of_python_values(cmc):
    path = case_path("challenge/reference-load-hardwall.toml")
    case = cmc.Case.load(path, set={"grid.n": np.int64(64), "solver.kind": "polonsky_keer",
                                    "loading.values": [1e5, 2e5], "observables.enabled": False,
                                    "case.description": 'quote " and \\ kept'})
    c = case.resolved
    assert case.shape == (64, 64)
    assert c["loading"]["values"] == [1e5, 2e5] and c["observables"]["enabled"] is False
    assert c["case"]["description"] == 'quote " and \\ kept'
    with pytest.raises(cmc.CaseError, match=r"\[grid\] n: expected"):
        cmc.Case.load(path, set={"grid.n": "many"})


def test_a_missing_case_file_is_named(cmc, tmp_path):
    missing = str(tmp_path / "none.toml")
    with pytest.raises(cmc.CaseError) as e:
        cmc.Case.load(missing)
    assert str(e.value) == cli_error(missing)
