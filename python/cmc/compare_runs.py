"""The command scripts/compare_runs.py: two run folders (or folders of them) compared bit for
bit, every summary.json value and result.h5 dataset."""
from __future__ import annotations
from typing import Any, Container
import json
import os
import sys

import h5py
import numpy as np

from . import run_folder

# Wall-clock times and what is derived from them (timing.fft_pair_s is timed at run start).
ALWAYS_IGNORED = {"wall_s", "fft_s", "fft_pair_s", "time_per_fft_pair", "time_per_iteration", "fft_share", "field_bytes_peak",
                  "row_column_pair_s", "floor_pair_s", "time_per_floor_pair"}


def runs(top: str) -> dict[str, str]:
    if os.path.exists(run_folder.summary_path(top)):
        return {"": top}
    return {os.path.basename(d): d for d in sorted(run_folder.find(top, recursive=False), key=os.path.basename)}


def compare_json(x: Any, y: Any, path: str, ignored: Container[str], out: list[str]) -> None:
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
    elif not same(x, y):
        out.append(f"{path}: {x!r} != {y!r}")


def same(x: Any, y: Any) -> bool:
    """Identical values (NaN is identical to NaN)."""
    if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
        if np.shape(x) != np.shape(y):
            return False
        try:
            return np.array_equal(np.asarray(x), np.asarray(y), equal_nan=True)
        except TypeError:  # not numbers
            return np.array_equal(np.asarray(x), np.asarray(y))
    if type(x) is not type(y):
        return False
    if isinstance(x, (float, np.floating)) and np.isnan(x) and np.isnan(y):
        return True
    return x == y


def compare_h5(a: str, b: str, out: list[str]) -> None:
    with h5py.File(a) as fa, h5py.File(b) as fb:
        def objects(f):
            names = {"/": f}
            f.visititems(lambda name, obj: names.setdefault(name, obj) and None)
            return names
        oa, ob = objects(fa), objects(fb)
        for name in sorted(set(oa) ^ set(ob)):
            out.append(f"result.h5/{name}: present in one run only")
        for name in sorted(set(oa) & set(ob)):
            x, y = oa[name], ob[name]
            if isinstance(x, h5py.Dataset) != isinstance(y, h5py.Dataset):
                out.append(f"result.h5/{name}: a dataset in one run only")
                continue
            if isinstance(x, h5py.Dataset) and not same(x[()], y[()]):
                out.append(f"result.h5/{name}: differs")
            for k in sorted(set(x.attrs) | set(y.attrs)):
                if k not in x.attrs or k not in y.attrs:
                    out.append(f"result.h5/{name} attribute {k}: present in one run only")
                elif not same(x.attrs[k], y.attrs[k]):
                    out.append(f"result.h5/{name} attribute {k}: {x.attrs[k]!r} != {y.attrs[k]!r}")


def main(argv: list[str], doc: str | None = None) -> int:
    if len(argv) < 2 or argv[0] in ("-h", "--help"):
        print((doc or __doc__))
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
        if not os.path.exists(os.path.join(pb, "summary.json")):
            diffs.append(f"{name + ': ' if name else ''}{pb}/summary.json: missing")
            continue
        out: list[str] = []
        compare_json(json.load(open(os.path.join(pa, "summary.json"))),
                     json.load(open(os.path.join(pb, "summary.json"))), "summary.json", ignored, out)
        if os.path.exists(os.path.join(pa, "result.h5")) != os.path.exists(os.path.join(pb, "result.h5")):
            out.append("result.h5: present in one run only")
        elif os.path.exists(os.path.join(pa, "result.h5")):
            compare_h5(os.path.join(pa, "result.h5"), os.path.join(pb, "result.h5"), out)
        diffs += [f"{name + ': ' if name else ''}{d}" for d in out]
    for d in diffs:
        print(d)
    print(f"compare_runs: {len(ra)} run(s), " + ("identical" if not diffs else f"{len(diffs)} differences"))
    return 1 if diffs else 0

