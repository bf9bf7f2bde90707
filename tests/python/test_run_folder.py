"""cmc.run_folder, the one reader of run folders: a small run folder made here (summary.json with
two load steps, result.h5 with their groups) read back as typed records, and folders that are
not finished runs (no summary, a truncated one, no result.h5, a step without its group)
refused with an error that names the folder or file and what is missing."""
import json
import os

import h5py
import numpy as np
import pytest

from cmc import run_folder
from cmc.report.challenge_runs import Run, _observables

GAPS = np.array([0.0, 1e-9, 2e-9, 4e-9])


def make_run(folder, steps=2, groups=2):
    """A run folder as `cmc run --out` lays it out, with `steps` steps in summary.json and the
    first `groups` of them in result.h5 (the second step's index is 5: groups go by index)."""
    os.makedirs(folder, exist_ok=True)
    records = [{"index": [0, 5][k], "mean_pressure": 1e5 * (k + 1), "contact_fraction": 0.01 * (k + 1),
                "mean_gap": 1e-6, "converged": True, "iterations": 10 + k,
                "observables": {"repulsive_fraction": 0.005 * (k + 1)}} for k in range(steps)]
    summary = {"status": "converged", "case": {"case": {"name": "challenge-test"}},
               "grid": {"nx": 32, "ny": 32}, "steps": records}
    with open(os.path.join(folder, "summary.json"), "w") as f:
        json.dump(summary, f)
    with h5py.File(os.path.join(folder, "result.h5"), "w") as f:
        for rec in records[:groups]:
            g = f.create_group(f"step_{rec['index']:04d}")
            g.attrs["mean_pressure"] = rec["mean_pressure"]
            g.create_group("observables").create_dataset("gap_distribution_edges", data=GAPS * (rec["index"] + 1))
    return folder


def test_a_finished_run_reads_as_typed_records(tmp_path):
    folder = make_run(str(tmp_path / "run"))
    s = run_folder.read_summary(folder)
    assert (s.status, s.case_name, s.path) == ("converged", "challenge-test", os.path.join(folder, "summary.json"))
    assert [(st.position, st.index) for st in s.steps] == [(0, 0), (1, 5)]
    assert s.steps[1].value("mean_pressure") == 2e5
    assert s.steps[1].scalar_observables == {"repulsive_fraction": 0.01}
    second = run_folder.observables(folder, s.steps[1])
    assert second.group == "step_0005"
    np.testing.assert_array_equal(second.arrays["gap_distribution_edges"], GAPS * 6)
    assert run_folder.step_attribute(folder, s.steps[1], "mean_pressure") == 2e5
    assert run_folder.step_attribute(folder, s.steps[1], "no_such_attribute") is None


def test_the_report_reads_the_same_numbers(tmp_path):
    folder = make_run(str(tmp_path / "run"))
    run = Run(run_folder.read_summary(folder).data, folder)
    assert [st["p"] for st in run.steps] == [1e5, 2e5]
    assert run.has_result and run.step(run.steps[1]).index == 5
    notes = []
    obs, st = _observables(run, notes)  # no step at 250 kPa within 5 %: nothing read, nothing said
    assert (obs, st, notes) == ({}, None, [])


def test_run_folders_are_found_below_a_folder(tmp_path):
    a, b = make_run(str(tmp_path / "r" / "a")), make_run(str(tmp_path / "r" / "b" / "deeper"))
    os.makedirs(tmp_path / "r" / "empty")
    assert run_folder.find(str(tmp_path / "r")) == [a, b]
    assert run_folder.find(str(tmp_path / "r"), recursive=False) == [a]


def test_a_folder_without_summary_is_named(tmp_path):
    with pytest.raises(run_folder.RunFolderError, match=f"{tmp_path}: no summary.json"):
        run_folder.read_summary(str(tmp_path))


def test_a_truncated_summary_is_refused_naming_its_file(tmp_path):
    folder = make_run(str(tmp_path / "run"))
    path = os.path.join(folder, "summary.json")
    with open(path) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(text[: len(text) // 2])
    with pytest.raises(run_folder.RunFolderError, match=f"{path}: not complete JSON"):
        run_folder.read_summary(folder)
    notes = []
    assert run_folder.read_summaries([folder], notes) == []
    assert len(notes) == 1 and path in notes[0]


def test_a_summary_whose_steps_are_not_a_list_is_refused(tmp_path):
    folder = str(tmp_path)
    with open(os.path.join(folder, "summary.json"), "w") as f:
        json.dump({"status": "converged", "steps": {"index": 0}}, f)
    with pytest.raises(run_folder.RunFolderError, match='"steps" is dict, expected a list'):
        run_folder.read_summary(folder)


def test_a_step_missing_from_result_h5_is_named(tmp_path):
    folder = make_run(str(tmp_path / "run"), steps=2, groups=1)
    last = run_folder.read_summary(folder).steps[1]
    with pytest.raises(run_folder.RunFolderError, match=r"result.h5: no group for load step 5 \(step_0005"):
        run_folder.observables(folder, last)


def test_a_run_without_result_h5_is_named(tmp_path):
    folder = make_run(str(tmp_path / "run"))
    os.remove(os.path.join(folder, "result.h5"))
    first = run_folder.read_summary(folder).steps[0]
    assert not run_folder.has_result(folder)
    with pytest.raises(run_folder.RunFolderError, match=f"{folder}: no result.h5"):
        run_folder.observables(folder, first)


def test_a_result_h5_cut_short_is_named(tmp_path):
    folder = make_run(str(tmp_path / "run"))
    path = os.path.join(folder, "result.h5")
    with open(path, "r+b") as f:
        f.truncate(os.path.getsize(path) // 3)
    first = run_folder.read_summary(folder).steps[0]
    with pytest.raises(run_folder.RunFolderError, match=f"{path}: cannot be read"):
        run_folder.observables(folder, first)
