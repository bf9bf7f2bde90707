"""The docs check's comments (scripts/check_docs.py --comments-only): every comment line (`//`,
`/* */`, `#`, a Python docstring) of the tracked sources in COMMENT_FOLDERS says what and why, not
when or by whom: none names an issue of the project's tracker, a date, a commit, or tells a
diary's story (HISTORY's patterns). Data files (CSV, JSON, HDF5, the fuzz corpus) are not read."""
import ast
import io
import os
import re
import subprocess
import tokenize
from typing import Optional

from .markdown import Problems

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


def comment_files(root: str) -> list[str]:
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


def slash_comments(text: str) -> list[tuple[int, str]]:
    """(line number, text) of each comment line of C++ source: // to the end of the line, and
    each line of a /* */ block; string and character literals skipped."""
    out: list[tuple[int, str]] = []
    i, n, line = 0, len(text), 1
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


def hash_comments(text: str) -> list[tuple[int, str]]:
    """(line number, text) of each # comment of a script or TOML file, outside quotes."""
    out: list[tuple[int, str]] = []
    for no, raw in enumerate(text.splitlines(), 1):
        quote: Optional[str] = None
        for k, c in enumerate(raw):
            if quote:
                quote = None if c == quote else quote
            elif c in "\"'":
                quote = c
            elif c == "#" and (k == 0 or raw[k - 1] in " \t(;"):
                out.append((no, raw[k + 1:]))
                break
    return out


def python_comments(text: str) -> list[tuple[int, str]]:
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


def history_in(comment: str) -> list[str]:
    """What of HISTORY the comment text tells (a list of descriptions, empty when none)."""
    found = []
    for what, pattern in HISTORY:
        for m in pattern.finditer(comment):
            if what == "an issue of the tracker" and CITED_TRACKER.search(comment[:m.start()]):
                continue
            found.append(f"{what} ('{m.group(0).strip()}')")
            break
    return found


def check_comments(root: str, out: Problems) -> None:
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
                out.add(path, n, f"a comment names {what}: say what the code does and why "
                                 "(history goes in CHANGELOG.md and commit messages)")
