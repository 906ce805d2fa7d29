"""Properties of `btgen verify`: LTL in SPIN's syntax over per-tick atoms, and named templates.

    formula := formula ('->' | '<->') formula | formula '||' formula | formula '&&' formula
             | formula ('U' | 'V' | 'W') formula | ('!' | '[]' | '<>') formula
             | '(' formula ')' | 'true' | 'false' | ATOM | TEMPLATE
    ATOM    := ticked(NAME) | running(NAME) | returned(NAME, STATUS) | root(STATUS)
             | ENTRY ('==' | '!=' | '<' | '<=' | '>' | '>=') VALUE   (the root blackboard)
    TEMPLATE:= absence(F) | response(F, G) | mutex(NAME, NAME, ...) | eventually_success[(NAME, ...)]

Binding, tightest first: the unary operators, then U V W, then &&, then ||, then -> and <->
(right to left); the formula given to SPIN is fully parenthesised, so SPIN's own precedence
never matters. `X` (next) is refused: the model takes many steps per tick, and a property
without X cannot tell them apart.

Atoms hold at the end of a tick: `ticked(N)` N was ticked in that tick, `returned(N, S)` N
returned S (at least once) in it, `running(N)` N is RUNNING after it, `root(S)` the root
returned S. NAME is a node's name or registration ID as traces print them, or `#UID`; a NAME
that matches no node or several is a located error that lists the candidates.

Templates: `absence(F)` is `[] !F`; `response(F, G)` is `[] (F -> <> G)`; `mutex(A, B, ...)`
says no two of the nodes are ticked in the same tick; `eventually_success(L, ...)` is
`<> root(SUCCESS)` under fairness of the leaves named (each one ticked infinitely often
returns SUCCESS infinitely often), all the mission's leaves when none is named (at most
MAX_FAIR: the never claim grows exponentially with them).

A property file has one property a line, optionally `NAME: ` first; `#` starts a comment.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.ir.lower import Program
from btgen.tools.verify.promela import STATUS, Observe

MAX_FAIR = 2
_TOKEN = re.compile(
    r"\s*(?:(?P<str>'[^']*')|(?P<op>\[\]|<->|<>|->|&&|\|\||==|!=|<=|>=|<|>|!|\(|\)|,)|(?P<word>#?(?:[A-Za-z0-9_.:@/]|-(?!>))+)|(?P<bad>\S))"
)
_RESULTS = ("SUCCESS", "FAILURE", "RUNNING", "SKIPPED")

Formula = tuple  # ("atom", key) | ("const", bool) | (op, sub...) ; see module docstring


@dataclass(frozen=True)
class Property:
    name: str  # the ltl block's name in the model
    text: str
    formula: Formula
    loc: Loc


class _Tok:
    __slots__ = ("kind", "text", "col")

    def __init__(self, kind: str, text: str, col: int) -> None:
        self.kind, self.text, self.col = kind, text, col


def _tokens(text: str, at: Loc) -> list[_Tok]:
    out: list[_Tok] = []
    pos = 0
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            break
        if m.group("bad") is not None:
            raise _err(at, m.start("bad"), f"unexpected `{m.group('bad')}` in a property")
        kind = "op" if m.group("op") is not None else "str" if m.group("str") is not None else "word"
        start = m.start(kind)
        out.append(_Tok(kind, m.group(kind), start))
        pos = m.end()
    out.append(_Tok("end", "", len(text)))
    return out


def _err(at: Loc, col: int, message: str) -> UserError:
    return UserError(Diagnostic(Loc(at.path, at.line, at.col + col), message))


class Names:
    """NAME -> node index, as traces name nodes."""

    def __init__(self, program: Program, entries: Optional[dict[str, str]] = None) -> None:
        self.program = program
        # the root blackboard's entries the scripts give values (name -> a value's description)
        self.entries = entries or {}
        self.by: dict[str, list[int]] = {}
        for n in program.nodes:
            self.by.setdefault(n.name, []).append(n.index)
            if n.id != n.name:
                self.by.setdefault(n.id, []).append(n.index)
            self.by.setdefault(f"#{n.uid}", []).append(n.index)

    def resolve(self, name: str, at: Loc, col: int) -> int:
        found = sorted(set(self.by.get(name, ())))
        if len(found) == 1:
            return found[0]
        if not found:
            from btgen.diagnostics import did_you_mean

            hint = did_you_mean(name, [k for k in self.by if not k.startswith("#")])
            extra = f" (did you mean `{hint}`?)" if hint else ""
            raise _err(at, col, f"no node is named `{name}`{extra}; use a node's name, its ID or #UID")
        cands = ", ".join(
            f'#{self.program.nodes[i].uid} ({self.program.nodes[i].id} "{self.program.nodes[i].name}")'
            for i in found[:8]
        )
        more = f" and {len(found) - 8} more" if len(found) > 8 else ""
        raise _err(at, col, f"`{name}` names {len(found)} nodes: {cands}{more}; say which with #UID")

    def leaves(self) -> list[int]:
        return [n.index for n in self.program.nodes if n.kind in ("Action", "Condition")]


class _Parser:
    def __init__(self, text: str, at: Loc, names: Names) -> None:
        self.text = text
        self.at = at
        self.names = names
        self.toks = _tokens(text, at)
        self.i = 0

    def peek(self) -> _Tok:
        return self.toks[self.i]

    def next(self) -> _Tok:
        t = self.toks[self.i]
        self.i += 1
        return t

    def expect(self, text: str) -> _Tok:
        t = self.next()
        if t.text != text:
            got = f"`{t.text}`" if t.kind != "end" else "the end of the property"
            raise _err(self.at, t.col, f"expected `{text}`, found {got}")
        return t

    def parse(self) -> Formula:
        f = self.implication()
        t = self.peek()
        if t.kind != "end":
            raise _err(self.at, t.col, f"unexpected `{t.text}` after a complete property")
        return f

    def implication(self) -> Formula:
        left = self.disjunction()
        t = self.peek()
        if t.text in ("->", "<->"):
            self.next()
            right = self.implication()
            return ("imp" if t.text == "->" else "iff", left, right)
        return left

    def disjunction(self) -> Formula:
        f = self.conjunction()
        while self.peek().text == "||":
            self.next()
            f = ("or", f, self.conjunction())
        return f

    def conjunction(self) -> Formula:
        f = self.until()
        while self.peek().text == "&&":
            self.next()
            f = ("and", f, self.until())
        return f

    def until(self) -> Formula:
        left = self.unary()
        t = self.peek()
        if t.kind == "word" and t.text in ("U", "V", "W"):
            self.next()
            return (t.text, left, self.until())
        return left

    def unary(self) -> Formula:
        t = self.peek()
        if t.text == "!":
            self.next()
            return ("not", self.unary())
        if t.text == "[]":
            self.next()
            return ("G", self.unary())
        if t.text == "<>":
            self.next()
            return ("F", self.unary())
        return self.primary()

    def primary(self) -> Formula:
        t = self.next()
        if t.text == "(":
            f = self.implication()
            self.expect(")")
            return f
        if t.kind != "word":
            got = f"`{t.text}`" if t.kind != "end" else "the end of the property"
            raise _err(self.at, t.col, f"expected an atom or `(`, found {got}")
        if t.text in ("true", "false"):
            return ("const", t.text == "true")
        if t.text == "X":
            raise _err(self.at, t.col, "`X` (next) is not supported: a tick is many model steps; use `<>` or `U`")
        word = t.text
        if word in ("ticked", "running", "returned", "root"):
            return self.atom(t)
        if word in ("absence", "response", "mutex", "eventually_success"):
            return self.template(t)
        if self.peek().text in ("==", "!=", "<", ">", "<=", ">="):
            return self.comparison(t)
        if re.match(r"[A-Za-z_]", word):
            raise _err(
                self.at,
                t.col,
                f"unknown atom `{word}`: use ticked(NAME), running(NAME), returned(NAME, STATUS), root(STATUS) "
                "or a blackboard comparison, ENTRY == VALUE (==, !=, <, <=, >, >=)",
            )
        raise _err(self.at, t.col, f"unexpected `{word}` in a property")

    def comparison(self, t: _Tok) -> Formula:
        """ENTRY OP VALUE over the root blackboard at the end of a tick (blackboard.compare_entry)."""
        if t.text not in self.names.entries:
            from btgen.diagnostics import did_you_mean

            hint = did_you_mean(t.text, list(self.names.entries))
            known = ", ".join(sorted(self.names.entries)[:8]) or "none: the mission has no scripts"
            extra = f" (did you mean `{hint}`?)" if hint else ""
            raise _err(
                self.at,
                t.col,
                f"`{t.text}` is no blackboard entry the mission's scripts write on the root blackboard{extra}; "
                f"entries: {known}",
            )
        op = self.next().text
        v = self.next()
        value: object
        if v.kind == "str":
            value = v.text[1:-1]
        elif v.text in ("true", "false"):
            value = 1 if v.text == "true" else 0
        elif v.kind == "word" and re.fullmatch(r"-?[0-9]+", v.text):
            value = int(v.text)
        elif v.kind == "word" and re.fullmatch(r"-?[0-9]*\.[0-9]+(?:[eE][-+]?[0-9]+)?", v.text):
            value = float(v.text)
        else:
            raise _err(self.at, v.col, "expected a value: a number, true, false or a 'string'")
        return ("atom", ("bb", t.text, op, value))

    def name_arg(self) -> int:
        t = self.next()
        if t.kind != "word":
            raise _err(self.at, t.col, "expected a node name (its name attribute, its ID or #UID)")
        return self.names.resolve(t.text, self.at, t.col)

    def status_arg(self, allowed: tuple[str, ...]) -> int:
        t = self.next()
        if t.text not in allowed:
            raise _err(self.at, t.col, f"expected a status ({', '.join(allowed)}), found `{t.text}`")
        return STATUS[t.text]

    def atom(self, t: _Tok) -> Formula:
        self.expect("(")
        if t.text == "root":
            key: tuple = ("root", self.status_arg(_RESULTS))
        elif t.text == "returned":
            node = self.name_arg()
            self.expect(",")
            key = ("returned", node, self.status_arg(_RESULTS))
        else:
            key = (t.text, self.name_arg())
        self.expect(")")
        return ("atom", key)

    def template(self, t: _Tok) -> Formula:
        word = t.text
        if word == "eventually_success" and self.peek().text != "(":
            leaves = self.names.leaves()
            if len(leaves) > MAX_FAIR:
                raise _err(
                    self.at,
                    t.col,
                    f"eventually_success assumes fairness of every leaf, and this mission has {len(leaves)} "
                    f"(at most {MAX_FAIR}: SPIN's never claim grows exponentially); name them: "
                    "eventually_success(A, B)",
                )
            return _eventually(leaves)
        self.expect("(")
        if word == "absence":
            f = self.implication()
            self.expect(")")
            return ("G", ("not", f))
        if word == "response":
            f = self.implication()
            self.expect(",")
            g = self.implication()
            self.expect(")")
            return ("G", ("imp", f, ("F", g)))
        nodes = [self.name_arg()]
        while self.peek().text == ",":
            self.next()
            nodes.append(self.name_arg())
        self.expect(")")
        if word == "mutex":
            if len(nodes) < 2:
                raise _err(self.at, t.col, "mutex needs at least two nodes")
            pairs: Optional[Formula] = None
            for a in range(len(nodes)):
                for b in range(a + 1, len(nodes)):
                    both = ("and", ("atom", ("ticked", nodes[a])), ("atom", ("ticked", nodes[b])))
                    pairs = both if pairs is None else ("or", pairs, both)
            assert pairs is not None
            return ("G", ("not", pairs))
        if len(nodes) > MAX_FAIR:
            raise _err(self.at, t.col, f"eventually_success takes at most {MAX_FAIR} leaves")
        return _eventually(nodes)


def _eventually(leaves: list[int]) -> Formula:
    goal: Formula = ("F", ("atom", ("root", STATUS["SUCCESS"])))
    fair: Optional[Formula] = None
    for i in leaves:
        one = ("imp", ("G", ("F", ("atom", ("ticked", i)))), ("G", ("F", ("atom", ("returned", i, STATUS["SUCCESS"])))))
        fair = one if fair is None else ("and", fair, one)
    return goal if fair is None else ("imp", fair, goal)


def parse_property(text: str, at: Loc, names: Names, index: int) -> Property:
    body = text
    offset = 0
    m = re.match(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*:(?!:)\s*", text)
    label = None
    if m and m.group(1) not in ("ticked", "running", "returned", "root"):
        label = m.group(1)
        offset = m.end()
        body = text[offset:]
    if not body.strip():
        raise _err(at, offset, "an empty property")
    shifted = Loc(at.path, at.line, at.col + offset)
    formula = _Parser(body, shifted, names).parse()
    return Property(f"p{index}", (f"{label}: " if label else "") + body.strip(), formula, at)


def parse_file(path: str, names: Names, start: int = 0) -> list[Property]:
    from btgen.diagnostics import read_bounded

    data = read_bounded(path, 1 << 20, "property file", "property files", cannot="cannot read the property file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise UserError(Diagnostic(Loc(path, 1, 1), "the property file is not UTF-8")) from None
    out: list[Property] = []
    for lineno, line in enumerate(text.split("\n"), start=1):
        cut = line.find("#") if not re.search(r"#[0-9]", line) else _comment_at(line)
        body = line if cut < 0 else line[:cut]
        if not body.strip():
            continue
        out.append(parse_property(body, Loc(path, lineno, 1), names, start + len(out)))
    if not out:
        raise UserError(Diagnostic(Loc(path, 1, 1), "the property file has no property"))
    return out


def _comment_at(line: str) -> int:
    """`#` starts a comment unless it is a `#UID` node reference."""
    for m in re.finditer("#", line):
        nxt = line[m.start() + 1 : m.start() + 2]
        if not nxt.isdigit():
            return m.start()
    return -1


# ---------------------------------------------------------------- to SPIN, and evaluation
def atom_expr(key: tuple, obs: Observe) -> str:
    kind = key[0]
    if kind == "ticked":
        obs.ticked.add(key[1])
        return f"tk{key[1]} == 1"
    if kind == "returned":
        obs.returned.add(key[1])
        return f"(rt{key[1]} & {1 << key[2]}) != 0"
    if kind == "running":
        return f"st[{key[1]}] == RUNNING"
    if kind == "bb":
        from btgen.tools.verify.blackboard import compare_entry

        holds = [f"bb == {k}" for k, values in enumerate(obs.bb_values) if compare_entry(values, key)]
        return "(" + " || ".join(holds) + ")" if holds else "false"
    return f"rootr == {key[1]}"


def to_spin(f: Formula, obs: Observe) -> str:
    op = f[0]
    if op == "atom":
        return obs.atom(atom_expr(f[1], obs))
    if op == "const":
        return "true" if f[1] else "false"
    if op == "not":
        return f"!({to_spin(f[1], obs)})"
    if op == "G":
        return f"[]({to_spin(f[1], obs)})"
    if op == "F":
        return f"<>({to_spin(f[1], obs)})"
    a, b = to_spin(f[1], obs), to_spin(f[2], obs)
    if op == "W":
        return f"((({a}) U ({b})) || []({a}))"
    sym = {"and": "&&", "or": "||", "imp": "->", "iff": "<->", "U": "U", "V": "V"}[op]
    return f"(({a}) {sym} ({b}))"


Frame = dict  # atom key -> bool, at the end of one tick


def holds_on_lasso(f: Formula, frames: list[Frame], loop: int) -> bool:
    """Truth of f at position 0 of the infinite word frames[:loop] (frames[loop:])^omega.
    An independent evaluation (fixpoints over the positions), not SPIN's."""
    n = len(frames)
    if not 0 <= loop < n:
        raise ValueError("the loop must start inside the frames")
    succ = [i + 1 if i + 1 < n else loop for i in range(n)]

    def ev(g: Formula) -> list[bool]:
        op = g[0]
        if op == "atom":
            return [bool(fr.get(g[1], False)) for fr in frames]
        if op == "const":
            return [g[1]] * n
        if op == "not":
            return [not x for x in ev(g[1])]
        if op in ("and", "or", "imp", "iff"):
            a, b = ev(g[1]), ev(g[2])
            fn = {
                "and": lambda x, y: x and y,
                "or": lambda x, y: x or y,
                "imp": lambda x, y: (not x) or y,
                "iff": lambda x, y: x == y,
            }[op]
            return [fn(x, y) for x, y in zip(a, b)]
        if op == "F":
            return until([True] * n, ev(g[1]))
        if op == "G":
            return [not x for x in until([True] * n, [not y for y in ev(g[1])])]
        a, b = ev(g[1]), ev(g[2])
        if op == "U":
            return until(a, b)
        if op == "V":  # a V b = !(!a U !b)
            return [not x for x in until([not y for y in a], [not y for y in b])]
        if op == "W":
            u = until(a, b)
            always = [not x for x in until([True] * n, [not y for y in a])]
            return [x or y for x, y in zip(u, always)]
        raise ValueError(op)

    def until(a: list[bool], b: list[bool]) -> list[bool]:
        sat = list(b)
        changed = True
        while changed:  # least fixpoint: sat = b or (a and sat[succ])
            changed = False
            for i in range(n - 1, -1, -1):
                if not sat[i] and a[i] and sat[succ[i]]:
                    sat[i] = True
                    changed = True
        return sat

    return ev(f)[0]


