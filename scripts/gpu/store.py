#!/usr/bin/python3
"""Store runs made by scripts/gpu/check.sh in the run store (reference/challenge/runs.json).

    /usr/bin/python3 scripts/gpu/store.py --device "NVIDIA H200 143771 MiB" --date YYYY-MM-DD \
        [--commit HASH] [--origin NAME] [--store FILE] CHECK_OUT [CHECK_OUT ...]

CHECK_OUT: a folder check.sh wrote (--out): runs/<backend>-<kind>-<n>/summary.json and, beside
it, <tag>.command (the command as check.sh ran it), <tag>.gpu-memory (nvidia-smi's samples) and
build.txt (the commit the pack was built from, scripts/gpu/pack.sh). Each run becomes one record
(python/cmc/analysis/runs.py), replacing a record of the same tag. --commit overrides build.txt
(for packs made before it was written); --origin names the batch the runs came in (default: the
folder's name). A run that left no summary (stopped at its cap) is listed and not stored.
"""
import argparse
import glob
import os
import sys

from cmc.analysis import runs  # noqa: E402

KINDS = ("hardwall", "hardwall_plain", "adhesive", "shape", "load", "shape_load", "hardwall_load")  # check.sh's stages
TABOR = ("tabor_mu", "shape_tabor_mu")  # check.sh's tabor:N:MU and shape_tabor:N:MU stages


def read_text(path):
    try:
        with open(path) as f:
            return f.read().strip()
    except FileNotFoundError:
        return None


def gpu_peak(path):
    """The largest of nvidia-smi's memory samples (MiB), or None."""
    text = read_text(path) or ""
    vals = [float(x) for x in text.split() if x.replace(".", "", 1).isdigit()]
    return max(vals) if vals else None


def build_commit(out):
    """The commit scripts/gpu/pack.sh recorded in the pack (check.sh copies it to OUT/build.txt)."""
    for line in (read_text(os.path.join(out, "build.txt")) or "").splitlines():
        if line.startswith("commit "):
            return line.split()[1]
    return None


def store_folder(out, a):
    """The records of one check.sh output folder; exits 2 naming what is missing."""
    got = []
    for d in sorted(glob.glob(os.path.join(out, "runs", "*"))):
        tag = os.path.basename(d)
        parts = tag.split("-")
        if len(parts) != 3 or not (parts[1] in KINDS or parts[1].startswith(TABOR)):
            print(f"store.py: {d}: not a check.sh run (<backend>-<kind>-<n>); skipped", file=sys.stderr)
            continue
        if not os.path.exists(os.path.join(d, "summary.json")):
            print(f"store.py: {d}: no summary.json (stopped before it was written); not stored", file=sys.stderr)
            continue
        command = read_text(os.path.join(out, tag + ".command"))
        if command is None:
            sys.exit(f"store.py: {d}: no {tag}.command beside it: run the stage again with a check.sh that records it")
        summary = runs.read_summary(os.path.join(d, "summary.json"))
        device = a.device if parts[0] == "cuda" else "host CPU of the GPU machine"
        got.append(runs.record(summary, tag=tag, command=command, device=device, date=a.date,
                               commit=a.commit or build_commit(out), origin=a.origin or os.path.basename(out.rstrip("/")),
                               gpu_peak_mib=gpu_peak(os.path.join(out, tag + ".gpu-memory"))))
    return got


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outs", nargs="+", help="folders scripts/gpu/check.sh wrote (--out)")
    ap.add_argument("--device", required=True, help="the GPU, as nvidia-smi names it (check.sh's first line)")
    ap.add_argument("--date", required=True, help="the day the runs were made (YYYY-MM-DD)")
    ap.add_argument("--commit", help="the commit the pack was built from (default: the pack's build.txt)")
    ap.add_argument("--origin", help="the batch the runs came in, e.g. the archive's name (default: the folder's)")
    ap.add_argument("--store", default=runs.RUN_STORE)
    a = ap.parse_args(argv)
    new = []
    for out in a.outs:
        if not os.path.isdir(out):
            print(f"store.py: {out}: no such folder (expected a check.sh --out folder)", file=sys.stderr)
            return 2
        new += store_folder(out, a)
    total = runs.add_to_store(new, a.store)
    print(f"store.py: {len(new)} runs stored; {total} records in {a.store}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
