#!/usr/bin/python3
"""The docs check: README.md and docs/ name only what exists, and the README's quickstarts run.

  check_docs.py [--root DIR] [--build DIR] [--links-only | --quickstarts-only | --comments-only] [--keep] [FILE ...]

Links and paths (every FILE, default README.md and docs/**/*.md):
  - every relative Markdown link or image resolves to a file or folder of the repository, and a
    link's #anchor to a heading of the page it names (GitHub's heading slugs);
  - every repository path named in code (inline `...` or a shell block), i.e. a word that starts
    with one of the repository's top-level folders or files, exists; `<...>` and `*` in a path
    match any name, and at least one file must match. Paths under the folders .gitignore
    anchors at the root (build*/, results/, reports/challenge/, ...) are outputs and not checked.
Comments (--comments-only): every comment line (`//`, `/* */`, `#`, a Python docstring) of
the tracked sources in COMMENT_FOLDERS says what and why, not when or by whom: none names an
issue of the project's tracker (the word issue and a number, or a number after a hash; one
after another project's owner/name is a citation), a date (year-month, with or without the
day, or a month's name and a year), a commit, or tells a diary's story (what day or time
of day it was written, or by whom): HISTORY's patterns. Data files (CSV, JSON, HDF5, the fuzz corpus) are
not read: run dates inside fixtures stay.
Quickstarts (README.md's section "Quickstart"): every command of its shell blocks runs, in a
mirror of the repository whose challenge cases are set to 64² (cases/challenge/*.toml, grid.n)
and whose scripts/setup.sh is the build under test (--build), so nothing is built, installed
or written in the repository. How each command runs there is `plan()`'s table; a command it
does not know fails the check. Exit 0: all good; 1: problems (one line each, file:line:
message); 2: bad arguments.
"""
import argparse
import ast
import fnmatch
import glob
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
import tokenize
import unicodedata
import urllib.parse

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOP_FILES = {"README.md", "CMakeLists.txt", "LICENSE", "CITATION.cff", "CHANGELOG.md"}
TOP_DIRS = {"solver", "validation", "cases", "scripts", "reports", "reference", "tests", "bench",
            "docs", "python", ".ci"}

