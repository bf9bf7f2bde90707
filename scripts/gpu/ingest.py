#!/usr/bin/python3
"""Turn the file scripts/gpu/reference_plan.py made on a GPU machine into the run store, the best
estimates and the challenge references:

    /usr/bin/python3 scripts/gpu/ingest.py PLAN.tgz [--store FILE] [--out DIR] [--results DIR] [--cmc build/cmc]
        [--replace] [--accept-outlier]

1. every run in it goes into the run store (scripts/gpu/store.py; device, date and commit from
   the file's machine.txt and build.txt): a converged run with an impossible value or out of
   force balance stops the ingest (exit 2); one not converged is listed and left out;
2. its run folders (summary.json and result.h5 with the observables) are copied to
   RESULTS/gpu/<date>/<tag>/, where scripts/report.sh and scripts/challenge_reference.py find them;
3. scripts/best_estimates.py rewrites best_estimates.json beside the curves, and
   scripts/apply_best_estimates.py the curves they decide (OUT, default reference/challenge).

The archive is untrusted input (scripts/gpu/archive.py): its names, modes, size and numbers are
checked before anything is written. All or nothing: the new store, best estimates, curves and run
folders are made in a scratch folder and checked; only then do they replace the old ones, by
renames. Any failure leaves every file as it was; the same archive twice gives the same bytes.
A stored tag or run folder holding something else is replaced only with --replace. A best
estimate from a new, finer grid that lies outside the previous estimate's band by more than
three band widths (python/cmc/analysis/plausibility.py) is adopted only with --accept-outlier.
Defaults write into the repository; --store, --out and --results elsewhere leave it untouched.
Exit codes: 0 done, 2 the archive or an argument refused (nothing written), 1 a step failed
(nothing written).
"""
import argparse
import filecmp
import json
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
import zlib

from archive import (FILE_MODE, Refused, check_tree, checked_component, checked_date, checked_device, copy_plain,
                     inside, safe_extract)

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
from cmc.analysis import plausibility, runs  # noqa: E402

PY = sys.executable or "/usr/bin/python3"


class StepFailed(Exception):
    """A step of the ingest failed; `code` is the exit code to give."""

    def __init__(self, message, code=1):
        super().__init__(message)
        self.code = code


def machine(folder):
    """{device, date, ...} from the plan's machine.txt; Refused where it is missing or unreadable,
    or where its device or date is not what reference_plan.py writes."""
    out = {}
    try:
        with open(os.path.join(folder, "machine.txt"), encoding="utf-8") as f:
            for line in f:
                k, _, v = line.strip().partition(" ")
                out[k] = v
    except (OSError, ValueError) as e:
        raise Refused(f"no readable machine.txt ({e})") from None
    if "device" not in out or "date" not in out:
        raise Refused("no machine.txt with device and date (made by scripts/gpu/reference_plan.py)")
    checked_device(out["device"])
    checked_date(out["date"])
    return out


def plan_folder(tmp):
    """The extracted plan's folder: the one folder with runs/ inside (or the archive's top)."""
    if os.path.isdir(os.path.join(tmp, "runs")):
        return tmp
    folders = [os.path.join(tmp, d) for d in sorted(os.listdir(tmp)) if os.path.isdir(os.path.join(tmp, d, "runs"))]
    if len(folders) != 1:
        raise Refused(f"expected one folder with runs/ inside, found {len(folders)}")
    return folders[0]


def run_destinations(folder, date, results):
    """(run folder in the archive, RESULTS/gpu/<date>/<run>) for each run with a summary.json; the
    date and every run's name checked as plain path components, each destination proven to lie
    inside RESULTS. Refused otherwise, before anything is written."""
    dest = inside(results, "gpu", checked_date(date))
    out = []
    for d in sorted(os.listdir(os.path.join(folder, "runs"))):
        src = os.path.join(folder, "runs", d)
        if os.path.isfile(os.path.join(src, "summary.json")):
            out.append((src, inside(dest, checked_component(d, "run folder"))))
            check_tree(src)
    return out


def step(args, what):
    """Run one of the scripts; StepFailed (its exit code where it refused its input: 2) if it fails."""
    r = subprocess.run([PY] + args, cwd=ROOT)
    if r.returncode != 0:
        raise StepFailed(f"{what} failed (exit {r.returncode}): {' '.join(args)}", 2 if r.returncode == 2 else 1)


