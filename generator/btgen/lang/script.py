"""The BehaviorTree.CPP 4.6.2 script language: lexer, parser, AST and evaluator.

Scripts appear in ``Script``/``ScriptCondition`` ``code``, ``Precondition``
``if`` and the ``_skipIf``/``_successIf``/``_failureIf``/``_while``/
``_onSuccess``/``_onFailure``/``_onHalted``/``_post`` attributes. The grammar
is 4.6.2's (``scripting/operators.hpp``, ``any_types.hpp``), lowest binding
first::

    script      := statement (';' statement)*        no `;` after the last one
    statement   := assignment
    assignment  := conditional [ASSIGN conditional]  ASSIGN: := = += -= *= /=
    conditional := logical ['?' statement ':' logical]
    logical     := comparison (('&&' | '||') comparison)*     one level, left
    comparison  := operand (CMP operand)*            CMP: == != < > <= >=, chained
    operand     := math | concat | bits              not mixed without ( )
      concat    := sum ('..' sum)*
      sum       := product (('+' | '-') product)*
      product   := negation (('*' | '/') negation)*
      negation  := '-' negation | atom
      bits      := bitand (('|' | '^') bitand)*
      bitand    := bitnot ('&' bitnot)*
      bitnot    := ('~' | '!') bitnot | atom
    atom        := '(' statement ')' | name | 'true' | 'false' | number | string

Where 4.6.2's parser has bugs fixed in later releases, the fixed meaning is
used (FORMAT.md): ``a - b == 2`` parses, ``A==-1`` parses, and ``A - B + C``
is ``(A - B) + C``.

Runtime values follow 4.6.2's ``BT::Any`` (see :mod:`btgen.lang.values`): integer
literals are integers, ``true``/``false`` are the integers 1/0, real literals
and the result of every arithmetic, comparison and logical operator are
doubles. ``None`` is 4.6.2's empty value.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Callable, Optional, TypeVar, Union

from btgen.diagnostics import Loc, UserError, read_bounded
from btgen.lang import values
from btgen.lang.blackboard import Blackboard, Entry
from btgen.lang.values import ConversionError, Queue, Value


class ScriptSyntaxError(Exception):
    """A script 4.6.2 cannot parse; ``offset`` indexes the code string."""

    def __init__(self, message: str, offset: int) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset


# The longest string the interpreter builds (a script doubling a string 40 times ran out of
# memory: MemoryError, exit 3). Generated C++ holds far less: its strings have fixed
# capacities of at most --string-capacity (1 MiB) or a bound the mission shows.
MAX_STRING_BYTES = 1 << 26


def _joined(a: str, b: str, op: str, offset: int) -> str:
    if len(a) + len(b) > MAX_STRING_BYTES // 4:
        size = len(a.encode("utf-8")) + len(b.encode("utf-8"))
        if size > MAX_STRING_BYTES:
            raise ScriptRuntimeError(
                f"`{op}` would make a string of {size} bytes; the interpreter holds "
                f"strings of at most {MAX_STRING_BYTES} bytes",
                offset,
            )
    return a + b


class ScriptRuntimeError(Exception):
    """A script that fails while running, where 4.6.2 throws; ``offset`` indexes the code."""

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

# ==================================================================== lexer


@dataclass(frozen=True)
class _Token:
    kind: str  # "num" | "str" | "name" | "op" | "end"
    text: str
    start: int
    end: int
    value: Union[int, float, str, None] = None


_OPERATORS = sorted(
    [
        ":=",
        "==",
        "!=",
        "<=",
        ">=",
        "&&",
        "||",
        "+=",
        "-=",
        "*=",
        "/=",
        "..",
        "<",
        ">",
        "=",
        "+",
        "-",
        "*",
        "/",
        "&",
        "|",
        "^",
        "~",
        "!",
        "?",
        ":",
        "(",
        ")",
        ";",
    ],
    key=len,
    reverse=True,
)
_WHITESPACE = " \t\n\r\f\v"
_HEX_RE = re.compile(r"0[xX]([0-9a-fA-F]+)")
_REAL_RE = re.compile(r"[0-9]+(?:\.[0-9]+(?:[eE][+-]?[0-9]+)?|[eE][+-]?[0-9]+)")
_INT_RE = re.compile(r"[0-9]+")


def _name_start(c: str) -> bool:
    if c.isascii():
        return c.isalpha() or c in "_@"
    return c.isidentifier()


def _name_continue(c: str) -> bool:
    if c.isascii():
        return c.isalnum() or c == "_"
    return ("a" + c).isidentifier()


def _tokens(code: str) -> Iterator[_Token]:
    i, n = 0, len(code)
    while True:
        while i < n:
            if code[i] in _WHITESPACE:
                i += 1
            elif code[i] == "\\" and i + 1 < n and code[i + 1] in "\r\n":
                i += 3 if code.startswith("\r\n", i + 1) else 2
            else:
                break
        if i >= n:
            yield _Token("end", "", n, n)
            return
        c = code[i]
        if c.isdigit():
            tok = _number(code, i)
        elif c in "'\"":
            end = code.find(c, i + 1)
            if end < 0:
                raise ScriptSyntaxError(f"unterminated string: missing closing {c}", i)
            text = code[i + 1 : end]
            for k, ch in enumerate(text):
                if not ch.isascii():
                    raise ScriptSyntaxError(
                        "only ASCII characters are allowed in a script string (BehaviorTree.CPP 4.6.2)", i + 1 + k
                    )
            tok = _Token("str", code[i : end + 1], i, end + 1, text)
        elif _name_start(c):
            j = i + 1
            while j < n and _name_continue(code[j]):
                j += 1
            word = code[i:j]
            if word == "@":
                raise ScriptSyntaxError("`@` must be followed by a name (`@key` is `key` on the root blackboard)", i)
            for lit in ("true", "false"):
                if word.startswith(lit) and word != lit:
                    raise ScriptSyntaxError(
                        f"`{word}`: BehaviorTree.CPP 4.6.2 reads a name starting with `{lit}` as the "
                        f"literal {lit} followed by `{word[len(lit) :]}`; rename it",
                        i,
                    )
            tok = _Token("name", word, i, j)
        else:
            for op in _OPERATORS:
                if code.startswith(op, i):
                    tok = _Token("op", op, i, i + len(op))
                    break
            else:
                what = repr(c) if c.isprintable() else f"U+{ord(c):04X}"
                raise ScriptSyntaxError(f"unexpected character {what}", i)
        yield tok
        i = tok.end


def _number(code: str, i: int) -> _Token:
    """An integer (decimal or 0x hex) or real literal starting at ``i`` (no sign)."""
    m = _HEX_RE.match(code, i)
    kind = "hex"
    if not m:
        m = _REAL_RE.match(code, i)
        kind = "real"
    if not m:
        m = _INT_RE.match(code, i)
        kind = "int"
    assert m is not None
    end = m.end()
    if end < len(code) and (code[end] == "." or code[end] == "_" or code[end].isalpha()):
        j = end
        while j < len(code) and (code[j] == "." or code[j] == "_" or code[j].isalnum()):
            j += 1
        raise ScriptSyntaxError(
            f"invalid number `{code[i:j]}`"
            + (" (write `..` with a space after a number, e.g. `1 .. x`)" if code.startswith("..", end) else ""),
            i,
        )
    text = code[i:end]
    value: Union[int, float]
    if kind == "hex":
        value = int(m.group(1), 16)
    elif kind == "int":
        value = int(text)
    else:
        try:
            value = values.convert_from_string(values.DOUBLE, text)  # type: ignore[assignment]
        except ConversionError:
            raise ScriptSyntaxError(f"number `{text}` is out of range for a double", i) from None
    if isinstance(value, int) and value > values.INT64_MAX:
        raise ScriptSyntaxError(f"integer `{text}` is out of range (at most {values.INT64_MAX})", i)
    return _Token("num", text, i, end, value)


# =================================================================== parser

_GROUP_OF = {
    "-": "math",
    "+": "math",
    "*": "math",
    "/": "math",
    "..": "math",
    "~": "bits",
    "!": "bits",
    "&": "bits",
    "|": "bits",
    "^": "bits",
}


class _Parser:
    def __init__(self, code: str) -> None:
        self.code = code
        self.toks = list(_tokens(code))
        self.i = 0
        # One frame per comparison operand being parsed: (op, offset) of the
        # math/bit operators used in it outside parentheses.
        self.groups: list[list[tuple[str, int]]] = []
        self.nesting = 0  # open parentheses, `?:` middles and prefix operators

    def enter(self, at: _Token) -> None:
        """Bound the parser's recursion: bad input must give an error, not a crash."""
        self.nesting += 1
        if self.nesting > MAX_NESTING:
            raise self.error(f"the expression is nested too deeply (more than {MAX_NESTING} levels)", at)

    # -- token helpers
    @property
    def tok(self) -> _Token:
        return self.toks[self.i]

    def peek(self, k: int = 1) -> _Token:
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def at_op(self, *ops: str) -> bool:
        return self.tok.kind == "op" and self.tok.text in ops

    def advance(self) -> _Token:
        t = self.tok
        self.i += 1
        return t

    def describe(self, t: _Token) -> str:
        return "the end of the script" if t.kind == "end" else f"`{t.text}`"

    def error(self, message: str, t: Optional[_Token] = None) -> ScriptSyntaxError:
        return ScriptSyntaxError(message, (t or self.tok).start)

    def note_op(self, op: str, offset: int) -> None:
        frame = self.groups[-1]
        group = _GROUP_OF[op]
        for prev, _ in frame:
            if _GROUP_OF[prev] != group:
                raise ScriptSyntaxError(
                    f"`{op}` cannot be mixed with `{prev}` without parentheses (BehaviorTree.CPP "
                    f"keeps arithmetic and bitwise operators apart)",
                    offset,
                )
        frame.append((op, offset))

    # -- grammar
    def script(self) -> Script:
        if self.tok.kind == "end":
            raise self.error("empty script")
        stmts = [self._statement()]  # top level: not nested
        while self.at_op(";"):
            semi = self.advance()
            if self.tok.kind == "end":
                raise ScriptSyntaxError(
                    "unexpected `;` after the last statement (BehaviorTree.CPP 4.6.2 rejects a trailing `;`)",
                    semi.start,
                )
            if self.at_op(";"):
                raise self.error("empty statement between two `;`")
            stmts.append(self._statement())
        if self.tok.kind != "end":
            raise self.error(f"unexpected {self.describe(self.tok)}; expected an operator, `;` or the end")
        return Script(tuple(stmts), self.code)

    def statement(self, opener: _Token) -> Expr:
        """A statement nested in `(` or `?`, the token ``opener``."""
        self.enter(opener)
        try:
            return self._statement()
        finally:
            self.nesting -= 1

    def _statement(self) -> Expr:
        start = self.tok.start
        lhs = self.conditional()
        if self.at_op(*ASSIGN_OPS):
            op = self.advance()
            if not isinstance(lhs, Name):
                raise ScriptSyntaxError(f"the left side of `{op.text}` must be a blackboard entry name", start)
            rhs = self.conditional()
            if self.at_op(*ASSIGN_OPS):
                raise self.error("assignments cannot be chained; separate them with `;`")
            return Assign(op.text, lhs.name, rhs, start, op.start)
        return lhs

    def conditional(self) -> Expr:
        cond = self.logical()
        if not self.at_op("?"):
            return cond
        q = self.advance()
        then = self.statement(q)
        if not self.at_op(":"):
            raise self.error(f"expected `:` of `?:` here, found {self.describe(self.tok)}")
        self.advance()
        orelse = self.logical()
        if self.at_op("?"):
            raise self.error("`?:` cannot be chained without parentheses: write `a ? b : (c ? d : e)`")
        return Ternary(cond, then, orelse, cond.offset, q.start)

    def logical(self) -> Expr:
        left = self.comparison()
        while self.at_op(*LOGIC_OPS):
            op = self.advance()
            right = self.comparison()
            left = Binary(op.text, left, right, left.offset, op.start)
        return left

    def comparison(self) -> Expr:
        first = self.operand()
        ops: list[str] = []
        offsets: list[int] = []
        operands = [first]
        while self.at_op(*COMPARE_OPS):
            op = self.advance()
            ops.append(op.text)
            offsets.append(op.start)
            operands.append(self.operand())
        if not ops:
            return first
        return Compare(tuple(ops), tuple(operands), first.offset, tuple(offsets))

    def operand(self) -> Expr:
        self.groups.append([])
        try:
            return self.bits_or()
        finally:
            self.groups.pop()

    def _left_assoc(self, ops: tuple[str, ...], sub: Callable[[], Expr]) -> Expr:
        left = sub()
        while self.at_op(*ops):
            op = self.advance()
            self.note_op(op.text, op.start)
            right = sub()
            left = Binary(op.text, left, right, left.offset, op.start)
        return left

    # Arithmetic and bitwise operators never share an operand, so their
    # relative precedence is immaterial; bitwise ones are placed lowest.
    def bits_or(self) -> Expr:
        return self._left_assoc(("|", "^"), self.bits_and)

    def bits_and(self) -> Expr:
        return self._left_assoc(("&",), self.concat)

    def concat(self) -> Expr:
        return self._left_assoc(("..",), self.sum)

    def sum(self) -> Expr:
        return self._left_assoc(("+", "-"), self.product)

    def product(self) -> Expr:
        return self._left_assoc(("*", "/"), self.prefix)

    def prefix(self) -> Expr:
        if self.at_op("-", "~", "!"):
            op = self.advance()
            self.note_op(op.text, op.start)
            if op.text in "~!":
                # The operand of `~`/`!` is an atom, and an atom may be a
                # signed number: `!-1` is `!` applied to the literal -1.
                signed = self.signed_number()
                if signed is not None:
                    return Unary(op.text, signed, op.start)
            self.enter(op)
            try:
                return Unary(op.text, self.prefix(), op.start)
            finally:
                self.nesting -= 1
        return self.atom()

    def signed_number(self) -> Optional[Literal]:
        """``+5`` / ``-5`` written without a blank: 4.6.2's literal with a sign."""
        if self.at_op("+", "-") and self.peek().kind == "num" and self.peek().start == self.tok.end:
            sign = self.advance()
            num = self.advance()
            assert num.value is not None and not isinstance(num.value, str)
            value = -num.value if sign.text == "-" else num.value
            if isinstance(value, int) and value < values.INT64_MIN:
                raise ScriptSyntaxError(f"integer `{sign.text}{num.text}` is out of range", sign.start)
            return Literal(value, sign.text + num.text, sign.start)
        return None

    def atom(self) -> Expr:
        t = self.tok
        if t.kind == "num":
            self.advance()
            assert t.value is not None
            return Literal(t.value, t.text, t.start)
        if t.kind == "str":
            self.advance()
            assert isinstance(t.value, str)
            return Literal(t.value, t.text, t.start)
        if t.kind == "name":
            self.advance()
            if t.text in ("true", "false"):
                return Literal(1 if t.text == "true" else 0, t.text, t.start)
            return Name(t.text, t.start)
        if self.at_op("("):
            self.advance()
            inner = self.statement(t)
            if not self.at_op(")"):
                raise self.error(f"expected `)` to close the `(` at offset {t.start}, found {self.describe(self.tok)}")
            self.advance()
            return inner
        signed = self.signed_number()
        if signed is not None:
            return signed
        raise self.error(f"expected a value, a name or `(`, found {self.describe(t)}")


