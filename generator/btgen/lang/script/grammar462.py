"""BehaviorTree.CPP 4.6.2's script grammar: its lexer and recursive-descent parser
(``scripting/operators.hpp``, ``any_types.hpp``), lowest binding first::

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

Where 4.6.2's parser has bugs fixed in later releases, the fixed meaning is
used (FORMAT.md): ``a - b == 2`` parses, ``A==-1`` parses, and ``A - B + C``
is ``(A - B) + C``.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Callable, Optional, Union

from btgen.lang import values
from btgen.lang.script.nodes import (
    ASSIGN_OPS,
    COMPARE_OPS,
    LOGIC_OPS,
    MAX_NESTING,
    Assign,
    Binary,
    Compare,
    Expr,
    Literal,
    Name,
    Script,
    ScriptSyntaxError,
    Ternary,
    Unary,
)
from btgen.lang.values import ConversionError

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


class Strict462Parser(_Parser):
    """4.6.2's parser as the real library applies it: a comparison's operands hold no operator
    outside parentheses (`a + 1 == 4`, `x == -1`, `!f == g` are refused: "operator cannot be
    mixed with previous operators", recorded on 4.6.2). btgen's own parser accepts them on
    purpose (as 4.9.0 does, docs/real-files.md); `btgen tests` uses this one to refuse a suite
    the real 4.6.2 cannot load."""

    last_ops: list[tuple[str, int]] = []

    def operand(self) -> Expr:
        self.groups.append([])
        try:
            return self.bits_or()
        finally:
            self.last_ops = self.groups.pop()

    def comparison(self) -> Expr:
        first = self.operand()
        mixed = self.last_ops[0][0] if self.last_ops else None
        ops: list[str] = []
        offsets: list[int] = []
        operands = [first]
        while self.at_op(*COMPARE_OPS):
            op = self.advance()
            if mixed is not None:
                raise ScriptSyntaxError(_mixed(op.text, mixed), op.start)
            ops.append(op.text)
            offsets.append(op.start)
            operands.append(self.operand())
            if self.last_ops:
                raise ScriptSyntaxError(_mixed(self.last_ops[0][0], op.text), self.last_ops[0][1])
        if not ops:
            return first
        return Compare(tuple(ops), tuple(operands), first.offset, tuple(offsets))


def _mixed(op: str, prev: str) -> str:
    return f"`{op}` cannot be mixed with `{prev}` without parentheses"
