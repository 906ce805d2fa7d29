"""The script language's syntax tree: its nodes, the operator groups, the limits on a tree's
nesting and depth, and the queries over a tree (`walk`, the entries a script reads and writes).
Both grammars (grammar462.py, grammar49.py) build these nodes; every later stage reads them."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Union


class ScriptSyntaxError(Exception):
    """A script 4.6.2 cannot parse; ``offset`` indexes the code string."""

    def __init__(self, message: str, offset: int) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset


# ====================================================================== AST


@dataclass(frozen=True)
class Literal:
    """A constant: ``int`` (decimal/hex integer, or ``true``=1 / ``false``=0),
    ``float`` (real literal, ``std::stod`` of its text) or ``str`` (quoted,
    no escapes). ``text`` is the literal as written."""

    value: Union[int, float, str]
    text: str
    offset: int


@dataclass(frozen=True)
class Name:
    """A blackboard entry read by name (``@name``: on the root blackboard).

    Evaluates to the entry's value (possibly empty); a missing entry is an
    error. A registered scripting enum of that name wins and evaluates to
    its value as a double."""

    name: str
    offset: int


@dataclass(frozen=True)
class Unary:
    """``-x`` (negation), ``!x`` (1.0 if x == 0 else 0.0), ``~x`` (bitwise
    complement of x truncated to int64). The operand must be a number; the
    result is a double."""

    op: str
    operand: Expr
    offset: int


@dataclass(frozen=True)
class Binary:
    """``left op right``; both sides are always evaluated, left first.

    Two numbers: ``+ - * /`` give the double result (IEEE: ``/ 0`` is
    inf/nan); ``& | ^`` convert both to int64 (whole numbers only) and give a
    double; ``&& ||`` convert both to bool (doubles: non-zero; integers: only
    0/1) and give 1.0/0.0; ``..`` gives an empty value (as 4.6.2).
    Two strings: ``+`` and ``..`` concatenate. A string and a number: ``..``
    concatenates with the number as ``std::to_string`` text (``5``,
    ``2.500000``). Anything else is an error."""

    op: str
    left: Expr
    right: Expr
    offset: int
    op_offset: int


@dataclass(frozen=True)
class Compare:
    """``a op1 b op2 c ...``: true (1.0) when every adjacent pair compares
    true, evaluated left to right and stopping (0.0) at the first false pair,
    so later operands are then not evaluated. Numbers compare as doubles
    (``==``/``!=`` with tolerance ``FLT_EPSILON`` = 1.1920929e-07), strings
    byte-wise; a string against a number is read as a number (``true`` 1,
    ``false`` 0, an enum name, else ``std::from_chars``)."""

    ops: tuple[str, ...]
    operands: tuple[Expr, ...]
    offset: int
    op_offsets: tuple[int, ...]


@dataclass(frozen=True)
class Ternary:
    """``cond ? then : orelse``: cond must be a number (or a string holding
    one), true when non-zero; only the chosen branch is evaluated."""

    cond: Expr
    then: Expr
    orelse: Expr
    offset: int
    op_offset: int


@dataclass(frozen=True)
class Assign:
    """``target op value``; the result is the entry's new value.

    ``:=`` creates the entry (type ``any``) when missing; ``=`` and the
    compound operators need it to exist. ``:=``/``=`` store the value: an
    ``any`` entry without a value takes it as is; a string into a non-string
    entry goes through the entry's converter (or, for a number, is read as a
    number); otherwise the value is copied with ``Any::copyInto`` rules (an
    integer entry stays an integer: 2.0 becomes 2, 2.5 is an error).
    ``+= -= *= /=`` need a value already: with a number they compute in
    doubles and copy the result back into the entry's kind; ``+=`` with a
    string appends to the entry's text. Every assignment bumps the entry's
    update counter."""

    op: str
    target: str
    value: Expr
    offset: int
    op_offset: int


Expr = Union[Literal, Name, Unary, Binary, Compare, Ternary, Assign]


@dataclass(frozen=True)
class Script:
    """A parsed script: its statements in order and the code they came from."""

    statements: tuple[Expr, ...]
    code: str


ASSIGN_OPS = (":=", "=", "+=", "-=", "*=", "/=")
COMPARE_OPS = ("==", "!=", "<", ">", "<=", ">=")
MATH_OPS = ("+", "-", "*", "/", "..")
BIT_OPS = ("&", "|", "^")
LOGIC_OPS = ("&&", "||")

MAX_NESTING = 32  # parentheses, `?:` middles and prefix operators inside each other
MAX_DEPTH = 100  # levels of the syntax tree (evaluation and C++ code recurse on it)


# ============================================================ static queries


def _children(node: Expr) -> tuple[Expr, ...]:
    if isinstance(node, Unary):
        return (node.operand,)
    if isinstance(node, Binary):
        return (node.left, node.right)
    if isinstance(node, Compare):
        return node.operands
    if isinstance(node, Ternary):
        return (node.cond, node.then, node.orelse)
    if isinstance(node, Assign):
        return (node.value,)
    return ()


def walk(node: Expr) -> Iterator[Expr]:
    """``node`` and all nodes below it, in evaluation order (pre-order)."""
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(_children(n)))


def _dedup(names: Iterator[str]) -> tuple[str, ...]:
    return tuple(dict.fromkeys(names))


def variables_read(script: Script) -> tuple[str, ...]:
    """Entry names the script may read (``@`` kept), in order of first appearance.

    The target of a compound assignment (``+=`` ...) counts as read; names
    that are registered enums at run time are included (the parser cannot
    tell them apart)."""

    def gen() -> Iterator[str]:
        for stmt in script.statements:
            for node in walk(stmt):
                if isinstance(node, Name):
                    yield node.name
                elif isinstance(node, Assign) and node.op not in (":=", "="):
                    yield node.target

    return _dedup(gen())


def variables_written(script: Script) -> tuple[str, ...]:
    """Entry names the script may assign (``@`` kept), in order of first appearance."""
    return _dedup(n.target for s in script.statements for n in walk(s) if isinstance(n, Assign))
