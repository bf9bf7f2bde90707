"""The command scripts/ensemble.py: the challenge on many realisations of its surface spectrum
(surface.seed), units of `cmc sweep` over blocks of seeds, a few at a time, within a deadline.
Standard library only: it runs on the GPU machine too (scripts/gpu/full_plan.sh)."""
import argparse
import json
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from typing import IO, Optional

from .challenge_cases import tabor_values

CASES = {"hardwall_load": "load-sweep-hardwall.toml", "reference_hardwall": "reference-load-hardwall.toml",
         "reference": "reference-load.toml", "load": "load-sweep.toml", "tabor": "tabor-sweep.toml"}
HOLDOUT_KINDS = ("hardwall_load",)  # the held-out seeds test the realisation band on the hard-wall curves
Unit = tuple[str, list[int]]  # a kind and its block of seeds


def seed_range(text: str, what: str) -> list[int]:
    """'1-32' or '1,5,9' (or both, comma-separated) as a sorted list of distinct seeds >= 0."""
    out: set[int] = set()
    try:
        for part in filter(None, (p.strip() for p in text.split(","))):
            a, _, b = part.partition("-")
            lo, hi = int(a), int(b or a)
            if lo < 0 or hi < lo or hi - lo > 100000:
                raise ValueError
            out.update(range(lo, hi + 1))
    except ValueError:
        raise SystemExit(f"ensemble: {what} {text!r}: expected seeds like 1-32 or 1,5,9 (whole numbers >= 0)")
    return sorted(out)


