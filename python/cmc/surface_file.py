"""The command scripts/surface_file.py, what scripts/main.sh --surface FILE runs: a surface file
of the user's recognised (the challenge's published layouts: HDF5 with one square dataset
`surface`, a square ASCII matrix, a Fourier list `kx ky re im`; or cmc's own height map) and the
challenge's case files written for it into RESULTS/surfaces/<name>-<sha256's first 8 digits>/."""
import argparse
import glob
import hashlib
import json
import os
import re
import sys
import tomllib
from collections.abc import Iterator, Sequence
from typing import Any

HDF5_SUFFIXES = (".h5", ".hdf5", ".hdf", ".he5")
DATASET = "surface"  # the published HDF5 files' one dataset


# What a format's heights are in, as cmc reads it by default (docs/user-guide/case-files.md).
UNITS = {"challenge_hdf5": "units of L = [grid] size", "challenge_ascii": "units of L = [grid] size",
         "fourier": "units of L = [grid] size", "hdf5": "metres"}


class BadSurface(Exception):
    pass


def sha256_of(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _hdf5_layout(path: str, size: float) -> tuple[str, int]:
    """('challenge_hdf5', n) for the published layout, one square 2-D dataset `surface` of heights in
    units of L; ('hdf5', n) for cmc's own height map (`cmc surface --write`: the same dataset in metres,
    its box in attributes lx and ly, which must be the challenge's `size`)."""
    import h5py
    try:
        with h5py.File(path, "r") as f:
            if DATASET not in f or not isinstance(f[DATASET], h5py.Dataset):
                raise BadSurface(f"an HDF5 file without a dataset '{DATASET}' (has: {', '.join(f.keys()) or 'nothing'}); "
                                 f"expected the challenge's layout, one 2-D dataset '{DATASET}' of heights in units of L")
            shape, box = f[DATASET].shape, [f[DATASET].attrs.get(k) for k in ("lx", "ly")]
    except OSError as e:
        raise BadSurface(f"not a readable HDF5 file ({e})") from None
    if len(shape) != 2 or shape[0] != shape[1] or shape[0] < 2:
        raise BadSurface(f"dataset '{DATASET}' has shape {shape}; expected a square 2-D map (n x n, n >= 2)")
    if box[0] is None and box[1] is None:
        return "challenge_hdf5", int(shape[0])
    if not all(b is not None and abs(float(b) / size - 1) < 1e-9 for b in box):
        raise BadSurface(f"a height map of {box[0]} x {box[1]} m (attributes lx, ly); the challenge's is {size} x {size} m")
    return "hdf5", int(shape[0])


def _text_rows(path: str) -> Iterator[list[str]]:
    """The fields of each line that holds data ('#' comments and blank lines dropped)."""
    try:
        with open(path, encoding="ascii") as f:
            for line in f:
                fields = line.split("#", 1)[0].replace(",", " ").split()
                if fields:
                    yield fields
    except UnicodeDecodeError:
        raise BadSurface("neither an HDF5 file nor plain ASCII text") from None


def _is_int(word: str) -> bool:
    return re.fullmatch(r"[-+]?\d+", word) is not None


def _text_layout(path: str) -> tuple[str, int]:
    """('challenge_ascii', n) for a square matrix, ('fourier', n) for a coefficient list."""
    rows, fourier, top_mode = 0, True, 0
    widths: set[int] = set()
    for fields in _text_rows(path):
        rows += 1
        widths.add(len(fields))
        if fourier and len(fields) == 4 and _is_int(fields[0]) and _is_int(fields[1]):
            top_mode = max(top_mode, abs(int(fields[0])), abs(int(fields[1])))
        else:
            fourier = False
    if rows == 0:
        raise BadSurface("holds no numbers")
    if widths == {rows} and rows >= 2:
        return "challenge_ascii", rows
    if fourier:
        n = 2  # the smallest power of two whose grid holds every mode (|k| < n/2), as cmc synthesises it
        while n // 2 <= top_mode:
            n *= 2
        return "fourier", n
    raise BadSurface(f"a text file of {rows} lines of {'/'.join(str(w) for w in sorted(widths))} fields: neither a "
                     "square height matrix (as many rows as columns) nor a Fourier list (lines 'kx ky re im', kx and "
                     "ky integers)")


def inspect(path: str, size: float = 1.0e-4) -> dict[str, Any]:
    """{path, format, points, bytes, sha256} of a surface file for a box of `size` (m, the challenge's
    L); BadSurface says what is wrong."""
    if not os.path.isfile(path):
        raise BadSurface("no such file" if not os.path.exists(path) else "not a regular file")
    if any(ord(c) < 32 or ord(c) == 127 for c in os.path.abspath(path)):
        raise BadSurface("its path holds a control character, which a case file cannot name")
    import h5py
    if h5py.is_hdf5(path):
        fmt, n = _hdf5_layout(path, size)
    elif path.lower().endswith(HDF5_SUFFIXES):
        raise BadSurface(f"named like an HDF5 file ({os.path.splitext(path)[1]}) but not one")
    else:
        fmt, n = _text_layout(path)
    return {"path": os.path.abspath(path), "format": fmt, "points": n, "bytes": os.path.getsize(path),
            "sha256": sha256_of(path)}


def folder_name(info: dict[str, Any]) -> str:
    """<file name without extension>-<first 8 digits of its SHA-256>, in characters safe for a path."""
    stem = re.sub(r"[^A-Za-z0-9._-]", "_", os.path.splitext(os.path.basename(info["path"]))[0]).strip(".") or "surface"
    return f"{stem[:60]}-{info['sha256'][:8]}"


def grid_points(base_n: int, file_n: int) -> int:
    """The runs' grid: the base's where the file is as fine or coarser and divides it (cmc interpolates a
    coarser band-limited map), else the file's own."""
    return base_n if file_n <= base_n and base_n % file_n == 0 else file_n


def toml_string(text: str) -> str:
    """A TOML basic string (inspect refuses paths with control characters)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def surface_base(base_text: str, info: dict[str, Any]) -> tuple[str, int]:
    """challenge-base.toml's text with its [surface] section taken from the file (and its grid raised
    to the file's where needed); returns (text, grid points)."""
    m = re.search(r"(?ms)^\[grid\]\s*$.*?^\s*n\s*=\s*(\d+)", base_text)
    if not m:
        raise ValueError("challenge-base.toml: no [grid] n to set")
    n = grid_points(int(m.group(1)), info["points"])
    text = base_text[:m.start(1)] + str(n) + base_text[m.end(1):]
    section = ("[surface]\n"
               f"kind = \"file\"\n"
               f"path = {toml_string(info['path'])}\n"
               f"format = \"{info['format']}\"   # heights in {UNITS[info['format']]} (height_unit's default)\n\n")
    text, count = re.subn(r"(?ms)^\[surface\]\s*$.*?(?=^\[|\Z)", section, text, count=1)
    if count != 1:
        raise ValueError("challenge-base.toml: no [surface] section")
    body = re.sub(r"\A(#[^\n]*\n)+", "", text)  # the base's own header speaks of cmc's surface
    head = (f"# Written by scripts/main.sh --surface (scripts/surface_file.py): the challenge's case base with its\n"
            f"# surface taken from {info['path']}\n"
            f"# ({info['format']}, {info['points']}² points, sha256 {info['sha256']}). Rewritten on each run.\n")
    return head + body, n


def write_if_changed(path: str, text: str) -> None:
    try:
        with open(path, encoding="utf-8") as f:
            if f.read() == text:
                return
    except OSError:
        pass
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def write_folder(info: dict[str, Any], base_text: str, cases_dir: str, results_dir: str) -> str:
    """RESULTS/surfaces/<name>/ with cases/ and surface.json; returns the folder."""
    folder = os.path.join(results_dir, "surfaces", folder_name(info))
    os.makedirs(os.path.join(folder, "cases"), exist_ok=True)
    base, n = surface_base(base_text, info)
    write_if_changed(os.path.join(folder, "cases", "challenge-base.toml"), base)
    for src in sorted(glob.glob(os.path.join(cases_dir, "*.toml")) + [os.path.join(cases_dir, "tabor-values")]):
        if os.path.basename(src) != "challenge-base.toml" and os.path.isfile(src):
            with open(src, encoding="utf-8") as f:
                write_if_changed(os.path.join(folder, "cases", os.path.basename(src)), f.read())
    write_if_changed(os.path.join(folder, "surface.json"), json.dumps(dict(info, grid_points=n), indent=1) + "\n")
    return folder


def main(argv: Sequence[str], doc: str) -> int:
    """scripts/surface_file.py with arguments argv (its usage text `doc`); exit 0 done, 2 a bad FILE."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("file")
    ap.add_argument("--cases", default="cases/challenge")
    ap.add_argument("--results", default="results")
    a = ap.parse_args(argv)
    with open(os.path.join(a.cases, "challenge-base.toml"), encoding="utf-8") as f:
        base_text = f.read()
    try:
        info = inspect(a.file, tomllib.loads(base_text)["grid"]["size"])
    except (BadSurface, OSError) as e:
        print(f"main: --surface {a.file}: {e}; expected one of the challenge's published layouts: an HDF5 file with "
              f"one square 2-D dataset '{DATASET}', a square ASCII height matrix, or a Fourier list 'kx ky re im' "
              "(heights in units of L = 0.1 mm), or cmc's own height map (cmc surface --write)", file=sys.stderr)
        return 2
    folder = write_folder(info, base_text, a.cases, a.results)
    print(f"main: surface {info['path']} ({info['format']}, {info['points']}² points, sha256 {info['sha256'][:16]}…): "
          f"runs in {folder}", file=sys.stderr)
    print(folder)
    return 0