SMALL_GRID = 64
SHOWN_FROM = [ROOT]  # problems name files relative to the repository checked (--root)
FENCE = re.compile(r"^\s*(```|~~~)\s*([\w+-]*)")
LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REF_LINK = re.compile(r"^\s*\[[^\]]+\]:\s*(\S+)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
SHELL_BLOCKS = {"", "sh", "bash", "shell", "console", "text"}


def problem(out, path, line, message):
    out.append(f"{os.path.relpath(path, SHOWN_FROM[0])}:{line}: {message}")


# ------------------------------------------------------------------ Markdown reading
def markdown_lines(path):
    """(line number, text, fence language or None outside a fence) for each line."""
    lang, rows = None, []
    with open(path, encoding="utf-8") as f:
        for n, text in enumerate(f, 1):
            m = FENCE.match(text)
            if m:
                lang = None if lang is not None else m.group(2).lower()
                continue
            rows.append((n, text.rstrip("\n"), lang))
    return rows


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|__", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    kept = "".join(c for c in text if c in " -_" or unicodedata.category(c)[0] in "LN")
    return kept.replace(" ", "-")


def anchors(path):
    seen, out = {}, set()
    for _, text, lang in markdown_lines(path):
        m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", text) if lang is None else None
        if m:
            s = slug(m.group(2))
            out.add(s if s not in seen else f"{s}-{seen[s]}")
            seen[s] = seen.get(s, 0) + 1
    return out


def without_code_spans(text):
    return CODE_SPAN.sub("", text)


# ------------------------------------------------------------------ links
def check_link(target, path, line, out, root):
    if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
        return  # a URL (https:, mailto:, doi:)
    file_part, _, anchor = target.partition("#")
    file_part = urllib.parse.unquote(file_part)
    dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
    if not (dest + os.sep).startswith(os.path.join(root, "")) and dest != root:
        problem(out, path, line, f"link '{target}' points outside the repository")
        return
    if not os.path.exists(dest):
        problem(out, path, line, f"broken link '{target}': {os.path.relpath(dest, root)} does not exist")
        return
    if anchor and dest.endswith(".md") and anchor not in anchors(dest):
        problem(out, path, line, f"broken link '{target}': no heading with anchor #{anchor} in "
                                 f"{os.path.relpath(dest, root)}")


def check_links(path, out, root):
    for n, text, lang in markdown_lines(path):
        if lang is not None:
            continue
        plain = without_code_spans(text)
        for m in LINK.finditer(plain):
            check_link(m.group(1), path, n, out, root)
        m = REF_LINK.match(plain)
        if m:
            check_link(m.group(1), path, n, out, root)


# ------------------------------------------------------------------ repository paths in code
def ignored_prefixes(root):
    """The root-anchored patterns of .gitignore (/build*/, /results/, ...): outputs."""
    pats = []
    try:
        with open(os.path.join(root, ".gitignore"), encoding="utf-8") as f:
            for line in f:
                line = line.strip()
                if line.startswith("/") and not line.startswith("#"):
                    pats.append(line.strip("/"))
    except OSError:
        pass
    return pats


def is_output(rel, pats):
    parts = rel.strip("/").split("/")
    for p in pats:
        n = p.count("/") + 1
        if len(parts) >= n and fnmatch.fnmatch("/".join(parts[:n]), p):
            return True
    return False


def path_words(text):
    """Words of a code span or shell line that look like repository paths."""
    for word in re.split(r"[\s=]+", text):
        word = word.strip("\"'(),;")
        word = re.sub(r":\d+(-\d+)?$", "", word).rstrip(".:")
        if not word or "$" in word or word.startswith("-"):
            continue
        first = word.split("/")[0]
        if (first in TOP_DIRS and "/" in word) or word in TOP_FILES:
            yield word


def exists_in(root, word):
    pattern = re.sub(r"<[^>]*>", "*", word)
    if any(c in pattern for c in "*?["):
        return bool(glob.glob(os.path.join(root, pattern)))
    return os.path.exists(os.path.join(root, pattern))


def check_paths(path, out, root):
    pats = ignored_prefixes(root)
    for n, text, lang in markdown_lines(path):
        if lang is None:
            chunks = [m.group(2) for m in CODE_SPAN.finditer(text)]
        elif lang in SHELL_BLOCKS:
            chunks = [text.split(" #")[0]]
        else:
            continue
        for chunk in chunks:
            for word in path_words(chunk):
                if is_output(word, pats):
                    continue
                if not exists_in(root, word):
                    problem(out, path, n, f"'{word}' is named as a repository path but does not exist")


def doc_files(root):
    files = [os.path.join(root, "README.md")]
    files += sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"), recursive=True))
    return [f for f in files if os.path.exists(f)]


# ------------------------------------------------------------------ comments
COMMENT_FOLDERS = ("solver", "validation", "tests", "bench", "python", "scripts", "reports", "cmake", "cases")
SLASH_COMMENTS = (".cpp", ".hpp", ".h", ".cc", ".cu", ".cuh")
HASH_COMMENTS = (".py", ".sh", ".cmake", ".toml", ".supp", ".slurm", ".in", ".cfg", ".dict")
NOT_READ = ("tests/fuzz/corpus/",)  # fixture inputs, data as they are
MONTHS = r"(?:jan|feb|mar|apr|may|jun|jul|aug|sep|oct|nov|dec)[a-z]*\.?"
HISTORY = [
    ("an issue of the tracker", re.compile(r"\b(?:issues?|tickets?)\s*#?\s*\d+|(?<![\w/&])#\d+\b"
                                           r"|\bthe\s+issue's", re.I)),
    ("a date", re.compile(r"\b(?:19|20)\d\d-(?:0[1-9]|1[0-2])(?:-(?:0[1-9]|[12]\d|3[01]))?(?![\d-])"
                          rf"|\b{MONTHS}\s+(?:\d{{1,2}},?\s+)?(?:19|20)\d\d\b", re.I)),
    ("a commit", re.compile(r"\bcommit\s+[0-9a-f]{7,40}\b", re.I)),
    ("when or by whom it was written", re.compile(
        r"\b(?:today|yesterday|tonight|(?:this|last)\s+(?:morning|afternoon|evening|night|week|session)"
        r"|sessions?|(?:morning|afternoon|evening)\b|the\s+lead(?:\s+engineer)?|reviewers?)\b", re.I)),
]
# A number after another project's name cites its tracker: "HDFGroup/hdf5 #5892", "PR #5958".
CITED_TRACKER = re.compile(r"(?:[\w.-]+/[\w.-]+|\bPR|\bpull request)[\s,]*(?:issues?\s*|PR\s*)?$", re.I)


def comment_files(root):
    """The tracked files of COMMENT_FOLDERS (git ls-files; every file where root is no checkout)."""
    try:
        r = subprocess.run(["git", "-C", root, "ls-files", "--", *COMMENT_FOLDERS], capture_output=True,
                           text=True, check=True)
        files = r.stdout.splitlines()
    except (OSError, subprocess.CalledProcessError):
        files = [os.path.relpath(os.path.join(d, f), root) for folder in COMMENT_FOLDERS
                 for d, _, names in os.walk(os.path.join(root, folder)) for f in names]
    return sorted(f for f in files if not f.startswith(NOT_READ) and
                  (f.endswith(SLASH_COMMENTS + HASH_COMMENTS) or os.path.basename(f) == "CMakeLists.txt"))


def slash_comments(text):
    """(line number, text) of each comment line of C++ source: // to the end of the line, and
    each line of a /* */ block; string and character literals skipped."""
    out, i, n, line = [], 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
        elif text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            out.append((line, text[i + 2:end]))
            i = end
            continue
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end
            for k, part in enumerate(text[i + 2:end].split("\n")):
                out.append((line + k, part))
            line += text.count("\n", i, end)
            i = end + 2
            continue
        elif c in "\"'" and not (c == "'" and i > 0 and text[i - 1].isalnum()):  # 1'000 is a number
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j
        i += 1
    return out


def hash_comments(text):
    """(line number, text) of each # comment of a script or TOML file, outside quotes."""
    out = []
    for no, raw in enumerate(text.splitlines(), 1):
        quote = None
        for k, c in enumerate(raw):
            if quote:
                quote = None if c == quote else quote
            elif c in "\"'":
                quote = c
            elif c == "#" and (k == 0 or raw[k - 1] in " \t(;"):
                out.append((no, raw[k + 1:]))
                break
    return out


def python_comments(text):
    """(line number, text) of each # comment and each line of each docstring of a Python file."""
    try:
        out = [(t.start[0], t.string[1:]) for t in tokenize.generate_tokens(io.StringIO(text).readline)
               if t.type == tokenize.COMMENT]
        tree = ast.parse(text)
    except (SyntaxError, tokenize.TokenError):
        return hash_comments(text)
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) and \
                isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
            first = body[0].value.lineno
            out += [(first + k, part) for k, part in enumerate(body[0].value.value.split("\n"))]
    return sorted(out)


