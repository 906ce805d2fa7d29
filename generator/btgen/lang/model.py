"""The checked mission model: plain frozen dataclasses, each with its source location.

The front end (frontend.py) builds it; the interpreter walks it; the
compiler lowers it. Nothing downstream of the front end sees lxml.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

from btgen.diagnostics import Diagnostic, Loc
from btgen.lang.catalogue import NodeSpec
from btgen.lang.nav2 import builtins_for
from btgen.lang.versions import DEFAULT_VERSION, Semantics, semantics


@dataclass(frozen=True)
class Attr:
    """An attribute as written: name, decoded value, and where both start."""

    name: str
    value: str
    loc: Loc  # the attribute's name
    value_loc: Loc  # the first character of its value
    # Parsed script when the attribute holds one (Script code, _skipIf, ...).
    script: Optional[Any] = None


@dataclass(frozen=True)
class Node:
    """One node of a BehaviorTree as written (SubTrees not yet expanded)."""

    id: str  # registration ID: element name, or ID attribute of the explicit form
    kind: str  # Action | Condition | Control | Decorator | SubTree
    name: Optional[str]  # the name attribute; None when absent
    ports: tuple[Attr, ...]  # port assignments (for a SubTree: its remappings)
    pre: tuple[Attr, ...]  # _failureIf, _successIf, _skipIf, _while as written
    post: tuple[Attr, ...]  # _onHalted, _onFailure, _onSuccess, _post as written
    children: tuple[Node, ...]
    loc: Loc
    autoremap: bool = False  # SubTree only
    tag: str = ""  # the element as written: the ID, or Action/Condition/... for the explicit form

    @property
    def display_name(self) -> str:
        """The name BehaviorTree.CPP gives the node: its name attribute, else its ID."""
        return self.name if self.name is not None else self.id

    @property
    def subtree_id(self) -> Optional[str]:
        return None  # overridden by SubTreeNode

    def port(self, name: str) -> Optional[Attr]:
        for p in self.ports:
            if p.name == name:
                return p
        return None

    def pre_condition(self, name: str) -> Optional[Attr]:
        for p in self.pre:
            if p.name == name:
                return p
        return None

    def post_condition(self, name: str) -> Optional[Attr]:
        for p in self.post:
            if p.name == name:
                return p
        return None


@dataclass(frozen=True)
class SubTreeNode(Node):
    """A <SubTree ID=...> instance; `target` is the BehaviorTree it runs."""

    target: str = ""

    @property
    def subtree_id(self) -> Optional[str]:
        return self.target


@dataclass(frozen=True)
class TreeDef:
    id: str
    root: Node
    loc: Loc


@dataclass(frozen=True)
class ProvidedEntry:
    """A blackboard entry the application sets before the first tick (`--entry`)."""

    tree: Optional[str]  # None: the root blackboard; else every instance of that BehaviorTree's
    key: str
    type: str  # canonical type name (values.normalize_type)

    def applies_to(self, tree_id: str, root: bool) -> bool:
        return self.tree == tree_id if self.tree is not None else root

    @property
    def option(self) -> str:
        return f"--entry {self.tree + ':' if self.tree else ''}{self.key}={self.type}"


@dataclass(frozen=True)
class Mission:
    path: str  # as the user gave it
    trees: tuple[TreeDef, ...]  # in file order, includes after their includer's own trees
    main_tree: str
    models: tuple[NodeSpec, ...]  # TreeNodesModel declarations (all files)
    files: tuple[str, ...]  # the mission file and every included file
    warnings: tuple[Diagnostic, ...] = ()
    # Scripting enums (enums.py): (name, value) as registerScriptingEnum registers them.
    enums: tuple[tuple[str, int], ...] = ()
    # User port types (usertypes.py: `--type NAME=CPP_TYPE@HEADER`): usertypes.UserType each.
    user_types: tuple[Any, ...] = ()
    # The BehaviorTree.CPP release whose semantics the mission was loaded for (versions.py).
    btcpp: str = DEFAULT_VERSION
    # The Nav2 distro whose Controls and Decorators are built in (lang/nav2.py), else None.
    nav2: Optional[str] = None

    @property
    def semantics(self) -> Semantics:
        return semantics(self.btcpp)

    @property
    def builtins(self) -> dict[str, NodeSpec]:
        return builtins_for(self.btcpp, self.nav2)

    # Entries the application provides (entries.py: `--entry [TREE:]NAME=TYPE`).
    provided: tuple[ProvidedEntry, ...] = ()

    def tree(self, tree_id: str) -> TreeDef:
        for t in self.trees:
            if t.id == tree_id:
                return t
        raise KeyError(tree_id)

    def spec(self, node_id: str) -> NodeSpec:
        """The spec of a node ID: built in, or declared in TreeNodesModel."""
        builtins = builtins_for(self.btcpp, self.nav2)
        if node_id in builtins:
            return builtins[node_id]
        for m in self.models:
            if m.id == node_id:
                return m
        raise KeyError(node_id)

    @property
    def main(self) -> TreeDef:
        return self.tree(self.main_tree)

    def leaf_models(self) -> tuple[NodeSpec, ...]:
        """User Actions and Conditions, in declaration order."""
        return tuple(m for m in self.models if m.kind in ("Action", "Condition"))

    def user_models(self) -> tuple[NodeSpec, ...]:
        """User Actions, Conditions, Controls and Decorators, in declaration order (a models
        palette may declare many the mission does not use: see used_user_models)."""
        return tuple(m for m in self.models if m.kind in ("Action", "Condition", "Control", "Decorator"))

    def used_user_models(self) -> tuple[NodeSpec, ...]:
        """The user models a node of the main tree or of a SubTree it runs instantiates, in
        declaration order: the models the generated code has a class and hooks for."""
        ids: set[str] = set()
        seen = {self.main_tree}
        stack: list[Node] = [self.main.root]
        while stack:
            node = stack.pop()
            if isinstance(node, SubTreeNode):
                if node.target not in seen:
                    seen.add(node.target)
                    stack.append(self.tree(node.target).root)
                continue
            ids.add(node.id)
            stack.extend(node.children)
        return tuple(m for m in self.user_models() if m.id in ids)
