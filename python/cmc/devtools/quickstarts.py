"""The README's quickstarts (scripts/check_docs.py --quickstarts-only): every command of the shell
blocks of README.md's section "Quickstart" runs, in a mirror of the repository whose challenge
cases are set to SMALL_GRID² (cases/challenge/*.toml, grid.n) and whose scripts/setup.sh is the
build under test, so nothing is built, installed or written in the repository. How each command
runs there is plan()'s table; a command it does not know fails the check."""
import glob
import os
import re
import shlex
import shutil
import subprocess
import tempfile
import time
from typing import Optional, Union

from .markdown import SHELL_BLOCKS, Problems, markdown_lines

SMALL_GRID = 64
# How one command runs: (argv, None where it is not run, or "unknown"; the exit codes accepted;
# text its stderr must hold, or None; a note).
Plan = tuple[Union[list[str], str, None], tuple[int, ...], Optional[str], str]


def quickstart_commands(readme: str) -> list[tuple[int, list[str]]]:
    """(line, command) for each command of the shell blocks in README's '## Quickstart' section."""
    cmds: list[tuple[int, list[str]]] = []
    inside, pending = False, ""
    for n, text, lang in markdown_lines(readme):
        if lang is None and text.startswith("## "):
            inside = text[3:].strip().lower().startswith("quickstart")
            continue
        if not inside or lang is None or lang not in SHELL_BLOCKS:
            continue
        line = text.rstrip()
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        line = pending + line
        pending = ""
        words = shlex.split(line, comments=True)
        if words:
            cmds.append((n, words))
    return cmds


def build_has(build: str, option: str) -> bool:
    try:
        with open(os.path.join(build, "CMakeCache.txt"), encoding="utf-8") as f:
            return any(line.strip() == f"{option}:BOOL=ON" for line in f)
    except OSError:
        return False


def small_grid(words: list[str]) -> list[str]:
    """The same command line with any --set grid.n=N above the small grid lowered to it."""
    out = list(words)
    for i, w in enumerate(out):
        m = re.fullmatch(r"grid\.n=(\d+)", w)
        if m and i > 0 and out[i - 1] == "--set" and int(m.group(1)) > SMALL_GRID:
            out[i] = f"grid.n={SMALL_GRID}"
    return out


def plan(words: list[str], build: str) -> Plan:
    """How the docs check runs one quickstart command: (argv or None, exit codes accepted, stderr
    text required or None, note). None: not run, and the note says why."""
    head = words[0]
    if head == "cmake":
        return None, (), None, "configures or builds a build folder (minutes): the test command's builds stand in"
    if head == "scripts/mpi.sh":
        return None, (), None, "builds build-mpi/ (minutes): scripts/test.sh runs it"
    if head == "mpirun":
        i = next((k for k, w in enumerate(words) if w.endswith("/cmc")), None)
        if i is None:
            return "unknown", (), None, ""
        return (["build/cmc"] + small_grid(words[i + 1:]), (0,), None,
                "the same arguments through the serial build (the MPI build is scripts/mpi.sh's)")
    if head == "build-cuda/cmc":
        argv = ["build/cmc"] + small_grid(words[1:])
        if build_has(build, "CMC_CUDA"):
            return argv, (0,), None, "the CUDA build under test"
        return argv, (2,), "has no CUDA backend", "a CPU build: the case and options are read, then refused by name"
    if head == "build/cmc":
        codes = (0, 5) if len(words) > 1 and words[1] == "check" else (0,)
        return ["build/cmc"] + small_grid(words[1:]), codes, None, ""
    if head in ("scripts/main.sh", "scripts/report.sh", "/usr/bin/python3"):
        return list(words), (0,), None, ""
    if head in ("less", "cat", "head"):
        return ["test", "-e", words[-1]], (0,), None, f"checks that {words[-1]} exists"
    return "unknown", (), None, ""