def _temporal(f: Formula) -> bool:
    if f[0] in ("atom", "const"):
        return False
    if f[0] in ("G", "F", "U", "V", "W"):
        return True
    return any(_temporal(g) for g in f[1:])


def _at_start(f: Formula) -> bool:
    """A state formula's value before the first tick (no atom holds there)."""
    return holds_on_lasso(f, [{}], 0)


def start_insensitive(f: Formula) -> bool:
    """True when f has the same truth on a run and on that run after an all-false first
    position (the model's state before the first tick): then SPIN can check f as it is;
    other formulas are checked from the end of the first tick (`build_model`)."""
    op = f[0]
    if op == "const":
        return True
    if op == "atom":
        return False
    if op in ("not", "and", "or", "imp", "iff"):
        return all(start_insensitive(g) for g in f[1:])
    if op == "F":
        g = f[1]
        return start_insensitive(g) or (not _temporal(g) and not _at_start(g))
    if op == "G":
        g = f[1]
        if start_insensitive(g) or (not _temporal(g) and _at_start(g)):
            return True
        return g[0] == "imp" and not _temporal(g[1]) and not _at_start(g[1])
    return False


def atoms_of(f: Formula, out: Optional[set] = None) -> set:
    out = set() if out is None else out
    if f[0] == "atom":
        out.add(f[1])
    elif f[0] != "const":
        for g in f[1:]:
            atoms_of(g, out)
    return out
