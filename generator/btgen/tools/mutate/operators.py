"""The mutation operators of `btgen mutate`: small edits of the mission's XML tree.

Each operator works on the parsed file (frontend/xmlsource: lxml with exact positions) and
yields `Mutant`s: an edit named by its operator, the node's path (`Tree/Tag#name/Tag[2]`), its
line and column, and a function that applies the edit to a copy of the tree. The mutant's XML
(`Mutant.xml`) is what `btgen mutate -o DIR` writes and what is loaded, with the checks of
`btgen validate`, before it counts. An edit whose XML is the original's (two equal children
swapped) or an earlier mutant's (one of two equal children removed) makes no new mutant.

Operators (the names `--format json` and the report use):
  swap-kind        Sequence <-> Fallback, in the same form (reactive, memory)
  swap-form        a Sequence or Fallback into another form of its kind (plain, reactive,
                   with memory); Nav2's PipelineSequence, RoundRobin and RecoveryNode into the
                   plain forms they resemble
  parallel         a Parallel's success_count / failure_count, ParallelAll's max_failures: +-1
  drop-child       a child of a node with two or more children, removed
  reorder          two neighbouring children swapped
  remove-decorator an Inverter, ForceSuccess or ForceFailure replaced by its child
  count            Repeat num_cycles, RetryUntilSuccessful num_attempts, Nav2's RecoveryNode
                   number_of_retries: +-1
  timeout          a Timeout's msec halved and doubled
  precondition     _successIf / _failureIf / _skipIf / _while: the condition negated
  script-operator  an operator of a script swapped (== !=, < <=, > >=, && ||, + -, * /, += -=)
                   or a `!` removed
  script-constant  a number +-1, true <-> false, a string emptied (or filled)
  remap            a SubTree port remapping removed, two remappings' values swapped,
                   _autoremap toggled
"""

from __future__ import annotations

import copy
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Callable

from lxml import etree

from btgen.diagnostics import Loc
from btgen.frontend.xmlsource import Source

_GENERIC = ("Action", "Condition", "Control", "Decorator")
_SEQ = ("Sequence", "ReactiveSequence", "SequenceWithMemory")
_FALL = ("Fallback", "ReactiveFallback")
# kind flip in the same form: (Sequence, Fallback), (ReactiveSequence, ReactiveFallback);
# memory has no Fallback form in BehaviorTree.CPP 4, so SequenceWithMemory flips to Fallback
_KIND = {
    "Sequence": "Fallback",
    "Fallback": "Sequence",
    "ReactiveSequence": "ReactiveFallback",
    "ReactiveFallback": "ReactiveSequence",
    "SequenceWithMemory": "Fallback",
}
_NAV2_FORMS = {
    "PipelineSequence": ("Sequence", "ReactiveSequence"),
    "RoundRobin": ("Fallback",),
    "RecoveryNode": ("Fallback",),
}
_COUNTS = {"Repeat": "num_cycles", "RetryUntilSuccessful": "num_attempts", "RecoveryNode": "number_of_retries"}
_PARALLEL = {"Parallel": ("success_count", "failure_count"), "ParallelAll": ("max_failures",)}
_REMOVABLE = ("Inverter", "ForceSuccess", "ForceFailure")
PRECONDITIONS = ("_successIf", "_failureIf", "_skipIf", "_while")
_POSTCONDITIONS = ("_onSuccess", "_onFailure", "_onHalted", "_post")
_SCRIPT_PORTS = {"Script": ("code",), "ScriptCondition": ("code",), "Precondition": ("if",)}
_SUBTREE_FIXED = ("ID", "name", "_autoremap")

