#!/usr/bin/python3
"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/) from the
files cmc ships: case files (cases/**/*.toml, with and without --set overrides; a case
that names a base with its bases merged in, and one whose base is itself),
reference curves (reference/*.csv, reference/challenge/*.csv, cut to their first rows),
and small height files in every format the readers take (ASCII matrices and Fourier
lists as the writers write them; HDF5 files as cmc's writer writes them plus the
variants other tools write: float32, integers, chunked and compressed, the newest file
format, wrong ranks). Deterministic: running it again rewrites the same bytes.

usage: . scripts/python_path.sh && /usr/bin/python3 tests/fuzz/make_corpus.py
(from the checkout; needs h5py, numpy and the package cmc: python_path.sh gives the build's)
"""
import glob
import json
import os
import re
import shutil
import tomllib

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from cmc.case_files import read_case_file  # noqa: E402
CORPUS = os.path.join(ROOT, "tests", "fuzz", "corpus")
MAX_ROWS = 40  # data rows kept from a reference curve: a small seed is a fast seed


def fresh(target):
    d = os.path.join(CORPUS, target)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


def write(d, name, data):
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # a JSON string is a TOML basic string
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return repr(v)


def toml_text(table, prefix=""):
    """A table (as tomllib reads it) written back as TOML: values, then sub-tables and arrays
    of tables, each under its header."""
    lines, subs = [], []
    for k, v in table.items():
        if isinstance(v, dict):
            subs.append(f"\n[{prefix}{k}]\n" + toml_text(v, f"{prefix}{k}."))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            subs += [f"\n[[{prefix}{k}]]\n" + toml_text(x, f"{prefix}{k}.") for x in v]
        else:
            lines.append(f"{k} = {toml_value(v)}\n")
    return "".join(lines) + "".join(subs)


def case_text(path):
    """A case file's bytes; one that names a base, with its bases merged in (the fuzz target
    writes one file, where a base could not be found), as the program merges them."""
    data = open(path, "rb").read()
    if "base" not in tomllib.loads(data.decode("utf-8")):
        return data
    return ("# " + os.path.relpath(path, ROOT) + " with its bases merged in (make_corpus.py)\n" +
            toml_text(read_case_file(path))).encode("utf-8")


def case_corpus():
    d = fresh("case")
    files = sorted(glob.glob(os.path.join(ROOT, "cases", "**", "*.toml"), recursive=True))
    for f in files:
        write(d, os.path.basename(f), case_text(f))
    # A base that is the file itself (the target's case.toml): the cycle check, and mutations
    # of the base key from there.
    write(d, "base-self.toml", 'base = "case.toml"\n\n[case]\nname = "base-self"\n')
    # --set strings follow the case text, each after a NUL byte (fuzz_case.cpp).
    overrides = {
        "hertz-free.toml": ["grid.n=64", "solver.tolerance=1e-8", "grid.boundary=periodic"],
        "reference-load.toml": ["grid.n=256", "loading.values=[1e5, 2e5]", "interaction.kind=hard_wall"],
        "westergaard.toml": ["surface.wavelength=5e-4", "observables.enabled=true", "output.fields=false"],
        "maugis-dugdale-lambda1.toml": ["interaction.smoothing=1e-9", "loading.refine_pulloff=2",
                                        "validation.reference=\"jkr\""],
    }
    # Inputs of findings (tests/test_case.cpp IntegerRangesFoundByFuzzing), replayed on every run.
    regressions = {
        "regress-int-wrap": ("hertz-free.toml", ["grid.n=4294967297", "solver.max_iterations=4294967296"]),
        "regress-grid-1e300": ("hertz-free.toml", ["validation.refinement.grids=[64, 1e300]"]),
        "regress-huge-grid": ("hertz-free.toml", ["grid.n=2147483647"]),
    }
    seeds = [(name.replace(".toml", ".set"), (name, sets)) for name, sets in overrides.items()]
    for out, (name, sets) in seeds + list(regressions.items()):
        (path,) = [f for f in files if os.path.basename(f) == name]
        write(d, out, case_text(path) + b"".join(b"\0" + s.encode() for s in sets))


def case_dictionary():
    """tests/fuzz/case.dict (libFuzzer -dict): the sections, keys and kind words of a case
    file (docs/user-guide/case-files.md's tables, input/Kinds.hpp's words) and some TOML, so that
    mutations write keys the parser knows instead of guessing them letter by letter."""
    readme = open(os.path.join(ROOT, "docs", "user-guide", "case-files.md"), encoding="utf-8").read()
    kinds = open(os.path.join(ROOT, "solver", "cmc", "input", "Kinds.hpp"), encoding="utf-8").read()
    sections = set(re.findall(r"^### `\[([a-z_.]+)\]`", readme, re.M))
    words = sections | {"[%s]" % s for s in sections} | {"[[validation.check]]", "[validation.refinement]"}
    for row in re.findall(r"^\| ([^|]+) \|", readme, re.M):
        words |= set(re.findall(r"`([a-z_]+)`", row))
    words |= {'"%s"' % w for w in re.findall(r'\{[A-Za-z0-9]+, "([a-z0-9_]+)"\}', kinds)}
    words |= {"grids", "quantity", "min_order", "check", "refinement"}  # [validation], documented in prose
    words |= {" = ", "\n", "[", "]", "{", "}", ", ", "#", "1e-3", "-1", "0", "true", "false", "inf", "nan",
              "'''", '"""', "1979-05-27T07:32:00Z", "9223372036854775807", "1e308", "\0"}
    escape = {"\\": "\\\\", '"': '\\"', "\n": "\\x0A", "\0": "\\x00"}
    with open(os.path.join(ROOT, "tests", "fuzz", "case.dict"), "w", encoding="utf-8") as f:
        f.write("# Generated by tests/fuzz/make_corpus.py: words of a case file, for fuzz_case -dict=.\n")
        for w in sorted(words):
            f.write('"%s"\n' % "".join(escape.get(c, c) for c in w))


def ascii_corpus():
    d = fresh("ascii_heights")
    rng = np.random.default_rng(12)
    m = rng.normal(size=(4, 4))
    write(d, "matrix-4x4.txt", "".join(" ".join("%.17g" % v for v in row) + "\n" for row in m))
    write(d, "matrix-3x2-commas.txt", "# heights in um\n1.5, -2, 3e-3\n\n+4,5.25,6 # last row\n")
    write(d, "matrix-1x1.txt", "0\n")
    # Fourier lists: "kx ky re im", one member of a pair, or both, comments.
    write(d, "fourier.txt", "# kx ky re im\n0 0 0.5 0\n1 0 0.25 -0.125\n0 1 1e-3 2e-3\n-1 2 3 4\n")
    write(d, "fourier-pair.txt", "2 1 0.5 0.25\n-2 -1 0.5 -0.25\n3.0 0 1 0\n")


def hdf5_choices_corpus():
    """fuzz_hdf5_heights reads its input as choices (FuzzedDataProvider), not as a file:
    its seeds are byte strings of a few lengths, from a fixed generator."""
    d = fresh("hdf5_heights")
    rng = np.random.default_rng(5)
    for n in (16, 64, 200, 600, 2000):
        write(d, "choices-%d" % n, rng.integers(0, 256, size=n, dtype=np.uint8).tobytes())


def hdf5_corpus():
    d = fresh("hdf5_bytes")
    rng = np.random.default_rng(3)

    def h5(name, build, libver=None):
        # No time stamps (the newest format stamps objects): the same bytes on every run.
        fcpl = h5py.h5p.create(h5py.h5p.FILE_CREATE)
        fcpl.set_obj_track_times(False)
        fapl = h5py.h5p.create(h5py.h5p.FILE_ACCESS)
        if libver:
            fapl.set_libver_bounds(h5py.h5f.LIBVER_LATEST, h5py.h5f.LIBVER_LATEST)
        fid = h5py.h5f.create(os.path.join(d, name).encode(), h5py.h5f.ACC_TRUNC, fcpl=fcpl, fapl=fapl)
        with h5py.File(fid) as f:
            build(f)

    def cmc_written(f):  # as write_hdf5_heights writes: {ny, nx} doubles, lx and ly
        ds = f.create_dataset("surface", data=rng.normal(size=(4, 4)), dtype="<f8")
        ds.attrs["lx"] = 1e-4
        ds.attrs["ly"] = 1e-4
    h5("cmc-4x4.h5", cmc_written)
    h5("challenge-f32-2x2.h5", lambda f: f.create_dataset("surface", data=np.arange(4, dtype="<f4").reshape(2, 2)))
    h5("int16-3x2.h5", lambda f: f.create_dataset("surface", data=np.arange(6, dtype="<i2").reshape(2, 3)))

    def chunked(f):
        ds = f.create_dataset("surface", data=rng.normal(size=(8, 8)), chunks=(4, 4), compression="gzip",
                              shuffle=True)
        ds.attrs["lx"] = 2.0
        ds.attrs["ly"] = 1.0
    h5("chunked-gzip-8x8.h5", chunked)

    def latest(f):
        ds = f.create_dataset("surface", data=np.full((2, 2), 0.5), track_times=False)
        ds.attrs["lx"] = 1.0
        ds.attrs["ly"] = 1.0
    h5("libver-latest-2x2.h5", latest, libver="latest")
    h5("rank1.h5", lambda f: f.create_dataset("surface", data=np.arange(5, dtype="<f8")))
    h5("group-not-dataset.h5", lambda f: f.create_group("surface").create_dataset("x", data=np.zeros((2, 2))))

    # Inputs of findings (tests/test_surface.cpp Hdf5FilesFoundByFuzzing).
    def lx_array(f):  # eight values where the reader read one into one double
        ds = f.create_dataset("surface", data=np.ones((4, 4)))
        ds.attrs["lx"] = np.arange(1.0, 9.0)
        ds.attrs["ly"] = 1.0
    h5("regress-lx-array.h5", lx_array)

    def unwritten(f):  # 2^20 x 2^20 declared, nothing written
        ds = f.create_dataset("surface", shape=(1 << 20, 1 << 20), dtype="<f8", chunks=(1024, 1024))
        ds.attrs["lx"] = 1.0
        ds.attrs["ly"] = 1.0
    h5("regress-unwritten.h5", unwritten)


def check_corpus():
    d = fresh("check_csv")
    for f in sorted(glob.glob(os.path.join(ROOT, "reference", "*.csv")) +
                    glob.glob(os.path.join(ROOT, "reference", "challenge", "*.csv"))):
        lines = open(f, encoding="utf-8").read().splitlines(keepends=True)
        header = next(i for i, l in enumerate(lines) if not l.startswith("#"))
        name = os.path.basename(f) if "challenge" not in f else "challenge-" + os.path.basename(f)
        write(d, name, "".join(lines[: header + 1 + MAX_ROWS]))
    # Predictions as a participant writes them: units in the column names, reduced units,
    # a decreasing abscissa, an extra column, a BOM.
    write(d, "pred-area-pressure.csv", "pressure_MPa,contact_fraction\n0.1,0.004\n0.25,0.0095\n0.5,0.02\n1,0.041\n")
    write(d, "pred-gap-reduced.csv", "# my run\ngap_over_L,pdf_times_L\n1e-4,3\n1e-3,50\n1e-2,7\n")
    write(d, "pred-stress-decreasing.csv", "stress_kPa,density_per_MPa,extra\n500,0.1,1\n100,2,2\n-20,0.5,3\n")
    write(d, "pred-bom.csv", "\ufeffy_um,gap_nm\n0,10\n50,20\n100,15\n")
    # The submissions' layouts: spaces, tabs, semicolons; a headerless file is bad input
    # unless --columns names its columns (which the fuzzer does not pass).
    write(d, "pred-spaces.txt", "# p/E*  a_r\n p_over_Estar   contact_fraction\n 1e-3  2.2e-3\n 1e-2   2.4e-2\n")
    write(d, "pred-tabs-semicolons.txt", "gap_nm;density_per_nm\n1;0.5\n10;0.05\n")
    write(d, "pred-headerless.txt", "1e4\t0.001\n2e4\t0.002\n")
    # A reference with its own error band (# band:), in cmc's format.
    write(d, "ref-band.csv", "# cmc-reference-csv: 1\n# name: band\n# quantity: contact_area_vs_pressure\n"
          "# source: cmc run\n# unit.pressure_Pa: Pa\n# unit.contact_fraction: 1\n# unit.contact_fraction_err: 1\n"
          "# columns: pressure_Pa,contact_fraction,contact_fraction_err\n# x: pressure_Pa\n# y: contact_fraction\n"
          "# representation: log-log\n# band: contact_fraction_err\n# estimated_error: test\n"
          "pressure_Pa,contact_fraction,contact_fraction_err\n1e4,0.001,1e-4\n1e5,0.01,2e-3\n1e6,0.1,0.2\n")
    # Inputs of findings (tests/test_check.cpp, "overflow in SI", "errors overflow").
    write(d, "regress-si-overflow.csv", "patch_area_m2,density_per_nm2\n1e-12,1e300\n1e-11,1e300\n")
    write(d, "regress-error-overflow.csv", "y_m,gap_m\n0,1e308\n1e-5,-1e308\n")


if __name__ == "__main__":
    case_corpus()
    case_dictionary()
    ascii_corpus()
    hdf5_corpus()
    hdf5_choices_corpus()
    check_corpus()
    for t in sorted(os.listdir(CORPUS)):
        files = os.listdir(os.path.join(CORPUS, t))
        size = sum(os.path.getsize(os.path.join(CORPUS, t, f)) for f in files)
        print("%-14s %3d seeds, %6d bytes" % (t, len(files), size))