def stored(path: Optional[str], n: int, root: str) -> dict[str, set[int]]:
    """{kind: {seed}} of the store's finished runs on n² points (every step converged; for the
    Tabor points every mu_T of cases/challenge/tabor-values)."""
    if not path:
        return {}
    try:
        with open(path) as f:
            records = json.load(f)["records"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise SystemExit(f"ensemble: --skip-stored {path}: not a readable store ({e})")
    done: dict[str, set[int]] = {}
    tabor: dict[int, set[float]] = {}
    for r in records:
        m = re.match(r"ens-(\w+?)-(cpu|cuda)-n(\d+)-s(\d+)(?:-mu(.+))?$", str(r.get("tag", "")))
        if not m or int(m.group(3)) != n or r.get("status") != "converged":
            continue
        kind, seed = m.group(1), int(m.group(4))
        if kind == "tabor":
            tabor.setdefault(seed, set()).add(float(m.group(5)))
        else:
            done.setdefault(kind, set()).add(seed)
    done["tabor"] = {s for s, mus in tabor.items() if len(mus) >= len(tabor_values(root))}
    return done


def units(kinds: list[str], seeds: list[int], holdout: list[int], block: int,
          skip: Optional[dict[str, set[int]]] = None, tabor_seeds: Optional[list[int]] = None) -> list[Unit]:
    """[(kind, [seeds])] in the order of the kinds, blocks of `block` seeds, without those in skip;
    the Tabor points on tabor_seeds alone where given."""
    out: list[Unit] = []
    for kind in kinds:
        these = seeds + ([s for s in holdout if s not in seeds] if kind in HOLDOUT_KINDS else [])
        if kind == "tabor" and tabor_seeds is not None:
            these = [s for s in these if s in tabor_seeds]
        these = [s for s in these if s not in (skip or {}).get(kind, set())]
        out += [(kind, these[i:i + block]) for i in range(0, len(these), block)]
    return out


def command(a: argparse.Namespace, kind: str, block: list[int]) -> tuple[list[str], str]:
    """The cmc sweep of one unit, and its folder."""
    folder = os.path.join(a.out, kind, f"{a.backend}-n{a.n}-s{block[0]}-{block[-1]}")
    cmd = [a.cmc, "sweep", os.path.join(a.root, "cases", "challenge", CASES[kind]), "--out", folder, "--quiet",
           "--over", "surface.seed=" + ",".join(str(s) for s in block)]
    if kind == "tabor":
        cmd += ["--over", "interaction.tabor=" + ",".join(tabor_values(a.root))]
    for kv in [f"grid.n={a.n}", f"grid.backend={a.backend}", "output.fields=false"] + a.set:
        cmd += ["--set", kv]
    return cmd, folder


def stop(p: subprocess.Popen[bytes]) -> None:
    """Stop a unit's process group (the sweep and anything it started)."""
    try:
        os.killpg(p.pid, signal.SIGTERM)
        p.wait(timeout=20)
    except (ProcessLookupError, subprocess.TimeoutExpired):
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        p.wait()


def run_units(a: argparse.Namespace, todo: list[Unit]) -> tuple[list[tuple[str, list[int], int, float]], list[Unit]]:
    """Run the units, a.workers at a time, until done or the deadline; returns (finished, stopped)."""
    t0 = time.monotonic()
    env = dict(os.environ, CMC_THREADS=str(a.threads))
    running: list[tuple[subprocess.Popen[bytes], str, list[int], IO[str], float]] = []
    finished: list[tuple[str, list[int], int, float]] = []
    stopped: list[Unit] = []
    while todo or running:
        left = a.deadline - (time.monotonic() - t0)
        while todo and len(running) < a.workers and left > 0:
            kind, block = todo.pop(0)
            cmd, folder = command(a, kind, block)
            os.makedirs(os.path.dirname(folder), exist_ok=True)
            log: IO[str] = open(folder + ".log", "w")
            p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
            running.append((p, kind, block, log, time.monotonic()))
            print(f"ensemble: started {kind} seeds {block[0]}-{block[-1]} ({left:.0f} s left)", flush=True)
        for item in list(running):
            p, kind, block, log, started = item
            if p.poll() is None and left > 0:
                continue
            if p.poll() is None:
                stop(p)
                stopped.append((kind, block))
                print(f"ensemble: stopped {kind} seeds {block[0]}-{block[-1]} at the deadline", flush=True)
            else:
                finished.append((kind, block, p.returncode, time.monotonic() - started))
                print(f"ensemble: {kind} seeds {block[0]}-{block[-1]}: exit {p.returncode} after "
                      f"{time.monotonic() - started:.0f} s", flush=True)
            log.close()
            running.remove(item)
        if left <= 0:
            stopped += todo
            todo = []
        time.sleep(0.2)
    return finished, stopped


def main(argv: Sequence[str], doc: str, root: str) -> int:
    """scripts/ensemble.py with arguments argv (its usage text `doc`, its repository `root`)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="where the units' sweeps go")
    ap.add_argument("--kinds", default=",".join(CASES), help="kinds in the order to run them (default: all)")
    ap.add_argument("--seeds", default="1-32", help="the ensemble's seeds (default %(default)s)")
    ap.add_argument("--holdout", default="101-110", help="seeds held out of the ensemble (default %(default)s)")
    ap.add_argument("--n", type=int, default=2048, help="points a side (default %(default)s)")
    ap.add_argument("--backend", choices=("cpu", "cuda"), default="cpu")
    ap.add_argument("--workers", type=int, default=1, help="units at a time (default %(default)s)")
    ap.add_argument("--threads", type=int, default=1, help="CMC_THREADS of each unit (default %(default)s)")
    ap.add_argument("--block", type=int, default=1, help="seeds per unit (default %(default)s)")
    ap.add_argument("--deadline", type=float, default=float("inf"), help="seconds for everything (default: none)")
    ap.add_argument("--cmc", default=os.path.join(root, "build", "cmc"))
    ap.add_argument("--set", action="append", default=[], help="a case override for every run (as cmc's --set)")
    ap.add_argument("--skip-stored", help="leave out the seeds this ensemble store already holds")
    ap.add_argument("--tabor-seeds", help="run the Tabor points on these of the seeds only (e.g. 1-16)")
    ap.add_argument("--dry-run", action="store_true", help="print the units and stop")
    a = ap.parse_args(argv)
    a.root = root
    kinds = [k.strip() for k in a.kinds.split(",") if k.strip()]
    bad = [k for k in kinds if k not in CASES]
    if bad or not kinds or len(set(kinds)) != len(kinds):
        print(f"ensemble: --kinds {a.kinds!r}: expected distinct kinds among {', '.join(CASES)}", file=sys.stderr)
        return 2
    if a.n < 16 or a.workers < 1 or a.threads < 1 or a.block < 1 or not a.deadline > 0:
        print("ensemble: --n must be >= 16, --workers, --threads and --block >= 1, --deadline > 0", file=sys.stderr)
        return 2
    if not a.dry_run and not os.access(a.cmc, os.X_OK):
        print(f"ensemble: {a.cmc}: no cmc program there (build it, or name it with --cmc)", file=sys.stderr)
        return 2
    todo = units(kinds, seed_range(a.seeds, "--seeds"), seed_range(a.holdout, "--holdout"), a.block,
                 stored(a.skip_stored, a.n, root), seed_range(a.tabor_seeds, "--tabor-seeds") if a.tabor_seeds else None)
    if a.dry_run:
        for kind, block in todo:
            print(" ".join(command(a, kind, block)[0]))
        return 0
    finished, stopped = run_units(a, todo)
    failed = [f for f in finished if f[2] not in (0, 3)]
    print(f"ensemble: {len(finished)} units finished ({len(failed)} failed), {len(stopped)} stopped or not started",
          flush=True)
    return 1 if failed else 3 if stopped else 0
