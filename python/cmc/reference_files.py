"""Reference curve files (reference/README.md, the format): read one as the curve that writes it
again, and have cmc format and write a curve (`cmc reference --run-curve`), so that every stored
file is formatted by one program and `cmc check` reads them all alike.

A curve is a dict: name, quantity, title, x, y, representation, band (a column name or None),
estimated_error (text), columns [[name, unit, meaning, values]], extra [(key, value)] (provenance
keys first, in the order cmc writes them, then any others).
"""
import json
import os
import subprocess
import tempfile
from typing import Dict, List, Optional

PROVENANCE = ("cmc_version", "case_file", "grid", "solver_tolerance", "date", "command")
STANDARD = {"cmc-reference-csv", "name", "quantity", "title", "source", "columns", "x", "y", "representation",
            "band", "estimated_error"} | set(PROVENANCE)


class CurveError(RuntimeError):
    """cmc refused to write a curve (its message says why)."""


def _toml_str(v: object) -> str:
    return json.dumps(str(v), ensure_ascii=False)  # a JSON string is a valid TOML basic string


def curve_spec(c: Dict) -> str:
    """The TOML spec `cmc reference --run-curve` reads (solver/app/run_curve.cpp)."""
    lines = [f"{k} = {_toml_str(c[k])}" for k in ("name", "quantity", "title", "x", "y", "representation",
                                                   "estimated_error")]
    if c.get("band"):
        lines.append(f"band = {_toml_str(c['band'])}")
    more = [(k, v) for k, v in c["extra"] if k not in PROVENANCE]
    lines.append("extra = [" + ", ".join(f"[{_toml_str(k)}, {_toml_str(v)}]" for k, v in more) + "]")
    lines.append("[provenance]")
    lines += [f"{k} = {_toml_str(v)}" for k, v in c["extra"] if k in PROVENANCE]
    for name, unit, meaning, values in c["columns"]:
        lines += ["[[columns]]", f"name = {_toml_str(name)}", f"unit = {_toml_str(unit)}",
                  f"meaning = {_toml_str(meaning)}",
                  "values = [" + ", ".join(repr(float(v)) for v in values) + "]"]
    return "\n".join(lines) + "\n"


def write_curve(cmc: str, c: Dict, path: str) -> str:
    """Has cmc format and write the curve at `path` (atomically); returns the file's text."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with tempfile.NamedTemporaryFile("w", suffix=".toml", encoding="utf-8", delete=False) as f:
        f.write(curve_spec(c))
        spec = f.name
    try:
        r = subprocess.run([cmc, "reference", "--run-curve", spec, "--out", path], capture_output=True, text=True)
    finally:
        os.remove(spec)
    if r.returncode != 0:
        raise CurveError(f"cmc reference --run-curve failed for {c['name']} (exit {r.returncode}): {r.stderr.strip()}")
    with open(path, encoding="utf-8") as f:
        return f.read()


def write_atomically(path: str, text: str) -> None:
    """A text file written whole or not at all, mode 0644."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)), prefix=".tmp-")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def read_curve(path: str) -> Optional[Dict]:
    """A stored reference CSV as the curve that writes it again: every metadata key in its order,
    the columns with unit and meaning; None where the file is missing."""
    if not os.path.isfile(path):
        return None
    meta: Dict[str, str] = {}
    names: Optional[List[str]] = None
    rows: List[List[float]] = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            s = line.rstrip("\n")
            if s.startswith("#"):
                if names is None and ":" in s:
                    k, v = s[1:].split(":", 1)
                    meta[k.strip()] = v.strip()
            elif s.strip():
                if names is None:
                    names = s.split(",")
                else:
                    rows.append([float(v) for v in s.split(",")])
    cols = []
    for i, n in enumerate(names or []):
        unit, _, meaning = meta.get(f"unit.{n}", "").partition(" (")
        cols.append([n, unit, meaning[:-1] if meaning.endswith(")") else meaning, [r[i] for r in rows]])
    return {"name": meta["name"], "quantity": meta["quantity"], "title": meta.get("title", ""), "x": meta["x"],
            "y": meta["y"], "representation": meta["representation"], "band": meta.get("band"),
            "estimated_error": meta.get("estimated_error", ""), "columns": cols,
            "extra": [(k, v) for k, v in meta.items()
                      if k in PROVENANCE or (k not in STANDARD and not k.startswith("unit."))]}