# ============================================================ the 4.9.0 parser
# BehaviorTree.CPP 4.9.0 replaced the lexy grammar with a tokenizer and a Pratt parser
# (d1983321). Binding powers, lowest first: assignment, `?:` (else branch nested),
# `||`, `&&`, comparisons (chained), `|` `^`, `&`, `+` `-` `..`, `*` `/`, prefix `-` `~` `!`.
# Every group mixes by precedence; `;` between statements is optional; `true`/`false` are
# the doubles 1.0/0.0; strings take single quotes only; there is no unary `+`.

_BP49 = {
    ":=": 2,
    "=": 2,
    "+=": 2,
    "-=": 2,
    "*=": 2,
    "/=": 2,
    "?": 4,
    "||": 6,
    "&&": 8,
    "==": 10,
    "!=": 10,
    "<": 10,
    ">": 10,
    "<=": 10,
    ">=": 10,
    "|": 12,
    "^": 12,
    "&": 14,
    "+": 16,
    "-": 16,
    "..": 16,
    "*": 18,
    "/": 18,
}
_PREFIX_BP49 = 20
_TERNARY_BP49 = 4
_COMPARISON_BP49 = 10
_TWO_CHAR_OPS49 = ("..", "&&", "||", "==", "!=", "<=", ">=", ":=", "+=", "-=", "*=", "/=")
_ONE_CHAR_OPS49 = "+-*/&|^~!<>=?:();"