def history_in(comment):
    """What of HISTORY the comment text tells (a list of descriptions, empty when none)."""
    found = []
    for what, pattern in HISTORY:
        for m in pattern.finditer(comment):
            if what == "an issue of the tracker" and CITED_TRACKER.search(comment[:m.start()]):
                continue
            found.append(f"{what} ('{m.group(0).strip()}')")
            break
    return found


def check_comments(root, out):
    for rel in comment_files(root):
        path = os.path.join(root, rel)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except (OSError, UnicodeDecodeError):
            continue  # a binary file among the sources is no comment
        comments = (slash_comments(text) if rel.endswith(SLASH_COMMENTS) else
                    python_comments(text) if rel.endswith(".py") else hash_comments(text))
        for n, comment in comments:
            for what in history_in(comment):
                problem(out, path, n, f"a comment names {what}: say what the code does and why "
                                      "(history goes in CHANGELOG.md and commit messages)")


# ------------------------------------------------------------------ quickstarts
def quickstart_commands(readme):
    """(line, command) for each command of the shell blocks in README's '## Quickstart' section."""
    cmds, inside, pending = [], False, ""
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


def build_has(build, option):
    try:
        with open(os.path.join(build, "CMakeCache.txt"), encoding="utf-8") as f:
            return any(line.strip() == f"{option}:BOOL=ON" for line in f)
    except OSError:
        return False


def small_grid(words):
    """The same command line with any --set grid.n=N above the small grid lowered to it."""
    out = list(words)
    for i, w in enumerate(out):
        m = re.fullmatch(r"grid\.n=(\d+)", w)
        if m and i > 0 and out[i - 1] == "--set" and int(m.group(1)) > SMALL_GRID:
            out[i] = f"grid.n={SMALL_GRID}"
    return out


def plan(words, build):
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


def make_mirror(root, build, tmp):
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


def link_folder(root, tmp, folder, skip):
    """tmp/folder as a real folder of links to root/folder's entries, but those in skip."""
    os.makedirs(os.path.join(tmp, folder), exist_ok=True)
    src = os.path.join(root, folder)
    for name in os.listdir(src) if os.path.isdir(src) else []:
        if name not in skip:
            os.symlink(os.path.join(src, name), os.path.join(tmp, folder, name))


