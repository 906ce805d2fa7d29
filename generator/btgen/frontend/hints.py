"""Hints from beyond the files a mission loads: what the XML files beside it declare.

A node model kept in `nodes.xml` and a BehaviorTree kept in `dock.xml` are the two mistakes
of a mission split over files that the loader alone cannot explain: it sees an unknown node
or SubTree. When one of the files in the same folder declares the name, the error says which
file and how to load it (`--models` for a file of models only, `<include path=...>` for one
with trees). The look is bounded: at most MAX_SIBLINGS files of at most MAX_SIBLING_BYTES
each, read with the same secure parser as missions; a file that does not parse is skipped.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.lang import blackboard as bbmod
from btgen.lang import script as script_lang
from btgen.lang.catalogue import KEY_NAME_PORTS
from btgen.lang.model import Mission, Node, SubTreeNode

MAX_SIBLINGS = 64
MAX_SIBLING_BYTES = 2 * 1024 * 1024
MODEL_TAGS = ("Action", "Condition", "Control", "Decorator", "SubTree")


@dataclass(frozen=True)
class Sibling:
    path: str  # as the user would write it: the folder as shown, then the file name
    name: str  # the file name (for an <include path=...> from a file in the same folder)
    models: frozenset[str]  # IDs its <TreeNodesModel> declares
    trees: frozenset[str]  # IDs of its <BehaviorTree>s
    models_only: bool  # <root> holds only <TreeNodesModel>: a file for --models
    mission: bool = False  # its <root> names a main_tree_to_execute: a mission of its own
    includes: frozenset[str] = frozenset()  # the real paths of the files its <include path=...> name
    parent_of: str = ""  # the file (shown) it includes that asks for the hint: including it is a cycle

    def include_advice(self, tree_id: str, loaded: set[str]) -> str:
        """How to load what this file defines: `<include>` it, unless it is a mission of its own,
        defines a tree the mission has (including it would define a BehaviorTree twice) or includes
        the file that would include it (an include cycle)."""
        twice = sorted(self.trees & loaded)
        if self.parent_of:
            return (
                f"`{self.path}` beside it defines `{tree_id}` and includes `{os.path.basename(self.parent_of)}` "
                f"(including it back would be a cycle): check `{self.path}`, which the program loads, or move "
                f"`{tree_id}` to a file of its own and include that"
            )
        if self.mission or twice:
            why = f"it defines `{twice[0]}` too" if twice else "it is a mission of its own (main_tree_to_execute)"
            return (
                f"`{self.path}` beside it defines `{tree_id}`, but {why}: move `{tree_id}` to a file of its own "
                f"and include that"
            )
        return f'`{self.path}` beside it defines it: add <include path="{self.name}"/> to <root>'


class SiblingIndex:
    """The XML files beside the files of a mission, read once per folder when a hint needs them."""

    def __init__(self, loaded: list[str]) -> None:
        self._loaded = loaded  # the shown paths of the files the mission loads (the loader's list)
        self._folders: dict[str, list[Sibling]] = {}

    def _read_folder(self, folder: str) -> list[Sibling]:
        from btgen.frontend.xmlsource import read_source

        real = folder or "."
        try:
            names = sorted(n for n in os.listdir(real) if n.lower().endswith(".xml"))
        except OSError:
            return []
        loaded = {os.path.realpath(p) for p in self._loaded}
        out = []
        for name in names[:MAX_SIBLINGS]:
            path = os.path.join(real, name)
            try:
                if os.path.realpath(path) in loaded or not os.path.isfile(path):
                    continue
                if os.path.getsize(path) > MAX_SIBLING_BYTES:
                    continue
                root = read_source(path).root
            except (OSError, UserError):
                continue
            if root.tag != "root":
                continue
            elements = [c for c in root if isinstance(c.tag, str)]
            models = frozenset(
                m.get("ID", "")
                for c in elements
                if c.tag == "TreeNodesModel"
                for m in c
                if isinstance(m.tag, str) and m.tag in MODEL_TAGS
            )
            trees = frozenset(c.get("ID", "") for c in elements if c.tag == "BehaviorTree")
            only = bool(elements) and all(c.tag == "TreeNodesModel" for c in elements)
            mission = root.get("main_tree_to_execute") is not None
            includes = frozenset(
                os.path.realpath(os.path.join(real, c.get("path") or ""))
                for c in elements
                if c.tag == "include" and c.get("path") and c.get("ros_pkg") is None
            )
            out.append(Sibling(os.path.join(folder, name), name, models, trees, only, mission, includes))
        return out

    def beside(self, file_shown: str) -> list[Sibling]:
        folder = os.path.dirname(file_shown)
        if folder not in self._folders:
            self._folders[folder] = self._read_folder(folder)
        return self._folders[folder]

    def declaring_model(self, file_shown: str, node_id: str) -> Optional[Sibling]:
        return next((s for s in self.beside(file_shown) if node_id in s.models), None)

    def defining_tree(self, file_shown: str, tree_id: str) -> Optional[Sibling]:
        # a file that can be included first, then a mission of its own, then one that includes
        # this file or the mission (a parent: including it back is a cycle)
        ours = {os.path.realpath(p): p for p in (*self._loaded[:1], file_shown)}
        found = [
            dataclasses.replace(s, parent_of=next(ours[r] for r in ours if r in s.includes))
            if s.includes & ours.keys()
            else s
            for s in self.beside(file_shown)
            if tree_id in s.trees
        ]
        return min(found, key=lambda s: (bool(s.parent_of), s.mission), default=None)


def model_advice(node_id: str, children: int) -> str:
    """How to declare a node with `children` child elements."""
    if children == 0:
        return f'declare it as <Action ID="{node_id}"/> or <Condition ID="{node_id}"/>'
    if children == 1:
        return f'declare it as <Decorator ID="{node_id}"/> (it has a child) or <Control ID="{node_id}"/>'
    return f'declare it as <Control ID="{node_id}"/> (it has {children} children)'


# ------------------------------------------------------- SubTree ports left unmapped
@dataclass
class _Keys:
    reads: dict[str, tuple[str, Loc]]  # key -> (what reads it, where): input ports `{key}`
    writes: set[str]  # keys something in the tree may write (or whose use is unclear)
    used: set[str]  # every key the tree names


def _remapped(value: str, port_name: str) -> Optional[str]:
    """The entry a `{key}` or `{=}` port value names, None for a literal: the loader's
    `is_remap` and `remap_key`, read from lang.blackboard (hints is imported by the loader)."""
    return bbmod.remapped_key(port_name, value) if bbmod.is_blackboard_pointer(value) else None


def _tree_keys(mission: Mission, root: Node) -> _Keys:
    """The blackboard keys the nodes of one tree (not the trees of its SubTrees) name."""
    keys = _Keys({}, set(), set())
    stack = [root]
    while stack:
        node = stack.pop()
        stack.extend(reversed(node.children))
        for attr in node.pre + node.post + node.ports:
            if attr.script is not None:
                for stmt in attr.script.statements:
                    for e in script_lang.walk(stmt):
                        if isinstance(e, script_lang.Assign):
                            keys.writes.add(e.target)
                            keys.used.add(e.target)
                        elif isinstance(e, script_lang.Name):
                            keys.used.add(e.name)
                continue
            if attr in node.pre or attr in node.post:
                continue
            if isinstance(node, SubTreeNode):
                key = _remapped(attr.value, attr.name)
                if key is not None:  # the SubTree may read or write it
                    keys.used.add(key)
                    keys.writes.add(key)
                continue
            try:
                port = mission.spec(node.id).port(attr.name)
            except KeyError:
                port = None
            if (node.id, attr.name) in KEY_NAME_PORTS:
                keys.used.add(attr.value)
                keys.writes.add(attr.value)
            elif (key := _remapped(attr.value, attr.name)) is not None:
                keys.used.add(key)
                if port is not None and port.direction == "input":
                    keys.reads.setdefault(key, (f"the `{attr.name}` port of `{node.id}`", attr.value_loc))
                else:
                    keys.writes.add(key)
    return keys


def unmapped_subtree_ports(mission: Mission) -> list[Diagnostic]:
    """Warnings for SubTree instances without `_autoremap` whose tree reads, through an input
    port, an entry `{key}` that nothing in it writes and the SubTree node does not remap, while
    the calling tree names the same key: the SubTree's blackboard is its own, so the read finds
    an empty entry of its own, not the caller's (the usual forgotten `key="{key}"`)."""
    trees = {t.id: t for t in mission.trees}
    cache: dict[str, _Keys] = {}

    def keys_of(tree_id: str) -> _Keys:
        if tree_id not in cache:
            cache[tree_id] = _tree_keys(mission, trees[tree_id].root)
        return cache[tree_id]

    out = []
    for tree in mission.trees:
        stack = [tree.root]
        while stack:
            node = stack.pop()
            stack.extend(reversed(node.children))
            if not isinstance(node, SubTreeNode) or node.autoremap or node.target not in trees:
                continue
            model = next((m for m in mission.models if m.id == node.target and m.kind == "SubTree"), None)
            mapped = {p.name for p in node.ports} | ({p.name for p in model.ports} if model else set())
            inner, caller = keys_of(node.target), keys_of(tree.id)
            for key, (what, where) in sorted(inner.reads.items(), key=lambda kv: (kv[1][1].line, kv[1][1].col)):
                if key in inner.writes or key in mapped or key.startswith("@") or key not in caller.used:
                    continue
                out.append(
                    Diagnostic(
                        node.loc,
                        f"SubTree `{node.target}` reads `{{{key}}}` ({what} at {where}), which this "
                        f"SubTree node does not remap: without `_autoremap` the SubTree has a "
                        f"blackboard of its own, so that is not `{key}` of `{tree.id}` (add "
                        f'{key}="{{{key}}}", or _autoremap="true")',
                        "warning",
                    )
                )
    return out
