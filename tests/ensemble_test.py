#!/usr/bin/python3
"""The seed ensemble end to end at 32² (grids / 64, the spectrum cut at 6.4 um as the plan's tests
do): scripts/ensemble.py runs the hard-wall sweep and the 250 kPa runs over three seeds (28 among
them) and one held out, with a deadline that stops nothing; scripts/ensemble_store.py stores them
from the folder and from an archive of it (the same records), refuses an archive with a member
outside it, and stores no impossible run; scripts/ensemble_references.py writes the ensemble and
realisation curves of the hard wall into a scratch folder. The repository is not touched.

    /usr/bin/python3 tests/ensemble_test.py BUILD/cmc
"""
import io
import json
import os
import subprocess
import sys
import tarfile
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
PY = [sys.executable]
ENV = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"), CMC_THREADS="1")


def run(args, **kw):
    return subprocess.run(PY + args, capture_output=True, text=True, env=ENV, cwd=ROOT, **kw)


def make_ensemble(cmc, out):
    r = run([os.path.join(ROOT, "scripts", "ensemble.py"), "--out", out, "--kinds", "hardwall_load,reference_hardwall",
             "--seeds", "26-28", "--holdout", "101", "--n", "32", "--workers", "2", "--deadline", "240", "--cmc", cmc,
             "--set", "surface.cutoff_wavelength=6.4e-06"])
    return r.returncode, r.stdout + r.stderr


def hostile(path, good):
    """An archive of the ensemble plus a member that climbs out of it."""
    with tarfile.open(path, "w:gz") as t:
        t.add(good, arcname="ensemble")
        data = b"{}"
        info = tarfile.TarInfo("ensemble/../../escape/summary.json")
        info.size = len(data)
        t.addfile(info, io.BytesIO(data))


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    cmc, fails = os.path.abspath(argv[1]), []
    with tempfile.TemporaryDirectory(prefix="cmc-ensemble-") as tmp:
        ens = os.path.join(tmp, "ensemble")
        rc, out = make_ensemble(cmc, ens)
        if rc != 0:
            return print(f"FAIL: scripts/ensemble.py exited {rc}:\n{out}") or 1
        store_a, store_b = os.path.join(tmp, "a.json"), os.path.join(tmp, "b.json")
        r = run([os.path.join(ROOT, "scripts", "ensemble_store.py"), ens, "--store", store_a, "--device", "test CPU",
                 "--date", "2026-01-01"])
        tgz = os.path.join(tmp, "ensemble.tgz")
        with tarfile.open(tgz, "w:gz") as t:
            t.add(ens, arcname="ensemble")
        r2 = run([os.path.join(ROOT, "scripts", "ensemble_store.py"), tgz, "--store", store_b, "--device", "test CPU",
                  "--date", "2026-01-01", "--origin", "ensemble"])
        if r.returncode or r2.returncode:
            return print(f"FAIL: ensemble_store.py: {r.stderr}{r2.stderr}") or 1
        a = [dict(x, origin=None) for x in json.load(open(store_a))["records"]]
        b = [dict(x, origin=None) for x in json.load(open(store_b))["records"]]
        if len(a) != 7 or a != b:
            fails.append(f"the folder gave {len(a)} records (expected 4 sweeps and 3 runs at 250 kPa), the archive "
                         f"{len(b)}, or they differ")
        bad = os.path.join(tmp, "bad.tgz")
        hostile(bad, ens)
        r = run([os.path.join(ROOT, "scripts", "ensemble_store.py"), bad, "--store", os.path.join(tmp, "c.json")])
        if r.returncode != 2 or os.path.exists(os.path.join(tmp, "c.json")) or os.path.exists(os.path.join(ROOT, "escape")):
            fails.append(f"an archive with a member outside it: exit {r.returncode} (expected 2, nothing stored):\n{r.stderr}")
        refs = os.path.join(tmp, "refs")
        r = run([os.path.join(ROOT, "scripts", "ensemble_references.py"), "--store", store_a, "--out", refs,
                 "--seeds", "26-28", "--cmc", cmc])
        if r.returncode != 0:
            fails.append(f"ensemble_references.py exited {r.returncode}:\n{r.stdout}{r.stderr}")
        elif not os.path.isfile(os.path.join(refs, "ensemble", "summary.json")):
            fails.append("ensemble_references.py wrote no summary.json")
    for f in fails:
        print("FAIL: " + f)
    print("ensemble_test: " + ("ok" if not fails else f"{len(fails)} failure(s)"))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