# a script's tokens: strings first (nothing inside them is mutated), then the operators,
# longest first, then numbers and the boolean literals
_TOKEN = re.compile(
    r"(?P<str>'[^']*')"
    r"|(?P<op>==|!=|<=|>=|&&|\|\||\+=|-=|\*=|/=|:=|<|>|\+|-|\*|/|!)"
    r"|(?P<num>(?<![A-Za-z0-9_.])[0-9]+(?:\.[0-9]+)?(?![A-Za-z0-9_.]))"
    r"|(?P<bool>\b(?:true|false)\b)"
)
_OP_SWAP = {
    "==": "!=",
    "!=": "==",
    "<": "<=",
    "<=": "<",
    ">": ">=",
    ">=": ">",
    "&&": "||",
    "||": "&&",
    "+": "-",
    "-": "+",
    "*": "/",
    "/": "*",
    "+=": "-=",
    "-=": "+=",
}


@dataclass
class Mutant:
    id: str  # M001, ...: in the order the operators find them
    operator: str
    loc: Loc  # where the edit is (the node, the attribute's value, the token)
    path: str  # the node's path: Tree/Tag#name/Tag[2]
    change: str  # what was changed, in words
    xml: bytes = b""  # the mutated file


Edit = Callable[[etree._Element], None]  # applied to the copy of the element


def node_id(elem: etree._Element) -> str:
    """The node's registration ID: the tag, or the ID attribute of the generic forms."""
    if elem.tag in _GENERIC:
        return elem.get("ID") or elem.tag
    return str(elem.tag)


def _set_id(elem: etree._Element, new: str) -> None:
    if elem.tag in _GENERIC:
        elem.set("ID", new)
    else:
        elem.tag = new


def _children(elem: etree._Element) -> list[etree._Element]:
    return [c for c in elem if isinstance(c.tag, str)]


def _path(elem: etree._Element) -> str:
    steps = []
    e = elem
    while e is not None and e.tag != "BehaviorTree":
        parent = e.getparent()
        step = str(e.tag)
        if e.get("ID") and (e.tag in _GENERIC or e.tag == "SubTree"):
            step += f"({e.get('ID')})"
        if e.get("name"):
            step += f"#{e.get('name')}"
        if parent is not None:
            same = [c for c in _children(parent) if c.tag == e.tag]
            if len(same) > 1:
                step += f"[{same.index(e) + 1}]"
        steps.append(step)
        e = parent
    tree = e.get("ID") if e is not None else "?"
    return "/".join([str(tree)] + list(reversed(steps)))


def _int(text: str | None) -> int | None:
    if text is None or not re.fullmatch(r"-?[0-9]+", text.strip()):
        return None
    return int(text.strip())


