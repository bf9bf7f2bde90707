"""The command scripts/gpu/reference_plan.py: the runs behind the challenge's best estimates on one
GPU within one deadline, in order of what the references gain, each stage estimated from the run
store (scaled by cmc.gpu_plan.iteration_scale) and kept while it fits; run through
scripts/gpu/batch.sh and packed into one archive for cmc.gpu_plan.ingest. Standard library only:
it runs on the GPU machine, whose Python has none of our packages."""
import argparse
import datetime
import json
import os
import subprocess
import sys
import tarfile
import time
from collections.abc import Sequence
from typing import Any, Optional

from ..challenge_cases import tabor_values
from . import iteration_scale
from .iteration_scale import Factors

Record = dict[str, Any]  # a run store's record (reference/challenge/runs.json)
Stage = tuple[int, str, list[str], str, int]  # priority, stage, overrides, kind, points a side
Kept = tuple[int, str, list[str], float, bool, int]  # priority, stage, overrides, estimate, a guess, cap
Dropped = tuple[int, str, float, bool]  # priority, stage, estimate, a guess
PLAIN_TABOR_MAX = 0.562  # 8192² resolves rho (dx <= 1.1 rho) up to this mu_T; shape above
STARTUP_S = {"cuda": 6.0, "cpu": 1.5}  # process start, surface, plans and writing (a floor per run)
MAX_PACK_MIB = 16


