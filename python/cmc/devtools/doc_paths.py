"""The docs check's links and paths (cmc.devtools.docs_check): every relative Markdown link or
image resolves to a file or folder of the repository (a link's #anchor to a heading of the page
it names), and every repository path named in code exists, but the outputs of .gitignore's
root-anchored folders."""
import fnmatch
import glob
import os
import re
import urllib.parse
from collections.abc import Iterator

from .markdown import CODE_SPAN, SHELL_BLOCKS, Problems, anchors, markdown_lines, without_code_spans

TOP_FILES = {"README.md", "CMakeLists.txt", "LICENSE", "CITATION.cff", "CHANGELOG.md"}
TOP_DIRS = {"solver", "validation", "cases", "scripts", "reports", "reference", "tests", "bench",
            "docs", "python", ".ci"}
LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REF_LINK = re.compile(r"^\s*\[[^\]]+\]:\s*(\S+)")


def check_link(target: str, path: str, line: int, out: Problems, root: str) -> None:
    if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
        return  # a URL (https:, mailto:, doi:)
    file_part, _, anchor = target.partition("#")
    file_part = urllib.parse.unquote(file_part)
    dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
    if not (dest + os.sep).startswith(os.path.join(root, "")) and dest != root:
        out.add(path, line, f"link '{target}' points outside the repository")
        return
    if not os.path.exists(dest):
        out.add(path, line, f"broken link '{target}': {os.path.relpath(dest, root)} does not exist")
        return
    if anchor and dest.endswith(".md") and anchor not in anchors(dest):
        out.add(path, line, f"broken link '{target}': no heading with anchor #{anchor} in "
                            f"{os.path.relpath(dest, root)}")


def check_links(path: str, out: Problems, root: str) -> None:
    for n, text, lang in markdown_lines(path):
        if lang is not None:
            continue
        plain = without_code_spans(text)
        for m in LINK.finditer(plain):
            check_link(m.group(1), path, n, out, root)
        ref = REF_LINK.match(plain)
        if ref:
            check_link(ref.group(1), path, n, out, root)


def ignored_prefixes(root: str) -> list[str]:
    """The root-anchored patterns of .gitignore (/build*/, /results/, ...): outputs."""
    pats = []
    try:
        with open(os.path.join(root, ".gitignore"), encoding="utf-8") as f:
            for line in f:
                line = line.strip()
                if line.startswith("/") and not line.startswith("#"):
                    pats.append(line.strip("/"))
    except OSError:
        pass
    return pats


def is_output(rel: str, pats: list[str]) -> bool:
    parts = rel.strip("/").split("/")
    for p in pats:
        n = p.count("/") + 1
        if len(parts) >= n and fnmatch.fnmatch("/".join(parts[:n]), p):
            return True
    return False


def path_words(text: str) -> Iterator[str]:
    """Words of a code span or shell line that look like repository paths."""
    for word in re.split(r"[\s=]+", text):
        word = word.strip("\"'(),;")
        word = re.sub(r":\d+(-\d+)?$", "", word).rstrip(".:")
        if not word or "$" in word or word.startswith("-"):
            continue
        first = word.split("/")[0]
        if (first in TOP_DIRS and "/" in word) or word in TOP_FILES:
            yield word


def exists_in(root: str, word: str) -> bool:
    pattern = re.sub(r"<[^>]*>", "*", word)
    if any(c in pattern for c in "*?["):
        return bool(glob.glob(os.path.join(root, pattern)))
    return os.path.exists(os.path.join(root, pattern))


def check_paths(path: str, out: Problems, root: str) -> None:
    pats = ignored_prefixes(root)
    for n, text, lang in markdown_lines(path):
        if lang is None:
            chunks = [m.group(2) for m in CODE_SPAN.finditer(text)]
        elif lang in SHELL_BLOCKS:
            chunks = [text.split(" #")[0]]
        else:
            continue
        for chunk in chunks:
            for word in path_words(chunk):
                if is_output(word, pats):
                    continue
                if not exists_in(root, word):
                    out.add(path, n, f"'{word}' is named as a repository path but does not exist")


def doc_files(root: str) -> list[str]:
    files = [os.path.join(root, "README.md")]
    files += sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"), recursive=True))
    return [f for f in files if os.path.exists(f)]
