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
or written in the repository. How each command runs there is `plan()`'s table
(python/cmc/devtools/quickstarts.py); a command it does not know fails the check. Exit 0:
all good; 1: problems (one line each, file:line: message); 2: bad arguments.
"""
import os
import sys

import cmc_on_path  # noqa: F401  (first: a clear message where cmc is not importable)
from cmc.devtools.docs_check import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], __doc__, os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
