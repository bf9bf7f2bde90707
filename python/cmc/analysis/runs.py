"""The store of challenge runs (reference/challenge/runs.json): one record per run, made from
its summary.json, with where it ran and what built it. The best estimates, the challenge
references and the reports read runs from here, whichever machine made them.
"""
from __future__ import annotations
from typing import Any
import json
import math
import os

from .. import run_folder

# The checkout (the build tree links these files: realpath finds the source).
REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", ".."))
RUN_STORE = os.path.join(REPO, "reference", "challenge", "runs.json")
STORE_WHAT = ("runs of the Contact Mechanics Challenge behind the best estimates and the performance tables: "
              "one record per run, made from its summary.json by scripts/store_runs.py or scripts/gpu/store.py")


def get(d: Any, *keys: str, default: Any = None) -> Any:
    """d[k0][k1]... or default if any level is missing or not a dict."""
    for k in keys:
        if not isinstance(d, dict) or k not in d:
            return default
        d = d[k]
    return d




def _finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def tabor_of(summary: dict[str, Any]) -> float | None:
    """The run's Tabor parameter as the problem defines it, R_c^(1/3) (w/E*)^(2/3) / rho with the
    specified range rho (a coarse-grained law's own range is longer): the case's interaction.tabor
    where it gives one, else from surface_facts; None without exponential adhesion."""
    inter = get(summary, "case", "interaction") or {}
    if inter.get("kind") != "exponential":
        return None
    if _finite(inter.get("tabor")):
        return inter["tabor"]
    facts: Any = summary.get("surface_facts") or {}
    rho = facts.get("specified_range") or facts.get("interaction_range")
    R, w = facts.get("curvature_radius"), inter.get("work_of_adhesion")
    E = get(summary, "case", "material", "contact_modulus")
    if not all(_finite(x) and x > 0 for x in (rho, R, w, E)):
        return None
    return R ** (1 / 3) * (w / E) ** (2 / 3) / rho


def strategy_of(summary: dict[str, Any]) -> str:
    """The run's resolution strategy: its interaction.coarse_graining ("range", "shape"), or "plain"."""
    cg = get(summary, "case", "interaction", "coarse_graining")
    return cg if cg in ("range", "shape") else "plain"


def dx_over_rho(summary: dict[str, Any]) -> float | None:
    """The grid spacing over the problem's range rho (the specified one, not a coarse-grained law's)."""
    f = summary.get("surface_facts") or {}
    rho: Any = f.get("specified_range") or f.get("interaction_range")
    dx = get(summary, "grid", "dx")
    return dx / rho if _finite(rho) and rho > 0 and _finite(dx) else None


def kind_of(summary: dict[str, Any]) -> str:
    """The run's kind, as scripts/gpu/check.sh names its stages: hardwall, adhesive (the reference
    load, plain), shape / range (the same coarse-grained), tabor_mu<MU> (one point of the Tabor
    sweep's case; shape_tabor_mu<MU> coarse-grained), load / shape_load / hardwall_load (the load
    sweeps)."""
    name = get(summary, "case", "case", "name") or ""
    strategy = strategy_of(summary)
    prefix = "" if strategy == "plain" else strategy + "_"
    if get(summary, "case", "interaction", "kind") != "exponential":
        return "hardwall_load" if "load-sweep" in name else "hardwall"
    if "load-sweep" in name:
        return prefix + "load"
    if "tabor" in name:
        return f"{prefix}tabor_mu{tabor_of(summary):g}"
    return strategy if strategy != "plain" else "adhesive"


def step_values(summary: dict[str, Any]) -> list[dict[str, Any]] | None:
    """Each load step's answer, for runs of several steps (load sweeps): [{pressure_Pa, a_r, a_rep,
    mean_gap_m, converged}]; None for a single step."""
    steps = summary.get("steps") or []
    if len(steps) < 2:
        return None
    return [{"pressure_Pa": s.get("mean_pressure"), "a_r": s.get("contact_fraction"),
             "a_rep": (s.get("observables") or {}).get("repulsive_fraction"), "mean_gap_m": s.get("mean_gap"),
             "converged": bool(s.get("converged"))} for s in steps]


