"""Predictions scored against the reference curves: cmc.check, as `cmc check` scores them."""
from __future__ import annotations
from typing import Any
import json
import os
import re
import tempfile

import numpy as np

from ._native import _core, flag, path_text, CaseError, InputError
from ._types import Json


class CheckReport:
    """The outcome of :func:`cmc.check`, as data.

    * ``passed``: the verdict (the metric within the tolerance and the reference's range
      covered);
    * ``verdict``: {"pass", "metric", "value", "tolerance", "tolerance_source", "covered",
      "min_coverage", "reason", ...};
    * ``metrics``: {"max_abs", "rms_abs", "max_rel", "rms_rel", "max_band", ...} (units in
      "abs_unit", definitions in "rel_definition");
    * ``report``: everything ``cmc check --out DIR`` writes to DIR/check.json (axes,
      common range, the evaluation points, prediction and reference in SI units);
    * ``text``: the summary ``cmc check`` prints.
    """

    def __init__(self, report, text):
        self.report = report
        self.text = text

    @property
    def passed(self) -> bool:
        return bool(self.report["verdict"]["pass"])

    @property
    def verdict(self) -> Json:
        return self.report["verdict"]

    @property
    def metrics(self) -> Json:
        return self.report["metrics"]

    def __repr__(self):
        v = self.verdict
        return (f"cmc.CheckReport({self.report['quantity']!r}, {'pass' if self.passed else 'FAIL'}: "
                f"{v['metric']} = {v['value']:.4g} (tolerance {v['tolerance']:.4g}))")


def _columns(prediction):
    """A prediction given as data: an (N, 2) array of (x, y) rows, or a pair (x, y) of 1-D arrays."""
    try:
        if isinstance(prediction, (tuple, list)) and len(prediction) == 2 and np.ndim(prediction[0]) == 1:
            a = np.column_stack([np.asarray(prediction[0], dtype=float), np.asarray(prediction[1], dtype=float)])
        else:
            a = np.asarray(prediction, dtype=float)
    except (TypeError, ValueError) as e:
        raise InputError("prediction: expected a CSV file, an (N, 2) array of (x, y) rows or a pair (x, y) "
                         f"({e})") from None
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"prediction: expected an (N, 2) array of (x, y) rows in SI units, got shape {a.shape}")
    return a


# The file cmc.check writes for an array: line N (after its header) is row N - 2 of the array;
# line 1, the header, stands for the array as a whole.
def _file_line(match):
    line = int(match.group(1))
    return f"prediction row {line - 2}" if line >= 2 else "prediction (array)"


def _line_note(match):
    line = int(match.group(1))
    return f" (row {line - 2})" if line >= 2 else ""


def check(prediction: Any, quantity: str | None = None, *, reference: str | os.PathLike[str] | None = None,
          tolerance: float | None = None, metric: str | None = None, min_coverage: float | None = None,
          adhesionless: bool = False, against: str | None = None) -> CheckReport:
    """Score a prediction against a reference curve, as ``cmc check`` does.

    `prediction`: a CSV file (the columns ``cmc check --help`` and reference/README.md
    name, any of their units), or the curve as data in SI units: an (N, 2) array of (x, y)
    rows or a pair (x, y) of 1-D arrays, e.g. ``cmc.check((pressure_pa, contact_fraction),
    "contact_area_vs_pressure")``. `quantity`: the challenge quantity (its stored reference
    is reference/challenge/QUANTITY.csv), needed for data; `reference`: another reference
    file instead. `tolerance`, `metric`, `min_coverage`, `adhesionless`: as the options of
    ``cmc check``; `against`: which stored reference ("surface", "ensemble" or "realisation";
    None: as ``cmc check`` without ``--against``).

    Returns a :class:`CheckReport`; bad input raises :class:`cmc.InputError` naming the file
    (or the prediction's row), column and what was expected.
    """
    args = ("" if quantity is None else str(quantity),
            "" if reference is None else path_text(reference, "reference"),
            None if tolerance is None else float(tolerance), "" if metric is None else str(metric),
            None if min_coverage is None else float(min_coverage), flag(adhesionless, "adhesionless"),
            "" if against is None else str(against))
    if isinstance(prediction, (str, os.PathLike)):
        json_text, text = _core.check(path_text(prediction, "prediction"), *args)
        return CheckReport(json.loads(json_text), text)
    if quantity is None:
        raise InputError("prediction given as data: name its quantity (quantity=, one of "
                         f"{', '.join(_core.check_quantities())}) so that its columns are known")
    rows = _columns(prediction)
    x, y = _core.check_columns(str(quantity))
    with tempfile.TemporaryDirectory(prefix="cmc-check-") as folder:
        path = os.path.join(folder, "prediction.csv")
        np.savetxt(path, rows, fmt="%.17g", delimiter=",", header=f"{x},{y}", comments="")
        try:
            json_text, text = _core.check(path, *args)
        except (InputError, CaseError) as e:
            message = re.sub(re.escape(path) + r":(\d+)", _file_line, str(e))
            message = re.sub(r" ?\(line (\d+)\)", _line_note, message)
            raise type(e)(message.replace(path, "prediction (array)")) from None
    report = json.loads(json_text)
    report["prediction_file"] = "(array)"
    return CheckReport(report, text.replace(path, "(array)"))
