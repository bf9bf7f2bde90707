"""The command scripts/store_runs.py: finished runs of `cmc run` put into the run store
(reference/challenge/runs.json), one record each (cmc.analysis.runs record)."""
from __future__ import annotations
from typing import Any
import argparse
import datetime
import os
import subprocess
import sys

from cmc import run_folder
from cmc.analysis import runs
from cmc.analysis.runs import REPO as ROOT


def this_cpu() -> str:
    model = "CPU"
    try:
        with open("/proc/cpuinfo") as f:
            model = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{model}, {os.cpu_count()} cores"


def this_commit() -> str | None:
    def git(*args):
        return subprocess.run(["git", "-C", ROOT, *args], capture_output=True, text=True).stdout.strip()
    head = git("rev-parse", "--short=12", "HEAD")
    return (head + ("-dirty" if git("status", "--porcelain", "--untracked-files=no") else "")) or None


def command_of(run_dir: str, summary: dict[str, Any]) -> str:
    """`cmc run CASE --set ... --out RUN_DIR` as far as the summary tells: its case file and the
    grid it ran on (other overrides show in the record's case fields)."""
    n = runs.get(summary, "grid", "nx")
    parts = ["cmc run", summary.get("case_file") or "?", f"--set grid.n={n}"]
    tabor = runs.get(summary, "case", "interaction", "tabor")
    if tabor is not None and "tabor" in (runs.get(summary, "case", "case", "name") or ""):
        parts.append(f"--set interaction.tabor={tabor:g}")
    tol = runs.get(summary, "case", "solver", "tolerance")
    if tol is not None:
        parts.append(f"--set solver.tolerance={tol:g}")
    return " ".join(parts + ["--out", run_dir])


def main(argv: list[str] | None, doc: str | None = None) -> int:
    ap = argparse.ArgumentParser(description=(doc or __doc__), formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+", help="cmc run output folders (each with a summary.json)")
    ap.add_argument("--device", default=None, help="what ran them (default: this machine's CPU)")
    ap.add_argument("--commit", default=None, help="the commit the program was built from (default: this checkout's)")
    ap.add_argument("--origin", default="cpu runs", help="the batch the runs belong to")
    ap.add_argument("--store", default=runs.RUN_STORE)
    a = ap.parse_args(argv)
    new = []
    for d in a.dirs:
        try:
            s = run_folder.read_summary(d).data
        except run_folder.RunFolderError as e:
            print(f"store_runs: {e} (expected a finished `cmc run` output folder)", file=sys.stderr)
            return 2
        path = run_folder.summary_path(d)
        backend = runs.get(s, "grid", "backend") or "cpu"
        tag = f"{backend}-{runs.kind_of(s)}-{runs.get(s, 'grid', 'nx')}"
        date = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc).strftime("%Y-%m-%d")
        new.append(runs.record(s, tag=tag, command=command_of(os.path.relpath(d, ROOT), s),
                               device=a.device or this_cpu(), date=date, commit=a.commit or this_commit(),
                               origin=a.origin))
    total = runs.add_to_store(new, a.store)
    print(f"store_runs: {len(new)} runs stored; {total} records in {a.store}", file=sys.stderr)
    return 0

