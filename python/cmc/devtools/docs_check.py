"""The command scripts/check_docs.py: README.md and docs/ name only what exists (doc_paths), the
sources' comments tell no history (comments), and the README's quickstarts run (quickstarts)."""
import argparse
import os
import sys
from collections.abc import Sequence

from .comments import check_comments, comment_files
from .doc_paths import check_links, check_paths, doc_files
from .markdown import Problems
from .quickstarts import run_quickstarts

MODES = ("links_only", "quickstarts_only", "comments_only")


def arguments(argv: Sequence[str], doc: str, root: str) -> argparse.Namespace:
    """The command's options (its usage text `doc`; `root`: the repository by default)."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("files", nargs="*", help="Markdown files (default: README.md and docs/**/*.md)")
    ap.add_argument("--root", default=root, help="the repository (default: this script's)")
    ap.add_argument("--build", default=None, help="the build folder whose cmc runs the quickstarts (default: ROOT/build)")
    ap.add_argument("--links-only", action="store_true", help="check links and paths, run nothing")
    ap.add_argument("--quickstarts-only", action="store_true", help="run the README's quickstarts only")
    ap.add_argument("--comments-only", action="store_true",
                    help="check the comments of the tracked sources (no dates, issue numbers or diary)")
    ap.add_argument("--keep", action="store_true", help="keep the mirror the quickstarts ran in")
    return ap.parse_args(argv)


def main(argv: Sequence[str], doc: str, root: str) -> int:
    """scripts/check_docs.py with arguments argv; exit 0 all good, 1 problems, 2 bad arguments."""
    a = arguments(argv, doc, root)
    root = os.path.abspath(a.root)
    build = os.path.abspath(a.build or os.path.join(root, "build"))
    files = [os.path.abspath(f) for f in a.files] or doc_files(root)
    missing = [f for f in files if not os.path.isfile(f)]
    modes = [m for m in MODES if getattr(a, m)]
    why = ("no such file: " + ", ".join(missing) if missing else
           f"no README.md or docs/ in {root}" if not files else
           "choose one of --links-only, --quickstarts-only and --comments-only" if len(modes) > 1 else None)
    if why:
        print(f"check_docs: {why}", file=sys.stderr)
        return 2
    out = Problems(root)
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
    for line in out.lines:
        print(line)
    print(f"check_docs: {'FAILED: ' + str(len(out.lines)) + ' problem(s)' if out.lines else 'ok'} ({what})")
    return 1 if out.lines else 0
