"""The command scripts/ensemble_store.py: the seed ensemble's runs (run folders or the GPU
plan's ensemble.tgz) put into reference/challenge/ensemble/runs.json, one record a point."""
from __future__ import annotations
import argparse
import json
import math
import os
import re
import sys
import tarfile

from cmc.analysis import runs
from cmc.analysis.runs import REPO as ROOT
from cmc._types import Json

STORE = os.path.join(ROOT, "reference", "challenge", "ensemble", "runs.json")
STORE_WHAT = ("the Contact Mechanics Challenge on many realisations of its surface spectrum (surface.seed), "
              "one record per run, made from its summary.json by scripts/ensemble_store.py")
KINDS = ("hardwall_load", "reference_hardwall", "reference", "load", "tabor")
POINT = re.compile(r"^(?:[^/]+/)?(" + "|".join(KINDS) + r")/(cpu|cuda)-n(\d+)-s\d+-\d+/surface\.seed_(\d+)/"
                   r"(?:interaction\.tabor_([0-9.eE+-]+)/)?summary\.json$")
MAX_FILE, MAX_MEMBERS = 4 * 2 ** 20, 20000


class Refused(Exception):
    """A source that is not an ensemble's output."""


def members(source: str) -> dict[str, bytes]:
    """{name: bytes} of the source's summaries and machine/build files."""
    if os.path.isdir(source):
        got = {}
        for d, _, files in os.walk(source):
            for f in files:
                if f in ("summary.json", "machine.txt", "build.txt"):
                    path = os.path.join(d, f)
                    if os.path.islink(path) or os.path.getsize(path) > MAX_FILE:
                        raise Refused(f"{path}: a link, or larger than {MAX_FILE} bytes")
                    with open(path, "rb") as fh:
                        got[os.path.relpath(path, source)] = fh.read()
        return got
    try:
        with tarfile.open(source, "r:*") as t:
            return _archive_members(t)
    except (tarfile.TarError, OSError, EOFError) as e:
        raise Refused(f"not a readable archive ({e})")


def _archive_members(t):
    got, count = {}, 0
    for m in t:
        count += 1
        if count > MAX_MEMBERS:
            raise Refused(f"more than {MAX_MEMBERS} members")
        name = m.name[2:] if m.name.startswith("./") else m.name
        if m.isdir() or name in ("", "."):
            continue
        if not m.isfile() or name.startswith("/") or ".." in name.split("/"):
            raise Refused(f"member {m.name!r} is not a plain file inside the archive")
        base = os.path.basename(name)
        if base in ("summary.json", "machine.txt", "build.txt"):
            if m.size > MAX_FILE:
                raise Refused(f"member {m.name!r} is larger than {MAX_FILE} bytes")
            got[name] = t.extractfile(m).read()
    return got


def key_values(text: str) -> dict[str, str]:
    """machine.txt's or build.txt's lines 'key value' as a dict."""
    out = {}
    for line in text.splitlines():
        k, _, v = line.strip().partition(" ")
        if k:
            out[k] = v
    return out


def plausible(rec: Json) -> str | None:
    """Why a record is impossible, or None."""
    pts = rec["steps"] or [{"a_r": rec["a_r"], "mean_gap_m": rec["mean_gap_m"]}]
    for p in pts:
        for k in ("a_r", "mean_gap_m"):
            v = p.get(k)
            if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v)):
                return f"{k} = {v} is not finite"
        if p.get("a_r") is not None and not 0.0 <= p["a_r"] <= 1.0:
            return f"a_r = {p['a_r']} outside [0, 1]"
        if p.get("mean_gap_m") is not None and p["mean_gap_m"] < 0:
            return f"mean gap {p['mean_gap_m']} m < 0"
    return None


def records(files: dict[str, bytes], a: argparse.Namespace, origin: str) -> tuple[list[Json], list[str]]:
    """The store records of one source's summaries, and the names of the points refused."""
    meta = {}
    for name in ("machine.txt", "build.txt"):
        meta.update(key_values(next((v.decode("utf-8", "replace") for k, v in files.items()
                                     if os.path.basename(k) == name), "")))
    out, refused = [], []
    for name, data in sorted(files.items()):
        m = POINT.match(name)
        if not m:
            continue
        kind, backend, n, seed, mu = m.groups()
        tag = f"ens-{kind}-{backend}-n{n}-s{seed}" + (f"-mu{mu}" if mu else "")
        device = a.device or meta.get("device") or "unknown"
        if backend == "cpu" and not a.device and "cpu" not in device.lower():
            device = f"host CPU of the machine of {device}" + (f" ({meta['cores']} cores)" if meta.get("cores") else "")
        try:
            summary = json.loads(data)
            rec = runs.record(summary, tag=tag, command=f"scripts/ensemble.py ({name[m.start(1):]})",
                              device=device,
                              date=a.date or meta.get("date"), commit=a.commit or meta.get("commit"), origin=origin)
        except (ValueError, TypeError, AttributeError, KeyError) as e:
            refused.append(f"{name}: not a cmc summary ({e})")
            continue
        why = plausible(rec) if rec.get("status") in ("converged", "not_converged") else f"status {rec.get('status')}"
        if why:
            refused.append(f"{name}: {why}")
            continue
        out.append(rec)
    return out, refused


def save(recs: list[Json], path: str) -> None:
    data = {"what": STORE_WHAT, "records": sorted(recs, key=lambda r: r["tag"])}
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True, allow_nan=False)
        f.write("\n")
    os.replace(tmp, path)


def main(argv: list[str] | None, doc: str | None = None) -> int:
    ap = argparse.ArgumentParser(description=(doc or __doc__), formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sources", nargs="+", help="folders scripts/ensemble.py wrote, or archives of them")
    ap.add_argument("--store", default=STORE, help="the ensemble's store (default %(default)s)")
    ap.add_argument("--device", help="what ran them (default: machine.txt's device)")
    ap.add_argument("--date", help="the day they ran, YYYY-MM-DD (default: machine.txt's date)")
    ap.add_argument("--commit", help="the commit of the program (default: build.txt's)")
    ap.add_argument("--origin", help="the batch they came in (default: the source's name)")
    a = ap.parse_args(argv)
    if a.date and not re.fullmatch(r"\d{4}-\d{2}-\d{2}", a.date):
        print(f"ensemble_store: --date {a.date!r}: expected YYYY-MM-DD", file=sys.stderr)
        return 2
    new, refused = [], []
    for src in a.sources:
        if not os.path.exists(src):
            print(f"ensemble_store: {src}: no such file or folder", file=sys.stderr)
            return 2
        try:
            got, bad = records(members(src), a, a.origin or os.path.basename(os.path.normpath(src)))
        except Refused as e:
            print(f"ensemble_store: {src}: {e}", file=sys.stderr)
            return 2
        new += got
        refused += bad
    for r in refused:
        print(f"ensemble_store: not stored: {r}", file=sys.stderr)
    try:
        old = runs.load_store(a.store)
    except ValueError as e:
        print(f"ensemble_store: {a.store}: not a readable store ({e})", file=sys.stderr)
        return 2
    merged = runs.merge(old, new)
    save(merged, a.store)
    print(f"ensemble_store: {len(new)} records stored, {len(refused)} refused; {len(merged)} in {a.store}")
    return 0

