"""Scripting enums: what BehaviorTree.CPP's ``registerScriptingEnum`` gives scripts.

Declared on the command line (``--enum Color=RED,GREEN,BLUE``, values 0, 1, 2 as
``registerScriptingEnums<Color>()`` numbers a plain C++ enum; ``--enum Mode=AUTO=2,MANUAL``
gives explicit values, a name without one the previous value plus one) or in a file
(``--enums FILE``: one such declaration per line, ``#`` comments). The enum's own name is
only documentation: 4.6.2 keeps one table of value names.

In a script a registered name reads as its value, a double, before any blackboard entry
of that name (4.6.2's ``ExprName``); a string holding such a name converts to that value
where 4.6.2 reads a string as a number (``StringToDouble``). Both engines apply the table
the same way: the parsed scripts get the values as literals (``apply``), and string
conversions consult the table at run time (the interpreter's evaluator; the generated
code's ``detail::kScriptingEnums``).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable, Sequence
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded
from btgen.lang import script as sc
from btgen.lang.model import Attr, Mission, Node

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_INT32 = (-(2**31), 2**31 - 1)
# The integer forms of a value: ASCII digits only (Python's int() also takes `1_000`, `٥`
# and `１２`, which no C++ enum declaration spells), decimal or 0x/0o/0b.
_INTEGER = re.compile(r"[+-]?(?:0[xX][0-9A-Fa-f]+|0[oO][0-7]+|0[bB][01]+|[0-9]+)\Z", re.ASCII)
MAX_ENUMS_BYTES = 1 << 20

Enums = tuple[tuple[str, int], ...]


class EnumSyntaxError(ValueError):
    """A declaration that does not parse; ``column`` is 1-based in the declaration."""

    def __init__(self, message: str, column: int = 1) -> None:
        super().__init__(message)
        self.message = message
        self.column = column


def parse_declaration(text: str) -> list[tuple[str, int]]:
    """``Type=NAME[=VALUE],NAME[=VALUE],...`` -> [(NAME, value), ...]."""
    type_name, eq, rest = text.partition("=")
    if not eq or not _NAME.match(type_name.strip()):
        raise EnumSyntaxError(
            f"`{text}` is not an enum declaration: write Type=NAME,NAME,... (for example Color=RED,GREEN,BLUE)"
        )
    out: list[tuple[str, int]] = []
    value = -1
    column = len(type_name) + 2
    for item in rest.split(","):
        name, eq, number = item.partition("=")
        name = name.strip()
        if not _NAME.match(name):
            raise EnumSyntaxError(
                f"`{name or item}` in enum `{type_name.strip()}` is not a name "
                f"(letters, digits and _, not starting with a digit)",
                column,
            )
        if eq:
            try:
                if not _INTEGER.match(number.strip()):
                    raise ValueError(number)
                value = int(number.strip(), 0)
            except ValueError:
                raise EnumSyntaxError(
                    f"the value of `{name}` in enum `{type_name.strip()}` is not an integer: `{number.strip()}`", column
                ) from None
        else:
            value += 1
        if not _INT32[0] <= value <= _INT32[1]:
            raise EnumSyntaxError(
                # (as written: 4,400 hex digits parse, but int -> str refuses past 4,300)
                f"the value of `{name}` ({number.strip() if eq else value}) does not fit an int "
                "(registerScriptingEnum takes an int)",
                column,
            )
        out.append((name, value))
        column += len(item) + 1
    return out


def _merge(into: dict[str, int], items: Iterable[tuple[str, int]], where: str) -> Optional[str]:
    for name, value in items:
        if name in into and into[name] != value:
            return f"{where}: enum value `{name}` is declared twice, as {into[name]} and as {value}"
        into[name] = value
    return None


def load(declarations: Sequence[str] = (), files: Sequence[str] = ()) -> Enums:
    """The table of `--enum` declarations and `--enums` files; UserError (path:line:col for a
    file, the option otherwise) when one does not parse or a name gets two values."""
    table: dict[str, int] = {}
    problems: list[Diagnostic] = []
    for path in files:
        try:
            data = read_bounded(path, MAX_ENUMS_BYTES, "enums", cannot="cannot read the enums file")
        except UserError as e:
            problems.extend(e.diagnostics)
            continue
        if data.startswith(b"\xef\xbb\xbf"):  # (a byte order mark, as Windows editors write)
            data = data[3:]
        try:
            lines = data.decode("utf-8").splitlines()
        except UnicodeDecodeError as e:
            good = data[: e.start].decode("utf-8")
            problems.append(
                Diagnostic(
                    Loc(path, good.count("\n") + 1, len(good) - (good.rfind("\n") + 1) + 1),
                    f"invalid UTF-8 (byte 0x{data[e.start]:02x}); enums files must be UTF-8",
                )
            )
            continue
        for number, line in enumerate(lines, 1):
            text = line.split("#", 1)[0]
            if not text.strip():
                continue
            indent = len(text) - len(text.lstrip())
            try:
                problem = _merge(table, parse_declaration(text.strip()), "")
            except EnumSyntaxError as e:
                problems.append(Diagnostic(Loc(path, number, indent + e.column), e.message))
                continue
            if problem:
                problems.append(Diagnostic(Loc(path, number, indent + 1), problem[2:]))
    for text in declarations:
        try:
            problem = _merge(table, parse_declaration(text), "--enum")
        except EnumSyntaxError as e:
            problems.append(Diagnostic(Loc("--enum", 1, e.column), e.message))
            continue
        if problem:
            problems.append(Diagnostic(Loc("--enum", 1, 1), problem[len("--enum: ") :]))
    if problems:
        raise UserError(problems)
    return tuple(table.items())


# ------------------------------------------------------------------ applying the table
def _substitute(e, table: dict[str, int]):
    if isinstance(e, sc.Name):
        if e.name in table:
            return sc.Literal(float(table[e.name]), e.name, e.offset)
        return e
    if not dataclasses.is_dataclass(e) or isinstance(e, type):
        return e
    changes = {}
    for f in dataclasses.fields(e):
        v = getattr(e, f.name)
        if dataclasses.is_dataclass(v):
            nv = _substitute(v, table)
        elif isinstance(v, tuple) and any(dataclasses.is_dataclass(x) for x in v):
            nv = tuple(_substitute(x, table) for x in v)
        else:
            continue
        if nv is not v:
            changes[f.name] = nv
    return dataclasses.replace(e, **changes) if changes else e


def _attrs(attrs: tuple[Attr, ...], table: dict[str, int]) -> tuple[Attr, ...]:
    return tuple(
        dataclasses.replace(a, script=_substitute(a.script, table)) if a.script is not None else a for a in attrs
    )


def _node(node: Node, table: dict[str, int]) -> Node:
    return dataclasses.replace(
        node,
        ports=_attrs(node.ports, table),
        pre=_attrs(node.pre, table),
        post=_attrs(node.post, table),
        children=tuple(_node(c, table) for c in node.children),
    )


def apply(mission: Mission, enums: Enums) -> Mission:
    """The mission with `enums` registered: every script reads the registered names as their
    values (doubles), as 4.6.2's ExprName does, and `mission.enums` holds the table."""
    if not enums:
        return mission
    table = dict(enums)
    trees = tuple(dataclasses.replace(t, root=_node(t.root, table)) for t in mission.trees)
    return dataclasses.replace(mission, trees=trees, enums=tuple(enums))
