"""scripts/gpu/ingest.py is all or nothing and trusts no number it was not shown to be able to
trust: against a scratch copy of the repository's references and run store, an archive with an
impossible run, a new finest grid far outside the previous band, a corrupt file or a step that
fails changes no file; a good archive ingested twice gives the same bytes."""
import gzip
import io
import json
import os
import shutil
import stat
import subprocess
import sys
import tarfile

import pytest

from hostile import A_R, CMC, ROOT, ingest, member, plan_archive, scratch_repo, snapshot, summary

TAG = "cuda-hardwall-32768"


def _unchanged(tmp, r, code, *words, before):
    assert r.returncode == code, r.stdout + r.stderr
    assert "Traceback" not in r.stderr, r.stderr
    for w in words:
        assert w in r.stderr, r.stderr
    assert snapshot(tmp) == before, "ingest changed files though it failed"


def _archive(tmp, *runs, name="plan.tgz", **kw):
    return plan_archive(os.path.join(tmp, name), list(runs) or [(TAG, summary(32768))], **kw)


@pytest.mark.parametrize("a_r, code, words", [(1.5, 2, "outside [0, 1]"), (float("nan"), 2, "not finite"),
                                              (0.5, 2, "outlier"), (0.03, 2, "outlier")])
def test_implausible_run_changes_nothing(tmp_path, a_r, code, words):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    archive = _archive(tmp, (TAG, summary(32768, a_r)))
    before = snapshot(tmp)
    _unchanged(tmp, ingest(tmp, archive), code, words, before=before)


def test_outlier_is_adopted_with_accept_outlier_and_named(tmp_path):
    # Adopted into the store and named; whether it becomes the estimate is the rules' choice: its
    # own sequence's error (a jump of 46 % from 16384²) is far larger than the 8192² sweep's.
    tmp = str(tmp_path)
    ref = scratch_repo(tmp)
    r = ingest(tmp, _archive(tmp, (TAG, summary(32768, 0.03))), "--accept-outlier")
    assert r.returncode == 0, r.stdout + r.stderr
    assert f"adopted outlier: 250 kPa, hardwall: a_r 0.03 from {TAG}" in r.stderr
    assert TAG in {x["tag"] for x in json.load(open(os.path.join(ref, "runs.json")))["records"]}


def test_failing_later_step_changes_nothing(tmp_path):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    failing = os.path.join(tmp, "failing-cmc")
    with open(failing, "w") as f:
        f.write("#!/bin/sh\necho 'cmc: refused' >&2\nexit 1\n")
    os.chmod(failing, stat.S_IRWXU)
    archive = _archive(tmp)
    before = snapshot(tmp)
    s = os.path.join(tmp, "scratch")
    r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "gpu", "ingest.py"), archive,
                        "--store", os.path.join(s, "ref", "runs.json"), "--out", os.path.join(s, "ref"),
                        "--results", os.path.join(s, "results"), "--cmc", failing], capture_output=True, text=True)
    _unchanged(tmp, r, 1, "rewriting the references failed", "nothing was written", before=before)


def test_same_archive_twice_gives_the_same_bytes(tmp_path):
    tmp = str(tmp_path)
    ref = scratch_repo(tmp)
    archive = _archive(tmp)
    r = ingest(tmp, archive)
    assert r.returncode == 0, r.stdout + r.stderr
    best = json.load(open(os.path.join(ref, "best_estimates.json")))
    assert best["reference_load"]["hardwall"]["run"] == TAG
    assert best["run_store"] == os.path.relpath(os.path.join(ref, "runs.json"), ROOT)
    text = open(os.path.join(ref, "adhesionless", "contact_area_vs_pressure.csv")).read()
    assert TAG in text
    header = next(line for line in text.splitlines() if line.startswith("# estimated_error:"))
    assert header.count("the other rows: ") <= 1, header  # once at most, however often applied
    once = snapshot(tmp)
    r = ingest(tmp, archive)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "nothing changed" in r.stdout
    assert snapshot(tmp) == once


def test_stored_tag_and_run_folder_are_replaced_only_with_replace(tmp_path):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    assert ingest(tmp, _archive(tmp)).returncode == 0
    other = _archive(tmp, (TAG, summary(32768, A_R * (1 + 1e-4))), name="other.tgz")
    before = snapshot(tmp)
    _unchanged(tmp, ingest(tmp, other), 2, "--replace", before=before)
    r = ingest(tmp, other, "--replace")
    assert r.returncode == 0, r.stdout + r.stderr
    stored = json.load(open(os.path.join(tmp, "scratch", "ref", "runs.json")))["records"]
    assert next(x for x in stored if x["tag"] == TAG)["a_r"] == A_R * (1 + 1e-4)


