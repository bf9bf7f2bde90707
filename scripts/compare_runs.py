#!/usr/bin/python3
"""Compare two run folders (or two folders of run folders) bit for bit.

usage: scripts/compare_runs.py A B [--ignore KEY ...]

Every number and string of each summary.json (timing and wall-clock keys are left out:
they differ on every run) and every dataset of each result.h5 must be identical. Prints
each difference and exits 1 if there is one, 0 if everything is identical. A folder
holding summary.json is one run; otherwise each subfolder holding one is compared with
its namesake in B.
"""
import json
import os
import sys

import h5py
import numpy as np

ALWAYS_IGNORED = {"wall_s", "timing"}


def runs(top):
    if os.path.exists(os.path.join(top, "summary.json")):
        return {"": top}
    return {n: os.path.join(top, n) for n in sorted(os.listdir(top))
            if os.path.exists(os.path.join(top, n, "summary.json"))}


def compare_json(x, y, path, ignored, out):
    if isinstance(x, dict) and isinstance(y, dict):
        for k in sorted(set(x) | set(y)):
            if k in ignored:
                continue
            if k not in x or k not in y:
                out.append(f"{path}/{k}: present in one run only")
            else:
                compare_json(x[k], y[k], f"{path}/{k}", ignored, out)
    elif isinstance(x, list) and isinstance(y, list) and len(x) == len(y):
        for i, (u, v) in enumerate(zip(x, y)):
            compare_json(u, v, f"{path}[{i}]", ignored, out)
    elif x != y or type(x) is not type(y):
        out.append(f"{path}: {x!r} != {y!r}")


def compare_h5(a, b, out):
    with h5py.File(a) as fa, h5py.File(b) as fb:
        def visit(name, obj):
            if not isinstance(obj, h5py.Dataset):
                return
            if name not in fb:
                out.append(f"result.h5/{name}: present in one run only")
                return
            x, y = obj[()], fb[name][()]
            if np.shape(x) != np.shape(y) or not np.array_equal(x, y):
                out.append(f"result.h5/{name}: differs")
        fa.visititems(visit)


def main(argv):
    if len(argv) < 2 or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 2
    a, b = argv[0], argv[1]
    ignored = ALWAYS_IGNORED | set(argv[3:] if len(argv) > 2 and argv[2] == "--ignore" else [])
    ra, rb = runs(a), runs(b)
    if not ra:
        print(f"compare_runs: {a} holds no summary.json (nor do its subfolders)", file=sys.stderr)
        return 2
    diffs = []
    for name, pa in ra.items():
        pb = os.path.join(b, name) if name else b
        if name and name not in rb:
            diffs.append(f"{name}: missing in {b}")
            continue
        out = []
        compare_json(json.load(open(os.path.join(pa, "summary.json"))),
                     json.load(open(os.path.join(pb, "summary.json"))), "summary.json", ignored, out)
        if os.path.exists(os.path.join(pa, "result.h5")):
            compare_h5(os.path.join(pa, "result.h5"), os.path.join(pb, "result.h5"), out)
        diffs += [f"{name + ': ' if name else ''}{d}" for d in out]
    for d in diffs:
        print(d)
    print(f"compare_runs: {len(ra)} run(s), " + ("identical" if not diffs else f"{len(diffs)} differences"))
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