def expand_steps(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The records with every load sweep replaced by one record per converged or stopped step (tag
    TAG@k, that step's load and answer, status "converged" where the step converged), so that a
    sweep's steps take part in the best estimates like single runs at their loads."""
    out = []
    for r in records:
        if not r.get("steps"):
            out.append(r)
            continue
        for k, st in enumerate(r["steps"]):
            out.append(dict(r, tag=f"{r['tag']}@{k}", pressure_Pa=st["pressure_Pa"], a_r=st["a_r"], a_rep=st["a_rep"],
                            mean_gap_m=st["mean_gap_m"], status="converged" if st["converged"] else "not_converged",
                            steps=None))
    return out


# The problem a run solves apart from its grid, strategy, range (mu_T) and load: runs of one
# physics only form refinement sequences and best estimates together.
PHYSICS_KEYS = (("grid", "size"), ("material", "contact_modulus"), ("surface", "hurst"),
                ("surface", "rolloff_wavelength"), ("surface", "cutoff_wavelength"), ("surface", "rms_gradient"),
                ("surface", "seed"), ("interaction", "work_of_adhesion"))


def physics_of(summary: dict[str, Any]) -> dict[str, Any]:
    """The run's physics (PHYSICS_KEYS of its resolved case), e.g. {"surface.seed": 28, ...}."""
    return {f"{a}.{b}": get(summary, "case", a, b) for a, b in PHYSICS_KEYS}


def same_physics(a: dict[str, Any], b: dict[str, Any]) -> bool:
    """Whether two physics dicts agree (numbers within 1e-9 relative; a key missing on one side
    is not compared)."""
    for k in set(a) & set(b):
        x, y = a[k], b[k]
        if x is None or y is None:
            if x is not y:
                return False
        elif isinstance(x, (int, float)) and isinstance(y, (int, float)):
            if abs(x - y) > 1e-9 * max(abs(x), abs(y)):
                return False
        elif x != y:
            return False
    return True


def record(summary: dict[str, Any], *, tag: str, command: str, device: str, date: str | None, commit: str | None = None,
           origin: str | None = None, gpu_peak_mib: float | None = None) -> dict[str, Any]:
    """One store record from a run's summary.json (parsed): what the run is (case, problem,
    strategy, grid, spacing, mu_T, load), how it ended, what it cost, its answer at the last
    step, and its provenance (command, device, date, the commit that built the program, the
    batch of runs it came in)."""
    steps, t = summary.get("steps") or [{}], summary.get("timing") or {}
    last = steps[-1]
    obs = last.get("observables", {})
    backend = get(summary, "grid", "backend") or "cpu"
    return {
        "tag": tag, "kind": kind_of(summary), "n": get(summary, "grid", "nx"), "backend": backend,
        "case_name": get(summary, "case", "case", "name"), "case_file": summary.get("case_file"),
        "problem": "hardwall" if get(summary, "case", "interaction", "kind") != "exponential" else "adhesive",
        "strategy": strategy_of(summary), "tabor": tabor_of(summary),
        "pressure_Pa": last.get("mean_pressure"),
        "tolerance": get(summary, "case", "solver", "tolerance"),
        "device": device, "host_threads": get(summary, "grid", "threads"),
        "command": command, "date": date, "commit": commit, "origin": origin,
        "cmc_version": summary.get("cmc_version"),
        "status": summary.get("status"), "message": summary.get("message") or None,
        "iterations": t.get("iterations"), "fft_pairs": t.get("fft_pairs"),
        "solve_s": sum(x.get("wall_s", 0.0) for x in steps), "run_s": t.get("wall_s"),
        "fft_pair_s": t.get("fft_pair_s"), "time_per_iteration": t.get("time_per_iteration"),
        "time_per_fft_pair": t.get("time_per_fft_pair"), "fft_share": t.get("fft_share"),
        "outer_steps": get(last, "diagnostics", "outer_iterations"),
        "dx_over_rho": dx_over_rho(summary),
        "bistability_number": get(summary, "surface_facts", "bistability_number"),
        "rms_height_m": get(summary, "surface_facts", "rms_height"),
        "a_r": last.get("contact_fraction"), "a_r_corrected": obs.get("contact_fraction_corrected"),
        "a_rep": obs.get("repulsive_fraction"), "mean_gap_m": last.get("mean_gap"),
        "gpu_peak_mib": gpu_peak_mib, "steps": step_values(summary), "physics": physics_of(summary),
    }


class StoreError(ValueError):
    """A run store or a summary that cannot be read as one; the message names the file."""


def load_store(path: str = RUN_STORE) -> list[dict[str, Any]]:
    """The store's records ([] when there is no store yet); StoreError where the file is not a
    run store (not JSON, no list of records, a record without its tag, kind, backend or grid)."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except FileNotFoundError:
        return []
    except (OSError, ValueError) as e:
        raise StoreError(f"{path}: not a readable run store ({e})") from None
    recs = data.get("records") if isinstance(data, dict) else None
    if not isinstance(recs, list):
        raise StoreError(f"{path}: not a run store (expected an object with a list \"records\")")
    for i, r in enumerate(recs):
        if not (isinstance(r, dict) and all(isinstance(r.get(k), str) for k in ("tag", "kind", "backend"))
                and isinstance(r.get("n"), int)):
            raise StoreError(f"{path}: record {i} is not a run record (expected tag, kind, backend and n)")
    return recs


def save_store(records: list[dict[str, Any]], path: str = RUN_STORE) -> None:
    """Write the records (sorted, one per tag) to the store, atomically; ValueError (nothing
    written) where a number is NaN or infinite, which JSON cannot hold."""
    data = {"what": STORE_WHAT, "records": sorted(records, key=lambda r: (r["kind"], r["backend"], r["n"], r["tag"]))}
    text = json.dumps(data, indent=1, sort_keys=True, allow_nan=False) + "\n"
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def add_to_store(new: list[dict[str, Any]], path: str = RUN_STORE) -> int:
    """Add records to the store (replacing those of the same tags); returns how many it holds."""
    records = merge(load_store(path), new)
    save_store(records, path)
    return len(records)


def merge(records: list[dict[str, Any]], new: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The records with `new` added, a new record replacing an old one of the same tag."""
    by_tag = {r["tag"]: r for r in records}
    for r in new:
        by_tag[r["tag"]] = r
    return list(by_tag.values())


def changed_tags(records: list[dict[str, Any]], new: list[dict[str, Any]]) -> list[str]:
    """The tags of `new` that the store holds with another record (a replacement, not a repeat)."""
    by_tag = {r["tag"]: r for r in records}
    return [r["tag"] for r in new if r["tag"] in by_tag and by_tag[r["tag"]] != json.loads(json.dumps(r))]


def read_summary(path: str) -> dict[str, Any]:
    """A run's summary.json (path FOLDER/summary.json), parsed, as cmc.run_folder reads it;
    StoreError naming the file where it is missing, truncated or not a run's summary."""
    if os.path.basename(path) != run_folder.SUMMARY:
        raise StoreError(f"{path}: expected a run folder's {run_folder.SUMMARY}")
    try:
        return run_folder.read_summary(os.path.dirname(path)).data
    except run_folder.RunFolderError as e:
        raise StoreError(str(e)) from None
