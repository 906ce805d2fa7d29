"""The mission as BehaviorTree.CPP 4.6.2 shows a running tree to Groot2.

``WriteTreeToXML(tree, add_metadata=true, add_builtin_models=true)`` is what a
``Groot2Publisher`` answers to FULLTREE and what ``FileLogger2`` writes at the
head of a ``.btlog``: one ``<BehaviorTree ID=... _fullpath=...>`` per tree
instance (the main tree first, then every SubTree instance in creation order),
each node with ``name`` (SubTrees: ``ID`` and ``_fullpath``), ``_uid``, its
ports (as written, plus the defaults its model gives) and its pre/post
conditions, then the ``TreeNodesModel`` of every registered node. Groot2 maps
status records to nodes by ``_uid``.

This module builds that text from the checked mission at generation time, and
the facts the Groot2 publisher needs besides: the tree instances (the
blackboard names BehaviorTree.CPP gives them) and the order of its status
buffer (instances in creation order, each with its own nodes in creation
order). What 4.6.2 leaves to hash order (a node's port attributes, a model's
ports) is written here in a fixed order: the file's order, then defaults.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Optional

from btgen.ir.numbering import Numbering, number_nodes, subtree_path
from btgen.lang.catalogue import POST_CONDITIONS, PRE_CONDITIONS, NodeSpec
from btgen.lang.model import Mission, Node, SubTreeNode

# 4.6.2's demangled type names for the canonical ones (values.normalize_type reads them back).
_CPP_TYPES = MappingProxyType(
    {
        "string": "std::string",
        "int": "int",
        "unsigned": "unsigned int",
        "double": "double",
        "bool": "bool",
        "NodeStatus": "BT::NodeStatus",
        "any": "BT::AnyTypeAllowed",
    }
)


def _cpp_type(canonical: str) -> str:
    if canonical in _CPP_TYPES:
        return _CPP_TYPES[canonical]
    if canonical.startswith("queue<") and canonical.endswith(">"):
        elem = _cpp_type(canonical[len("queue<") : -1])
        return f"std::shared_ptr<std::deque<{elem}, std::allocator<{elem}> > >"
    return canonical


def escape(text: str) -> str:
    """tinyxml2's escaping of text and attribute values."""
    return (
        text.replace("&", "&amp;")
        .replace("<", "&lt;")
        .replace(">", "&gt;")
        .replace('"', "&quot;")
        .replace("'", "&apos;")
    )


@dataclass(frozen=True)
class TreeInstance:
    """One tree instance of the running mission (BT::Tree::Subtree)."""

    tree_id: str
    path: str  # instance_name: "" for the main tree, else the SubTree path
    nodes: tuple[int, ...]  # node indices (UID - 1) in creation order

    @property
    def blackboard_name(self) -> str:
        """The name Groot2Publisher gives its blackboard: the path, or the tree ID for the main tree."""
        return self.path if self.path else self.tree_id


@dataclass(frozen=True)
class Groot2Tree:
    xml: str
    instances: tuple[TreeInstance, ...]

    @property
    def status_order(self) -> tuple[int, ...]:
        """Node indices in the order of 4.6.2's STATUS buffer."""
        return tuple(i for inst in self.instances for i in inst.nodes)