def _tokens49(code: str) -> list[_Token]:
    """4.9.0's tokenizer (script_tokenizer.cpp); a character it cannot read becomes an
    "error" token, refused when the parser reaches it."""
    toks: list[_Token] = []
    i, n = 0, len(code)

    def ident_char(c: str) -> bool:
        return c.isascii() and (c.isalnum() or c == "_")

    while i < n:
        c = code[i]
        if c in " \t\n\r":
            i += 1
            continue
        start = i
        if c == "'":
            end = code.find("'", i + 1)
            if end < 0:
                toks.append(_Token("error", code[i:], i, n))
                i = n
            else:
                toks.append(_Token("str", code[i : end + 1], i, end + 1, code[i + 1 : end]))
                i = end + 1
            continue
        if c.isascii() and c.isdigit():
            bad = False
            real = False
            if c == "0" and i + 1 < n and code[i + 1] in "xX":
                i += 2
                if i >= n or code[i] not in "0123456789abcdefABCDEF":
                    bad = True
                while i < n and code[i] in "0123456789abcdefABCDEF":
                    i += 1
                if i < n and (code[i] == "." or ident_char(code[i])):
                    bad = True
                    while i < n and (ident_char(code[i]) or code[i] == "."):
                        i += 1
                text = code[start:i]
                if not bad:
                    v = int(text[2:], 16)
                    toks.append(_Token("num", text, start, i, v if v <= values.INT64_MAX else 0))
                    continue
            else:
                while i < n and code[i].isascii() and code[i].isdigit():
                    i += 1
                if i < n and code[i] == ".":
                    if i + 1 < n and code[i + 1] == ".":
                        pass  # `65..` is 65 then `..`
                    elif i + 1 < n and code[i + 1].isascii() and code[i + 1].isdigit():
                        real = True
                        i += 1
                        while i < n and code[i].isascii() and code[i].isdigit():
                            i += 1
                    else:
                        bad = True
                        i += 1
                        while i < n and (ident_char(code[i]) or code[i] == "."):
                            i += 1
                if not bad and i < n and code[i] in "eE":
                    real = True
                    i += 1
                    if i < n and code[i] in "+-":
                        i += 1
                    if i >= n or not (code[i].isascii() and code[i].isdigit()):
                        bad = True
                    while i < n and code[i].isascii() and code[i].isdigit():
                        i += 1
                if not bad and i < n and code[i].isascii() and (code[i].isalpha() or code[i] in "_@"):
                    bad = True
                    while i < n and ident_char(code[i]):
                        i += 1
            text = code[start:i]
            if bad:
                toks.append(_Token("error", text, start, i))
            elif real:
                try:
                    value = float(values.convert_from_string(values.DOUBLE, text, double_from_chars=True))  # type: ignore[arg-type]
                except ConversionError:
                    raise ScriptSyntaxError(f"number `{text}` is out of range for a double", start) from None
                toks.append(_Token("num", text, start, i, value))
            else:
                v = int(text)
                # std::from_chars leaves the value 0 when it does not fit an int64
                toks.append(_Token("num", text, start, i, v if v <= values.INT64_MAX else 0))
            continue
        if c.isascii() and (c.isalpha() or c in "_@"):
            i += 1
            while i < n and ident_char(code[i]):
                i += 1
            toks.append(_Token("name", code[start:i], start, i))
            continue
        two = code[i : i + 2]
        if two in _TWO_CHAR_OPS49:
            toks.append(_Token("op", two, i, i + 2))
            i += 2
            continue
        if c in _ONE_CHAR_OPS49:
            toks.append(_Token("op", c, i, i + 1))
        else:
            toks.append(_Token("error", c, i, i + 1))
        i += 1
    toks.append(_Token("end", "", n, n))
    return toks


