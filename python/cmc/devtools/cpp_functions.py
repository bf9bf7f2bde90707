"""C++ and CUDA function bodies for the size limits (cmc.devtools.sizes): where each function of a
source starts and ends, found without a compiler.

How functions are found: comments, string and character literals and preprocessor lines
are blanked, then the braces are paired. At namespace and class scope, a brace is a
function body when what precedes it since the last ';', '{' or '}' has a parameter list
and, after its last ')', nothing but qualifiers (const, noexcept, override, a trailing
return type ...) or, in a constructor, a member-initializer list; `namespace`, `extern`,
class, struct, union and enum braces open a scope; any other brace is an initializer.
A heuristic rather than clang's AST: it needs no compile flags or CUDA headers (the .cu
and .cuh files parse too), no package beyond Python, and runs in well under a second.
"""
import re
from typing import Optional

SOURCE_EXTENSIONS = (".cpp", ".hpp", ".h", ".cc", ".cu", ".cuh")
QUALIFIERS = {"const", "volatile", "noexcept", "override", "final", "&", "&&", "mutable", "try", "throw",
              "constexpr", "consteval"}
NOT_A_NAME = {"noexcept", "decltype", "requires", "throw", "alignas", "sizeof", "alignof", "__launch_bounds__",
              "__attribute__", "__declspec"}
SCOPE_KEYWORDS = {"class", "struct", "union", "enum"}
ACCESS = {"public", "private", "protected"}


def blank_literals(text: str) -> str:
    """text with comments, string and character literals and preprocessor lines replaced by
    spaces (newlines kept, so line numbers stay)."""
    out: list[str] = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            out.append(c)
            i += 1
            line_start = True
            continue
        if line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if line_start and c == "#":  # a directive, with its continuation lines
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
        elif c == '"' or (c == "'" and not digit_separator(text, i)):
            j = raw_string_end(text, i) if c == '"' else -1
            if j < 0:
                j = i + 1
                while j < n and text[j] != c and text[j] != "\n":
                    j += 2 if text[j] == "\\" else 1
                j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def digit_separator(text: str, i: int) -> bool:
    """Whether the ' at i separates digits (1'000'000), not a character literal."""
    m = re.search(r"[0-9A-Za-z_.']*$", text[max(0, i - 64):i])
    return bool(m and m.group(0) and m.group(0)[0].isdigit())


def raw_string_end(text: str, i: int) -> int:
    """The end of a raw string literal R"d(...)d" opening at the quote at i, or -1."""
    if i == 0 or text[i - 1] != "R" or (i >= 2 and (text[i - 2].isalnum() or text[i - 2] == "_")
                                         and text[i - 2:i] not in ("uR", "UR", "LR", "8R")):
        return -1
    paren = text.find("(", i)
    if paren < 0:
        return -1
    close = text.find(")" + text[i + 1:paren] + '"', paren)
    return len(text) if close < 0 else close + len(text[i + 1:paren]) + 2


TOKEN = re.compile(r"[A-Za-z_][A-Za-z_0-9]*|[0-9][0-9A-Za-z_.]*|::|->|&&|\S")


def tokens(text: str) -> list[tuple[str, int]]:
    """(token, line) for every token of blanked source."""
    out: list[tuple[str, int]] = []
    line = 1
    for m in re.finditer(r"\n|" + TOKEN.pattern, text):
        if m.group(0) == "\n":
            line += 1
        else:
            out.append((m.group(0), line))
    return out


def skip_template_prefix(head: list[str]) -> list[str]:
    """head without leading `template <...>` clauses and [[attributes]]."""
    k = 0
    while k < len(head):
        if head[k] == "template" and k + 1 < len(head) and head[k + 1] == "<":
            depth, k = 0, k + 1
            while k < len(head):
                depth += {"<": 1, ">": -1}.get(head[k], 0)
                k += 1
                if depth == 0:
                    break
        elif head[k] == "[" and k + 1 < len(head) and head[k + 1] == "[":
            while k < len(head) and not (head[k] == "]" and k > 0 and head[k - 1] == "]"):
                k += 1
            k += 1
        elif head[k] in ("export", "inline"):
            k += 1
        else:
            break
    return head[k:]


