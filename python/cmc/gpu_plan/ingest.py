"""The command scripts/gpu/ingest.py: the archive the GPU reference plan made (cmc.gpu_plan.plan),
read as untrusted input (cmc.gpu_plan.archive), turned into the run store, the best estimates,
the challenge references and the run folders under RESULTS/gpu/<date>/, all or nothing: made in
a scratch folder and checked, then put in place by renames."""
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
from collections.abc import Sequence
from typing import Any

from ..analysis import plausibility, runs
from .archive import (FILE_MODE, Refused, check_tree, checked_component, checked_date, checked_device, copy_plain,
                      inside, safe_extract)

Record = dict[str, Any]  # a run store's record, or best_estimates.json
PY = sys.executable or "/usr/bin/python3"


class StepFailed(Exception):
    """A step of the ingest failed; `code` is the exit code to give."""

    def __init__(self, message: str, code: int = 1) -> None:
        super().__init__(message)
        self.code = code


def machine(folder: str) -> dict[str, str]:
    """{device, date, ...} from the plan's machine.txt; Refused where it is missing or unreadable,
    or where its device or date is not what reference_plan.py writes."""
    out: dict[str, str] = {}
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


def plan_folder(tmp: str) -> str:
    """The extracted plan's folder: the one folder with runs/ inside (or the archive's top)."""
    if os.path.isdir(os.path.join(tmp, "runs")):
        return tmp
    folders = [os.path.join(tmp, d) for d in sorted(os.listdir(tmp)) if os.path.isdir(os.path.join(tmp, d, "runs"))]
    if len(folders) != 1:
        raise Refused(f"expected one folder with runs/ inside, found {len(folders)}")
    return folders[0]


def run_destinations(folder: str, date: str, results: str) -> list[tuple[str, str]]:
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


def step(args: list[str], what: str, root: str) -> None:
    """Run one of the scripts; StepFailed (its exit code where it refused its input: 2) if it fails."""
    r = subprocess.run([PY] + args, cwd=root)
    if r.returncode != 0:
        raise StepFailed(f"{what} failed (exit {r.returncode}): {' '.join(args)}", 2 if r.returncode == 2 else 1)


def same_tree(a: str, b: str) -> bool:
    """Whether folders a and b hold the same names and bytes."""
    c = filecmp.dircmp(a, b)
    if c.left_only or c.right_only or c.funny_files or c.common_funny:
        return False
    if any(not filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False) for f in c.common_files):
        return False
    return all(same_tree(os.path.join(a, d), os.path.join(b, d)) for d in c.common_dirs)


def stage_store(a: argparse.Namespace, m: dict[str, str], folder: str, stage: str) -> str:
    """The new run store, made in stage/ from the old one and the plan's runs."""
    store = os.path.join(stage, "runs.json")
    if os.path.exists(a.store):
        shutil.copyfile(a.store, store)
    step([os.path.join(a.root, "scripts", "gpu", "store.py"), "--device", m["device"], "--date", m["date"],
          "--origin", os.path.basename(a.plan), "--store", store, folder] + (["--replace"] if a.replace else []),
         "storing the runs", a.root)
    return store


def stage_references(a: argparse.Namespace, store: str, stage: str) -> str:
    """The new best estimates and curves, made in a copy of OUT inside stage/; returns the copy."""
    out = os.path.join(stage, "out")
    if os.path.isdir(a.out):
        shutil.copytree(a.out, out, symlinks=True)
    else:
        os.makedirs(out)
    best = os.path.join(out, "best_estimates.json")
    step([os.path.join(a.root, "scripts", "best_estimates.py"), "--store", store, "--out", best]
         + (["--any-physics"] if a.any_physics else []), "the best estimates", a.root)
    with open(best) as f:  # name the store the file will sit beside, not the scratch copy
        data = json.load(f)
    data["run_store"] = os.path.relpath(a.store, a.root)
    with open(best, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")
    check_outliers(a, data, added_records(a.store, store))
    step([os.path.join(a.root, "scripts", "apply_best_estimates.py"), "--best", best, "--out", out, "--cmc", a.cmc],
         "rewriting the references", a.root)
    return out


def added_records(old_store: str, new_store: str) -> list[Record]:
    """The records of new_store that old_store does not hold as they are (new or replaced tags)."""
    old = {json.dumps(r, sort_keys=True) for r in runs.load_store(old_store)} if os.path.exists(old_store) else set()
    return [r for r in runs.load_store(new_store) if json.dumps(r, sort_keys=True) not in old]


def check_outliers(a: argparse.Namespace, new: Record, records: Sequence[Record] = ()) -> None:
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


def changed_files(staged: str, target: str, skip: set[str]) -> list[tuple[str, str]]:
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


def folder_moves(copies: list[tuple[str, str]], replace: bool) -> list[tuple[str, str]]:
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


def prepare(files: list[tuple[str, str]], folders: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Copy every new file and run folder beside its target (same file system, hidden name), so
    that the last step is only renames; returns [(prepared, target)]. On failure removes what it
    made and raises."""
    made: list[tuple[str, str]] = []
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


def put_in_place(made: list[tuple[str, str]]) -> None:
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


def ingest(a: argparse.Namespace, tmp: str) -> tuple[list[str], list[str]]:
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


def main(argv: Sequence[str], doc: str, root: str) -> int:
    """scripts/gpu/ingest.py with arguments argv (its usage text `doc`; `root`: the repository it
    writes into by default and whose scripts run the steps)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plan", help="the .tgz scripts/gpu/reference_plan.py wrote")
    ap.add_argument("--store", default=os.path.join(root, "reference", "challenge", "runs.json"))
    ap.add_argument("--out", default=os.path.join(root, "reference", "challenge"))
    ap.add_argument("--results", default=os.path.join(root, "results"))
    ap.add_argument("--cmc", default=os.path.join(root, "build", "cmc"))
    ap.add_argument("--any-physics", action="store_true", help="scripts/best_estimates.py --any-physics (tests)")
    ap.add_argument("--replace", action="store_true", help="replace stored runs and run folders of the same tags")
    ap.add_argument("--accept-outlier", action="store_true",
                    help="adopt a finer grid's estimate far outside the previous band (it is named)")
    a = ap.parse_args(argv)
    a.root = root
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
        print(f"ingest: wrote {os.path.relpath(path, root)}")
    for path in folders:
        print(f"ingest: run folder {os.path.relpath(path, root)}")
    if not files and not folders:
        print("ingest: every run of the archive was already in place; nothing changed")
    return 0