class _Parser49:
    """The Pratt parser of 4.9.0 (script_parser.cpp), building btgen's AST."""

    def __init__(self, code: str) -> None:
        self.code = code
        self.toks = _tokens49(code)
        self.i = 0
        self.nesting = 0

    @property
    def tok(self) -> _Token:
        return self.toks[self.i]

    def advance(self) -> _Token:
        t = self.toks[self.i]
        if t.kind != "end":
            self.i += 1
        return t

    def at_op(self, *ops: str) -> bool:
        return self.tok.kind == "op" and self.tok.text in ops

    def enter(self, at: _Token) -> None:
        self.nesting += 1
        if self.nesting > MAX_NESTING:
            raise ScriptSyntaxError(f"the expression is nested too deeply (more than {MAX_NESTING} levels)", at.start)

    def script(self) -> Script:
        stmts: list[Expr] = []
        while self.tok.kind != "end":
            stmts.append(self.expr(0))
            while self.at_op(";"):
                self.advance()
        if not stmts:
            raise ScriptSyntaxError("empty script", 0)
        return Script(tuple(stmts), self.code)

    def describe(self, t: _Token) -> str:
        return "the end of the script" if t.kind == "end" else f"`{t.text}`"

    def prefix(self) -> Expr:
        t = self.tok
        if t.kind == "op" and t.text in ("-", "~", "!"):
            self.advance()
            self.enter(t)
            try:
                return Unary(t.text, self.expr(_PREFIX_BP49), t.start)
            finally:
                self.nesting -= 1
        if t.kind == "op" and t.text == "(":
            self.advance()
            self.enter(t)
            try:
                inner = self.expr(0)
            finally:
                self.nesting -= 1
            if not self.at_op(")"):
                raise ScriptSyntaxError(
                    f"expected `)` to close the `(` at offset {t.start}, found {self.describe(self.tok)}",
                    self.tok.start,
                )
            self.advance()
            return inner
        if t.kind == "name":
            self.advance()
            if t.text in ("true", "false"):
                return Literal(1.0 if t.text == "true" else 0.0, t.text, t.start)
            return Name(t.text, t.start)
        if t.kind in ("num", "str"):
            self.advance()
            assert t.value is not None
            return Literal(t.value, t.text, t.start)
        if t.kind == "error":
            what = "a double-quoted string (BehaviorTree.CPP 4.9.0 and later take single quotes only)"
            if t.text[:1] == "'":
                what = "an unterminated string: missing closing '"
            elif t.text[:1].isdigit():
                what = f"the invalid number `{t.text}`"
            elif t.text != '"':
                c = t.text[:1]
                what = f"the character {repr(c) if c.isprintable() else f'U+{ord(c):04X}'}"
            raise ScriptSyntaxError(f"invalid token: {what}", t.start)
        if t.kind == "op" and t.text == "+":
            raise ScriptSyntaxError("expected a value, found `+` (BehaviorTree.CPP 4.9.0 has no unary `+`)", t.start)
        raise ScriptSyntaxError(f"expected a value, a name or `(`, found {self.describe(t)}", t.start)

    def expr(self, min_bp: int) -> Expr:
        left = self.prefix()
        while True:
            t = self.tok
            lbp = _BP49.get(t.text, -1) if t.kind == "op" else -1
            if lbp < 0 or lbp < min_bp:
                return left
            if t.text in ASSIGN_OPS:
                self.advance()
                if not isinstance(left, Name):
                    raise ScriptSyntaxError(f"the left side of `{t.text}` must be a blackboard entry name", left.offset)
                right = self.expr(0)
                return Assign(t.text, left.name, right, left.offset, t.start)
            if t.text == "?":
                self.advance()
                self.enter(t)
                try:
                    then = self.expr(0)
                    if not self.at_op(":"):
                        raise ScriptSyntaxError(
                            f"expected `:` of `?:` here, found {self.describe(self.tok)}", self.tok.start
                        )
                    self.advance()
                    orelse = self.expr(_TERNARY_BP49)
                finally:
                    self.nesting -= 1
                return Ternary(left, then, orelse, left.offset, t.start)
            if t.text in COMPARE_OPS:
                ops: list[str] = []
                offsets: list[int] = []
                operands = [left]
                while self.at_op(*COMPARE_OPS):
                    op = self.advance()
                    ops.append(op.text)
                    offsets.append(op.start)
                    operands.append(self.expr(_COMPARISON_BP49 + 1))
                left = Compare(tuple(ops), tuple(operands), left.offset, tuple(offsets))
                continue
            self.advance()
            right = self.expr(lbp + 1)
            left = Binary(t.text, left, right, left.offset, t.start)