def mirror_challenge_cases(root, tmp):
    """Copies of cases/challenge/*.toml whose [grid] n is the small grid."""
    os.makedirs(os.path.join(tmp, "cases", "challenge"), exist_ok=True)
    for src in glob.glob(os.path.join(root, "cases", "challenge", "*")):
        with open(src, encoding="utf-8") as f:
            text = f.read()
        if src.endswith(".toml"):
            text = re.sub(r"(?m)^(\s*n\s*=\s*)\d+", rf"\g<1>{SMALL_GRID}", text, count=1)
        with open(os.path.join(tmp, "cases", "challenge", os.path.basename(src)), "w", encoding="utf-8") as f:
            f.write(text)


def run_quickstarts(root, build, out, keep):
    readme = os.path.join(root, "README.md")
    cmds = quickstart_commands(readme)
    if not cmds:
        problem(out, readme, 1, "no shell commands found under a '## Quickstart' heading")
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


def run_one(readme, n, words, build, tmp, env, out):
    argv, codes, need, note = plan(words, build)
    shown = shlex.join(words)
    if argv == "unknown":
        problem(out, readme, n, f"quickstart command '{shown}': the docs check does not know how to run it "
                                "(add a rule to plan() in scripts/check_docs.py)")
        return
    if argv is None:
        print(f"check_docs: line {n}: not run: {shown} ({note})")
        return
    t0 = time.monotonic()
    try:
        r = subprocess.run(argv, cwd=tmp, env=env, capture_output=True, text=True, timeout=300)
    except (OSError, subprocess.TimeoutExpired) as e:
        problem(out, readme, n, f"quickstart command '{shown}' did not run: {e}")
        return
    took = time.monotonic() - t0
    print(f"check_docs: line {n}: exit {r.returncode} in {took:.1f} s: {shlex.join(argv)}"
          + (f" ({note})" if note else ""))
    if r.returncode not in codes or (need and need not in r.stderr):
        tail = (r.stderr or r.stdout).strip().splitlines()[-5:]
        problem(out, readme, n, f"quickstart command '{shown}' (run as '{shlex.join(argv)}') exited "
                                f"{r.returncode}, expected {' or '.join(map(str, codes))}"
                                + (f" with '{need}' in its message" if need else "") + ": " + " | ".join(tail))


# ------------------------------------------------------------------ main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="*", help="Markdown files (default: README.md and docs/**/*.md)")
    ap.add_argument("--root", default=ROOT, help="the repository (default: this script's)")
    ap.add_argument("--build", default=None, help="the build folder whose cmc runs the quickstarts (default: ROOT/build)")
    ap.add_argument("--links-only", action="store_true", help="check links and paths, run nothing")
    ap.add_argument("--quickstarts-only", action="store_true", help="run the README's quickstarts only")
    ap.add_argument("--comments-only", action="store_true",
                    help="check the comments of the tracked sources (no dates, issue numbers or diary)")
    ap.add_argument("--keep", action="store_true", help="keep the mirror the quickstarts ran in")
    a = ap.parse_args(argv)
    root = os.path.abspath(a.root)
    SHOWN_FROM[0] = root
    build = os.path.abspath(a.build or os.path.join(root, "build"))
    files = [os.path.abspath(f) for f in a.files] or doc_files(root)
    missing = [f for f in files if not os.path.isfile(f)]
    modes = [m for m in ("links_only", "quickstarts_only", "comments_only") if getattr(a, m)]
    why = ("no such file: " + ", ".join(missing) if missing else
           f"no README.md or docs/ in {root}" if not files else
           "choose one of --links-only, --quickstarts-only and --comments-only" if len(modes) > 1 else None)
    if why:
        print(f"check_docs: {why}", file=sys.stderr)
        return 2
    out = []
    if a.comments_only:
        check_comments(root, out)
        what = f"{len(comment_files(root))} source file(s)"
    else:
        if not a.quickstarts_only:
            for f in files:
                check_links(f, out, root)
                check_paths(f, out, root)
        if not a.links_only:
            if not os.access(os.path.join(build, "cmc"), os.X_OK):
                print(f"check_docs: {build}/cmc not found: build first (scripts/setup.sh)", file=sys.stderr)
                return 2
            run_quickstarts(root, build, out, a.keep)
        what = f"{len(files)} file(s){'' if a.links_only else ', quickstarts run'}"
    for line in out:
        print(line)
    print(f"check_docs: {'FAILED: ' + str(len(out)) + ' problem(s)' if out else 'ok'} ({what})")
    return 1 if out else 0

if __name__ == "__main__":
    sys.exit(main())
