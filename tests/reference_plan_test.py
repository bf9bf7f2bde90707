#!/usr/bin/python3
"""The GPU reference plan end to end on the CPU backend at grids divided by 64: runs
(scripts/gpu/reference_plan.py --scale 64 --cpu), pack, store and references rebuilt into a
scratch folder (scripts/gpu/ingest.py), the repository's references untouched.

    /usr/bin/python3 tests/reference_plan_test.py BUILD/cmc
"""
import hashlib
import json
import os
import subprocess
import sys
import tarfile
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))


def digest(folder):
    h = hashlib.sha256()
    for d, _, files in sorted(os.walk(folder)):
        for f in sorted(files):
            with open(os.path.join(d, f), "rb") as fh:
                h.update(f.encode() + fh.read())
    return h.hexdigest()


def main(argv):
    if len(argv) != 2 or not os.access(argv[1], os.X_OK):
        print("usage: reference_plan_test.py BUILD/cmc", file=sys.stderr)
        return 2
    cmc = os.path.abspath(argv[1])
    before = digest(os.path.join(ROOT, "reference", "challenge"))
    fails = []
    with tempfile.TemporaryDirectory(prefix="cmc-plan-") as tmp:
        pack = os.path.join(tmp, "pack")
        os.makedirs(os.path.join(pack, "bin"))
        os.symlink(cmc, os.path.join(pack, "bin", "cmc"))
        open(os.path.join(pack, "env.sh"), "w").close()
        with open(os.path.join(pack, "build.txt"), "w") as f:
            f.write("commit 0123456789ab\n")
        tgz = os.path.join(tmp, "plan.tgz")
        env = dict(os.environ, CMC_THREADS="1")
        r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "gpu", "reference_plan.py"), "--scale", "64",
                            "--cpu", "--deadline", "400", "--keep-all", "--pack", pack, "--work", os.path.join(tmp, "work"),
                            "--tar", tgz], capture_output=True, text=True, env=env, cwd=ROOT)
        out = r.stdout + r.stderr
        if r.returncode != 0 or not os.path.isfile(tgz):
            return print(f"FAIL: reference_plan.py exited {r.returncode}:\n{out}") or 1
        if "estimate" not in out.splitlines()[0] or "no summary" in out or "dropped" in out:
            fails.append("the plan did not print its estimates, dropped a stage or left a run without its summary:\n" + out)
        if os.path.getsize(tgz) > 16 * 2 ** 20:
            fails.append(f"the pack is {os.path.getsize(tgz)} bytes, more than 16 MiB")
        with tarfile.open(tgz) as t:
            names = t.getnames()
        if not any(n.endswith("machine.txt") for n in names) or not any(n.endswith("result.h5") for n in names):
            fails.append("the pack lacks machine.txt or the runs' result.h5 (observables)")
        scratch = os.path.join(tmp, "scratch")
        os.makedirs(scratch)
        subprocess.run(["cp", "-r", os.path.join(ROOT, "reference", "challenge"), os.path.join(scratch, "ref")], check=True)
        store = os.path.join(scratch, "runs.json")
        r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "gpu", "ingest.py"), tgz, "--store", store,
                            "--out", os.path.join(scratch, "ref"), "--results", os.path.join(scratch, "results"),
                            "--cmc", cmc, "--any-physics"], capture_output=True, text=True, cwd=ROOT)
        if r.returncode != 0:
            return print(f"FAIL: ingest.py exited {r.returncode}:\n{r.stdout}{r.stderr}") or 1
        recs = json.load(open(store))["records"]
        if len(recs) < 15 or any(x["commit"] != "0123456789ab" or x["device"] != "host CPU of the GPU machine" for x in recs):
            fails.append(f"the store holds {len(recs)} records, or records without the pack's commit and device")
        best = json.load(open(os.path.join(scratch, "ref", "best_estimates.json")))
        hw = best["reference_load"]["hardwall"]
        if not hw or not hw["run"].startswith("cpu-hardwall"):
            fails.append(f"the scaled hard-wall runs made no best estimate at 250 kPa: {hw}")
        text = open(os.path.join(scratch, "ref", "adhesionless", "contact_area_vs_pressure.csv")).read()
        if "# best_estimate: every row is the best estimate at its load" not in text:
            fails.append("adhesionless/contact_area_vs_pressure.csv was not rebuilt from the best estimates")
    if digest(os.path.join(ROOT, "reference", "challenge")) != before:
        fails.append("reference/challenge/ of the repository changed")
    if fails:
        print("FAIL: " + "\nFAIL: ".join(fails))
        return 1
    print("reference_plan_test: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
