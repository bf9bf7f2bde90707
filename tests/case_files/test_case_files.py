"""python/cmc/case_files.py: a case file read with its bases as the program reads it (the C++
side: tests/test_case_bases.cpp), and the challenge cases read through their shared base."""
import glob
import os

import pytest

from cmc.case_files import MAX_BASE_DEPTH, read_case_file

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# A whole case but for its name and its surface (shared with tests/test_case_bases.cpp).
with open(os.path.join(ROOT, "tests", "data", "bases", "common.toml"), encoding="utf-8") as f:
    BASE = f.read()


def write(folder, name, text):
    path = os.path.join(folder, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def test_including_file_overrides_table_by_table(tmp_path):
    write(tmp_path, "base.toml", BASE)
    t = read_case_file(write(tmp_path, "case.toml", 'base = "base.toml"\n[grid]\nn = 32\n[loading]\nvalues = [3e-4]\n'))
    assert t["grid"] == {"n": 32, "size": 1e-3}
    assert t["material"] == {"contact_modulus": 1e6}
    assert t["loading"] == {"control": "force", "values": [3e-4]}
    assert "base" not in t


def test_nested_bases_in_other_folders_rebase_the_surface_path(tmp_path):
    write(tmp_path, "common/root.toml", BASE + '[surface]\nkind = "file"\npath = "h.txt"\n')
    write(tmp_path, "sub/middle.toml", 'base = "../common/root.toml"\n[grid]\nn = 8\n')
    t = read_case_file(write(tmp_path, "case.toml", 'base = "sub/middle.toml"\n'))
    assert t["grid"]["n"] == 8
    assert t["surface"]["path"] == "common/h.txt"


@pytest.mark.parametrize("files, start, needle", [
    ({"case.toml": 'base = "nope.toml"\n'}, "case.toml", 'case.toml: base = "nope.toml": '),
    ({"case.toml": 'base = 3\n'}, "case.toml", "base: expected the path of a base case file (a string)"),
    ({"a.toml": 'base = "b.toml"\n', "b.toml": 'base = "a.toml"\n'}, "a.toml", "a cycle of bases (a.toml -> b.toml -> a.toml)"),
    ({"base.toml": BASE, "case.toml": 'base = "base.toml"\ngrid = 3\n'}, "case.toml", "[grid]: a table in one of it"),
    ({"bad.toml": "[grid\n", "case.toml": 'base = "bad.toml"\n'}, "case.toml", "bad.toml: not valid TOML"),
])
def test_errors_name_both_files(tmp_path, files, start, needle):
    for name, text in files.items():
        write(tmp_path, name, text)
    with pytest.raises(ValueError) as e:
        read_case_file(os.path.join(tmp_path, start))
    assert needle in str(e.value)


def test_chain_deeper_than_the_limit(tmp_path):
    write(tmp_path, f"b{MAX_BASE_DEPTH}.toml", BASE)
    for k in range(MAX_BASE_DEPTH - 1, -1, -1):
        write(tmp_path, f"b{k}.toml", f'base = "b{k + 1}.toml"\n')
    assert read_case_file(write(tmp_path, "ok.toml", 'base = "b1.toml"\n'))["grid"]["n"] == 16
    with pytest.raises(ValueError, match=f"more than {MAX_BASE_DEPTH} bases deep"):
        read_case_file(write(tmp_path, "deep.toml", 'base = "b0.toml"\n'))


def test_challenge_cases_hold_the_challenge():
    cases = [f for f in glob.glob(os.path.join(ROOT, "cases", "challenge", "*.toml"))
             if not f.endswith("challenge-base.toml")]
    assert len(cases) == 7
    for f in cases:
        t = read_case_file(f)
        assert t["grid"] == {"n": 2048, "size": 1.0e-4}, f
        assert t["material"] == {"contact_modulus": 25.0e6}, f
        assert t["surface"]["seed"] == 28 and t["surface"]["hurst"] == 0.8, f
        assert t["loading"]["control"] == "mean_pressure", f
        scaled = "scaled-family" in f
        assert t["surface"]["cutoff_wavelength"] == (3.2e-6 if scaled else 0.1e-6), f
        assert len(t["loading"]["values"]) == (14 if "load-sweep" in f else 1), f
