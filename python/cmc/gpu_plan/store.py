"""The command scripts/gpu/store.py: the runs scripts/gpu/check.sh made, each checked
(cmc.analysis.plausibility) and stored with its provenance in the run store
(reference/challenge/runs.json, cmc.analysis.runs)."""
import argparse
import glob
import os
import sys
from collections.abc import Sequence
from typing import Any, Optional

from ..analysis import plausibility, runs
from .archive import Refused, checked_date

Record = dict[str, Any]  # a run store's record, or a run's summary.json

KINDS = ("hardwall", "hardwall_plain", "adhesive", "shape", "load", "shape_load", "hardwall_load")  # check.sh's stages
TABOR = ("tabor_mu", "shape_tabor_mu")  # check.sh's tabor:N:MU and shape_tabor:N:MU stages


def read_text(path: str) -> Optional[str]:
    """The file's text, stripped; None where there is none; Refused where it is not UTF-8 text."""
    try:
        with open(path, encoding="utf-8") as f:
            return f.read().strip()
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as e:
        raise Refused(f"{path}: not a readable text file ({e})") from None


def gpu_peak(path: str) -> Optional[float]:
    """The largest of nvidia-smi's memory samples (MiB), or None."""
    text = read_text(path) or ""
    vals = [float(x) for x in text.split() if x.replace(".", "", 1).isdigit()]
    return max(vals) if vals else None


def build_commit(out: str) -> Optional[str]:
    """The commit scripts/gpu/pack.sh recorded in the pack (check.sh copies it to OUT/build.txt)."""
    for line in (read_text(os.path.join(out, "build.txt")) or "").splitlines():
        if line.startswith("commit "):
            return line.split()[1]
    return None


def run_tag(d: str) -> Optional[str]:
    """The folder's tag (<backend>-<kind>-<n>), or None where it is not a check.sh run's."""
    parts = os.path.basename(d).split("-")
    if len(parts) != 3 or parts[0] not in ("cpu", "cuda") or not parts[2].isdigit() \
            or not (parts[1] in KINDS or parts[1].startswith(TABOR)):
        return None
    return os.path.basename(d)


def checked_record(d: str, rec: Record, summary: Record) -> Record:
    """rec, if the run may be stored: Refused naming what is impossible or out of balance."""
    problems: list[str] = plausibility.record_problems(rec) + plausibility.balance_problems(summary)
    if rec["n"] != int(rec["tag"].split("-")[2]) or rec["backend"] != rec["tag"].split("-")[0]:
        problems.append(f"its grid {rec['n']!r} and backend {rec['backend']!r} are not its tag's")
    if problems:
        raise Refused(f"{d}: refused, " + "; ".join(problems))
    return rec


def store_folder(out: str, a: argparse.Namespace) -> list[Record]:
    """The records of one check.sh output folder; Refused naming what is missing or wrong."""
    got: list[Record] = []
    for d in sorted(glob.glob(os.path.join(out, "runs", "*"))):
        tag = run_tag(d)
        if tag is None:
            print(f"store.py: {d}: not a check.sh run (<backend>-<kind>-<n>); skipped", file=sys.stderr)
            continue
        if not os.path.exists(os.path.join(d, "summary.json")):
            print(f"store.py: {d}: no summary.json (stopped before it was written); not stored", file=sys.stderr)
            continue
        command = read_text(os.path.join(out, tag + ".command"))
        if command is None:
            raise Refused(f"{d}: no {tag}.command beside it: run the stage again with a check.sh that records it")
        summary = runs.read_summary(os.path.join(d, "summary.json"))
        if summary.get("status") != "converged":
            print(f"store.py: {d}: {summary.get('status')!r}, not converged; not stored", file=sys.stderr)
            continue
        device = a.device if tag.startswith("cuda-") else "host CPU of the GPU machine"
        try:
            rec = runs.record(summary, tag=tag, command=command, device=device, date=a.date,
                              commit=a.commit or build_commit(out), origin=a.origin or os.path.basename(out.rstrip("/")),
                              gpu_peak_mib=gpu_peak(os.path.join(out, tag + ".gpu-memory")))
        except (AttributeError, TypeError, ValueError, KeyError) as e:
            raise Refused(f"{d}/summary.json: not a cmc run's summary ({type(e).__name__}: {e})") from None
        got.append(checked_record(d, rec, summary))
    return got


def main(argv: Sequence[str], doc: str) -> int:
    """scripts/gpu/store.py with arguments argv (its usage text `doc`): 0 stored, 2 refused (nothing stored)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outs", nargs="+", help="folders scripts/gpu/check.sh wrote (--out)")
    ap.add_argument("--device", required=True, help="the GPU, as nvidia-smi names it (check.sh's first line)")
    ap.add_argument("--date", required=True, help="the day the runs were made (YYYY-MM-DD)")
    ap.add_argument("--commit", help="the commit the pack was built from (default: the pack's build.txt)")
    ap.add_argument("--origin", help="the batch the runs came in, e.g. the archive's name (default: the folder's)")
    ap.add_argument("--store", default=runs.RUN_STORE)
    ap.add_argument("--replace", action="store_true", help="replace stored records of the same tags")
    a = ap.parse_args(argv)
    new: list[Record] = []
    try:
        checked_date(a.date, "--date")
        for out in a.outs:
            if not os.path.isdir(out):
                print(f"store.py: {out}: no such folder (expected a check.sh --out folder)", file=sys.stderr)
                return 2
            new += store_folder(out, a)
        old = runs.load_store(a.store)
    except (Refused, runs.StoreError) as e:
        print(f"store.py: {e}; nothing stored", file=sys.stderr)
        return 2
    changed = runs.changed_tags(old, new)
    if changed and not a.replace:
        print(f"store.py: {a.store} holds other records of {', '.join(changed)}: give --replace to replace them; "
              "nothing stored", file=sys.stderr)
        return 2
    runs.save_store(runs.merge(old, new), a.store)
    print(f"store.py: {len(new)} runs stored{' (replacing ' + ', '.join(changed) + ')' if changed else ''}; "
          f"{len(runs.merge(old, new))} records in {a.store}", file=sys.stderr)
    return 0
