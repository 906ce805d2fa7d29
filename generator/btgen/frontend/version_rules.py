"""Loading rules that differ between BehaviorTree.CPP releases (lang/versions.py names them).

The loader asks this module what a later release refuses in a mission
(:func:`loading_findings`); it reports each finding as an error when the selected
version refuses it, and as a warning under 4.6.2, which loads it. ``upgrade-check``
lists the same findings.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from btgen.diagnostics import DiagnosticSink, Loc
from btgen.lang import values
from btgen.lang.catalogue import KINDS
from btgen.lang.model import Attr, Mission, Node, SubTreeNode
from btgen.lang.versions import SINCE, Semantics

LOOP_QUEUE_PORTS = {(loop, "queue") for loop in ("LoopInt", "LoopBool", "LoopDouble", "LoopString")}

# findForbiddenChar (4.8.4): blanks and these break XML, paths or Groot2; control characters too.
_FORBIDDEN = " \t\n\r<>&\"'/\\:*?|."
_RESERVED = ("_failureIf", "_successIf", "_skipIf", "_while", "_onHalted", "_onFailure", "_onSuccess", "_post")


def forbidden_char(name: str) -> str:
    """The first character 4.8.4's findForbiddenChar rejects in `name`, or ""."""
    for c in name:
        o = ord(c)
        if o >= 0x80:
            continue  # UTF-8 multibyte sequences are allowed
        if o < 32 or o == 127 or c in _FORBIDDEN:
            return c
    return ""


def allowed_name(name: str) -> str:
    """`name` with each run of characters 4.8.4 forbids made one `_` (the rename an
    upgrade warning proposes): `I. DetectVisitor` -> `I_DetectVisitor`."""
    out: list[str] = []
    for c in name:
        if forbidden_char(c):
            if out and out[-1] != "_":
                out.append("_")
        else:
            out.append(c)
    fixed = "".join(out).strip("_")
    if not fixed or fixed in ("Root", "root"):
        fixed = f"Tree_{fixed}" if fixed else "Tree"
    return fixed


def _shown(c: str) -> str:
    if ord(c) < 32 or ord(c) == 127:
        return f"the control character {ord(c)}"
    return f"`{c}`"


def is_port_name(name: str, sem: Semantics) -> bool:
    """IsAllowedPortName: what a node attribute must look like to be a port (other
    attributes are ignored by the library). 4.6.2: an ASCII letter first; 4.8.4 also
    refuses the forbidden characters and the reserved names."""
    if not name or not (name[0].isascii() and name[0].isalpha()):
        return False
    if not sem.attribute_names_484:
        return True
    return not forbidden_char(name) and name not in _RESERVED + ("name", "ID", "_autoremap")


def check_literal_queue(sink: DiagnosticSink, attr: Attr, node_id: str, sem: Semantics) -> None:
    """A Loop node's literal `queue`: converted when the node is created, so a bad
    element is a load error (4.9.0 converts doubles with std::from_chars)."""
    elem = {"LoopInt": "int", "LoopBool": "bool", "LoopDouble": "double", "LoopString": "string"}[node_id]
    what = f"port `queue` of `{node_id}`"
    try:
        read = values.convert_from_string(f"queue<{elem}>", attr.value, double_from_chars=sem.double_from_chars)
    except values.ConversionError as e:
        sink.error(attr.value_loc, f"{what}: {e}")
        return
    try:
        values.convert_from_string(f"queue<{elem}>", attr.value, strict=True, double_from_chars=sem.double_from_chars)
    except values.ConversionError as e:
        # numbers are read as a prefix (`1.5` is 1 for an int): loads, with a warning
        shown = str(list(read)) if isinstance(read, values.Queue) else values.describe(read)
        sink.warning(attr.value_loc, f"{what}: {e}; BehaviorTree.CPP {sem.version} reads it as {shown}")


@dataclass(frozen=True)
class Finding:
    """Something a later release refuses at load: the switch that refuses it, where, what."""

    switch: str
    loc: Loc
    message: str

    @property
    def since(self) -> str:
        return SINCE[self.switch]


def _nodes(root: Node) -> Iterator[Node]:
    stack = [root]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(n.children))


