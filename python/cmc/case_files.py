"""A case file's table as the cmc program reads it before its checks: the file's TOML with the
bases it names (``base = "other.toml"``) merged under it. Pure Python (tomllib), for scripts
that read case files without the compiled core.

The rules are the program's (solver/cmc/input/CaseFile.cpp; docs/user-guide/case-files.md,
"Shared bases"): ``base`` is a top-level string, a path relative to the file that names it;
tables are merged key by key, the including file's keys replacing the base's, and any other
value (an array too) replaces the base's whole; a base may name a base of its own, at most
MAX_BASE_DEPTH deep and never in a cycle; a relative [surface] path stated in a base in
another folder is rewritten relative to the including file. Each error raises ValueError
naming the including file, its base key and the base. No defaults are added and no key is
checked: the program's resolved case (summary.json "case") is the place for those.
"""
from __future__ import annotations
from typing import Any
import os
import posixpath
import tomllib

MAX_BASE_DEPTH = 8  # CaseLimits::kMaxBaseDepth


def read_case_file(path: str) -> dict[str, Any]:
    """The table of the case file at ``path`` with its bases merged (no ``base`` key left)."""
    return _read(path, "", [])


def _read_toml(path, context):
    if not os.path.exists(path):
        raise ValueError(f"{context}{path}: cannot open the case file: no such file")
    if not os.path.isfile(path):
        raise ValueError(f"{context}{path}: expected a case file (TOML), a regular file")
    with open(path, "rb") as f:
        try:
            return tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise ValueError(f"{context}{path}: not valid TOML: {e}") from None


def _read(path, context, chain):
    table = _read_toml(path, context)
    if "base" not in table:
        return table
    value = table.pop("base")
    if not isinstance(value, str):
        raise ValueError(f"{path}: base: expected the path of a base case file (a string)")
    here = f'{path}: base = "{value}": '
    base = os.path.join(os.path.dirname(path), value)
    chain = chain + [os.path.realpath(path)]
    if os.path.realpath(base) in chain:
        way = " -> ".join(os.path.basename(f) for f in chain + [base])
        raise ValueError(f"{here}a cycle of bases ({way}): a base cannot include a file on the way to it")
    if len(chain) > MAX_BASE_DEPTH:
        raise ValueError(f"{here}more than {MAX_BASE_DEPTH} bases deep (a base naming a base ...)")
    merged = _read(base, here, chain)
    _rebase_surface_path(merged, posixpath.dirname(value))
    _merge(merged, table, path, base, "")
    return merged


def _rebase_surface_path(table, folder):
    surface = table.get("surface")
    if folder and isinstance(surface, dict) and isinstance(surface.get("path"), str) \
            and not posixpath.isabs(surface["path"]):
        surface["path"] = posixpath.normpath(posixpath.join(folder, surface["path"]))


def _merge(into, over, over_file, base_file, section):
    for key, value in over.items():
        if key in into and isinstance(into[key], dict) != isinstance(value, dict):
            name = f"[{section}] {key}" if section else f"[{key}]"
            raise ValueError(f"{over_file}: {name}: a table in one of it and its base {base_file}, a value in the "
                             "other: a key is a table in both files or in neither")
        if key in into and isinstance(value, dict):
            _merge(into[key], value, over_file, base_file, f"{section}.{key}" if section else key)
        else:
            into[key] = value
