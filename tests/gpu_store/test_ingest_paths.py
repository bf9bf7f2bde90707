"""scripts/gpu/ingest.py treats the archive as untrusted: a date or run name that is not a plain
path component, or a member with special mode bits, is refused (exit 2) before anything is
written, and what it copies has plain modes."""
import os
import stat

import pytest

from hostile import ingest, plan_archive, scratch_repo, snapshot, summary


def _victim(folder):
    """A folder with a run-like subfolder and a file that must survive."""
    os.makedirs(os.path.join(folder, "cuda-hardwall-64"), exist_ok=True)
    with open(os.path.join(folder, "cuda-hardwall-64", "keep.txt"), "w") as f:
        f.write("not ingest's to touch\n")


def _refused(tmp, archive, word):
    before = snapshot(tmp)
    r = ingest(tmp, archive)
    assert r.returncode == 2, r.stdout + r.stderr
    assert word in r.stderr
    assert "Traceback" not in r.stderr
    assert snapshot(tmp) == before, "ingest changed files though it refused the archive"


@pytest.mark.parametrize("date", ["ABSOLUTE", "../../..", "../../../victim", "2026-01-02/../../..", "2026-13-40"])
def test_date_that_is_not_a_day_is_refused(tmp_path, date):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    victim = os.path.join(tmp, "victim")
    _victim(victim)
    _victim(tmp)  # what ../../.. from results/gpu reaches
    date = victim if date == "ABSOLUTE" else date
    archive = plan_archive(os.path.join(tmp, "plan.tgz"), [("cuda-hardwall-64", summary(64, 0.02))], date=date)
    _refused(tmp, archive, "date")


@pytest.mark.parametrize("tag", ["a b", ".hidden", "-x"])
def test_run_folder_that_is_not_a_plain_name_is_refused(tmp_path, tag):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    archive = plan_archive(os.path.join(tmp, "plan.tgz"), [(tag, summary(64, 0.02))])
    _refused(tmp, archive, "run folder")


@pytest.mark.parametrize("mode", [0o4755, 0o2755, 0o1777], ids=oct)
def test_member_with_special_mode_bits_is_refused(tmp_path, mode):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    archive = plan_archive(os.path.join(tmp, "plan.tgz"), [("cuda-hardwall-64", summary(64, 0.02))],
                           extra=[("plan/runs/cuda-hardwall-64/tool", "#!/bin/sh\n", mode)])
    _refused(tmp, archive, "mode")


def test_copied_files_have_plain_modes(tmp_path):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    archive = plan_archive(os.path.join(tmp, "plan.tgz"), [("cuda-hardwall-64", summary(64, 0.02))],
                           extra=[("plan/runs/cuda-hardwall-64/notes", "x\n", 0o777),
                                  ("plan/runs/cuda-hardwall-64/sub/more", "y\n", 0o700)])
    r = ingest(tmp, archive)
    assert r.returncode == 0, r.stdout + r.stderr
    run = os.path.join(tmp, "scratch", "results", "gpu", "2026-01-02", "cuda-hardwall-64")
    seen = snapshot(run)
    assert {"notes", "sub", "sub/more", "summary.json"} <= set(seen)
    for name, (mode, digest) in seen.items():
        want = 0o644 if digest is not None else 0o755
        assert stat.S_IMODE(mode) == want, f"{name}: {stat.S_IMODE(mode):04o}"
