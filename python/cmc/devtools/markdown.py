"""Reading the Markdown pages for the docs check (cmc.devtools.docs_check): lines with the
fence each sits in, GitHub's heading anchors, and the problems found, one line each."""
import os
import re
import unicodedata
from typing import Optional

FENCE = re.compile(r"^\s*(```|~~~)\s*([\w+-]*)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
SHELL_BLOCKS = {"", "sh", "bash", "shell", "console", "text"}


class Problems:
    """The problems found, each as file:line: message with the file relative to the repository
    checked (--root)."""

    def __init__(self, root: str) -> None:
        self.root = root
        self.lines: list[str] = []

    def add(self, path: str, line: int, message: str) -> None:
        self.lines.append(f"{os.path.relpath(path, self.root)}:{line}: {message}")


def markdown_lines(path: str) -> list[tuple[int, str, Optional[str]]]:
    """(line number, text, fence language or None outside a fence) for each line."""
    lang: Optional[str] = None
    rows = []
    with open(path, encoding="utf-8") as f:
        for n, text in enumerate(f, 1):
            m = FENCE.match(text)
            if m:
                lang = None if lang is not None else m.group(2).lower()
                continue
            rows.append((n, text.rstrip("\n"), lang))
    return rows


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|__", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    kept = "".join(c for c in text if c in " -_" or unicodedata.category(c)[0] in "LN")
    return kept.replace(" ", "-")


def anchors(path: str) -> set[str]:
    seen: dict[str, int] = {}
    out = set()
    for _, text, lang in markdown_lines(path):
        m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", text) if lang is None else None
        if m:
            s = slug(m.group(2))
            out.add(s if s not in seen else f"{s}-{seen[s]}")
            seen[s] = seen.get(s, 0) + 1
    return out


def without_code_spans(text: str) -> str:
    return CODE_SPAN.sub("", text)
