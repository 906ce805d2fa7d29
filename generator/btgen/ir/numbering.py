"""The one numbering of a mission's nodes: BehaviorTree.CPP's creation order.

BehaviorTree.CPP 4.6.2 creates the nodes of the main tree depth first, a SubTree node
before the nodes of the tree it instantiates, and gives each the next UID (from 1).
Every stage that speaks of "node i" means the i-th node of that walk: the node table
(lower.py), the data analysis (data/), the Groot2 tree (treexml.py), the scenario tools.
This module is the only place that walks the expanded tree; the others read its table,
so they cannot disagree (test_numbering.py checks that no other module walks it).
"""

from __future__ import annotations

from dataclasses import dataclass

from btgen.lang.model import Mission, Node, SubTreeNode


@dataclass(frozen=True)
class NumberedNode:
    """One node instance of the expanded main tree."""

    index: int  # position in creation order; the UID is index + 1
    node: Node
    parent: int  # index of the parent (for a tree's root: the SubTree node), -1 for the main root
    depth: int  # 1 for the main root
    tree: str  # ID of the tree whose XML holds the node
    instance: int  # index of the SubTree node of the tree instance holding it, -1: the main tree
    children: tuple[int, ...]  # in order; a SubTree node's one child is the root of its tree

    @property
    def uid(self) -> int:
        return self.index + 1

    @property
    def reg_id(self) -> str:
        """The registration ID BehaviorTree.CPP created it with."""
        return "SubTree" if isinstance(self.node, SubTreeNode) else self.node.id


def subtree_path(prefix: str, node: SubTreeNode, uid: int) -> str:
    """4.6.2's instance name of a SubTree: the parent's path, `/`, then its name, else ID::UID."""
    return prefix + (node.name if node.name is not None else f"{node.target}::{uid}")


@dataclass(frozen=True)
class Numbering:
    """The nodes of the main tree, SubTrees inlined, in creation order (index + 1 = UID)."""

    nodes: tuple[NumberedNode, ...]

    def __len__(self) -> int:
        return len(self.nodes)

    def __iter__(self):
        return iter(self.nodes)

    def __getitem__(self, index: int) -> NumberedNode:
        return self.nodes[index]

    def instances(self) -> tuple[int, ...]:
        """The tree instances in creation order: -1 (the main tree), then each SubTree node."""
        return (-1, *(n.index for n in self.nodes if isinstance(n.node, SubTreeNode)))

    def instance_paths(self) -> dict[int, str]:
        """Each instance's path as 4.6.2 names it (`Tree::Subtree::instance_name`): "" for the
        main tree, else the parent's path, `/`, and the SubTree's name (else `ID::UID`)."""
        paths: dict[int, str] = {-1: ""}
        for n in self.nodes:
            if isinstance(n.node, SubTreeNode):
                parent = paths[n.instance]
                paths[n.index] = subtree_path(parent + "/" if parent else "", n.node, n.uid)
        return paths


def number_nodes(mission: Mission) -> Numbering:
    """The creation order of `mission`'s main tree. Iterative, so deep trees (SubTree chains
    tens of thousands deep) do not hit Python's recursion limit."""
    rows: list[list] = []  # [node, parent, depth, tree, instance, children]
    stack: list[tuple[Node, int, int, str, int]] = [(mission.main.root, -1, 1, mission.main_tree, -1)]
    while stack:
        node, parent, depth, tree, instance = stack.pop()
        me = len(rows)
        rows.append([node, parent, depth, tree, instance, []])
        if parent >= 0:
            rows[parent][5].append(me)
        if isinstance(node, SubTreeNode):
            target = mission.tree(node.target)
            stack.append((target.root, me, depth + 1, target.id, me))
        else:
            for child in reversed(node.children):
                stack.append((child, me, depth + 1, tree, instance))
    return Numbering(tuple(NumberedNode(i, r[0], r[1], r[2], r[3], r[4], tuple(r[5])) for i, r in enumerate(rows)))
