"""The compiled core (cmc._core), imported with a message that says how to build it, and
the small conversions every part of the package shares."""
from __future__ import annotations
from typing import Any
import math
import numbers
import os
import re

import numpy as np

try:
    from . import _core
except ImportError as e:  # the pure-Python files alone (python/ on sys.path), or a stale build
    raise ImportError(
        f"cmc's compiled core (cmc._core) cannot be imported ({e}): build it with scripts/setup.sh "
        "(Debian packages pybind11-dev, python3-pybind11, python3-dev) and put the build's python "
        "folder first on the path: PYTHONPATH=build/python /usr/bin/python3 (docs/user-guide/python.md)"
    ) from e

CaseError = _core.CaseError
CaseError.__doc__ = ("Bad input to a case (a file, a --set override or an argument of cmc.solve or "
                     "cmc.self_affine): the message names the file or argument, the key and what was expected.")
InputError = _core.InputError
InputError.__doc__ = "Bad input to cmc.check: the message names the file (or row), column and what was expected."
SurfaceFileError = _core.SurfaceFileError
SurfaceFileError.__doc__ = "A height file that cannot be read: the message names the file and what was expected."


def plain(value: Any, what: str) -> Any:
    """`value` as bool, int, float, str or a list of them (numpy scalars and arrays
    included): what a case's key takes. CaseError naming `what` otherwise."""
    if isinstance(value, (bool, str)):
        return value
    if hasattr(value, "tolist") and not isinstance(value, (int, float)):  # numpy scalar or array
        return plain(value.tolist(), what)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, (list, tuple)):
        return [plain(v, what) for v in value]
    raise CaseError(f"{what}: expected a bool, number, string or list, got {type(value).__name__} {value!r}")


def toml_text(value: Any, what: str) -> str:
    """`value` written as a TOML value (what `cmc run --set key=VALUE` takes)."""
    v = plain(value, what)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return '"' + "".join(_toml_char(c) for c in v) + '"'
    return "[" + ", ".join(toml_text(x, what) for x in v) + "]"


def _toml_char(c):
    if c in '"\\':
        return "\\" + c
    return c if c >= " " and c != "\x7f" else f"\\u{ord(c):04x}"


def length(value: Any, what: str) -> float:
    """A length or other quantity that must be a finite number > 0, as a float."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CaseError(f"{what}: expected a number > 0, got {type(value).__name__} {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise CaseError(f"{what}: expected a finite number > 0, got {v!r}")
    return v


def renamed(error: Exception, label: str, names: dict[str, str]) -> Exception:
    """`error` (a CaseError from the case layer, `label: [section] key: ...`) with each
    case key that stands for an argument named as that argument: `label: size ([grid] size): ...`."""
    text = str(error)
    for key, argument in names.items():
        text = re.sub(re.escape(f"{label}: {key}") + r"(?=:)", f"{label}: {argument} ({key})", text)
    return type(error)(text)


def path_text(path: Any, what: str) -> str:
    """A file or folder name given as str or os.PathLike (bytes decoded as the file system does);
    CaseError for anything else and for a name with a NUL character, which no file has."""
    try:
        text = os.fsdecode(os.fspath(path))
    except (TypeError, UnicodeDecodeError):
        raise CaseError(f"{what}: expected a path (str or os.PathLike), got {type(path).__name__}") from None
    if "\0" in text:
        raise CaseError(f"{what}: {text!r} holds a NUL character; expected a file or folder name")
    return text


def flag(value: Any, what: str) -> bool:
    """A yes/no argument: True or False (numpy's bools too); CaseError for anything else, such as
    the string 'no', which Python would take as true."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise CaseError(f"{what}: expected True or False, got {type(value).__name__} {value!r}")
