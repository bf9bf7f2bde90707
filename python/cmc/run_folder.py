"""A run's output folder, read in one place: what `cmc run --out FOLDER` (and each point of
`cmc sweep`) writes there (solver/cmc/output/Writer.cpp; docs/user-guide/outputs.md):

* summary.json: the run's record (case as run, grid, status, timing, one record per load step)
  -> :class:`Summary` with its :class:`Step` records;
* result.h5: one group step_NNNN per load step, with its observables (distributions, spectrum,
  cross sections) in the subgroup "observables" -> :class:`Observables`.

Every reader of run folders in the package (the reports, the references, the stores, the
round-off spread, the scaled family) goes through here. A folder that is not a finished run
raises :class:`RunFolderError` naming the folder and what is missing or broken (no summary.json,
a truncated one, a summary without its steps, no result.h5, no group for a step); the numbers
are handed on as the files hold them, nothing is converted or recomputed.
"""
from __future__ import annotations

import glob
import json
import os
from dataclasses import dataclass, field
from typing import Any, Iterable

import numpy as np

from ._types import Json

SUMMARY = "summary.json"
RESULT = "result.h5"


class RunFolderError(ValueError):
    """A folder that cannot be read as a finished cmc run; the message names the folder (or its
    file) and what is missing."""


@dataclass(frozen=True)
class Step:
    """One load step of summary.json "steps": its place in the list (`position`), the index it
    was written under (summary "index", which names its group step_NNNN in result.h5), and its
    record (every key: mean_pressure, contact_fraction, mean_gap, converged, iterations, and
    the scalar "observables" where computed)."""
    position: int
    index: int
    record: Json

    @property
    def scalar_observables(self) -> Json:
        """The step's scalar observables (summary.json steps[k].observables), {} without."""
        ob = self.record.get("observables")
        return ob if isinstance(ob, dict) else {}

    def value(self, key: str) -> Any:
        """The step's record's value of `key`, None where it has none."""
        return self.record.get(key)


@dataclass(frozen=True)
class Summary:
    """summary.json of one run folder: its parsed record (`data`, every key as written) and its
    load steps in order. Records that are not JSON objects are kept out of `steps`."""
    folder: str
    data: Json
    steps: tuple[Step, ...] = field(default=())

    @property
    def path(self) -> str:
        return os.path.join(self.folder, SUMMARY)

    @property
    def status(self) -> str | None:
        """"converged", "not_converged" or "failed", None where the summary does not say."""
        s = self.data.get("status")
        return s if isinstance(s, str) else None

    @property
    def case_name(self) -> str | None:
        """The name of the case as run (case.case.name), None where it has none."""
        c = self.data.get("case")
        name = (c.get("case") or {}).get("name") if isinstance(c, dict) else None
        return name if isinstance(name, str) else None


@dataclass(frozen=True)
class Observables:
    """The observables of one load step in result.h5 (group step_NNNN/observables): 1-D float
    arrays by dataset name, {} where the run computed none."""
    folder: str
    group: str
    arrays: dict[str, np.ndarray]


def summary_path(folder: str) -> str:
    return os.path.join(folder, SUMMARY)


def result_path(folder: str) -> str:
    return os.path.join(folder, RESULT)


def read_summary(folder: str) -> Summary:
    """The folder's summary.json; RunFolderError where it is missing, not complete JSON (a run
    stopped while writing it), not an object, or its "steps" is not a list."""
    path = summary_path(folder)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except FileNotFoundError:
        raise RunFolderError(f"{folder}: no {SUMMARY} (not a cmc run folder, or its run has not "
                             "finished)") from None
    except OSError as e:
        raise RunFolderError(f"{path}: cannot be read ({e})") from None
    try:
        data = json.loads(text)
    except ValueError as e:
        raise RunFolderError(f"{path}: not complete JSON ({e}; a run stopped while writing it?)") from None
    if not isinstance(data, dict):
        raise RunFolderError(f"{path}: expected a JSON object (a run's summary), got {type(data).__name__}")
    return summary_of(folder, data)


