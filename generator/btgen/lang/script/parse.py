"""Parsing a script with the grammar of a release, and placing a script's characters in
its file (entity references in the attribute counted as one character each)."""

from __future__ import annotations

import re
from typing import Optional

from btgen.diagnostics import Loc, UserError, read_bounded
from btgen.lang.script.grammar49 import _Parser49
from btgen.lang.script.grammar462 import _Parser
from btgen.lang.script.nodes import MAX_DEPTH, Expr, Script, ScriptSyntaxError, _children


def _depth(node: Expr) -> tuple[int, int]:
    """(depth of the tree under ``node``, offset of its deepest node), without recursion."""
    best = (0, node.offset)
    stack = [(node, 1)]
    while stack:
        n, d = stack.pop()
        if d > best[0]:
            best = (d, n.offset)
        stack.extend((c, d + 1) for c in reversed(_children(n)))
    return best


def parse_script(code: str, grammar_49: bool = False) -> Script:
    """Parse a script; raises :class:`ScriptSyntaxError` with the offset of the problem.

    ``grammar_49``: the grammar of BehaviorTree.CPP 4.9.0 and later (versions.py
    ``script_grammar_49``); else 4.6.2's."""
    script = _Parser49(code).script() if grammar_49 else _Parser(code).script()
    for stmt in script.statements:
        depth, offset = _depth(stmt)
        if depth > MAX_DEPTH:
            raise ScriptSyntaxError(
                f"the expression is too deep ({depth} levels, at most {MAX_DEPTH}); split it into several statements",
                offset,
            )
    return script


def script_error_loc(attr_value_loc: Loc, code: str, offset: int, raw_value: Optional[str] = None) -> Loc:
    """Where character ``offset`` of a script is in the file.

    ``attr_value_loc`` is the first character of the attribute value and
    ``code`` its decoded text. Newlines in the value move to the next line.
    Pass the value as written in the file (``raw_value``) when it may
    contain entity or character references (``&amp;``, ``&#10;``): each
    then counts as one decoded character.
    """
    offset = max(0, min(offset, len(code)))
    if raw_value is None:
        raw_text, raw_offset = code, offset
    else:
        raw_text = raw_value
        raw_offset = decoded = 0
        ref = re.compile(r"&(?:#[0-9]+|#x[0-9a-fA-F]+|[A-Za-z_][\w.-]*);")
        while raw_offset < len(raw_value) and decoded < offset:
            m = ref.match(raw_value, raw_offset) if raw_value[raw_offset] == "&" else None
            raw_offset = m.end() if m else raw_offset + 1
            decoded += 1
    before = raw_text[:raw_offset]
    newlines = before.count("\n")
    if newlines == 0:
        return attr_value_loc.shifted(raw_offset)
    return Loc(attr_value_loc.path, attr_value_loc.line + newlines, raw_offset - before.rfind("\n"))


# The text of a script attribute as written in its file (for error columns past entity
# references), shared by the compiler's and the interpreter's script error positions.
_FILE_LINES: dict[str, list[str]] = {}


def raw_attr_value(value_loc: Loc) -> Optional[str]:
    """The attribute value as written in the file (entity references undecoded)."""
    lines = _FILE_LINES.get(value_loc.path)
    if lines is None:
        try:
            data = read_bounded(value_loc.path, 16 << 20, "mission")  # (the mission's own bound)
            lines = data.decode("utf-8-sig").split("\n")
        except (UserError, UnicodeDecodeError):
            return None
        _FILE_LINES[value_loc.path] = lines
    if not 1 <= value_loc.line <= len(lines):
        return None
    line = lines[value_loc.line - 1]
    start = value_loc.col - 1
    if start < 1 or start > len(line) or line[start - 1] not in "\"'":
        return None
    quote = line[start - 1]
    # Up to the closing quote, joining the following lines only while it is not found (joining
    # the whole rest of the file for every attribute made large missions quadratic).
    text = line[start:]
    end = text.find(quote)
    following = value_loc.line
    while end < 0 and following < len(lines):
        searched = len(text) + 1
        text += "\n" + lines[following]
        following += 1
        end = text.find(quote, searched)
    return text[:end] if end >= 0 else None
