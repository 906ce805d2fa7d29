"""Substitution rules as data: the test node configs and rules of BehaviorTree.CPP 4.x's
`TestNodeConfigs` / `SubstitutionRules` (read by `frontend/substitution.py`), and which rule
matches which node. Both engines apply them: the interpreter while it builds the tree
(`interp/substitute.py`), the compiled executor on the lowered program (`ir/substitute.py`).

A rule's filter matches a node when it equals the node's name or its registration ID, or when
it matches, as a wildcard pattern, the node's path (`SubTreePath/name`, a node without a name
attribute being `ID::UID`, as 4.6.2's `config.path`). The first rule that matches, in the
file's order, applies (BehaviorTree.CPP keeps the rules in an unordered map, so which of two
matching rules wins is not defined there). Only leaves are substituted: a rule that matches a
Control, a Decorator or a SubTree is an error (a TestNode cannot hold their children).
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.lang.catalogue import BUILTINS
from btgen.lang.model import Attr, Mission, Node, SubTreeNode


@dataclass(frozen=True)
class TestConfig:
    name: str
    return_status: int
    async_delay: int
    success_script: Optional[Attr]
    failure_script: Optional[Attr]
    post_script: Optional[Attr]
    grammar_49: bool = False


class Wildcard:
    """A filter as a wildcard pattern, compiled once: `*` any run of characters, `?` one,
    `\\` escapes the next (the library's wildcards::match). Matching takes time linear in the
    text for a given pattern (no backtracking): the pattern is cut at its stars into pieces of
    fixed length; the first must start the text, the last end it, and each other is found
    leftmost after the one before (a fixed-length piece found earlier never spoils a match)."""

    __slots__ = ("pieces", "literal", "prefix")

    def __init__(self, pattern: str) -> None:
        pieces: list[list[Optional[str]]] = [[]]
        i = 0
        while i < len(pattern):
            c = pattern[i]
            if c == "\\" and i + 1 < len(pattern):
                pieces[-1].append(pattern[i + 1])
                i += 2
                continue
            if c == "*":
                pieces.append([])
            else:
                pieces[-1].append(None if c == "?" else c)
            i += 1
        self.literal = not any(c in pattern for c in "*?\\")  # matches the text equal to it only
        # the characters every text it matches starts with (to index many patterns)
        self.prefix = "".join(c for c in itertools.takewhile(lambda c: c is not None, pieces[0]) if c is not None)
        # each piece: (length, its text when it has no `?`, else a regex of it); literal
        # pieces are found with str methods, and only pieces with `?` compile a regex
        self.pieces: list[tuple[int, Optional[str], Optional[re.Pattern[str]]]] = [
            (len(p), "".join(c for c in p if c is not None), None)
            if None not in p
            else (len(p), None, re.compile("".join("." if c is None else re.escape(c) for c in p), re.DOTALL))
            for p in pieces
        ]

    @staticmethod
    def _at(text: str, piece: tuple[int, Optional[str], Optional[re.Pattern[str]]], pos: int) -> bool:
        n, lit, rx = piece
        if lit is not None:
            return text.startswith(lit, pos)
        return rx is not None and rx.match(text, pos) is not None

    def match(self, text: str) -> bool:
        pieces = self.pieces
        n0 = pieces[0][0]
        if len(pieces) == 1:
            return len(text) == n0 and self._at(text, pieces[0], 0)
        nl = pieces[-1][0]
        if len(text) < n0 + nl or not self._at(text, pieces[0], 0) or not self._at(text, pieces[-1], len(text) - nl):
            return False
        pos, end = n0, len(text) - nl
        for n, lit, rx in pieces[1:-1]:
            if n == 0:
                continue
            if lit is not None:
                at = text.find(lit, pos, end)
                if at < 0:
                    return False
                pos = at + n
                continue
            m = rx.search(text, pos, end) if rx is not None else None
            if m is None:
                return False
            pos = m.end()
        return True


@dataclass(frozen=True)
class Rule:
    filter: str
    target: str  # a TestNodeConfig's name or a node ID
    loc: Loc
    config: Optional[TestConfig]
    pattern: Wildcard = field(init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "pattern", Wildcard(self.filter))


class Rules(tuple):
    """The rules of a file, in its order, with their index (built once: a node is matched
    against a dict of the exact filters and the list of the wildcard ones)."""

    @cached_property
    def exact(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for i, r in enumerate(self):
            out.setdefault(r.filter, i)
        return out

    @cached_property
    def literal(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for i, r in enumerate(self):
            if r.pattern.literal:
                out.setdefault(r.filter, i)
        return out

    @cached_property
    def wild(self) -> list[int]:
        return [i for i, r in enumerate(self) if not r.pattern.literal]

    @cached_property
    def _trie(self) -> dict:
        """The wildcard rules by the literal prefix of their pattern (key None: the indexes
        of the rules whose prefix ends there)."""
        root: dict = {}
        for i in self.wild:
            node = root
            for c in self[i].pattern.prefix:
                node = node.setdefault(c, {})
            node.setdefault(None, []).append(i)
        return root

    def wild_candidates(self, path: str) -> list[int]:
        """The wildcard rules whose literal prefix starts `path`, in file order: the only ones
        that may match it (one walk down the path, not one try per rule)."""
        node: Optional[dict] = self._trie
        out: list[int] = []
        for c in itertools.chain((None,), path):
            if c is not None:
                node = node.get(c) if node is not None else None
            if node is None:
                break
            out.extend(node.get(None, ()))
        out.sort()
        return out


def wildcard_match(text: str, pattern: str) -> bool:
    """`*` any run of characters, `?` one, `\\` escapes the next (the library's wildcards::match)."""
    return Wildcard(pattern).match(text)


def node_path(prefix: str, node: Node, uid: int) -> str:
    name = node.name if node.name is not None else f"{node.id}::{uid}"
    return prefix + name


def match_index(rules: tuple[Rule, ...], node: Node, path: str) -> Optional[int]:
    """The index of the first rule that matches `node` at `path` (its name, its registration ID,
    or its path as a wildcard pattern), or None."""
    if not isinstance(rules, Rules):
        rules = Rules(rules)
    reg = "SubTree" if isinstance(node, SubTreeNode) else node.id
    best: Optional[int] = None
    for i in (rules.exact.get(node.display_name), rules.exact.get(reg), rules.literal.get(path)):
        if i is not None and (best is None or i < best):
            best = i
    for i in rules.wild_candidates(path):
        if best is not None and i > best:
            break
        if rules[i].pattern.match(path):
            return i
    return best


def match(rules: tuple[Rule, ...], node: Node, path: str) -> Optional[Rule]:
    i = match_index(rules, node, path)
    return None if i is None else rules[i]


def check_leaf(rule: Rule, node: Node, mission: Mission) -> None:
    """Only leaves can be substituted (a TestNode cannot hold children): UserError otherwise."""
    kind = "SubTree" if isinstance(node, SubTreeNode) else mission.spec(node.id).kind
    if kind not in ("Action", "Condition"):
        raise UserError(
            Diagnostic(
                rule.loc,
                f'the rule `{rule.filter}` matches `{node.id}` "{node.display_name}" ({node.loc}), a '
                f"{kind}: only leaves can be substituted",
            )
        )
    if rule.config is not None or rule.target in BUILTINS:
        return
    try:
        target = mission.spec(rule.target)
    except KeyError:
        return  # (reported where the node is built)
    if target.kind in ("Action", "Condition") and target.kind != kind:
        # A scripted Action and a scripted Condition answer differently (RUNNING, what is taken
        # from the scenario when): both engines refuse the change rather than differ.
        raise UserError(
            Diagnostic(
                rule.loc,
                f'the rule `{rule.filter}` builds `{node.id}` "{node.display_name}" ({node.loc}), '
                f"{'an' if kind == 'Action' else 'a'} {kind}, as `{rule.target}`, a {target.kind}: a mission's "
                "own leaf can stand only for a leaf of its kind",
            )
        )