def paren_groups(head: list[str]) -> list[tuple[int, int]]:
    """(open, close) indices of the top-level parenthesised groups of head."""
    groups: list[tuple[int, int]] = []
    depth, start = 0, 0
    for k, t in enumerate(head):
        if t in "([":
            if depth == 0 and t == "(":
                start = k
            depth += 1
        elif t in ")]":
            depth -= 1
            if depth == 0 and t == ")":
                groups.append((start, k))
    return groups


def function_name(head: list[str], groups: list[tuple[int, int]]) -> str:
    for open_, _ in reversed(groups):
        if open_ > 0 and re.match(r"[A-Za-z_~]", head[open_ - 1]) and head[open_ - 1] not in NOT_A_NAME:
            k = open_ - 1
            while k >= 2 and head[k - 1] == "::":
                k -= 2
                if head[k] == ">":  # Class<T>::name: the name of the class without its arguments
                    depth = 0
                    while k > 0:
                        depth += {">": 1, "<": -1}.get(head[k], 0)
                        if depth == 0:
                            break
                        k -= 1
                    k -= 1
            return "".join(t for t in head[k:open_] if t not in "<>") if "<" not in head[k:open_] else \
                "".join(head[k:k + 1]) + "::" + head[open_ - 1]
        if open_ > 0 and head[open_ - 1] == ")" and "operator" in head[:open_]:
            return "operator()"
    return "(lambda)" if "[" in head else "?"


def classify(head: list[str]) -> str:
    """What a '{' after head (the tokens since the last ';', '{' or '}' at this scope) opens:
    'namespace', 'class', 'function' or 'init'."""
    if "namespace" in head or head == ["extern"]:
        return "namespace"
    core = skip_template_prefix(head)
    if core and core[0] in SCOPE_KEYWORDS:
        return "class"
    groups = paren_groups(core)
    eq = [k for k, t in enumerate(core) if t == "=" and "operator" not in core[max(0, k - 3):k]
          and not any(a < k < b for a, b in groups)]
    if eq:  # an initializer: a lambda's body, or braces of a value
        lambda_body = "[" in core[eq[0]:] and core[-1] in (")", "]", "mutable", "noexcept")
        return "function" if lambda_body else "init"
    if not groups:
        return "init"
    after = core[groups[-1][1] + 1:]
    if "->" in after or "requires" in after or all(t in QUALIFIERS for t in after):
        return "function"
    if ":" in core[groups[0][1] + 1:]:  # a constructor's member-initializer list
        return "function" if core[-1] in (")", "{}") else "init"
    return "init"


def matching_brace(toks: list[tuple[str, int]], k: int) -> Optional[int]:
    """The index of the '}' that closes the '{' at k (None if it is missing)."""
    depth = 0
    for j in range(k, len(toks)):
        if toks[j][0] == "{":
            depth += 1
        elif toks[j][0] == "}":
            depth -= 1
            if depth == 0:
                return j
    return None


def functions(text: str) -> list[tuple[str, int, int]]:
    """(name, first line, last line) of every function body in the source text; raises
    ValueError where the braces do not pair up."""
    toks = tokens(blank_literals(text))
    found: list[tuple[str, int, int]] = []
    head: list[str] = []
    depth, scopes = 0, 0
    k = 0
    while k < len(toks):
        t, line = toks[k]
        if t in "([":
            depth += 1
        elif t in ")]":
            depth = max(0, depth - 1)
        if t == ";" and depth == 0:
            head = []
        elif t == ":" and len(head) == 1 and head[0] in ACCESS:
            head = []
            k += 1
            continue
        elif t == "}":
            scopes -= 1
            if scopes < 0:
                raise ValueError(f"line {line}: a '}}' that closes nothing")
            head, depth = [], 0
        elif t == "{":
            kind = "init" if depth > 0 else classify(head)
            if kind in ("namespace", "class"):
                scopes += 1
                head = []
            else:
                end = matching_brace(toks, k)
                if end is None:
                    raise ValueError(f"line {line}: a '{{' that is never closed")
                if kind == "function":
                    core = skip_template_prefix(head)
                    groups = paren_groups(core)
                    if groups and ":" in core[groups[0][1] + 1:]:  # a constructor: not its initializers
                        groups = [g for g in groups if g[1] < core.index(":", groups[0][1] + 1)]
                    found.append((function_name(core, groups), line, toks[end][1]))
                    head = []
                else:
                    head.append("{}")
                k = end + 1
                continue
        if t not in (";", "}", "{"):
            head.append(t)
        k += 1
    if scopes != 0:
        raise ValueError("a namespace or class whose '{' is never closed")
    return found
