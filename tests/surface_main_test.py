#!/usr/bin/python3
"""scripts/main.sh --surface FILE end to end (ctest challenge.surface_file), in a mirror of the
repository whose challenge cases are at 64² (the docs check's, cmc.devtools.quickstarts, with BUILD's cmc):

  - surface files in the challenge's published layout, made here from cmc's own surfaces at 64²:
    an HDF5 file with one 2-D dataset `surface` (seed 28's heights) and a real-space ASCII
    matrix (seed 29's), heights in units of L = 0.1 mm;
  - `scripts/main.sh --quick` (seed 28) and `--surface FILE --quick` for each file (the ASCII
    one given relative to another folder) write runs and reports of their own;
  - every run on a file records it (summary.json: case.surface and "surface"), its rms height is
    the file's times L, and the HDF5 file's runs give seed 28's numbers (the same heights);
  - each surface report names the file's path and SHA-256 and says that the best estimates are
    cmc's surface's; the seed-28 report names no file;
  - a missing file, a text file in no layout and an HDF5 file without the dataset `surface` exit 2
    naming the file, and write no results folder;
  - scripts/surface_file.py reads cmc's own HDF5 and a Fourier list (whose generated case gives
    the list's rms height), and picks the file's grid where the base's cannot hold it.

    /usr/bin/python3 tests/surface_main_test.py BUILD
"""
import glob
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
from cmc.devtools.quickstarts import SMALL_GRID, make_mirror  # the package cmc is on PYTHONPATH (ctest sets it)

L = 1.0e-4  # m, the challenge's system size: the published files' height unit
# The HDF5 file holds seed 28's heights divided by L; cmc multiplies them back. Measured (same build
# and threads for both runs): a_r equal, mean gap 8.9e-16 relative apart without adhesion and equal
# with it (the heights' one rounding); 1e-12 leaves nothing for a wrong unit, orientation or surface.
SAME_RUN = 1e-12


def sh(args, mirror, cwd=None):
    env = dict(os.environ, CMC_THREADS="1", CMC_PROGRESS_EVERY="600")
    return subprocess.run(args, cwd=cwd or mirror, env=env, capture_output=True, text=True, timeout=600)


def cmc_heights(mirror, seed):
    """Seed `seed`'s surface on the mirror's 64² challenge grid, in metres, as cmc writes it (rows: y)."""
    out = os.path.join(mirror, f"seed{seed}.h5")
    r = sh(["build/cmc", "surface", "cases/challenge/reference-load-hardwall.toml", "--set", f"surface.seed={seed}",
            "--write", out], mirror)
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        return np.array(f["surface"])


def published_files(mirror, folder):
    """The two files in the published layout: HDF5 (seed 28) and ASCII (seed 29), in units of L."""
    h5 = os.path.join(folder, "organisers-like.h5")
    with h5py.File(h5, "w") as f:
        f.create_dataset("surface", data=cmc_heights(mirror, 28) / L)
    txt = os.path.join(folder, "organisers-like.txt")
    np.savetxt(txt, cmc_heights(mirror, 29) / L, fmt="%.17g")
    return h5, txt


def summaries(folder):
    out = {}
    for name in ("challenge-reference", "challenge-hardwall"):
        with open(os.path.join(folder, name, "summary.json")) as f:
            out[name] = json.load(f)
    return out


def check_surface_run(mirror, path, fmt, cwd, failures):
    """main.sh --surface PATH --quick: its runs used the file and its report names it; returns the runs."""
    r = sh(["bash", os.path.join(mirror, "scripts", "main.sh"), "--surface", os.path.basename(path), "--quick"],
           mirror, cwd=cwd)
    if r.returncode != 0:
        failures.append(f"main.sh --surface {path} --quick: exit {r.returncode}: {r.stderr[-2000:]}")
        return None
    digest = hashlib.sha256(open(path, "rb").read()).hexdigest()
    name = f"{os.path.splitext(os.path.basename(path))[0]}-{digest[:8]}"
    runs = summaries(os.path.join(mirror, "results", "surfaces", name))
    heights = np.loadtxt(path) if fmt == "challenge_ascii" else np.array(h5py.File(path, "r")["surface"])
    file_rms = float(np.sqrt(np.mean((heights - heights.mean()) ** 2))) * L
    for run, s in runs.items():
        surf = s["case"]["surface"]
        if surf.get("kind") != "file" or surf.get("path") != path or surf.get("format") != fmt or path not in s["surface"]:
            failures.append(f"{name}/{run}: summary.json's surface is {surf} / '{s['surface']}', not {fmt} {path}")
        if s["grid"]["nx"] != SMALL_GRID:
            failures.append(f"{name}/{run}: ran on {s['grid']['nx']}², not the file's {SMALL_GRID}²")
        rms = s["surface_facts"]["rms_height"]
        if abs(rms / file_rms - 1) > 1e-9:
            failures.append(f"{name}/{run}: rms height {rms} m, the file's is {file_rms} m (a unit other than L?)")
    report = os.path.join(mirror, "reports", "surfaces", name, "challenge", "index.md")
    text = open(report).read() if os.path.isfile(report) else ""
    for needle in (path, digest, "## Your surface", "best estimate (cmc's surface, seed 28)",
                   f"your run on `{os.path.basename(path)}`", "--against realisation"):
        if needle not in text:
            failures.append(f"{report}: does not say '{needle}'")
    return runs


