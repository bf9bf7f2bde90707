"""Imported first by the Python commands in scripts/: where the package cmc cannot be
imported, say how to make it importable instead of printing a traceback."""
import os
import sys

try:
    import cmc  # noqa: F401
except ModuleNotFoundError:
    sys.exit(f"{os.path.basename(sys.argv[0])}: the Python package cmc is not importable: run "
             "`. scripts/python_path.sh` first (it puts build/python or python/ on PYTHONPATH), "
             "or install cmc (docs/install.md)")