def same_tree(a, b):
    """Whether folders a and b hold the same names and bytes."""
    c = filecmp.dircmp(a, b)
    if c.left_only or c.right_only or c.funny_files or c.common_funny:
        return False
    if any(not filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False) for f in c.common_files):
        return False
    return all(same_tree(os.path.join(a, d), os.path.join(b, d)) for d in c.common_dirs)


def stage_store(a, m, folder, stage):
    """The new run store, made in stage/ from the old one and the plan's runs."""
    store = os.path.join(stage, "runs.json")
    if os.path.exists(a.store):
        shutil.copyfile(a.store, store)
    step([os.path.join(ROOT, "scripts", "gpu", "store.py"), "--device", m["device"], "--date", m["date"],
          "--origin", os.path.basename(a.plan), "--store", store, folder] + (["--replace"] if a.replace else []),
         "storing the runs")
    return store


def stage_references(a, store, stage):
    """The new best estimates and curves, made in a copy of OUT inside stage/; returns the copy."""
    out = os.path.join(stage, "out")
    if os.path.isdir(a.out):
        shutil.copytree(a.out, out, symlinks=True)
    else:
        os.makedirs(out)
    best = os.path.join(out, "best_estimates.json")
    step([os.path.join(ROOT, "scripts", "best_estimates.py"), "--store", store, "--out", best]
         + (["--any-physics"] if a.any_physics else []), "the best estimates")
    with open(best) as f:  # name the store the file will sit beside, not the scratch copy
        data = json.load(f)
    data["run_store"] = os.path.relpath(a.store, ROOT)
    with open(best, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")
    check_outliers(a, data, added_records(a.store, store))
    step([os.path.join(ROOT, "scripts", "apply_best_estimates.py"), "--best", best, "--out", out, "--cmc", a.cmc],
         "rewriting the references")
    return out


def added_records(old_store, new_store):
    """The records of new_store that old_store does not hold as they are (new or replaced tags)."""
    old = {json.dumps(r, sort_keys=True) for r in runs.load_store(old_store)} if os.path.exists(old_store) else set()
    return [r for r in runs.load_store(new_store) if json.dumps(r, sort_keys=True) not in old]


def check_outliers(a, new, records=()):
    """StepFailed (2) where a new finer grid's estimate, or a run this ingest adds on a finer grid,
    lies far outside the previous band, unless --accept-outlier; the adopted ones are named either
    way."""
    try:
        with open(os.path.join(a.out, "best_estimates.json")) as f:
            old = json.load(f)
    except (OSError, ValueError):
        return
    found = plausibility.outliers(old if isinstance(old, dict) else {}, new, records=records)
    lines = []
    for point, short, o, e in found:
        qo, qn = o["quantities"][short], e["quantities"][short]
        lines.append(f"{point}: {short} {qn['value']:.6g} from {e['run']} ({e['n']}^2) lies outside the previous "
                     f"band {qo['value']:.6g} +- {qo['error']:.2g} ({o['run']}, {o['n']}^2) by more than "
                     f"{plausibility.OUTLIER_WIDTHS:g} band widths")
    for line in lines:
        print(f"ingest: {'adopted outlier' if a.accept_outlier else 'outlier'}: {line}", file=sys.stderr)
    if lines and not a.accept_outlier:
        raise StepFailed("a new finer grid disagrees with the previous best estimate: check its runs, then ingest "
                         "again with --accept-outlier to adopt it", 2)


def changed_files(staged, target, skip):
    """(staged file, target file) for every file under `staged` whose bytes differ from the one at
    the same place under `target` (or that is new there); `skip`: target paths left out."""
    out = []
    for d, _, files in os.walk(staged):
        for f in sorted(files):
            src = os.path.join(d, f)
            dst = os.path.join(target, os.path.relpath(src, staged))
            if os.path.abspath(dst) not in skip and not (os.path.isfile(dst) and filecmp.cmp(src, dst, shallow=False)):
                out.append((src, dst))
    return sorted(out)


def folder_moves(copies, replace):
    """The run folders to put in place: (archive folder, destination) for those new or changed;
    Refused where a destination holds something else and --replace was not given."""
    out = []
    for src, dst in copies:
        if not os.path.lexists(dst):
            out.append((src, dst))
        elif os.path.isdir(dst) and not os.path.islink(dst) and same_tree(src, dst):
            continue
        elif not replace:
            raise Refused(f"{dst} holds another run: give --replace to replace it")
        else:
            out.append((src, dst))
    return out


def prepare(files, folders):
    """Copy every new file and run folder beside its target (same file system, hidden name), so
    that the last step is only renames; returns [(prepared, target)]. On failure removes what it
    made and raises."""
    made = []
    try:
        for src, dst in files:
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            tmp = os.path.join(os.path.dirname(dst), f".{os.path.basename(dst)}.ingest-new")
            shutil.copyfile(src, tmp)
            os.chmod(tmp, FILE_MODE)
            made.append((tmp, dst))
        for src, dst in folders:
            os.makedirs(os.path.dirname(dst), mode=0o755, exist_ok=True)
            tmp = os.path.join(os.path.dirname(dst), f".{os.path.basename(dst)}.ingest-new")
            shutil.rmtree(tmp, ignore_errors=True)
            made.append((tmp, dst))
            copy_plain(src, tmp)
    except BaseException:
        for tmp, _ in made:
            if os.path.isdir(tmp):
                shutil.rmtree(tmp, ignore_errors=True)
            elif os.path.exists(tmp):
                os.remove(tmp)
        raise
    return made


def put_in_place(made):
    """Rename each prepared file or folder onto its target (an old folder goes aside first)."""
    for tmp, dst in made:
        if os.path.isdir(tmp) and os.path.lexists(dst):
            old = os.path.join(os.path.dirname(dst), f".{os.path.basename(dst)}.ingest-old")
            shutil.rmtree(old, ignore_errors=True)
            os.replace(dst, old)
            os.replace(tmp, dst)
            shutil.rmtree(old)
        else:
            os.replace(tmp, dst)


def ingest(a, tmp):
    """Extract, check, stage and put in place; returns what changed, for the report."""
    extracted = os.path.join(tmp, "plan")
    os.makedirs(extracted)
    try:
        safe_extract(a.plan, extracted)
    except (tarfile.TarError, OSError, EOFError, zlib.error) as e:
        raise Refused(f"not a readable .tgz ({type(e).__name__}: {e})") from None
    folder = plan_folder(extracted)
    m = machine(folder)
    copies = run_destinations(folder, m["date"], a.results)
    moves = folder_moves(copies, a.replace)
    stage = os.path.join(tmp, "stage")
    os.makedirs(stage)
    store = stage_store(a, m, folder, stage)
    out = stage_references(a, store, stage)
    files = changed_files(out, a.out, {os.path.abspath(a.store)})
    if not (os.path.isfile(a.store) and filecmp.cmp(store, a.store, shallow=False)):
        files.append((store, a.store))
    put_in_place(prepare(files, moves))
    return [dst for _, dst in files], [dst for _, dst in moves]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plan", help="the .tgz scripts/gpu/reference_plan.py wrote")
    ap.add_argument("--store", default=os.path.join(ROOT, "reference", "challenge", "runs.json"))
    ap.add_argument("--out", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--results", default=os.path.join(ROOT, "results"))
    ap.add_argument("--cmc", default=os.path.join(ROOT, "build", "cmc"))
    ap.add_argument("--any-physics", action="store_true", help="scripts/best_estimates.py --any-physics (tests)")
    ap.add_argument("--replace", action="store_true", help="replace stored runs and run folders of the same tags")
    ap.add_argument("--accept-outlier", action="store_true",
                    help="adopt a finer grid's estimate far outside the previous band (it is named)")
    a = ap.parse_args(argv)
    if not os.path.isfile(a.plan):
        print(f"ingest: {a.plan}: no such file (expected the .tgz of scripts/gpu/reference_plan.py)", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="cmc-ingest-") as tmp:
        try:
            files, folders = ingest(a, tmp)
        except Refused as e:
            print(f"ingest: {a.plan}: {e}; nothing was written", file=sys.stderr)
            return 2
        except StepFailed as e:
            print(f"ingest: {e}; nothing was written", file=sys.stderr)
            return e.code
    for path in files:
        print(f"ingest: wrote {os.path.relpath(path, ROOT)}")
    for path in folders:
        print(f"ingest: run folder {os.path.relpath(path, ROOT)}")
    if not files and not folders:
        print("ingest: every run of the archive was already in place; nothing changed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