MAX_NESTING = 32  # parentheses, `?:` middles and prefix operators inside each other
MAX_DEPTH = 100  # levels of the syntax tree (evaluation and C++ code recurse on it)


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


def format_expr(node: Expr) -> str:
    """The expression fully parenthesized, e.g. ``((a - b) + c)``; for tests and messages."""
    if isinstance(node, Literal):
        return node.text
    if isinstance(node, Name):
        return node.name
    if isinstance(node, Unary):
        return f"{node.op}{format_expr(node.operand)}"
    if isinstance(node, Binary):
        return f"({format_expr(node.left)} {node.op} {format_expr(node.right)})"
    if isinstance(node, Compare):
        parts = [format_expr(node.operands[0])]
        for op, o in zip(node.ops, node.operands[1:]):
            parts += [op, format_expr(o)]
        return "(" + " ".join(parts) + ")"
    if isinstance(node, Ternary):
        return f"({format_expr(node.cond)} ? {format_expr(node.then)} : {format_expr(node.orelse)})"
    return f"({node.target} {node.op} {format_expr(node.value)})"


# ================================================================ evaluation

FLT_EPSILON = 1.1920928955078125e-07


class _Evaluator:
    def __init__(self, bb: Blackboard, enums: Mapping[str, int], int53: bool = False) -> None:
        self.bb = bb
        self.enums = enums
        self.int53 = int53

    def eval(self, node: Expr) -> Optional[Value]:
        if isinstance(node, Literal):
            return node.value
        if isinstance(node, Name):
            return self.name(node)
        if isinstance(node, Unary):
            return self.unary(node)
        if isinstance(node, Binary):
            return self.binary(node)
        if isinstance(node, Compare):
            return self.compare(node)
        if isinstance(node, Ternary):
            return self.ternary(node)
        return self.assign(node)

    # -- helpers
    def double(self, v: Value, offset: int, what: str) -> float:
        if self.int53 and isinstance(v, int) and abs(int(v)) > _MAX_EXACT_53:
            # 4.7.0 (versions.py int_to_double_53_bits): a limit, exact or not
            raise ScriptRuntimeError(
                f"{what}: loss of precision when converting the large integer {int(v)} to floating point "
                f"(at most 2^53-1)",
                offset,
            )
        try:
            return values.to_double(v)
        except ConversionError as e:
            raise ScriptRuntimeError(f"{what}: {e}", offset) from None

    def string_to_double(self, s: str, offset: int) -> float:
        """4.6.2 ``StringToDouble``: `true`/`false`, an enum name, else from_chars."""
        if s == "true":
            return 1.0
        if s == "false":
            return 0.0
        if s in self.enums:
            return float(self.enums[s])
        try:
            return values.to_double(s)
        except ConversionError:
            raise ScriptRuntimeError(f"the string {values.describe(s)} is not a number", offset) from None

    @staticmethod
    def kind(v: Optional[Value]) -> str:
        return "an empty value" if v is None else f"a {values.type_of(v)}"

    # -- nodes
    def name(self, node: Name) -> Optional[Value]:
        if node.name in self.enums:
            return float(self.enums[node.name])
        entry = self.bb.get_entry(node.name)
        if entry is None:
            raise ScriptRuntimeError(
                f"unknown variable `{node.name}` (no blackboard entry of that name; "
                f"create it with `{node.name} := ...`)",
                node.offset,
            )
        return entry.value

    def unary(self, node: Unary) -> Value:
        v = self.eval(node.operand)
        if values.is_number(v):
            assert v is not None
            x = self.double(v, node.offset, f"operand of `{node.op}`")
            if node.op == "-":
                return -x
            if node.op == "!":
                return 1.0 if x == 0.0 else 0.0
            if math.isnan(x) or not float(values.INT64_MIN) <= x < 2.0**63:
                raise ScriptRuntimeError(f"{values.describe(v)} is out of range for `~`", node.offset)
            return float(~int(x))
        if v is None:
            raise ScriptRuntimeError(f"the operand of `{node.op}` has no value", node.offset)
        raise ScriptRuntimeError(f"`{node.op}` cannot be applied to {self.kind(v)}", node.offset)

    def binary(self, node: Binary) -> Optional[Value]:
        op, off = node.op, node.op_offset
        lv = self.eval(node.left)
        rv = self.eval(node.right)
        if lv is None:
            raise ScriptRuntimeError(f"the left operand of `{op}` has no value", off)
        if rv is None:
            raise ScriptRuntimeError(f"the right operand of `{op}` has no value", off)
        if values.is_number(lv) and values.is_number(rv):
            if op in ("+", "-", "*", "/"):
                a = self.double(lv, off, f"left operand of `{op}`")
                b = self.double(rv, off, f"right operand of `{op}`")
                return _arith(op, a, b)
            if op in BIT_OPS:
                try:
                    a, b = values.to_int64(lv), values.to_int64(rv)
                except ConversionError as e:
                    raise ScriptRuntimeError(f"`{op}` needs whole-number operands: {e}", off) from None
                return float(a & b if op == "&" else a | b if op == "|" else a ^ b)
            if op in LOGIC_OPS:
                try:
                    a_b = values.cast(lv, values.BOOL)
                    b_b = values.cast(rv, values.BOOL)
                except ConversionError as e:
                    raise ScriptRuntimeError(f"`{op}` needs operands that convert to bool: {e}", off) from None
                return float(bool(a_b and b_b) if op == "&&" else bool(a_b or b_b))
            return None  # `..` of two numbers: 4.6.2 yields an empty value
        if isinstance(lv, str) and isinstance(rv, str) and op in ("+", ".."):
            return _joined(lv, rv, op, off)
        if (
            op == ".."
            and (isinstance(lv, str) or isinstance(rv, str))
            and (values.is_number(lv) or isinstance(lv, str))
            and (values.is_number(rv) or isinstance(rv, str))
        ):
            return _joined(values.to_text(lv), values.to_text(rv), op, off)
        raise ScriptRuntimeError(f"`{op}` cannot be applied to {self.kind(lv)} and {self.kind(rv)}", off)

    def compare(self, node: Compare) -> float:
        lv = self.eval(node.operands[0])
        for op, off, operand in zip(node.ops, node.op_offsets, node.operands[1:]):
            rv = self.eval(operand)
            if lv is None:
                raise ScriptRuntimeError(f"the left operand of `{op}` has no value", off)
            if rv is None:
                raise ScriptRuntimeError(f"the right operand of `{op}` has no value", off)
            if values.is_number(lv) and values.is_number(rv):
                ok = _compare(
                    op,
                    self.double(lv, off, f"left operand of `{op}`"),
                    self.double(rv, off, f"right operand of `{op}`"),
                    True,
                )
            elif isinstance(lv, str) and isinstance(rv, str):
                ok = _compare(op, lv.encode(), rv.encode(), False)
            elif isinstance(lv, str) and values.is_number(rv):
                ok = _compare(
                    op, self.string_to_double(lv, off), self.double(rv, off, f"right operand of `{op}`"), True
                )
            elif values.is_number(lv) and isinstance(rv, str):
                ok = _compare(op, self.double(lv, off, f"left operand of `{op}`"), self.string_to_double(rv, off), True)
            else:
                raise ScriptRuntimeError(f"cannot compare {self.kind(lv)} with {self.kind(rv)} using `{op}`", off)
            if not ok:
                return 0.0
            lv = rv
        return 1.0

    def ternary(self, node: Ternary) -> Optional[Value]:
        v = self.eval(node.cond)
        if v is None:
            raise ScriptRuntimeError("the condition of `?:` has no value", node.op_offset)
        if isinstance(v, str):
            try:
                x = values.to_double(v)
            except ConversionError:
                raise ScriptRuntimeError(
                    f"the condition of `?:` is the string {values.describe(v)}, which is not a number", node.op_offset
                ) from None
        elif values.is_number(v):
            x = self.double(v, node.op_offset, "condition of `?:`")
        else:
            raise ScriptRuntimeError(f"the condition of `?:` is {self.kind(v)}", node.op_offset)
        return self.eval(node.then if x != 0.0 else node.orelse)

    def assign(self, node: Assign) -> Optional[Value]:
        op, key, off = node.op, node.target, node.op_offset
        entry = self.bb.get_entry(key)
        if entry is None:
            if op != ":=":
                raise ScriptRuntimeError(f"blackboard entry `{key}` does not exist yet; use `:=` to create it", off)
            self.bb.create_entry(key, values.ANY)
            entry = self.bb.get_entry(key)
            assert entry is not None
        value = self.eval(node.value)
        if value is None:
            raise ScriptRuntimeError(f"the right operand of `{op}` has no value", off)
        if op in (":=", "="):
            entry.value = self._store(entry, key, value, off)
        else:
            entry.value = self._compound(entry, key, op, value, off)
        entry.bump()
        return entry.value

    def _store(self, entry: Entry, key: str, value: Value, off: int) -> Value:
        dst = entry.value
        # The first value of an entry created untyped (AnyTypeAllowed) is taken as it is; an
        # empty entry typed BT::Any (4.7.0's SetBlackboard, blackboard.ANY_TYPED) is not one.
        if dst is None and entry.type_name == values.ANY:
            return value
        if isinstance(value, str) and not isinstance(dst, str):
            if entry.has_converter:
                try:
                    return entry.convert(value)
                except ConversionError as e:
                    raise ScriptRuntimeError(
                        f"cannot assign {values.describe(value)} to `{key}` ({entry.type_name}): {e}", off
                    ) from None
            if values.is_number(dst):
                return self.string_to_double(value, off)
            raise ScriptRuntimeError(
                f"cannot assign the string {values.describe(value)} to `{key}`, which holds {self.kind(dst)}", off
            )
        try:
            return values.copy_into(value, dst)
        except ConversionError as e:
            raise ScriptRuntimeError(f"cannot assign {values.describe(value)} to `{key}`: {e}", off) from None

    def _compound(self, entry: Entry, key: str, op: str, value: Value, off: int) -> Value:
        current = entry.value
        if current is None:
            raise ScriptRuntimeError(f"`{key}` has no value yet, so `{op}` cannot update it", off)
        result: Value = current
        if values.is_number(value):
            if not values.is_number(current):
                raise ScriptRuntimeError(
                    f"`{op}` with a number needs a numeric `{key}`, but it holds {self.kind(current)}", off
                )
            a = self.double(current, off, f"`{key}`")
            b = self.double(value, off, f"right operand of `{op}`")
            result = _arith(op[0], a, b)
        elif isinstance(value, str):
            if op != "+=":
                raise ScriptRuntimeError(f"`{op}` cannot be used with a string", off)
            try:
                result = values.to_text(current) + value
            except ConversionError as e:
                raise ScriptRuntimeError(f"`+=` on `{key}`: {e}", off) from None
        try:
            return values.copy_into(result, current)
        except ConversionError as e:
            raise ScriptRuntimeError(f"cannot store the result of `{op}` in `{key}`: {e}", off) from None


