"""Which nodes of a mission the robot's code implements: its leaves and its own Controls.

A user Action or Condition is a *scripted leaf* (a scenario or the robot decides what it
returns); a Control or Decorator declared in the mission's TreeNodesModel is a *user node*
(only robot code can tick it). Every stage asks these questions the same way.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Optional

from btgen.lang.model import Mission, Node, SubTreeNode
from btgen.lang.nav2 import ENV_INPUTS, ROS_NODES, ros_node_message


@dataclass(frozen=True)
class LeafUse:
    """One leaf node instance of the running mission (SubTrees expanded)."""

    name: str  # its scenario name: the name attribute, else the ID
    kind: str  # "Action" | "Condition"
    node: Node


def is_scripted_leaf(mission: Mission, node: Node) -> bool:
    """A node whose results come from the scenario: a user Action or Condition."""
    if isinstance(node, SubTreeNode) or node.children:
        return False
    try:
        spec = mission.spec(node.id)
    except KeyError:
        return True  # used but not declared: an Action
    return not spec.builtin and spec.kind in ("Action", "Condition")


def user_node_kind(mission: Mission, node: Node) -> Optional[str]:
    """ "Control" or "Decorator" for a node of the mission's own TreeNodesModel Controls and
    Decorators (implemented only by robot code), else None."""
    if isinstance(node, SubTreeNode):
        return None
    try:
        spec = mission.spec(node.id)
    except KeyError:
        return None
    return spec.kind if not spec.builtin and spec.kind in ("Control", "Decorator") else None


def user_node_message(node_id: str, kind: str) -> str:
    """Why `btgen run` cannot run a user Control/Decorator (the same on both engines)."""
    if node_id in ROS_NODES:
        return ros_node_message(node_id, kind)
    return (
        f"`{node_id}` is a {kind} of this mission's TreeNodesModel: it needs your implementation "
        f"(its tick() hook in the C++ that `btgen compile` generates), which `btgen run` does not have"
    )


def has_env_input(mission: Mission, node: Node) -> bool:
    """A built-in Nav2 Decorator with an input of the environment (lang/nav2.py ENV_INPUTS):
    the scenario scripts that input under the node's name, as a Condition's results."""
    return (
        mission.nav2 is not None
        and not isinstance(node, SubTreeNode)
        and node.id in ENV_INPUTS
        and node.id in mission.builtins
    )


def leaf_kind(mission: Mission, node: Node) -> str:
    try:
        spec = mission.spec(node.id)
    except KeyError:
        return "Action"
    return "Condition" if spec.kind == "Condition" else "Action"


def mission_leaves(mission: Mission, builtin_names: Optional[set] = None) -> Iterator[LeafUse]:
    """Every scripted leaf instance of the main tree, SubTrees expanded, in creation order.

    The display names of built-in leaves go to `builtin_names` when it is given.
    """
    trees = {t.id: t for t in mission.trees}
    if mission.main_tree not in trees:
        return
    stack: list[Node] = [trees[mission.main_tree].root]  # iterative: SubTree chains can be deep
    while stack:
        node = stack.pop()
        if isinstance(node, SubTreeNode):
            target = trees.get(node.target)
            if target is not None:
                stack.append(target.root)
            continue
        if is_scripted_leaf(mission, node):
            yield LeafUse(node.display_name, leaf_kind(mission, node), node)
            continue
        if has_env_input(mission, node):
            yield LeafUse(node.display_name, "Condition", node)  # its input, scripted as a Condition
        if not node.children and builtin_names is not None:
            builtin_names.add(node.display_name)
        stack.extend(reversed(node.children))


def _tree_with_leaf(mission: Mission, name: str) -> Optional[str]:
    """The first BehaviorTree (in file order) with a scripted leaf called `name`, if any."""

    def walk(node: Node) -> bool:
        if (is_scripted_leaf(mission, node) or has_env_input(mission, node)) and node.display_name == name:
            return True
        return any(walk(c) for c in node.children)

    for t in mission.trees:
        if walk(t.root):
            return t.id
    return None
