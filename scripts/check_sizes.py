#!/usr/bin/python3
"""Size limits of the C++ and Python sources: no function over 80 lines, no file over 600 lines.

usage: scripts/check_sizes.py [--root DIR] [--exclude PATH ...] [--max-function N] [--max-file N]
                              [--max-script-average N] [FOLDER ...]

FOLDERs (default: solver validation) are relative to --root (default: this repository).
Every Python file (.py) under --root counts too, wherever it is, for both limits, except
under folders whose names start with '.' and, at the top, build* and results (made, not
written). A Python function's lines run from its `def` line to its last line (Python's own
parser, ast); a function nested in another counts inside it too.
Every file under them counts for the file limit (its lines, as wc -l counts them); the C++
and CUDA sources (.cpp .hpp .h .cc .cu .cuh) also for the function limit. A function's
lines run from the line of its body's opening brace to the line of its closing brace, both
counted; a lambda counts inside the function that holds it. --exclude leaves out a file or
a folder (relative to --root). Prints each breach as PATH:LINE and exits 1 if there is one;
a source whose braces do not pair up is reported as such (exit 1), never passed silently.
--max-script-average N: the .py files directly in scripts/ under --root average at most N
lines (ctest sizes.limits gives 60: the scripts are thin commands over the package cmc).

How C++ functions are found: python/cmc/devtools/cpp_functions.py (a heuristic, no compiler).
"""
import os
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.devtools.sizes import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__, os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
