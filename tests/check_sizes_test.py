#!/usr/bin/python3
"""scripts/check_sizes.py fails on what it is there to catch (ctest sizes.checker_fails_on_breaches).

Each case writes a small source tree (solver/, validation/) into a temporary folder and runs
the checker on it:
  - a function of 81 lines and a file of 601 lines each exit 1 and name the file and line;
    a function of exactly 80 lines and a file of exactly 600 lines exit 0;
  - a long function is found at namespace scope, as a member defined in its class, as an
    out-of-line member of a class template, as a constructor with a member-initializer
    list, and in a .cu file; a lambda counts inside its function;
  - braces in comments, strings, raw strings, character literals and preprocessor lines,
    a long class, enum, namespace or table of values, and a long brace initializer are no
    function: only the long function after them is reported, at its line;
  - --exclude leaves out a folder; a source whose braces do not pair up exits 1;
  - a Python file anywhere in the tree (not only under the FOLDERs) counts: a function of 81
    lines (a nested one counting inside it) and a file of 601 lines exit 1, 80 and 600 exit 0;
    a `def` inside a string is no function; build* and hidden folders are left out; a Python
    file that does not parse exits 1.
  - --max-script-average N: scripts/*.py averaging N + 1 lines exit 1 and name the longest;
    averaging N lines, or a tree without scripts/, exit 0.
"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECKER = os.path.join(ROOT, "scripts", "check_sizes.py")


def body(lines):
    """lines statements: a function body of lines + 2 lines with its braces."""
    return "".join(f"  x += {k};\n" for k in range(lines))


def py_body(lines, indent=4):
    """lines statements of a Python function body."""
    return "".join(" " * indent + f"x += {k}\n" for k in range(lines))


def tree(tmp, name, files):
    root = os.path.join(tmp, name)
    for folder in ("solver/cmc", "validation"):
        os.makedirs(os.path.join(root, folder))
    for rel, text in files.items():
        os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
        with open(os.path.join(root, rel), "w", encoding="utf-8") as f:
            f.write(text)
    return root


def run(root, extra=()):
    r = subprocess.run(["/usr/bin/python3", CHECKER, "--root", root, *extra], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


CASES = [
    # (name, files, expected exit, text expected in the output)
    ("function_of_81_lines", {"solver/cmc/Long.cpp": "int f(int x) {\n" + body(79) + "}\n"}, 1,
     "solver/cmc/Long.cpp:1: function f of 81 lines"),
    ("function_of_80_lines", {"solver/cmc/Fits.cpp": "int f(int x) {\n" + body(78) + "}\n"}, 0, "0 breach"),
    ("file_of_601_lines", {"validation/Big.hpp": "// a line\n" * 601}, 1, "validation/Big.hpp:1: file of 601 lines"),
    ("file_of_600_lines", {"validation/Fits.hpp": "// a line\n" * 600}, 0, "0 breach"),
    ("member_in_class", {"solver/cmc/Member.hpp":
                         "namespace cmc {\nclass A {\n public:\n  int g(int x) const {\n" + body(90) + "  }\n};\n}\n"},
     1, "solver/cmc/Member.hpp:4: function g of 92 lines"),
    ("member_of_template", {"solver/cmc/Template.hpp":
                            "template <class T, int N = 2>\nauto Run<T, N>::step(T x) -> T {\n" + body(90) + "}\n"},
     1, "solver/cmc/Template.hpp:2: function Run::step of 92 lines"),
    ("constructor_with_initializers", {"solver/cmc/Ctor.cpp":
                                       "A::A(int n) : n_{n}, m_(2 * n), v_{1, 2} {\n" + body(90) + "}\n"},
     1, "solver/cmc/Ctor.cpp:1: function A::A of 92 lines"),
    ("cuda_kernel", {"solver/cmc/Kernel.cu":
                     "__global__ void __launch_bounds__(256) kern(double* x) {\n" + body(90) + "}\n"},
     1, "solver/cmc/Kernel.cu:1: function kern of 92 lines"),
    ("lambda_inside", {"solver/cmc/Lambda.cpp":
                       "void f(int x) {\n  auto g = [&](int y) {\n" + body(90) + "  };\n  g(1);\n}\n"},
     1, "solver/cmc/Lambda.cpp:1: function f of 95 lines"),
    ("braces_not_code", {"solver/cmc/Text.cpp":
                         "// void commented() {\n/* int f() {\n*/\n#define OPEN {\n"
                         "const char* s = \"void f() {\";\nconst char* r = R\"x(int g() { )\" })x\";\n"
                         "char c = '{';\nlong big = 1'000'000;\nint h(int x) {\n" + body(90) + "}\n"}, 1,
     "solver/cmc/Text.cpp:9: function h of 92 lines (at most 80)\ncheck_sizes: 1 breach"),
    ("scopes_and_tables", {"solver/cmc/Scopes.hpp":
                           "namespace cmc {\nnamespace {\nstruct S {\n" + "  int a = 0;\n" * 90 + "};\n"
                           "enum class E : int {\n" + "".join(f"  k{k},\n" for k in range(90)) + "};\n"
                           "const int table[] = {\n" + "  1,\n" * 90 + "};\n"
                           "const S s{\n" + "  1,\n" * 90 + "};\n}\nint tail(int x) {\n" + body(90) + "}\n}\n"}, 1,
     "solver/cmc/Scopes.hpp:372: function tail of 92 lines (at most 80)\ncheck_sizes: 1 breach"),
    ("exclude_folder", {"solver/cmc/Long.cpp": "int f(int x) {\n" + body(90) + "}\n"}, 0, "0 breach"),
    ("unpaired_braces", {"solver/cmc/Broken.cpp": "int f(int x) {\n  x += 1;\n"}, 1,
     "solver/cmc/Broken.cpp: cannot pair the braces"),
    ("python_function_of_81_lines", {"scripts/long.py": "import os\n\n\ndef f(x):\n" + py_body(80)}, 1,
     "scripts/long.py:4: function f of 81 lines"),
    ("python_function_of_80_lines", {"scripts/fits.py": "def f(x):\n" + py_body(79)}, 0, "0 breach"),
    ("python_nested_function", {"python/pkg/nested.py": "def outer(x):\n    def inner(x):\n" + py_body(40, 8)
                                + "        return x\n" + py_body(40) + "    return inner(x)\n"}, 1,
     "python/pkg/nested.py:1: function outer of 84 lines (at most 80)\ncheck_sizes: 1 breach"),
    ("python_file_of_601_lines", {"reports/big.py": "# a line\n" * 601}, 1, "reports/big.py:1: file of 601 lines"),
    ("python_file_of_600_lines", {"reports/fits.py": "# a line\n" * 600}, 0, "0 breach"),
    ("python_def_in_string", {"tests/text.py": 'TEXT = """\ndef f(x):\n' + py_body(90) + '"""\n'}, 0, "0 breach"),
    ("python_made_folders_left_out", {"build/long.py": "def f(x):\n" + py_body(90),
                                      ".hidden/long.py": "def f(x):\n" + py_body(90)}, 0, "0 breach"),
    ("python_syntax_error", {"scripts/broken.py": "def f(x:\n    return x\n"}, 1, "scripts/broken.py:1: cannot parse"),
]


# (name, lines of each scripts/*.py, expected exit, text expected in the output) with --max-script-average 60
AVERAGE_CASES = [("scripts_average_61", (40, 61, 82), 1, "3 scripts (*.py) of 183 lines, 61.0 on average (at most 60; "
                  "the longest, s2.py, 82)"),
                 ("scripts_average_60", (40, 60, 80), 0, "0 breach"),
                 ("no_scripts_folder", (), 0, "0 breach")]


def script_average_cases(tmp):
    """The failures of AVERAGE_CASES, each printed as it runs."""
    failures = []
    for name, counts, code, needle in AVERAGE_CASES:
        root = tree(tmp, name, {f"scripts/s{k}.py": "# a line\n" * n for k, n in enumerate(counts)})
        got, out = run(root, ["--max-script-average", "60"])
        ok = got == code and needle in out
        print(f"{'ok  ' if ok else 'FAIL'} {name}: exit {got} (expected {code})")
        if not ok:
            failures.append(f"{name}: expected exit {code} and '{needle}' in the output, got exit {got}:\n{out}")
    return failures


def main():
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, files, code, needle in CASES:
            root = tree(tmp, name, files)
            got, out = run(root, ["--exclude", "solver/cmc"] if name == "exclude_folder" else [])
            ok = got == code and needle in out
            print(f"{'ok  ' if ok else 'FAIL'} {name}: exit {got} (expected {code})")
            if not ok:
                failures.append(f"{name}: expected exit {code} and '{needle}' in the output, got exit {got}:\n{out}")
        failures += script_average_cases(tmp)
        got, out = run(os.path.join(tmp, "no-such-tree"))
        if got != 2 or "no such folder" not in out:
            failures.append(f"missing_tree: expected exit 2 and 'no such folder', got exit {got}:\n{out}")
    for f in failures:
        print(f, file=sys.stderr)
    print(f"{len(CASES) + len(AVERAGE_CASES) + 1 - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