class Finder:
    """Every mutant of one file, in document order, operator by operator within a node."""

    def __init__(self, source: Source, builtins: frozenset[str], relocate: Callable[[etree._Element], None]) -> None:
        self.source = source
        self.builtins = builtins
        self.relocate = relocate  # makes the copy loadable from elsewhere (include paths)
        self.elems = [e for e in source.root.iter() if isinstance(e.tag, str)]
        self.index = {e: i for i, e in enumerate(self.elems)}
        self.mutants: list[Mutant] = []
        # the original's XML and every mutant's: an edit that gives one of them again is no new mutant
        original = copy.deepcopy(source.root)
        relocate(original)
        self.seen = {etree.tostring(original, xml_declaration=True, encoding="UTF-8")}
        self.skipped = 0

    # ------------------------------------------------------------ building a mutant
    def _add(self, elem: etree._Element, op: str, loc: Loc, change: str, edit: Edit) -> None:
        root = copy.deepcopy(self.source.root)
        twin = [e for e in root.iter() if isinstance(e.tag, str)][self.index[elem]]
        edit(twin)
        self.relocate(root)
        xml = etree.tostring(root, xml_declaration=True, encoding="UTF-8")
        if xml in self.seen:  # the file unchanged (two equal children swapped), or an earlier mutant's
            self.skipped += 1
            return
        self.seen.add(xml)
        m = Mutant(f"M{len(self.mutants) + 1:03d}", op, loc, _path(elem), change, xml)
        self.mutants.append(m)

    def _builtin(self, elem: etree._Element, ids: tuple[str, ...] | dict) -> str | None:
        nid = node_id(elem)
        return nid if nid in ids and nid in self.builtins else None

    # ------------------------------------------------------------ the operators
    def find(self) -> list[Mutant]:
        for tree in self.source.root.iter("BehaviorTree"):
            for elem in tree.iter():
                if isinstance(elem.tag, str) and elem is not tree:
                    self._node(elem)
        return self.mutants

    def _node(self, elem: etree._Element) -> None:
        src = self.source
        loc = src.loc(elem)
        nid = node_id(elem)
        kids = _children(elem)
        if self._builtin(elem, _KIND):
            new = _KIND[nid]
            self._add(elem, "swap-kind", loc, f"{nid} -> {new}", _retag(new))
        family = _SEQ if nid in _SEQ else _FALL if nid in _FALL else ()
        if nid in self.builtins:
            for new in [f for f in family if f != nid]:
                if new in self.builtins:
                    self._add(elem, "swap-form", loc, f"{nid} -> {new}", _retag(new))
            for new in _NAV2_FORMS.get(nid, ()):
                if new in self.builtins:  # the Nav2 node's own ports (number_of_retries, ...) go
                    self._add(elem, "swap-form", loc, f"{nid} -> {new}", _retag(new, portless=True))
        if self._builtin(elem, _PARALLEL):
            for attr in _PARALLEL[nid]:
                self._numbers(elem, "parallel", attr, lambda n: [n - 1, n + 1])
        if self._builtin(elem, _COUNTS):
            self._numbers(
                elem, "count", _COUNTS[nid], lambda n: [1] if n < 0 else [v for v in (n - 1, n + 1) if v >= 0]
            )
        if self._builtin(elem, ("Timeout",)):
            self._numbers(elem, "timeout", "msec", lambda n: [n // 2, n * 2] if n > 0 else [100])
        if len(kids) >= 2:
            for i, kid in enumerate(kids):
                self._add(
                    elem,
                    "drop-child",
                    src.loc(kid),
                    f"child {i + 1} of {len(kids)} ({_path(kid).rsplit('/', 1)[-1]}) removed",
                    _dropper(i),
                )
            for i in range(len(kids) - 1):
                self._add(elem, "reorder", src.loc(kids[i + 1]), f"children {i + 1} and {i + 2} swapped", _swapper(i))
        if self._builtin(elem, _REMOVABLE) and len(kids) == 1:
            self._add(elem, "remove-decorator", loc, f"{nid} removed (its child in its place)", _unwrap)
        for attr in PRECONDITIONS:
            value = elem.get(attr)
            if value is not None:
                self._add(
                    elem,
                    "precondition",
                    src.attr_loc(elem, attr),
                    f"{attr} negated: `!({value})`",
                    _setter(attr, f"!({value})"),
                )
        script_attrs = [a for a in PRECONDITIONS + _POSTCONDITIONS if elem.get(a) is not None]
        if nid in self.builtins:
            script_attrs += [a for a in _SCRIPT_PORTS.get(nid, ()) if elem.get(a) is not None]
        for attr in script_attrs:
            self._script(elem, attr)
        if elem.tag == "SubTree":
            self._remaps(elem)

    def _numbers(self, elem: etree._Element, op: str, attr: str, values: Callable[[int], list[int]]) -> None:
        n = _int(elem.get(attr))
        if n is None:
            return  # absent (the default) or read from the blackboard
        for v in values(n):
            self._add(
                elem,
                op,
                self.source.attr_loc(elem, attr),
                f'{attr}="{n}" -> "{v}"',
                _setter(attr, str(v)),
            )

    def _script(self, elem: etree._Element, attr: str) -> None:
        text = elem.get(attr) or ""
        for m in _TOKEN.finditer(text):
            kind = m.lastgroup
            tok = m.group(0)
            news: list[tuple[str, str]] = []
            if kind == "op":
                if tok in ("+", "-") and not _binary(text, m.start()):
                    continue
                if tok == "!":
                    news.append(("script-operator", ""))
                elif tok in _OP_SWAP:
                    news.append(("script-operator", _OP_SWAP[tok]))
            elif kind == "num":
                if "." in tok:
                    news.append(("script-constant", repr(float(tok) + 1.0)))
                else:
                    n = int(tok)
                    news += [("script-constant", str(v)) for v in (n - 1, n + 1) if v >= 0]
            elif kind == "bool":
                news.append(("script-constant", "false" if tok == "true" else "true"))
            elif kind == "str":
                news.append(("script-constant", "''" if tok != "''" else "'x'"))
            for op, new in news:
                mutated = text[: m.start()] + new + text[m.end() :]
                shown = f"`{tok}` removed" if new == "" else f"`{tok}` -> `{new}`"
                self._add(
                    elem,
                    op,
                    self.source.value_loc(elem, attr, m.start()),
                    f"{attr}: {shown}",
                    _setter(attr, mutated),
                )

    def _remaps(self, elem: etree._Element) -> None:
        src = self.source
        ports = [a for a in src.attr_names_in_order(elem) if a not in _SUBTREE_FIXED and not a.startswith("_")]
        for a in ports:
            self._add(
                elem,
                "remap",
                src.attr_loc(elem, a),
                f'{a}="{elem.get(a)}" removed',
                _popper(a),
            )
        keyed = [a for a in ports if re.fullmatch(r"\{[^{}]+\}", (elem.get(a) or "").strip())]
        for a, b in zip(keyed, keyed[1:]):
            if elem.get(a) != elem.get(b):
                self._add(
                    elem,
                    "remap",
                    src.attr_loc(elem, b),
                    f"the values of {a} and {b} swapped",
                    _attr_swapper(a, b),
                )
        auto = (elem.get("_autoremap") or "false").strip().lower()
        new = "false" if auto in ("true", "1") else "true"
        self._add(
            elem,
            "remap",
            src.attr_loc(elem, "_autoremap"),
            f'_autoremap="{new}"',
            _setter("_autoremap", new),
        )


def _count_values(n: int) -> list[int]:
    return [1] if n < 0 else [v for v in (n - 1, n + 1) if v >= 0]


def _binary(text: str, at: int) -> bool:
    """Whether the + or - at `at` is a binary operator (an operand before it)."""
    before = text[:at].rstrip()
    return bool(before) and (before[-1].isalnum() or before[-1] in "_)'}")


def _swapper(i: int) -> Edit:
    def edit(e: etree._Element) -> None:
        kids = _children(e)
        kids[i].addprevious(kids[i + 1])  # lxml moves the element (its tail with it)

    return edit


def _retag(new: str, portless: bool = False) -> Edit:
    def edit(e: etree._Element) -> None:
        _set_id(e, new)
        if portless:
            for a in [a for a in e.attrib if a not in ("ID", "name") and not str(a).startswith("_")]:
                del e.attrib[a]

    return edit


def _dropper(k: int) -> Edit:
    return lambda e: e.remove(_children(e)[k])


def _setter(attr: str, value: str) -> Edit:
    return lambda e: e.set(attr, value)


def _popper(attr: str) -> Edit:
    def edit(e: etree._Element) -> None:
        del e.attrib[attr]

    return edit


def _attr_swapper(a: str, b: str) -> Edit:
    return lambda e: _swap_attrs(e, a, b)


def _unwrap(e: etree._Element) -> None:
    (child,) = _children(e)
    child.tail = e.tail
    parent = e.getparent()
    assert parent is not None
    parent.replace(e, child)


def _swap_attrs(e: etree._Element, a: str, b: str) -> None:
    va, vb = e.get(a), e.get(b)
    assert va is not None and vb is not None
    e.set(a, vb)
    e.set(b, va)


def all_mutants(
    source: Source, builtins: frozenset[str], relocate: Callable[[etree._Element], None]
) -> Iterator[Mutant]:
    yield from Finder(source, builtins, relocate).find()
