"""Case files and runs: cmc.Case, cmc.run and the cmc.Result they give."""
from __future__ import annotations
import os
from typing import Any, Callable
import json

import numpy as np

from ._native import _core, path_text, toml_text, CaseError
from ._types import Json


class Case:
    """A case file, read and checked by cmc's input layer.

    The same checks and messages as ``cmc run CASE.toml --set ...``: a wrong key or value
    raises :class:`cmc.CaseError` (a ``ValueError``) naming the file, the key and what was
    expected. Build one with :meth:`Case.load`.
    """

    def __init__(self, native):
        self._native = native
        self._resolved = None

    @classmethod
    def load(cls, path: str | os.PathLike[str], set: dict[str, Any] | None = None) -> Case:
        """Read the case file `path`, with `set` overriding keys as ``--set`` does.

        `set`: a dict ``{"section.key": value}`` (values: bool, number, string or list,
        numpy scalars too) or a list of ``"section.key=value"`` strings (TOML values, as on
        the command line), e.g. ``Case.load("cases/challenge/reference-load-hardwall.toml",
        set={"grid.n": 512})``.
        """
        overrides = []
        if isinstance(set, dict):
            for key, value in set.items():
                if not isinstance(key, str):
                    raise CaseError(f"set: the key {key!r}: expected a string 'section.key'")
                overrides.append(f"{key}={toml_text(value, 'set: ' + key)}")
        elif set is not None:
            if isinstance(set, str):
                set = [set]
            for item in set:
                if not isinstance(item, str):
                    raise CaseError(f"set: {item!r}: expected 'section.key=value' strings or a dict")
                overrides.append(item)
        return cls(_core.load_case(path_text(path, "path"), overrides))

    @property
    def file(self) -> str:
        """The case file (as messages name it)."""
        return self._native.file

    @property
    def name(self) -> str:
        return self._native.name

    @property
    def description(self) -> str:
        return self._native.description

    @property
    def shape(self) -> tuple[int, int]:
        """The grid as numpy arrays of it are shaped: (ny, nx)."""
        return (self._native.ny, self._native.nx)

    @property
    def resolved(self) -> Json:
        """The case as it runs, as a dict: overrides applied, every default filled in
        (what summary.json records under "case")."""
        if self._resolved is None:
            self._resolved = json.loads(self._native.resolved_json())
        return self._resolved

    def __repr__(self):
        return f"cmc.Case({self.file!r}, name={self.name!r}, grid={self._native.nx}x{self._native.ny})"


class Result:
    """What a run gives: the summary and the arrays, in SI units.

    * ``summary``: a dict with the records of summary.json: "case" (as run), "grid",
      "surface", "surface_facts", "warnings", "status", "message", "timing", "steps" (one
      dict per load step: mean_pressure, force, penetration, mean_gap, contact_fraction,
      energy, iterations, converged, residual, ... and "observables" when computed) and,
      for adhesive load paths, "load_path". A run written into a folder (``out=``) gives
      that folder's summary.json, every key of it.
    * ``heights``: the indenter's heights h, shape (ny, nx) (row i at y = i dy, x fastest).
    * ``fields``: one dict per step, {"pressure", "displacement", "gap"} -> (ny, nx) arrays,
      when the case keeps fields (``output.fields``, the default).
    * ``observables``: one dict per step, name -> 1-D array, when the case computes them
      (``observables.enabled``): distributions, stress spectrum, cross-section.
    * ``units``: the unit of every array above, by name ("Pa", "m", "1/m", ...).

    The arrays are numpy views of the memory the run filled (no copies).
    """

    def __init__(self, native):
        self.summary = json.loads(native["summary_json"])
        self.heights = native["heights"]
        self.fields = list(native["fields"])
        self.observables = []
        self.units = {"heights": "m", "pressure": "Pa", "displacement": "m", "gap": "m"}
        for step in native["observables"]:
            arrays = {}
            for name, (values, unit) in step.items():
                arrays[name] = values
                self.units[name] = unit
            self.observables.append(arrays)

    @property
    def status(self) -> str:
        """"converged", "not_converged" or "failed" (summary.json's status)."""
        return self.summary["status"]

    @property
    def converged(self) -> bool:
        return self.status == "converged"

    @property
    def steps(self) -> list[Json]:
        """The records of the load steps (summary["steps"])."""
        return self.summary["steps"]

    def field(self, name: str, step: int = -1) -> np.ndarray:
        """Field `name` ("pressure", "displacement", "gap") of load step `step` (the last by default)."""
        if not self.fields:
            raise KeyError("this run kept no fields (the case sets output.fields = false)")
        return self.fields[step][name]

    def __repr__(self):
        g = self.summary.get("grid", {})
        return (f"cmc.Result({self.summary.get('case', {}).get('case', {}).get('name', '?')!r}, "
                f"{len(self.steps)} steps, {self.status}, grid {g.get('nx')}x{g.get('ny')})")


def run(case: Case | str | os.PathLike[str], out: str | os.PathLike[str] | None = None,
        progress: Callable[[Json], Any] | None = None) -> Result:
    """Run `case` (a :class:`Case`, or a case file's path) as ``cmc run`` does.

    The same driver and solvers as the command line: the same numbers, bit for bit, at
    the same thread count (CMC_THREADS) and FFT plans. Nothing is written unless `out`
    is given; then the folder gets what ``cmc run --out OUT`` writes (summary.json,
    result.h5, result.xdmf, checkpoints while it runs), and ``summary`` is its summary.json.

    `progress`: None or a callable, called every 25 solver iterations (every outer step of
    the quasi-static solver) with a dict {"step", "iteration", "residual", "outer",
    "inner"}; an exception it raises stops the run. Ctrl-C stops the run cleanly
    (KeyboardInterrupt) at the next such point. The solver runs without the GIL.

    Returns a :class:`Result`.
    """
    if not isinstance(case, Case):
        case = Case.load(case)
    if progress is not None and not callable(progress):
        raise CaseError(f"progress: expected a callable or None, got {type(progress).__name__}")
    folder = "" if out is None else path_text(out, "out")
    if out is not None and not folder:
        raise CaseError("out: expected a folder name, got ''")
    return Result(_core.run(case._native, None, folder, progress))
