"""Archives like scripts/gpu/reference_plan.py's, made here to feed scripts/gpu/ingest.py: a
summary.json per run with the keys the run store reads, and ways to make them hostile."""
import hashlib
import io
import json
import os
import subprocess
import sys
import tarfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
INGEST = os.path.join(ROOT, "scripts", "gpu", "ingest.py")
CMC = os.environ.get("CMC_EXE", os.path.join(ROOT, "build", "cmc"))
# The challenge's hard-wall problem (cases/challenge/reference-load-hardwall.toml), as a run's
# resolved case records it.
HARDWALL_CASE = {"case": {"name": "challenge-hardwall"}, "interaction": {"kind": "hard_wall"},
                 "solver": {"tolerance": 1e-6}, "material": {"contact_modulus": 25e6},
                 "grid": {"size": 1e-4}, "loading": {"control": "mean_pressure", "values": [250e3]},
                 "surface": {"hurst": 0.8, "rolloff_wavelength": 20e-6, "cutoff_wavelength": 0.1e-6,
                             "rms_gradient": 1.0, "seed": 28}}
# The stored 16384² hard-wall run's answer (reference/challenge/runs.json), which a 32768² run
# of the same sequence agrees with to within the best estimate's band.
A_R, MEAN_GAP = 0.020484112203121185, 1.0127047979740923e-06


def summary(n, a_r=A_R, *, mean_gap=MEAN_GAP, pressure=250e3, status="converged", backend="cuda"):
    """A hard-wall run's summary.json (parsed) on n² with this answer, in force balance."""
    return {"cmc_version": "0.1.0", "case_file": "cases/challenge/reference-load-hardwall.toml",
            "status": status, "message": "", "case": HARDWALL_CASE,
            "grid": {"nx": n, "ny": n, "backend": backend, "dx": 1e-4 / n, "size_x": 1e-4, "size_y": 1e-4,
                     "threads": 16},
            "surface_facts": {"rms_height": 1.1e-6},
            "timing": {"iterations": 150, "fft_pairs": 380, "wall_s": 20.0},
            "steps": [{"index": 0, "mean_pressure": pressure, "force": pressure * 1e-8, "contact_fraction": a_r,
                       "mean_gap": mean_gap, "converged": status == "converged", "wall_s": 10.0,
                       "observables": {"repulsive_fraction": a_r}}]}


def member(t, name, data=None, *, mode=None, kind=tarfile.REGTYPE):
    """Add one member to the open tarfile t: a file with data (bytes or str), or a folder."""
    info = tarfile.TarInfo(name)
    info.type = kind
    info.mtime = 1_700_000_000
    if kind == tarfile.DIRTYPE:
        info.mode = 0o755 if mode is None else mode
        t.addfile(info)
        return
    raw = data.encode() if isinstance(data, str) else (data or b"")
    info.size, info.mode = len(raw), 0o644 if mode is None else mode
    t.addfile(info, io.BytesIO(raw))


def plan_archive(path, runs, *, date="2026-01-02", device="NVIDIA test GPU", top="plan", extra=()):
    """Write a .tgz with top/machine.txt and, per (tag, summary) in runs, top/runs/TAG/summary.json
    and top/TAG.command; `extra` adds (name, data, mode) members."""
    with tarfile.open(path, "w:gz") as t:
        member(t, f"{top}/machine.txt", f"device {device}\ncores 16\ndate {date}\n")
        member(t, f"{top}/build.txt", "commit 0123456789ab\n")
        for tag, s in runs:
            member(t, f"{top}/runs/{tag}/summary.json", json.dumps(s))
            member(t, f"{top}/{tag}.command", f"cmc run cases/challenge/reference-load-hardwall.toml   ({tag})\n")
        for name, data, mode in extra:
            member(t, name, data, mode=mode)
    return path


def scratch_repo(tmp):
    """A scratch copy of reference/challenge (ref/, its runs.json the store) and an empty results/."""
    ref = os.path.join(tmp, "scratch", "ref")
    os.makedirs(os.path.join(tmp, "scratch", "results"))
    subprocess.run(["cp", "-r", os.path.join(ROOT, "reference", "challenge"), ref], check=True)
    return ref


def ingest(tmp, archive, *more):
    """Run ingest.py on the archive against the scratch copy; the finished process."""
    s = os.path.join(tmp, "scratch")
    return subprocess.run([sys.executable, INGEST, archive, "--store", os.path.join(s, "ref", "runs.json"),
                           "--out", os.path.join(s, "ref"), "--results", os.path.join(s, "results"), "--cmc", CMC,
                           *more], capture_output=True, text=True, cwd=ROOT)


def snapshot(folder):
    """{relative path: (mode, sha256 or None for a folder)} of everything under folder."""
    out = {}
    for d, dirs, files in os.walk(folder):
        for name in dirs + files:
            p = os.path.join(d, name)
            st = os.lstat(p)
            digest = None
            if os.path.isfile(p) and not os.path.islink(p):
                with open(p, "rb") as f:
                    digest = hashlib.sha256(f.read()).hexdigest()
            out[os.path.relpath(p, folder)] = (st.st_mode, digest)
    return out
