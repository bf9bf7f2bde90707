#!/usr/bin/python3
"""No import circle among the repository's Python modules (ctest imports.no_circles).

    /usr/bin/python3 tests/import_cycles_test.py [--root DIR]

Reads (never runs) every module of the package python/cmc and every file under scripts/ and
reports/, and follows each import statement, those inside functions too (a deferred import
closes a circle as surely as one at the top). A name is resolved as Python resolves it when
these files run: a file's own folder first (a script's sys.path[0]), then the package cmc and
the folders reports/ and scripts/ (PYTHONPATH, scripts/python_path.sh); standard and
third-party modules are not followed. `from P import N` depends on the module P.N where that
is a file, else on P. A package's __init__ imported by its own submodules is no circle worth
refusing (Python finishes the package first), so a parent is not implied by importing a child.

Prints every circle as its files in order and exits 1 if there is one; before that, checks
itself on a small tree with a known circle (which it must find) and one without.
"""
import argparse
import ast
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDERS = ("python/cmc", "scripts", "reports")


def module_files(root):
    """{relative path: dotted name as imported} for the files checked."""
    found = {}
    for folder in FOLDERS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, folder)):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith((".", "__")))
            for name in sorted(filenames):
                if name.endswith(".py"):
                    rel = os.path.relpath(os.path.join(dirpath, name), root)
                    found[rel] = dotted_name(rel)
    return found


def dotted_name(rel):
    """cmc.analysis.best for python/cmc/analysis/best.py, cmc.analysis for its __init__.py,
    the file's stem for a script or report."""
    parts = rel[:-len(".py")].split(os.sep)
    if parts[0] == "python":
        parts = parts[1:]
        return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
    return parts[-1]


def imported_names(tree, own):
    """Dotted names the module `own` (its dotted name; relative imports resolve against it)
    imports, with `from P import N` giving both P.N and P."""
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [(a.name, None) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                package = own.split(".")[:-node.level]  # own ends in its module's name or __init__
                base = ".".join(package + ([base] if base else []))
            names += [(base, a.name) for a in node.names]
    return names


def resolve(name, child, folder, by_name, root):
    """The relative path of the file that `from name import child` (or `import name`) loads,
    looked up from a file in `folder`, or None where it is not one of ours."""
    candidates = [f"{name}.{child}", name] if child else [name]
    for cand in candidates:
        sibling = os.path.join(folder, cand + ".py")
        if "." not in cand and os.path.isfile(os.path.join(root, sibling)):
            return sibling
        for path in by_name.get(cand, []):
            return path
    return None


def import_graph(root):
    """{file: set of files it imports}, all relative to root."""
    files = module_files(root)
    by_name = {}
    for rel, name in files.items():
        if rel.startswith("python" + os.sep) or os.path.dirname(rel) in ("scripts", "reports"):
            by_name.setdefault(name, []).append(rel)
    graph = {}
    for rel, name in files.items():
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            tree = ast.parse(f.read(), filename=rel)
        own = name + (".__init__" if rel.endswith("__init__.py") else "")
        edges = set()
        for base, child in imported_names(tree, own):
            target = resolve(base, child, os.path.dirname(rel), by_name, root)
            if target and target != rel:
                edges.add(target)
        graph[rel] = edges
    return graph


def circles(graph):
    """The strongly connected components of more than one file (Tarjan), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def self_check():
    """The check finds a deferred circle between two scripts and one inside the package, and
    passes a tree without one; returns the failures."""
    trees = {
        "circle": ({"scripts/a.py": "import b\n", "scripts/b.py": "def f():\n    from a import g\n"}, 1),
        "package_circle": ({"python/cmc/__init__.py": "", "python/cmc/x.py": "from . import y\n",
                            "python/cmc/y.py": "from cmc.x import z\n"}, 1),
        "no_circle": ({"python/cmc/__init__.py": "from . import x\n", "python/cmc/x.py": "from . import y\n",
                       "python/cmc/y.py": "import numpy\n", "scripts/a.py": "from cmc import x\nimport b\n",
                       "scripts/b.py": "from cmc.y import q\n", "reports/r.py": "import a\n"}, 0),
    }
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (files, expected) in trees.items():
            for rel, text in files.items():
                path = os.path.join(tmp, name, rel)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path, "w", encoding="utf-8") as f:
                    f.write(text)
            got = len(circles(import_graph(os.path.join(tmp, name))))
            if got != expected:
                failures.append(f"self-check {name}: {got} circle(s) found, expected {expected}")
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=ROOT)
    a = ap.parse_args()
    failures = self_check()
    graph = import_graph(a.root)
    for c in circles(graph):
        failures.append("import circle: " + " <-> ".join(c))
    for f in failures:
        print(f, file=sys.stderr)
    print(f"import_cycles: {len(graph)} modules, {sum(len(e) for e in graph.values())} imports among them, "
          f"{len(failures)} problem(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
