#!/usr/bin/python3
"""scripts/check_docs.py fails on what it is there to catch (ctest docs.checker_fails_on_broken_links).

  check_docs_test.py BUILD

Each case writes a small repository into a temporary folder and runs the checker on it:
  - a broken relative link, a path in code that does not exist, an anchor with no heading, and
    a link out of the repository each exit 1 and name the line;
  - a file whose links, anchors and paths all exist (outputs under .gitignore's folders
    included) exits 0;
  - a README whose quickstart fails (a case file that does not exist), and one whose quickstart
    the checker does not know how to run, exit 1;
  - a comment (C++ //, /* */, #, a Python docstring) naming a tracker issue, a date or a commit,
    or telling when or by whom it was written, exits 1 naming the line; comments that cite
    another project's tracker, give a year in a citation, or hold the same words inside a
    string or a CSV fixture exit 0.
"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECKER = os.path.join(ROOT, "scripts", "check_docs.py")


def run(args):
    r = subprocess.run(["/usr/bin/python3", CHECKER] + args, capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


def expect(name, args, code, needle, failures):
    got, out = run(args)
    ok = got == code and needle in out
    print(f"{'ok  ' if ok else 'FAIL'} {name}: exit {got} (expected {code})")
    if not ok:
        failures.append(f"{name}: expected exit {code} and '{needle}' in the output, got exit {got}:\n{out}")


def page(tmp, name, text):
    path = os.path.join(tmp, name)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def small_repository(tmp):
    """A repository of a few files: README.md, docs/guide.md with two headings, a solver source,
    a case, and .gitignore anchoring results/ and build*/ (outputs, not checked)."""
    root = os.path.join(tmp, "repo")
    for folder in ("docs", "solver/cmc/grid", "cases/validation", "scripts/gpu"):
        os.makedirs(os.path.join(root, folder))
    page(root, "README.md", "# repo\n")
    page(root, "docs/guide.md", "# Guide\n\n## Building by hand\n\ntext\n")
    page(root, "solver/cmc/grid/Grid.hpp", "")
    page(root, "cases/validation/hertz-free.toml", "")
    page(root, ".gitignore", "/build*/\n/results/\n")
    return root


def link_cases(tmp, failures):
    root = small_repository(tmp)
    bad = [("broken_link", "See [the guide](no/such/page.md).\n", "broken link 'no/such/page.md'"),
           ("broken_path", "The grid is in `solver/cmc/grid/NoSuchGrid.hpp`.\n",
            "'solver/cmc/grid/NoSuchGrid.hpp' is named as a repository path but does not exist"),
           ("broken_path_in_shell_block", "```sh\nbuild/cmc run cases/validation/no-such-case.toml --out out/x\n```\n",
            "'cases/validation/no-such-case.toml' is named"),
           ("broken_anchor", "See [the guide](guide.md#no-such-heading).\n", "no heading with anchor #no-such-heading"),
           ("link_out_of_the_repository", "See [notes](../../outside.md).\n", "points outside the repository")]
    for name, text, needle in bad:
        path = page(os.path.join(root, "docs"), f"{name}.md", text)
        expect(name, ["--links-only", "--root", root, path], 1, f"docs/{name}.md:", failures)
        expect(name + " (message)", ["--links-only", "--root", root, path], 1, needle, failures)
        os.remove(path)
    good = page(os.path.join(root, "docs"), "good.md",
                "[README](../README.md) and [the guide](guide.md#building-by-hand).\n"
                "`solver/cmc/grid/Grid.hpp`, `cases/validation/*.toml`, `cases/<folder>/hertz-free.toml`,\n"
                "and outputs `results/challenge-reference/summary.json` and `build/cmc`.\n\n"
                "```sh\nbuild/cmc run cases/validation/hertz-free.toml --out out/h\n```\n")
    expect("good_page", ["--links-only", "--root", root, good], 0, "check_docs: ok", failures)
    expect("whole_repository", ["--links-only", "--root", root], 0, "check_docs: ok", failures)


def quickstart_cases(tmp, build, failures):
    for name, command, needle in (
            ("failing_quickstart", "build/cmc run cases/no-such-case.toml --out out/x", "exited 2, expected 0"),
            ("unknown_quickstart", "frobnicate --all", "does not know how to run it")):
        root = os.path.join(tmp, name)
        os.makedirs(root)
        page(root, "README.md", f"# x\n\n## Quickstart\n\n```sh\n{command}\n```\n")
        expect(name, ["--quickstarts-only", "--root", root, "--build", build], 1, needle, failures)


def comment_cases(tmp, failures):
    root = os.path.join(tmp, "comments")
    os.makedirs(os.path.join(root, "tests", "data"))
    os.makedirs(os.path.join(root, "scripts"))
    page(root, "README.md", "# x\n")
    bad = [("tests/a.cpp", "int x;  // " + "Issue 12: sizes\n", "an issue of the tracker"),
           ("tests/b.cpp", "/* measured\n   on " + "2026-11-27 */\n", "tests/b.cpp:2: a comment names a date"),
           ("tests/c.py", '"""Helpers (' + 'issue 15)."""\n', "an issue of the tracker"),
           ("scripts/d.sh", "# " + "Added this morning\n", "when or by whom"),
           ("tests/e.cmake", "# see #" + "42\n", "an issue of the tracker"),
           ("tests/f.hpp", "// as of " + "Nov 2026\n", "a date"),
           ("tests/g.cpp", "// reverted in commit " + "1a2b3c4d\n", "a commit")]
    for rel, text, needle in bad:
        path = page(root, rel, text)
        expect("comment " + rel, ["--comments-only", "--root", root], 1, needle, failures)
        os.remove(path)
    page(root, "tests/ok.cpp", '// HDFGroup/hdf5 #5892, fixed by PR #5958; Tribol. Int. 114 (2017) 161\n'
                               'const char* s = "issue 12 on 2026-11-27";  // a string, not a comment\n')
    page(root, "tests/ok.py", 's = "# Issue 3"\n')
    page(root, "tests/data/run.csv", "# date: " + "2026-11-23T20:36:25Z\n1,2\n")
    expect("comments that are fine", ["--comments-only", "--root", root], 0, "check_docs: ok", failures)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    build = os.path.abspath(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory(prefix="cmc-check-docs-test-") as tmp:
        link_cases(tmp, failures)
        quickstart_cases(tmp, build, failures)
        comment_cases(tmp, failures)
    for f in failures:
        print(f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