def summary_of(folder: str, data: Json) -> Summary:
    """The Summary of a parsed summary.json (`data`) of `folder`; RunFolderError where its
    "steps" is not a list (a missing or empty one is no step)."""
    raw = data.get("steps") or []
    if not isinstance(raw, list):
        raise RunFolderError(f"{summary_path(folder)}: \"steps\" is {type(raw).__name__}, expected a list of "
                             "load steps")
    steps = tuple(Step(position=k, index=_step_index(st, k), record=st) for k, st in enumerate(raw)
                  if isinstance(st, dict))
    return Summary(folder=folder, data=data, steps=steps)


def _step_index(record: Json, position: int) -> int:
    index = record.get("index", position)
    return int(index) if isinstance(index, (int, float)) and not isinstance(index, bool) else position


def find(top: str, recursive: bool = True) -> list[str]:
    """The run folders under `top` (those holding a summary.json; every level below it, or only
    its direct subfolders with recursive=False), in the order of their summaries' paths."""
    pattern = os.path.join(top, "**", SUMMARY) if recursive else os.path.join(top, "*", SUMMARY)
    return [os.path.dirname(f) for f in sorted(glob.glob(pattern, recursive=recursive))]


def has_result(folder: str) -> bool:
    """Whether the folder holds a result.h5."""
    return os.path.isfile(result_path(folder))


def _h5py() -> Any:
    try:
        import h5py
    except ImportError as e:
        raise ImportError(f"reading {RESULT} needs h5py (install python3-h5py): {e}") from None
    return h5py


def _step_group(f: Any, step: Step) -> str | None:
    """The result.h5 group of a step: step_NNNN by its index, else the position-th step group."""
    name = f"step_{step.index:04d}"
    if name in f:
        return name
    groups = sorted(k for k in f.keys() if k.startswith("step_"))
    return groups[step.position] if step.position < len(groups) else None


def _open_result(folder: str) -> Any:
    """The folder's result.h5 opened for reading; RunFolderError where it is missing or cannot be
    opened, ImportError without h5py."""
    h5py = _h5py()
    path = result_path(folder)
    if not os.path.isfile(path):
        raise RunFolderError(f"{folder}: no {RESULT} (the run kept no results, or has not finished)")
    try:
        return h5py.File(path, "r")
    except OSError as e:
        raise RunFolderError(f"{path}: cannot be read ({e})") from None


def observables(folder: str, step: Step) -> Observables:
    """The step's observables in the folder's result.h5 (datasets read as 1-D float arrays; one
    that is not numeric is left out). RunFolderError where result.h5 is missing or unreadable or
    holds no group for the step; ImportError without h5py."""
    path = result_path(folder)
    arrays: dict[str, np.ndarray] = {}
    try:
        with _open_result(folder) as f:
            group = _step_group(f, step)
            if group is None:
                raise RunFolderError(f"{path}: no group for load step {step.index} (step_{step.index:04d}; "
                                     "a run stopped before writing it?)")
            for k, v in (f[group]["observables"].items() if "observables" in f[group] else ()):
                try:
                    arrays[k] = np.asarray(v[()], dtype=float).ravel()
                except (TypeError, ValueError):
                    pass
    except OSError as e:
        raise RunFolderError(f"{path}: cannot be read ({e})") from None
    return Observables(folder=folder, group=group, arrays=arrays)


def step_attribute(folder: str, step: Step, name: str) -> float | None:
    """An attribute of the step's group step_NNNN in result.h5 (e.g. "mean_pressure") as a float,
    None where the group or the attribute is missing; RunFolderError where result.h5 is missing
    or unreadable."""
    try:
        with _open_result(folder) as f:
            g = f.get(f"step_{step.index:04d}")
            return float(g.attrs[name]) if g is not None and name in g.attrs else None
    except OSError as e:
        raise RunFolderError(f"{result_path(folder)}: cannot be read ({e})") from None


def read_summaries(folders: Iterable[str], notes: list[str] | None = None) -> list[Summary]:
    """read_summary of each folder; one that cannot be read is left out, with RunFolderError's
    message in `notes` where given."""
    out = []
    for folder in folders:
        try:
            out.append(read_summary(folder))
        except RunFolderError as e:
            if notes is not None:
                notes.append(f"{e}; skipped")
    return out
