"""scripts/gpu/store.py and scripts/best_estimates.py against runs no machine could have made:
impossible values, runs out of balance or not converged, malformed files, a stored tag given
again. Each refusal exits 2 with a message and leaves the store as it was."""
import json
import os
import shutil
import subprocess
import sys

import pytest

from hostile import ROOT, summary

STORE_PY = os.path.join(ROOT, "scripts", "gpu", "store.py")
BEST_PY = os.path.join(ROOT, "scripts", "best_estimates.py")
REAL_STORE = os.path.join(ROOT, "reference", "challenge", "runs.json")


def check_folder(tmp, runs):
    """A check.sh --out folder holding the runs [(tag, summary or raw text)]."""
    out = os.path.join(tmp, "check")
    for tag, s in runs:
        os.makedirs(os.path.join(out, "runs", tag), exist_ok=True)
        with open(os.path.join(out, "runs", tag, "summary.json"), "w") as f:
            f.write(s if isinstance(s, str) else json.dumps(s))
        with open(os.path.join(out, tag + ".command"), "w") as f:
            f.write(f"cmc run ... ({tag})\n")
    return out


def store(tmp, out, *more, store_file=None):
    store_file = store_file or os.path.join(tmp, "runs.json")
    return subprocess.run([sys.executable, STORE_PY, "--device", "test GPU", "--date", "2026-01-02",
                           "--store", store_file, out, *more], capture_output=True, text=True)


def _refused(r, *words):
    assert r.returncode == 2, r.stdout + r.stderr
    assert "Traceback" not in r.stderr, r.stderr
    for w in words:
        assert w in r.stderr, r.stderr


def _bytes(path):
    with open(path, "rb") as f:
        return f.read()


@pytest.mark.parametrize("a_r, words", [(1.5, "outside [0, 1]"), (-0.02, "outside [0, 1]"),
                                        (float("nan"), "not finite"), (float("inf"), "not finite")])
def test_impossible_contact_fraction_is_refused(tmp_path, a_r, words):
    tmp = str(tmp_path)
    shutil.copyfile(REAL_STORE, os.path.join(tmp, "runs.json"))
    before = _bytes(os.path.join(tmp, "runs.json"))
    out = check_folder(tmp, [("cuda-hardwall-32768", summary(32768, a_r))])
    _refused(store(tmp, out), "cuda-hardwall-32768", words)
    assert _bytes(os.path.join(tmp, "runs.json")) == before


def test_negative_mean_gap_under_a_hard_wall_is_refused(tmp_path):
    out = check_folder(str(tmp_path), [("cuda-hardwall-64", summary(64, mean_gap=-1e-7))])
    _refused(store(str(tmp_path), out), "negative under a hard wall")
    assert not os.path.exists(os.path.join(str(tmp_path), "runs.json"))


def test_run_out_of_force_balance_is_refused(tmp_path):
    off = summary(64)
    off["steps"][0]["mean_pressure"] = 200e3  # the load asked for is 250 kPa
    off["steps"][0]["force"] = 200e3 * 1e-8
    wrong_force = summary(128)
    wrong_force["steps"][0]["force"] *= 1.01
    for tag, s, words in (("cuda-hardwall-64", off, "the load asked for"),
                          ("cuda-hardwall-128", wrong_force, "times the area")):
        out = check_folder(os.path.join(str(tmp_path), tag), [(tag, s)])
        _refused(store(str(tmp_path), out), words)
    assert not os.path.exists(os.path.join(str(tmp_path), "runs.json"))


def test_tag_that_is_not_the_runs_grid_is_refused(tmp_path):
    out = check_folder(str(tmp_path), [("cuda-hardwall-32768", summary(64))])
    _refused(store(str(tmp_path), out), "not its tag's")


def test_run_not_converged_is_left_out_with_a_word(tmp_path):
    out = check_folder(str(tmp_path), [("cuda-hardwall-64", summary(64)),
                                       ("cuda-hardwall-128", summary(128, 3.0, status="not_converged"))])
    r = store(str(tmp_path), out)
    assert r.returncode == 0, r.stderr
    assert "cuda-hardwall-128: 'not_converged', not converged; not stored" in r.stderr
    recs = json.load(open(os.path.join(str(tmp_path), "runs.json")))["records"]
    assert [x["tag"] for x in recs] == ["cuda-hardwall-64"]