def loading_findings(mission: Mission) -> list[Finding]:
    """Every place of `mission` that 4.7.0 to 4.10.0 refuse when they load it."""
    out: list[Finding] = []
    builtins = mission.builtins
    created = _created_trees(mission)
    out.extend(_subtree_path_findings(mission))
    for tree in mission.trees:
        # X1: tree IDs, SubTree IDs and the element names of user nodes (validateModelName)
        out.extend(_name_findings(tree.id, tree.loc, "BehaviorTree ID"))
        for node in _nodes(tree.root):
            if isinstance(node, SubTreeNode):
                out.extend(_name_findings(node.target, node.loc, "SubTree ID"))
            elif node.id not in builtins and node.tag not in KINDS:
                out.extend(_name_findings(node.id, node.loc, "node ID"))
            if node.id == "ReactiveSequence" and node.id in builtins:
                out.extend(_reactive_findings(node))
            if tree.id in created and node.name:
                # X3: validateInstanceName, when a node is created (trees the main tree runs only)
                bad = next((c for c in node.name if (ord(c) < 32 and c not in "\t\n\r") or ord(c) == 127), "")
                if bad:
                    out.append(
                        Finding(
                            "name_validation_484",
                            node.loc,
                            f"the name of `{node.id}` contains {_shown(bad)} (only tab, newline and carriage "
                            f"return are allowed among the control characters)",
                        )
                    )
    return out


def _subtree_path_findings(mission: Mission) -> list[Finding]:
    """X2: every SubTree instance of the created tree has the path `parent path/name` (its `name`
    only under the main tree, whose own path is empty); 4.8.4 refuses two equal paths, which
    `name=""` under the main tree makes with the main tree itself, and `name="a/x"` with the
    SubTree `x` inside the SubTree `a`. An instance without a name gets a path of its own."""
    by_id = {t.id: t for t in mission.trees}
    seen: dict[str, Loc] = {"": by_id[mission.main_tree].loc} if mission.main_tree in by_id else {}
    out: list[Finding] = []
    todo: list[tuple[str, str, tuple[str, ...]]] = [(mission.main_tree, "", ())]
    budget = 100_000  # instances visited (the 16-bit node count is checked apart)
    reported: set[Loc] = set()
    while todo and budget > 0:
        tid, prefix, stack = todo.pop()
        if tid not in by_id or tid in stack:
            continue
        for node in _nodes(by_id[tid].root):
            if not isinstance(node, SubTreeNode):
                continue
            budget -= 1
            path = None if node.name is None else (f"{prefix}/{node.name}" if prefix else node.name)
            if path is not None and path in seen and node.loc not in reported:
                reported.add(node.loc)
                first = seen[path]
                out.append(
                    Finding(
                        "unique_subtree_paths",
                        node.loc,
                        f"the SubTree path `{path}` is taken (by the "
                        + ("main tree" if path == "" else f"SubTree at {first}")
                        + "): SubTree paths must be unique"
                        + (" (an empty name is the main tree's path)" if path == "" else ""),
                    )
                )
            elif path is not None:
                seen[path] = node.loc
            own = path if path is not None else f"{prefix}/{node.target}::{id(node)}"
            todo.append((node.target, own, stack + (tid,)))
    return out


def _created_trees(mission: Mission) -> set[str]:
    """The BehaviorTrees the library creates: the main tree and the trees its SubTrees run."""
    by_id = {t.id: t for t in mission.trees}
    seen: set[str] = set()
    todo = [mission.main_tree]
    while todo:
        tid = todo.pop()
        if tid in seen or tid not in by_id:
            continue
        seen.add(tid)
        todo.extend(n.target for n in _nodes(by_id[tid].root) if isinstance(n, SubTreeNode))
    return seen


def _name_findings(name: str, loc: Loc, what: str) -> list[Finding]:
    if name in ("Root", "root"):
        return [
            Finding(
                "name_validation_484",
                loc,
                f"{what} `{name}`: `Root` is a reserved name: rename it `{allowed_name(name)}`",
            )
        ]
    c = forbidden_char(name)
    if c:
        return [
            Finding(
                "name_validation_484",
                loc,
                f"{what} `{name}` contains the forbidden character {_shown(c)}: rename it `{allowed_name(name)}`",
            )
        ]
    return []


def _reactive_findings(node: Node) -> list[Finding]:
    out = []
    asyncs = 0
    for child in node.children:
        if child.tag in KINDS and child.tag != "SubTree":
            out.append(
                Finding(
                    "reactive_sequence_child_checks",
                    child.loc,
                    f"a direct child of ReactiveSequence written <{child.tag} ID=...>: the library looks its "
                    f"element name up as a node type (write <{child.id}/>)",
                )
            )
        elif child.id == "AsyncSequence":
            asyncs += 1
            if asyncs == 2:
                out.append(
                    Finding(
                        "reactive_sequence_child_checks",
                        node.loc,
                        "a ReactiveSequence with more than one AsyncSequence child",
                    )
                )
    return out