def _arith(op: str, a: float, b: float) -> float:
    """IEEE double arithmetic, as C++ does it (division by zero gives inf or nan)."""
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if b == 0.0:
        if math.isnan(a):
            return a  # a NaN operand comes through as it is
        if a == 0.0:
            # 0/0 gives x86-64's default NaN, whose sign bit is set: std::to_string
            # writes it `-nan` (edges table N1)
            return -math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)
    return a / b


_Ordered = TypeVar("_Ordered", float, bytes)


def _compare(op: str, a: _Ordered, b: _Ordered, numeric: bool) -> bool:
    """4.6.2 ``ExprComparison::SwitchImpl``: ``==``/``!=`` on doubles within FLT_EPSILON."""
    if op in ("==", "!="):
        if isinstance(a, float) and isinstance(b, float):
            same = abs(a - b) <= FLT_EPSILON
        else:
            same = a == b
        return same if op == "==" else not same
    if op == "<":
        return not a >= b
    if op == ">":
        return not a <= b
    if op == "<=":
        return not a > b
    return not a < b


_MAX_EXACT_53 = 2**53 - 1


def evaluate(
    script: Script, blackboard: Blackboard, enums: Optional[Mapping[str, int]] = None, int53: bool = False
) -> Optional[Value]:
    """Run a script on a blackboard; returns the value of its last statement.

    ``enums`` are scripting enums (4.6.2 ``registerScriptingEnum``; none by
    default). The result may be None (an empty value, e.g. a variable that
    has none yet). Raises :class:`ScriptRuntimeError`.
    """
    ev = _Evaluator(blackboard, enums or {}, int53)
    result: Optional[Value] = None
    for stmt in script.statements:
        result = ev.eval(stmt)
    return result


def script_truth(value: Optional[Value]) -> bool:
    """A script result as a condition (``cast<bool>()`` in ScriptCondition,
    Precondition and the ``_skipIf``/``_successIf``/``_failureIf``/``_while``
    checks of 4.6.2): a double is true when non-zero; an integer must be 0
    or 1; a string, a queue or an empty value is an error."""
    if value is None:
        raise ScriptRuntimeError("the script gives no value, so it cannot be used as a condition", 0)
    if isinstance(value, (str, Queue)):
        raise ScriptRuntimeError(
            f"the script gives {values.describe(value)} ({values.type_of(value)}), which is not a condition", 0
        )
    try:
        return bool(values.cast(value, values.BOOL))
    except ConversionError as e:
        raise ScriptRuntimeError(f"the script's result cannot be used as a condition: {e}", 0) from None


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
