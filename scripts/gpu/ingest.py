#!/usr/bin/python3
"""Turn the file scripts/gpu/reference_plan.py made on a GPU machine into the run store, the best
estimates and the challenge references:

    /usr/bin/python3 scripts/gpu/ingest.py PLAN.tgz [--store FILE] [--out DIR] [--results DIR] [--cmc build/cmc]

1. every run in it goes into the run store (scripts/gpu/store.py; device, date and commit from
   the file's machine.txt and build.txt);
2. its run folders (summary.json and result.h5 with the observables) are copied to
   RESULTS/gpu/<date>/<tag>/, where scripts/report.sh and scripts/challenge_reference.py find them;
3. scripts/best_estimates.py rewrites best_estimates.json beside the curves, and
   scripts/apply_best_estimates.py the curves they decide (OUT, default reference/challenge).
Defaults write into the repository; --store, --out and --results elsewhere leave it untouched.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile

from archive import Refused, check_tree, checked_component, checked_date, copy_plain, inside, safe_extract

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PY = sys.executable or "/usr/bin/python3"


def machine(folder):
    """{device, date, cores} from the plan's machine.txt."""
    out = {}
    try:
        with open(os.path.join(folder, "machine.txt")) as f:
            for line in f:
                k, _, v = line.strip().partition(" ")
                out[k] = v
    except OSError:
        pass
    return out


def run_destinations(folder, date, results):
    """(run folder in the archive, RESULTS/gpu/<date>/<run>) for each run with a summary.json; the
    date and every run's name checked as plain path components, each destination proven to lie
    inside RESULTS. Refused otherwise, before anything is written."""
    dest = inside(results, "gpu", checked_date(date))
    out = []
    for d in sorted(os.listdir(os.path.join(folder, "runs"))):
        src = os.path.join(folder, "runs", d)
        if os.path.exists(os.path.join(src, "summary.json")):
            out.append((src, inside(dest, checked_component(d, "run folder"))))
            check_tree(src)
    return out


def step(args, what):
    r = subprocess.run([PY] + args, cwd=ROOT)
    if r.returncode != 0:
        sys.exit(f"ingest: {what} failed (exit {r.returncode}): {' '.join(args)}")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plan", help="the .tgz scripts/gpu/reference_plan.py wrote")
    ap.add_argument("--store", default=os.path.join(ROOT, "reference", "challenge", "runs.json"))
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--results", default=os.path.join(ROOT, "results"))
    ap.add_argument("--cmc", default=os.path.join(ROOT, "build", "cmc"))
    ap.add_argument("--any-physics", action="store_true", help="scripts/best_estimates.py --any-physics (tests)")
    a = ap.parse_args(argv)
    if not os.path.isfile(a.plan):
        print(f"ingest: {a.plan}: no such file (expected the .tgz of scripts/gpu/reference_plan.py)", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="cmc-ingest-") as tmp:
        try:
            safe_extract(a.plan, tmp)
        except (tarfile.TarError, OSError, EOFError, Refused) as e:
            print(f"ingest: {a.plan}: not a readable .tgz of plain files ({e})", file=sys.stderr)
            return 2
        folders = [os.path.join(tmp, d) for d in sorted(os.listdir(tmp)) if os.path.isdir(os.path.join(tmp, d, "runs"))]
        if len(folders) != 1:
            print(f"ingest: {a.plan}: expected one folder with runs/ inside, found {len(folders)}", file=sys.stderr)
            return 2
        folder = folders[0]
        m = machine(folder)
        if "device" not in m or "date" not in m:
            print(f"ingest: {a.plan}: no machine.txt with device and date (made by scripts/gpu/reference_plan.py)",
                  file=sys.stderr)
            return 2
        try:
            copies = run_destinations(folder, m["date"], a.results)
        except Refused as e:
            print(f"ingest: {a.plan}: {e}; nothing was written", file=sys.stderr)
            return 2
        step([os.path.join(ROOT, "scripts", "gpu", "store.py"), "--device", m["device"], "--date", m["date"],
              "--origin", os.path.basename(a.plan), "--store", a.store, folder], "storing the runs")
        for src, dst in copies:
            shutil.rmtree(dst, ignore_errors=True)
            os.makedirs(os.path.dirname(dst), mode=0o755, exist_ok=True)
            copy_plain(src, dst)
        if copies:
            print(f"ingest: run folders in {os.path.dirname(copies[0][1])}")
    best = os.path.join(a.out, "best_estimates.json")
    step([os.path.join(ROOT, "scripts", "best_estimates.py"), "--store", a.store, "--out", best]
         + (["--any-physics"] if a.any_physics else []), "the best estimates")
    step([os.path.join(ROOT, "scripts", "apply_best_estimates.py"), "--best", best, "--out", a.out, "--cmc", a.cmc],
         "rewriting the references")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
