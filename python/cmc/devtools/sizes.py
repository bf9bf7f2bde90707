"""The command scripts/check_sizes.py: the size limits of the C++ and Python sources (no
function over 80 lines, no file over 600 lines) and, with --max-script-average, the thin
commands of scripts/ (its .py files average at most that many lines). The C++ function
bodies are cmc.devtools.cpp_functions's."""
import argparse
import ast
import os
import sys
from collections.abc import Iterator, Sequence

from .cpp_functions import SOURCE_EXTENSIONS, functions


def source_files(root: str, folders: Sequence[str], excludes: Sequence[str]) -> Iterator[str]:
    excluded = [os.path.normpath(e) for e in excludes]
    for folder in folders:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, folder)):
            dirnames.sort()
            for name in sorted(filenames):
                path = os.path.join(dirpath, name)
                rel = os.path.normpath(os.path.relpath(path, root))
                if any(rel == e or rel.startswith(e + os.sep) for e in excluded):
                    continue
                if os.path.isfile(path) and not os.path.islink(path):
                    yield rel


def python_files(root: str, excludes: Sequence[str]) -> Iterator[str]:
    """Every .py file under root (relative paths, sorted), but in hidden folders and the
    top-level build* and results folders."""
    excluded = [os.path.normpath(e) for e in excludes]
    for dirpath, dirnames, filenames in os.walk(root):
        top = os.path.normpath(os.path.relpath(dirpath, root)) == "."
        dirnames[:] = sorted(d for d in dirnames if not d.startswith(".")
                             and not (top and (d.startswith("build") or d == "results")))
        for name in sorted(filenames):
            rel = os.path.normpath(os.path.relpath(os.path.join(dirpath, name), root))
            if name.endswith(".py") and not any(rel == e or rel.startswith(e + os.sep) for e in excluded):
                yield rel


def python_breaches(root: str, rel: str, max_function: int, max_file: int) -> list[str]:
    """The breaches of one Python file; one that does not parse is reported as such."""
    with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
        text = f.read()
    lines = text.count("\n")
    found = [f"{rel}:1: file of {lines} lines (at most {max_file})"] if lines > max_file else []
    try:
        tree = ast.parse(text, filename=rel)
    except SyntaxError as e:
        return found + [f"{rel}:{e.lineno}: cannot parse: {e.msg}"]
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            length = (node.end_lineno or node.lineno) - node.lineno + 1
            if length > max_function:
                found.append(f"{rel}:{node.lineno}: function {node.name} of {length} lines (at most {max_function})")
    return sorted(found, key=lambda b: int(b.split(":")[1]))


def script_average(root: str, max_average: float) -> list[str]:
    """The breach of scripts/*.py averaging more than max_average lines (as wc -l counts them),
    where root has such files: the scripts are thin commands over the package cmc."""
    folder = os.path.join(root, "scripts")
    names = sorted(n for n in os.listdir(folder) if n.endswith(".py")) if os.path.isdir(folder) else []
    counts = []
    for name in names:
        with open(os.path.join(folder, name), encoding="utf-8", errors="replace") as f:
            counts.append(f.read().count("\n"))
    if not counts or sum(counts) / len(counts) <= max_average:
        return []
    longest = max(zip(counts, names))
    return [f"scripts:1: {len(counts)} scripts (*.py) of {sum(counts)} lines, {sum(counts) / len(counts):.1f} on "
            f"average (at most {max_average:g}; the longest, {longest[1]}, {longest[0]}): move their logic into "
            "the package python/cmc"]


def check(root: str, folders: Sequence[str], excludes: Sequence[str], max_function: int, max_file: int) -> list[str]:
    breaches = []
    for rel in python_files(root, excludes):
        breaches += python_breaches(root, rel, max_function, max_file)
    for rel in source_files(root, folders, excludes):
        if rel.endswith(".py"):
            continue  # counted above
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
            text = f.read()
        lines = text.count("\n")
        if lines > max_file:
            breaches.append(f"{rel}:1: file of {lines} lines (at most {max_file})")
        if not rel.endswith(SOURCE_EXTENSIONS):
            continue
        try:
            for name, first, last in functions(text):
                if last - first + 1 > max_function:
                    breaches.append(f"{rel}:{first}: function {name} of {last - first + 1} lines (at most {max_function})")
        except ValueError as e:
            breaches.append(f"{rel}: cannot pair the braces: {e}")
    return breaches


def main(argv: Sequence[str], doc: str, root: str) -> int:
    """scripts/check_sizes.py with arguments argv (its usage text `doc`, its repository `root`)."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("folders", nargs="*", default=["solver", "validation"])
    ap.add_argument("--root", default=root)
    ap.add_argument("--exclude", action="append", default=[], metavar="PATH")
    ap.add_argument("--max-function", type=int, default=80)
    ap.add_argument("--max-file", type=int, default=600)
    ap.add_argument("--max-script-average", type=float, default=None, metavar="N")
    args = ap.parse_args(argv)
    for folder in args.folders:
        if not os.path.isdir(os.path.join(args.root, folder)):
            print(f"check_sizes: {os.path.join(args.root, folder)}: no such folder", file=sys.stderr)
            return 2
    breaches = check(args.root, args.folders, args.exclude, args.max_function, args.max_file)
    if args.max_script_average is not None:
        breaches += script_average(args.root, args.max_script_average)
    for b in breaches:
        print(b)
    print(f"check_sizes: {len(breaches)} breach(es) of {args.max_function} lines a function, "
          f"{args.max_file} lines a file in {' '.join(args.folders)} and every Python file"
          + (f", {args.max_script_average:g} lines a script on average" if args.max_script_average is not None else ""))
    return 1 if breaches else 0