def _refused_beside(tmp, path, text, words):
    """A good archive refused because of what the scratch folder holds: `text` written to `path`."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    archive = _archive(tmp)
    before = snapshot(tmp)
    _unchanged(tmp, ingest(tmp, archive), 2, words, before=before)


def test_run_folder_holding_something_else_needs_replace(tmp_path):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    mine = os.path.join(tmp, "scratch", "results", "gpu", "2026-01-02", TAG, "notes.txt")
    _refused_beside(tmp, mine, "the user's\n", "--replace")


def _truncated(tmp):
    data = open(_archive(tmp), "rb").read()
    return data[: len(data) // 2]


def _raw_archive(tmp, members):
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w:gz") as t:
        for name, data in members:
            member(t, name, data, kind=tarfile.DIRTYPE if data is None else tarfile.REGTYPE)
    return buf.getvalue()


CORRUPT = {
    "truncated gzip": _truncated,
    "not an archive": lambda tmp: b"just some text\n",
    "gzip of no tar": lambda tmp: gzip.compress(b"x" * 1000),
    "summary is a folder": lambda tmp: _raw_archive(tmp, [("plan/machine.txt", "device d\ndate 2026-01-02\n"),
                                                          (f"plan/runs/{TAG}/summary.json/", None),
                                                          (f"plan/{TAG}.command", "cmc run\n")]),
    "summary is a list": lambda tmp: _raw_archive(tmp, [("plan/machine.txt", "device d\ndate 2026-01-02\n"),
                                                        (f"plan/runs/{TAG}/summary.json", "[1, 2]"),
                                                        (f"plan/{TAG}.command", "cmc run\n")]),
    "summary is bad JSON": lambda tmp: _raw_archive(tmp, [("plan/machine.txt", "device d\ndate 2026-01-02\n"),
                                                          (f"plan/runs/{TAG}/summary.json", "{oops"),
                                                          (f"plan/{TAG}.command", "cmc run\n")]),
    "machine.txt not text": lambda tmp: _raw_archive(tmp, [("plan/machine.txt", b"device \xff\xfe\ndate x\n"),
                                                           (f"plan/runs/{TAG}/summary.json", "{}")]),
    "device on two lines": lambda tmp: _raw_archive(tmp, [("plan/machine.txt", "device \x1b[31mred\ndate 2026-01-02\n"),
                                                          (f"plan/runs/{TAG}/summary.json", "{}")]),
    "too many members": lambda tmp: _raw_archive(tmp, [("plan/machine.txt", "device d\ndate 2026-01-02\n")]
                                                 + [(f"plan/runs/x/f{i}", "") for i in range(2001)]),
}


@pytest.mark.parametrize("kind", sorted(CORRUPT))
def test_corrupt_archive_is_refused(tmp_path, kind):
    tmp = str(tmp_path)
    scratch_repo(tmp)
    path = os.path.join(tmp, "corrupt.tgz")
    with open(path, "wb") as f:
        f.write(CORRUPT[kind](tmp))
    before = snapshot(tmp)
    _unchanged(tmp, ingest(tmp, path), 2, "nothing was written", before=before)


def test_malformed_run_store_is_refused(tmp_path):
    tmp = str(tmp_path)
    ref = scratch_repo(tmp)
    _refused_beside(tmp, os.path.join(ref, "runs.json"), '{"records": {"tag": 1}}', "runs.json")


def test_archive_written_from_inside_its_folder_is_read(tmp_path):
    """`tar czf plan.tgz -C folder .` names its members ./..., the first one './'."""
    tmp = str(tmp_path)
    scratch_repo(tmp)
    path = os.path.join(tmp, "dot.tgz")
    with tarfile.open(path, "w:gz") as t:
        member(t, "./", kind=tarfile.DIRTYPE)
        member(t, "./machine.txt", "device d\ndate 2026-01-02\n")
        member(t, f"./runs/{TAG}/summary.json", json.dumps(summary(32768)))
        member(t, f"./{TAG}.command", "cmc run\n")
    r = ingest(tmp, path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert os.path.isfile(os.path.join(tmp, "scratch", "results", "gpu", "2026-01-02", TAG, "summary.json"))


HOSTILE = {"absolute date": {"date": "/tmp"}, "date up the tree": {"date": "../../.."},
           "setuid member": {"extra": [(f"plan/runs/{TAG}/tool", "#!/bin/sh\n", 0o4755)]},
           "impossible a_r": {"runs": [(TAG, summary(32768, 1.5))]}, "failing later step": {"cmc": "/bin/false"}}


@pytest.mark.parametrize("kind", sorted(HOSTILE))
def test_hostile_archive_leaves_the_repository_clean(tmp_path, kind):
    """With its defaults ingest writes into the repository: here a mirror of it, a git checkout
    of the files ingest reads and writes, whose `git status` must stay clean."""
    tmp = str(tmp_path)
    repo = os.path.join(tmp, "repo")
    for part in ("scripts", "python", "reference", "reports", "cases"):
        shutil.copytree(os.path.join(ROOT, part), os.path.join(repo, part), ignore=shutil.ignore_patterns("__pycache__"))
    git = ["git", "-C", repo, "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run(git + ["init", "-q"], check=True)
    subprocess.run(git + ["add", "-A"], check=True)
    subprocess.run(git + ["commit", "-q", "-m", "mirror"], check=True)
    spec = dict(HOSTILE[kind])
    runs = spec.pop("runs", [(TAG, summary(32768))])
    cmc = spec.pop("cmc", CMC)
    archive = plan_archive(os.path.join(tmp, "plan.tgz"), runs, **spec)
    r = subprocess.run([sys.executable, os.path.join(repo, "scripts", "gpu", "ingest.py"), archive, "--cmc", cmc],
                       capture_output=True, text=True, cwd=repo)
    assert r.returncode != 0 and "Traceback" not in r.stderr, r.stdout + r.stderr
    status = subprocess.run(git + ["status", "--porcelain", "--ignored"], capture_output=True, text=True).stdout
    assert status == "", status
