#!/usr/bin/python3
"""Every public function of the package cmc carries type hints (ctest python.type_hints).

    /usr/bin/python3 tests/type_hints_test.py [--root DIR]

Reads (never runs) every module under python/cmc of --root (default: this repository). A public
function is one whose name does not start with "_", defined at a module's top level or in a class
body (a method; nested classes too); functions inside functions are the enclosing one's business.
Each needs a return annotation and an annotation on every parameter (*args and **kwargs
included), except the first parameter of a method (self or cls) and of a static method none.
mypy (ctest python.mypy) then checks the bodies of these functions against their hints.

Prints every function lacking one as PATH:LINE NAME: what is missing, and exits 1 if there is
one; before that, checks itself on a small module with known gaps (which it must find).
"""
import argparse
import ast
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = os.path.join("python", "cmc")


def _is_static(node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    return any(isinstance(d, ast.Name) and d.id == "staticmethod" for d in node.decorator_list)


def gaps_of(node: ast.FunctionDef | ast.AsyncFunctionDef, in_class: bool) -> list[str]:
    """What the function's signature lacks: "return" and/or the names of unannotated parameters."""
    a = node.args
    params = [*a.posonlyargs, *a.args]
    if in_class and params and not _is_static(node):
        params = params[1:]  # self / cls
    params += [*a.kwonlyargs, *(p for p in (a.vararg, a.kwarg) if p is not None)]
    missing = [p.arg for p in params if p.annotation is None]
    return (["return"] if node.returns is None else []) + missing


def public_gaps(source: str, path: str) -> list[str]:
    """'PATH:LINE NAME: lacks ...' for each public function of one module's source."""
    out: list[str] = []

    def visit(body: list[ast.stmt], in_class: bool, prefix: str) -> None:
        for node in body:
            if isinstance(node, ast.ClassDef):
                visit(node.body, True, prefix + node.name + ".")
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_"):
                gaps = gaps_of(node, in_class)
                if gaps:
                    out.append(f"{path}:{node.lineno} {prefix}{node.name}: lacks annotations on "
                               + ", ".join(gaps))

    visit(ast.parse(source, filename=path).body, False, "")
    return out


def package_gaps(root: str) -> list[str]:
    out: list[str] = []
    for dirpath, dirnames, filenames in os.walk(os.path.join(root, PACKAGE)):
        dirnames[:] = sorted(d for d in dirnames if not d.startswith((".", "__")))
        for name in sorted(f for f in filenames if f.endswith(".py")):
            path = os.path.join(dirpath, name)
            with open(path, encoding="utf-8") as f:
                out += public_gaps(f.read(), os.path.relpath(path, root))
    return out


SELF_CHECK = '''
def bare(a, b: int): pass
def fine(a: int, *rest: str, **kw: float) -> None: pass
def half(a: int, *rest, key=1, **kw) -> None: pass
def _private(a): pass
class Thing:
    def method(self, x) -> int: return 0
    def _hidden(self, y): pass
    @staticmethod
    def build(x: int): pass
    class Inner:
        def deep(self): pass
def outer() -> None:
    def inner(z): pass
'''
SELF_EXPECTED = ["m.py:2 bare: lacks annotations on return, a",
                 "m.py:4 half: lacks annotations on key, rest, kw",
                 "m.py:7 Thing.method: lacks annotations on x",
                 "m.py:10 Thing.build: lacks annotations on return",
                 "m.py:12 Thing.Inner.deep: lacks annotations on return"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=ROOT)
    a = ap.parse_args()
    found = public_gaps(SELF_CHECK, "m.py")
    if found != SELF_EXPECTED:
        print("type_hints_test: the checker misread its own example:\n  " + "\n  ".join(found), file=sys.stderr)
        return 1
    gaps = package_gaps(a.root)
    for g in gaps:
        print(g)
    if gaps:
        print(f"type_hints_test: {len(gaps)} public functions of {PACKAGE} lack type hints", file=sys.stderr)
        return 1
    print(f"type_hints_test: every public function of {PACKAGE} has type hints")
    return 0


if __name__ == "__main__":
    sys.exit(main())