@pytest.mark.parametrize("text", ["{not json", "[1, 2]", "null", "\udcff"])
def test_malformed_summary_is_refused(tmp_path, text):
    out = check_folder(str(tmp_path), [("cuda-hardwall-64", text.encode("utf-8", "surrogateescape").decode("latin-1"))])
    _refused(store(str(tmp_path), out), "summary")
    assert not os.path.exists(os.path.join(str(tmp_path), "runs.json"))


def test_summary_that_is_a_folder_is_refused(tmp_path):
    out = check_folder(str(tmp_path), [])
    os.makedirs(os.path.join(out, "runs", "cuda-hardwall-64", "summary.json"))
    with open(os.path.join(out, "cuda-hardwall-64.command"), "w") as f:
        f.write("cmc run\n")
    _refused(store(str(tmp_path), out), "summary.json")


@pytest.mark.parametrize("text", ["{", "[]", '{"records": 3}', '{"records": [{"tag": 1}]}'])
def test_malformed_store_is_refused(tmp_path, text):
    path = os.path.join(str(tmp_path), "runs.json")
    with open(path, "w") as f:
        f.write(text)
    out = check_folder(str(tmp_path), [("cuda-hardwall-64", summary(64))])
    _refused(store(str(tmp_path), out), "runs.json")
    assert open(path).read() == text
    r = subprocess.run([sys.executable, BEST_PY, "--store", path, "--out", os.path.join(str(tmp_path), "b.json")],
                       capture_output=True, text=True)
    _refused(r, "runs.json")


def test_stored_tag_is_replaced_only_with_replace(tmp_path):
    tmp = str(tmp_path)
    first = check_folder(os.path.join(tmp, "a"), [("cuda-hardwall-64", summary(64, 0.0204))])
    assert store(tmp, first).returncode == 0
    before = _bytes(os.path.join(tmp, "runs.json"))
    assert store(tmp, first).returncode == 0, "the same run again is no replacement"
    assert _bytes(os.path.join(tmp, "runs.json")) == before
    second = check_folder(os.path.join(tmp, "b"), [("cuda-hardwall-64", summary(64, 0.0206))])
    _refused(store(tmp, second), "--replace", "cuda-hardwall-64")
    assert _bytes(os.path.join(tmp, "runs.json")) == before
    r = store(tmp, second, "--replace")
    assert r.returncode == 0 and "replacing cuda-hardwall-64" in r.stderr, r.stderr
    assert json.load(open(os.path.join(tmp, "runs.json")))["records"][0]["a_r"] == 0.0206


@pytest.mark.parametrize("a_r", [-0.02, 1.7])
def test_best_estimates_refuses_a_store_with_impossible_values(tmp_path, a_r):
    recs = json.load(open(REAL_STORE))
    bad = dict(next(r for r in recs["records"] if r["tag"] == "cuda-hardwall-16384"), tag="cuda-hardwall-32768",
               n=32768, a_r=a_r)
    recs["records"].append(bad)
    path = os.path.join(str(tmp_path), "runs.json")
    json.dump(recs, open(path, "w"))
    out = os.path.join(str(tmp_path), "best.json")
    r = subprocess.run([sys.executable, BEST_PY, "--store", path, "--out", out], capture_output=True, text=True)
    _refused(r, "cuda-hardwall-32768", "outside [0, 1]")
    assert not os.path.exists(out)


def test_best_estimates_with_a_hard_wall_contact_fraction_of_zero(tmp_path):
    """The ratio of the two a_r has no value when the hard wall's is 0: no ZeroDivisionError."""
    recs = json.load(open(REAL_STORE))
    for r in recs["records"]:
        if r["kind"] == "hardwall":
            r["a_r"] = r["a_rep"] = 0.0
    path = os.path.join(str(tmp_path), "runs.json")
    json.dump(recs, open(path, "w"))
    out = os.path.join(str(tmp_path), "best.json")
    r = subprocess.run([sys.executable, BEST_PY, "--store", path, "--out", out], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    best = json.load(open(out))["reference_load"]
    assert best["hardwall"]["quantities"]["a_r"]["value"] == 0.0
    assert best["ratio"] is None