def stages(scale: int, tabor: Sequence[str]) -> list[Stage]:
    """[(priority, stage, overrides, kind, n)] of the full plan, grids divided by scale; tabor: the
    Tabor sweep's mu_T as written in cases/challenge/tabor-values."""
    def g(n: int) -> int:
        return max(16, n // scale)
    fine = ["solver.tolerance=1e-8"]  # the shape runs' tolerance on the finest grids (the stored 16384² run's)
    out: list[Stage] = [(1, f"hardwall:{g(8192)}", [], "hardwall", g(8192)), (1, f"hardwall:{g(16384)}", [], "hardwall", g(16384)),
           (1, f"shape:{g(8192)}", fine, "shape", g(8192))]
    out += [(2, f"hardwall_load:{g(n)}", [], "hardwall_load", g(n)) for n in (2048, 4096, 8192, 16384)]
    out += [(3, f"shape_load:{g(n)}", [], "shape_load", g(n)) for n in (2048, 4096, 8192)]
    out += [(4, f"shape:{g(16384)}", fine, "shape", g(16384))]
    for mu in tabor:
        if float(mu) <= PLAIN_TABOR_MAX:
            out.append((5, f"tabor:{g(8192)}:{mu}", [], f"tabor_mu{float(mu):g}", g(8192)))
        elif float(mu) < 3.0:  # mu_T = 3 with shape is stage 1's case
            out.append((5, f"shape_tabor:{g(8192)}:{mu}", [], f"shape_tabor_mu{float(mu):g}", g(8192)))
    out += [(6, f"adhesive:{g(16384)}", ["output.fields=true"], "adhesive", g(16384)),
            (6, f"adhesive_from:{g(32768)}:{g(16384)}", [], "adhesive", g(32768))]
    return out


def estimate(kind: str, n: int, backend: str, records: Sequence[Record], stage: str = "",
             tables: Sequence[Factors] = ()) -> tuple[float, bool]:
    """Seconds a stage takes: the stored run of this kind and backend on the nearest grid, scaled by
    the points (n²) and by the present solver's iterations over those of the program that made it
    (cmc.gpu_plan.iteration_scale, from `tables`), plus STARTUP_S; where none is stored, the nearest adhesive
    or hard-wall run of any kind on this backend, times 3 (a guess, printed as one)."""
    base = "shape" if kind.startswith("shape_tabor") else "tabor_mu" if kind.startswith("tabor_mu") else kind
    # A sweep with none of its own stored is estimated from its single-load kind (hardwall_load
    # from hardwall, shape_load from shape): its 14 loads, no more a guess than that run.
    single = {"hardwall_load": "hardwall", "shape_load": "shape", "load": "adhesive"}.get(kind)
    same = [r for r in records if r.get("backend") == backend and r.get("run_s") and
            (r["kind"] == kind or r["kind"].startswith(base))]
    if not same and single:
        same = [r for r in records if r.get("backend") == backend and r.get("run_s") and r["kind"] == single]
    guess = False
    if not same:
        family = "hardwall" if kind.startswith("hardwall") else "adhesive"
        same = [r for r in records if r.get("backend") == backend and r.get("run_s") and r.get("problem") == family]
        guess = True
    if not same:
        return 60.0, True
    # The nearest grid, a converged run before one stopped at a cap (which says little of a whole solve).
    r = min(same, key=lambda r: (r.get("status") != "converged", abs((r["n"] or 1) - n)))
    t = (r["run_s"] * (n / r["n"]) ** 2 * (3.0 if guess else 1.0)
         * iteration_scale.factor(kind, stage, r.get("tolerance"), tables))
    if kind.endswith("load"):
        t *= 14 if r.get("steps") is None else 1  # a sweep of 14 loads from a single-load run
    return STARTUP_S[backend] + t, guess


PACK_S = 20  # the deadline's reserve for the last pack


def plan(a: argparse.Namespace, records: Sequence[Record], tables: Sequence[Factors] = ()
         ) -> tuple[list[Kept], list[Dropped], float]:
    """The stages whose estimates fit in the deadline, in order, each with its cap (its estimate
    plus half, and 10 s), and those dropped. A run started from another needs that one kept."""
    backend = "cpu" if a.cpu else "cuda"
    kept: list[Kept] = []
    dropped: list[Dropped] = []
    total = 0.0
    for prio, stage, sets, kind, n in stages(a.scale, tabor_values(a.root)):
        if prio in a.skip:
            continue
        est, guess = estimate(kind, n, backend, records, stage, tables)
        needs = stage.startswith("adhesive_from") and not any(k[1].endswith(f"adhesive:{stage.split(':')[2]}") for k in kept)
        if needs or (total + est > a.deadline - PACK_S and not a.keep_all):
            dropped.append((prio, stage, est, guess))
            continue
        total += est
        kept.append((prio, ("cpu-" if a.cpu else "") + stage, sets, est, guess, int(est * 1.5 + 10)))
    return kept, dropped, total


def print_fit(dropped: Sequence[Dropped], total: float, deadline: int, tables: Sequence[Factors]) -> None:
    """What the whole plan would need against the deadline, each stage too long for a deadline
    of its own, and the iteration factors the estimates were scaled by."""
    room = deadline - PACK_S
    if dropped:
        need = total + sum(est for _, _, est, _ in dropped)
        print(f"reference_plan: every stage together needs about {need:.0f} s, {need - room:.0f} s more than the "
              f"deadline less the pack's reserve ({room} s)")
    over = [(prio, stage, est) for prio, stage, est, _ in dropped if est > room]
    for prio, stage, est in over:
        print(f"reference_plan: [{prio}] {stage} alone needs {est:.0f} s: over {room} s by {est - room:.0f} s")
    if dropped and not over:
        prio, stage, est, _ = max(dropped, key=lambda d: d[2])
        print(f"reference_plan: every dropped stage fits {room} s on its own (the longest, [{prio}] {stage}, "
              f"{est:.0f} s): run them with --skip in further calls")
    for line in iteration_scale.describe(tables):
        print(f"reference_plan: stored times scaled by the iterations measured on the CPU: {line}")


def machine_text(a: argparse.Namespace) -> str:
    """What ran the plan: the GPU (nvidia-smi) or the CPU, cores, the time (UTC)."""
    if a.cpu:
        dev = "host CPU"
    else:
        r = subprocess.run(["nvidia-smi", "--query-gpu=name,memory.total,driver_version", "--format=csv,noheader"],
                           capture_output=True, text=True)
        fields = [x.strip() for x in r.stdout.strip().splitlines()[0].split(",")] if r.returncode == 0 and r.stdout.strip() else []
        # As the run store names devices: "NVIDIA H200 143771 MiB (driver 580.159.04)".
        dev = f"{fields[0]} {fields[1]} (driver {fields[2]})" if len(fields) == 3 else "GPU (nvidia-smi failed)"
    now = datetime.datetime.now(datetime.timezone.utc)
    return f"device {dev}\ncores {os.cpu_count()}\ndate {now:%Y-%m-%d}\nstarted {now:%Y-%m-%dT%H:%M:%SZ}\n"


def unusable_paths(a: argparse.Namespace) -> Optional[str]:
    """Why the plan cannot save its results (a message), or None: the folder of --tar must
    exist, and --pack must be a pack (bin/cmc and env.sh, scripts/gpu/pack.sh)."""
    folder = os.path.dirname(os.path.abspath(a.tar))
    if not os.path.isdir(folder):
        return f"--tar {a.tar}: the folder {folder} does not exist (the results could not be saved)"
    missing = [f for f in ("bin/cmc", "env.sh") if not os.path.isfile(os.path.join(a.pack, f))]
    if missing:
        return f"--pack {a.pack}: no {' or '.join(missing)} (expected a pack made by scripts/gpu/pack.sh)"
    return None


def saved_runs(tar: str, since: float) -> Optional[int]:
    """How many runs with a summary the archive `tar` holds, if this plan wrote it (not older
    than `since`); None where it did not."""
    try:
        if os.path.getmtime(tar) < since - 1:
            return None
        with tarfile.open(tar) as t:
            return sum(1 for n in t.getnames() if n.endswith("/summary.json") and "/runs/" in n)
    except (OSError, tarfile.TarError, EOFError):
        return None


def saved_report(tar: str, since: float, batch_code: int) -> int:
    """Say what was saved; the exit code: batch.sh's, or 1 where no run's summary was saved."""
    count = saved_runs(tar, since)
    if not count:
        what = "no archive was written" if count is None else "no run left its summary (every stage failed)"
        print(f"reference_plan: {tar}: {what}; nothing was saved", file=sys.stderr)
        return batch_code or 1
    size = os.path.getsize(tar) / 2 ** 20
    print(f"reference_plan: {tar}: {count} runs, {size:.2f} MiB"
          + (f" (more than {MAX_PACK_MIB} MiB)" if size > MAX_PACK_MIB else ""))
    return batch_code


def arguments(argv: Sequence[str], doc: str, root: str) -> Optional[argparse.Namespace]:
    """The command's options (its usage text `doc`; `root`: the repository), or None where one is
    refused (the message printed)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--deadline", type=int, default=540, help="seconds for the whole plan (default %(default)s)")
    ap.add_argument("--scale", type=int, default=1, help="divide every grid by this (default %(default)s)")
    ap.add_argument("--cpu", action="store_true", help="run the stages on the CPU backend")
    ap.add_argument("--pack", default=".gpucarry", help="scripts/gpu/pack.sh's pack (default %(default)s)")
    ap.add_argument("--work", default="reference-plan", help="where the runs go (default %(default)s)")
    ap.add_argument("--tar", default=os.path.join(os.environ.get("OUT", "."), "reference-plan.tgz"))
    ap.add_argument("--store", default=os.path.join(root, "reference", "challenge", "runs.json"))
    ap.add_argument("--skip", default="", help="priorities to leave out, e.g. 1,2 for a second call (default: none)")
    ap.add_argument("--keep-all", action="store_true",
                    help="keep every stage whatever its estimate: the deadline alone stops them (estimates "
                         "from runs of an older program can be far off)")
    ap.add_argument("--dry-run", action="store_true", help="print the plan and stop")
    a = ap.parse_args(argv)
    a.root = root
    try:
        a.skip = {int(p) for p in a.skip.split(",") if p.strip()}
    except ValueError:
        print(f"reference_plan: --skip {a.skip}: expected priorities 1-6 separated by commas", file=sys.stderr)
        return None
    if a.scale < 1 or a.deadline < 60:
        print("reference_plan: --scale must be >= 1 and --deadline >= 60 s", file=sys.stderr)
        return None
    return a


def print_plan(a: argparse.Namespace, kept: Sequence[Kept], dropped: Sequence[Dropped], total: float) -> None:
    """The stages kept, with their estimates and caps, and those dropped."""
    print(f"reference_plan: {len(kept)} stages, about {total:.0f} s estimated in a deadline of {a.deadline} s "
          f"({'CPU' if a.cpu else 'GPU'}, grids / {a.scale}):")
    for prio, stage, sets, est, guess, cap in kept:
        print(f"  [{prio}] {stage:32s} estimate {est:6.0f} s{' (guess)' if guess else '':8s} cap {cap:4d} s"
              + (f"  {' '.join(sets)}" if sets else ""))
    for prio, stage, est, guess in dropped:
        print(f"  [{prio}] {stage:32s} estimate {est:6.0f} s: dropped, it does not fit")


def run_batch(a: argparse.Namespace, kept: Sequence[Kept]) -> int:
    """The kept stages through scripts/gpu/batch.sh into a.tar; the exit code (saved_report's)."""
    os.makedirs(a.work, exist_ok=True)
    with open(os.path.join(a.work, "machine.txt"), "w") as f:
        f.write(machine_text(a))
    # Scaled down, the spectrum is cut at the grid's own resolution as the full plan's grids hold
    # it (lambda_s = 2 dx of 2048² / K): every grid then has the same surface, and a run can start
    # from a coarser one.
    scaled = [f"surface.cutoff_wavelength={0.1e-6 * a.scale:g}"] if a.scale > 1 else []
    specs = [f"{stage}@{cap}" + "".join("," + s for s in sets + scaled) for _, stage, sets, _, _, cap in kept]
    env = dict(os.environ, DEADLINE=str(a.deadline))
    started = time.time()
    r = subprocess.run([os.path.join(a.root, "scripts", "gpu", "batch.sh"), "--pack", a.pack, "--work", a.work,
                        "--tar", a.tar, "--keep-h5", "8", "--deadline", str(a.deadline)] + specs, env=env, cwd=a.root)
    return saved_report(a.tar, started, r.returncode)


def main(argv: Sequence[str], doc: str, root: str) -> int:
    """scripts/gpu/reference_plan.py with arguments argv (its usage text `doc`, its repository
    `root`): 0 done or a dry run, 2 a refused argument, else batch.sh's code or 1 (nothing saved)."""
    a = arguments(argv, doc, root)
    if a is None:
        return 2
    records = json.load(open(a.store)).get("records", []) if os.path.exists(a.store) else []
    tables = iteration_scale.load(root)
    kept, dropped, total = plan(a, records, tables)
    print_plan(a, kept, dropped, total)
    print_fit(dropped, total, a.deadline, tables)
    if a.dry_run or not kept:
        return 0
    refused = unusable_paths(a)
    if refused:
        print(f"reference_plan: {refused}; nothing was run", file=sys.stderr)
        return 2
    return run_batch(a, kept)
