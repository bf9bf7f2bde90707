"""The repository's own checks, the commands behind scripts/check_docs.py and
scripts/check_sizes.py (ctest docs.* and sizes.*): they read the source tree, never a run.
docs_check (links and paths: doc_paths; comments: comments; the README's quickstarts:
quickstarts; Markdown reading: markdown) and sizes (C++ function bodies: cpp_functions)."""
