"""BehaviorTree.CPP 4.9.0's script grammar (and every later release's): its tokenizer and
Pratt parser, which replaced 4.6.2's (versions.py ``script_grammar_49``)."""

from __future__ import annotations

from btgen.lang import values
from btgen.lang.script.grammar462 import _Token
from btgen.lang.script.nodes import (
    ASSIGN_OPS,
    COMPARE_OPS,
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