def make_mirror(root: str, build: str, tmp: str) -> None:
    """A copy of the repository's layout in tmp, of links except where a run would write or build."""
    for name in sorted(os.listdir(root)):
        if name.startswith(".git") or name in ("build", "results", "out") or name.startswith("build"):
            continue
        if name in ("scripts", "cases", "reports"):
            continue
        os.symlink(os.path.join(root, name), os.path.join(tmp, name))
    os.symlink(os.path.abspath(build), os.path.join(tmp, "build"))
    link_folder(root, tmp, "scripts", skip=("setup.sh",))
    with open(os.path.join(tmp, "scripts", "setup.sh"), "w", encoding="utf-8") as f:
        f.write("#!/bin/sh\n# docs check: the build under test stands in for installing and building\n"
                "test -x build/cmc || { echo 'docs check: build/cmc missing' >&2; exit 1; }\n")
    os.chmod(os.path.join(tmp, "scripts", "setup.sh"), 0o755)
    link_folder(root, tmp, "reports", skip=("challenge", "validation", "performance", "surfaces", "__pycache__"))
    link_folder(root, tmp, "cases", skip=("challenge",))
    mirror_challenge_cases(root, tmp)


def link_folder(root: str, tmp: str, folder: str, skip: tuple[str, ...]) -> None:
    """tmp/folder as a real folder of links to root/folder's entries, but those in skip."""
    os.makedirs(os.path.join(tmp, folder), exist_ok=True)
    src = os.path.join(root, folder)
    for name in os.listdir(src) if os.path.isdir(src) else []:
        if name not in skip:
            os.symlink(os.path.join(src, name), os.path.join(tmp, folder, name))


def mirror_challenge_cases(root: str, tmp: str) -> None:
    """Copies of cases/challenge/*.toml whose [grid] n is the small grid."""
    os.makedirs(os.path.join(tmp, "cases", "challenge"), exist_ok=True)
    for src in glob.glob(os.path.join(root, "cases", "challenge", "*")):
        with open(src, encoding="utf-8") as f:
            text = f.read()
        if src.endswith(".toml"):
            text = re.sub(r"(?m)^(\s*n\s*=\s*)\d+", rf"\g<1>{SMALL_GRID}", text, count=1)
        with open(os.path.join(tmp, "cases", "challenge", os.path.basename(src)), "w", encoding="utf-8") as f:
            f.write(text)


def run_quickstarts(root: str, build: str, out: Problems, keep: bool) -> None:
    readme = os.path.join(root, "README.md")
    cmds = quickstart_commands(readme)
    if not cmds:
        out.add(readme, 1, "no shell commands found under a '## Quickstart' heading")
        return
    tmp = tempfile.mkdtemp(prefix="cmc-docs-check-")
    env = dict(os.environ, CMC_THREADS=os.environ.get("CMC_THREADS", "1"), CMC_PROGRESS_EVERY="600")
    try:
        make_mirror(root, build, tmp)
        for n, words in cmds:
            run_one(readme, n, words, build, tmp, env, out)
    finally:
        if keep:
            print(f"check_docs: the mirror is kept in {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)


def run_one(readme: str, n: int, words: list[str], build: str, tmp: str, env: dict[str, str],
            out: Problems) -> None:
    argv, codes, need, note = plan(words, build)
    shown = shlex.join(words)
    if argv == "unknown":
        out.add(readme, n, f"quickstart command '{shown}': the docs check does not know how to run it "
                           "(add a rule to plan() in python/cmc/devtools/quickstarts.py)")
        return
    if argv is None:
        print(f"check_docs: line {n}: not run: {shown} ({note})")
        return
    t0 = time.monotonic()
    try:
        r = subprocess.run(argv, cwd=tmp, env=env, capture_output=True, text=True, timeout=300)
    except (OSError, subprocess.TimeoutExpired) as e:
        out.add(readme, n, f"quickstart command '{shown}' did not run: {e}")
        return
    took = time.monotonic() - t0
    print(f"check_docs: line {n}: exit {r.returncode} in {took:.1f} s: {shlex.join(argv)}"
          + (f" ({note})" if note else ""))
    if r.returncode not in codes or (need and need not in r.stderr):
        tail = (r.stderr or r.stdout).strip().splitlines()[-5:]
        out.add(readme, n, f"quickstart command '{shown}' (run as '{shlex.join(argv)}') exited "
                           f"{r.returncode}, expected {' or '.join(map(str, codes))}"
                           + (f" with '{need}' in its message" if need else "") + ": " + " | ".join(tail))