def check_refused(mirror, args, needles, failures):
    before = sorted(glob.glob(os.path.join(mirror, "results", "surfaces", "*")))
    r = sh(["scripts/main.sh"] + args + ["--quick"], mirror)
    missing = [n for n in needles if n not in r.stderr]
    if r.returncode != 2 or missing:
        failures.append(f"main.sh {' '.join(args)}: exit {r.returncode} (expected 2), message lacks {missing}: "
                        f"{r.stderr.strip()[-600:]}")
    if sorted(glob.glob(os.path.join(mirror, "results", "surfaces", "*"))) != before:
        failures.append(f"main.sh {' '.join(args)}: wrote a results folder for a refused file")


def bad_files(mirror, folder, failures):
    missing = os.path.join(folder, "no-such-surface.h5")
    check_refused(mirror, ["--surface", missing], [missing, "no such file"], failures)
    words = os.path.join(folder, "notes.txt")
    with open(words, "w") as f:
        f.write("these are not heights\nnor a fourier list\n")
    check_refused(mirror, ["--surface", words], [words, "neither a square height matrix"], failures)
    wrong = os.path.join(folder, "heights.h5")
    with h5py.File(wrong, "w") as f:
        f.create_dataset("heights", data=np.zeros((SMALL_GRID, SMALL_GRID)))
    check_refused(mirror, ["--surface", wrong], [wrong, "without a dataset 'surface'"], failures)


def layouts(mirror, folder, failures):
    """scripts/surface_file.py's reading of the other layouts: cmc's own HDF5 height map (metres, its
    box in attributes), a Fourier list (its grid: the smallest power of two that holds its modes),
    and the grid the runs take for files finer than, coarser than or not dividing the base's."""
    from cmc.surface_file import grid_points, inspect, surface_base
    info = inspect(os.path.join(mirror, "seed28.h5"))
    if (info["format"], info["points"]) != ("hdf5", SMALL_GRID):
        failures.append(f"cmc surface --write's file read as {info['format']}, {info['points']}² (expected hdf5, 64²)")
    modes = [(1, 0, 1e-3, 0.0), (0, 3, 0.0, -5e-4)]
    four = os.path.join(folder, "modes.txt")
    with open(four, "w") as f:
        f.write("# kx ky re im\n" + "".join(f"{kx} {ky} {re!r} {im!r}\n" for kx, ky, re, im in modes))
    info = inspect(four)
    if (info["format"], info["points"]) != ("fourier", 8):
        failures.append(f"{four}: read as {info['format']}, {info['points']}² (expected fourier, 8²)")
    base = open(os.path.join(mirror, "cases", "challenge", "challenge-base.toml")).read()
    if surface_base(base, dict(info, points=4096))[1] != 4096:
        failures.append("a 4096² file on the 64² base does not run on 4096² (cmc never down-samples)")
    for base_n, file_n, want in ((2048, 512, 2048), (2048, 2048, 2048), (2048, 8192, 8192), (2048, 1000, 1000)):
        if grid_points(base_n, file_n) != want:
            failures.append(f"grid_points({base_n}, {file_n}) = {grid_points(base_n, file_n)}, expected {want}")
    r = sh(["/usr/bin/python3", "scripts/surface_file.py", four], mirror)
    case = os.path.join(r.stdout.strip(), "cases", "reference-load-hardwall.toml")
    out = os.path.join(folder, "modes.h5")
    r = sh(["build/cmc", "surface", case, "--write", out], mirror)
    if r.returncode != 0:
        return failures.append(f"cmc surface {case}: exit {r.returncode}: {r.stderr}")
    h = np.array(h5py.File(out, "r")["surface"])
    want = np.sqrt(2 * sum(re * re + im * im for _, _, re, im in modes)) * L  # each mode and its conjugate
    rms = float(np.sqrt(np.mean((h - h.mean()) ** 2)))
    if abs(rms / want - 1) > 1e-9:
        failures.append(f"{four}: rms height {rms} m on the generated case, expected {want} m (a unit other than L?)")


def main(argv):
    if len(argv) != 2 or not os.access(os.path.join(argv[1], "cmc"), os.X_OK):
        print(__doc__, file=sys.stderr)
        return 2
    failures = []
    mirror = tempfile.mkdtemp(prefix="cmc-surface-test-")
    try:
        make_mirror(ROOT, os.path.abspath(argv[1]), mirror)
        files = os.path.join(mirror, "user-files")
        os.makedirs(files)
        h5, txt = published_files(mirror, files)
        r = sh(["scripts/main.sh", "--quick"], mirror)
        assert r.returncode == 0, f"main.sh --quick: exit {r.returncode}: {r.stderr[-2000:]}"
        own = summaries(os.path.join(mirror, "results"))
        from_h5 = check_surface_run(mirror, h5, "challenge_hdf5", files, failures)
        check_surface_run(mirror, txt, "challenge_ascii", files, failures)
        for run in own if from_h5 else ():
            a, b = own[run]["steps"][-1], from_h5[run]["steps"][-1]
            for key in ("contact_fraction", "mean_gap"):
                if abs(b[key] / a[key] - 1) > SAME_RUN:
                    failures.append(f"{run}: {key} {b[key]!r} on the HDF5 file of seed 28's heights, {a[key]!r} on "
                                    f"seed 28 itself (relative {b[key] / a[key] - 1:.2g}, allowed {SAME_RUN:g})")
        seed28 = open(os.path.join(mirror, "reports", "challenge", "index.md")).read()
        if "organisers-like" in seed28 or "## Your surface" in seed28:
            failures.append("reports/challenge/index.md (seed 28) names a surface file: the runs mixed")
        bad_files(mirror, files, failures)
        layouts(mirror, files, failures)
    finally:
        shutil.rmtree(mirror, ignore_errors=True)
    for f in failures:
        print("FAIL:", f)
    print("surface_main_test:", "FAILED" if failures else "ok")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