class _Builder:
    def __init__(self, mission: Mission, numbering: Numbering) -> None:
        self.m = mission
        self.numbering = numbering

    def build(self) -> Groot2Tree:
        paths = self.numbering.instance_paths()
        members: dict[int, list[int]] = {i: [] for i in self.numbering.instances()}
        for n in self.numbering:
            members[n.instance].append(n.index)
        lines = ['<root BTCPP_format="4">']
        instances = []
        for inst, nodes in members.items():
            tree_id = self.m.main_tree if inst < 0 else self.numbering[inst].node.target  # type: ignore[attr-defined]
            path = paths[inst]
            instances.append(TreeInstance(tree_id, path, tuple(nodes)))
            lines.append(f'    <BehaviorTree ID="{escape(tree_id)}" _fullpath="{escape(path)}">')
            self._body(nodes[0], path + "/" if path else "", lines)
            lines.append("    </BehaviorTree>")
        lines.extend(self._models())
        lines.append("</root>")
        return Groot2Tree("\n".join(lines) + "\n", tuple(instances))

    def _body(self, root: int, prefix: str, lines: list[str]) -> None:
        """The elements of one tree instance, its SubTree nodes without children, with an
        explicit stack (a tree may be deep)."""
        stack: list[tuple[int, int] | str] = [(root, 2)]
        while stack:
            item = stack.pop()
            if isinstance(item, str):
                lines.append(item)
                continue
            index, depth = item
            n = self.numbering[index]
            indent = "    " * depth
            attrs = self._attributes(n.node, n.uid, prefix)
            children = () if isinstance(n.node, SubTreeNode) else n.children
            if children:
                lines.append(f"{indent}<{n.reg_id}{attrs}>")
                stack.append(f"{indent}</{n.reg_id}>")
                for child in reversed(children):
                    stack.append((child, depth + 1))
            else:
                lines.append(f"{indent}<{n.reg_id}{attrs}/>")

    def _attributes(self, node: Node, uid: int, prefix: str) -> str:
        out: list[tuple[str, str]] = []
        if isinstance(node, SubTreeNode):
            out.append(("ID", node.target))
            out.append(("_fullpath", subtree_path(prefix, node, uid)))
        else:
            out.append(("name", node.display_name))
        out.append(("_uid", str(uid)))
        given = set()
        for p in node.ports:
            out.append((p.name, p.value))
            given.add(p.name)
        if isinstance(node, SubTreeNode) and node.autoremap and "_autoremap" not in given:
            out.append(("_autoremap", "true"))
        if not isinstance(node, SubTreeNode):
            spec = self._spec(node.id)
            if spec is not None:
                for ps in spec.ports:
                    if ps.name not in given and ps.default is not None and ps.default != "":
                        if ps.direction != "output" or (ps.default.startswith("{") and ps.default.endswith("}")):
                            out.append((ps.name, ps.default))
        for name in PRE_CONDITIONS:
            a = node.pre_condition(name)
            if a is not None:
                out.append((name, a.value))
        for name in POST_CONDITIONS:
            a = node.post_condition(name)
            if a is not None:
                out.append((name, a.value))
        return "".join(f' {k}="{escape(v)}"' for k, v in out)

    def _spec(self, node_id: str):
        try:
            return self.m.spec(node_id)
        except KeyError:
            return None

    def _models(self) -> list[str]:
        """TreeNodesModel: every built-in node and every leaf, control or decorator the
        mission declares, sorted by ID (4.6.2 iterates a std::map)."""
        specs: dict[str, NodeSpec] = dict(self.m.builtins)
        for m in self.m.models:
            if m.kind != "SubTree":
                specs[m.id] = m
        lines = ["    <TreeNodesModel>"]
        for node_id in sorted(specs):
            spec = specs[node_id]
            head = f'        <{spec.kind} ID="{escape(node_id)}"'
            if not spec.ports:
                lines.append(head + "/>")
                continue
            lines.append(head + ">")
            for ps in spec.ports:
                attrs = f' name="{escape(ps.name)}"'
                if ps.type != "any" or spec.builtin:
                    attrs += f' type="{escape(_cpp_type(ps.type))}"'
                if ps.default is not None and ps.default != "":
                    attrs += f' default="{escape(ps.default)}"'
                tag = f"{ps.direction}_port"
                if ps.description:
                    lines.append(f"            <{tag}{attrs}>{escape(ps.description)}</{tag}>")
                else:
                    lines.append(f"            <{tag}{attrs}/>")
            lines.append(f"        </{spec.kind}>")
        lines.append("    </TreeNodesModel>")
        return lines


def groot2_tree(mission: Mission, numbering: Optional[Numbering] = None) -> Groot2Tree:
    """The tree XML Groot2 receives for `mission`, and its instances (`numbering`: the
    mission's, when the caller has it)."""
    return _Builder(mission, numbering or number_nodes(mission)).build()
