"""Node shapes: which nodes can share one piece of straight-line code.

The engine ticks the first part of a mission as straight-line code, one
function per node (btgen::Engine::tick_node in runtime/include/btgen/engine.hpp),
with everything about the node that decides its control flow folded in: its
kind, its model, its pre-/post-condition bits, its parameters and, through
its children's functions, the same for its whole subtree. Two nodes whose
subtrees agree on all of that tick the same way; only where their state lives
differs (a node's subtree is a contiguous run of the table, so its children
are at the same offsets from it). They share one function, called with the
node's index: the shape. SubTree instances of one BehaviorTree are the common
case; repeated patterns inside a tree are the others.

A node deeper than the engine's kCompiledDepth gets the shape `deep`, which
the engine runs on its table interpreter, so that the native recursion of the
straight-line code stays bounded whatever the tree's depth.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Optional

from btgen.ir.lower import Program
from btgen.lang.nav2 import ALL_FAMILY_IDS as NAV2_KINDS

# btgen::Engine::kCompiledDepth: nodes at this depth (the root at 0) and below
# are interpreted.
COMPILED_DEPTH = 48
NO_NODE = 0xFFFF


SCRIPTED_KINDS = ("Script", "ScriptCondition", "Precondition")


@dataclass(frozen=True)
class Shapes:
    of_node: tuple[int, ...]  # shape of every node, numbered by first appearance in creation order
    rep: tuple[int, ...]  # the first node of every shape (NO_NODE for the deep shape)
    uses: tuple[int, ...]  # how many nodes have each shape
    # For BTGEN_STRAIGHT_LINE_BUDGET, summed here rather than in constant evaluation (a loop
    # over 65,535 nodes passes clang's step limit): the weight of all nodes, the first node of
    # every compiled shape in creation order and the weight of the ones before it.
    total_weight: int = 0
    rep_nodes: tuple[int, ...] = ()
    rep_weight_before: tuple[int, ...] = ()
    has_deep: bool = False
    user_control_flow: bool = False


def node_weight(n) -> int:
    """What a node's straight-line code costs against the budget: 1, or 6 when it runs
    scripts, plus its children's call sites."""
    scripted = n.scripts != 0 or n.kind in SCRIPTED_KINDS
    return (6 if scripted else 1) + len(n.children)


def shapes(program: Program, node_scripts: Optional[Sequence[tuple[str, ...]]] = None) -> Shapes:
    """The shapes of `program`'s nodes. `node_scripts[i]`: the script functions node i calls,
    in ScriptSlot order (emit.script_tables); nodes of one shape call the same ones, which
    the straight-line code then calls directly."""
    nodes = program.nodes
    fns = node_scripts if node_scripts is not None else [()] * len(nodes)
    key_id: dict[tuple, int] = {}
    temp = [0] * len(nodes)
    # Children come after their parent in creation order: keys bottom-up.
    for n in reversed(nodes):
        if n.depth - 1 >= COMPILED_DEPTH:
            key: tuple = ("deep",)
        else:
            key = (n.kind, n.model, n.scripts, fns[n.index], n.params, tuple(temp[c] for c in n.children))
        temp[n.index] = key_id.setdefault(key, len(key_id))
    deep = key_id.get(("deep",))
    number: dict[int, int] = {}
    rep: list[int] = []
    uses: list[int] = []
    of_node: list[int] = []
    for n in nodes:
        t = temp[n.index]
        if t not in number:
            number[t] = len(rep)
            rep.append(NO_NODE if t == deep else n.index)
            uses.append(0)
        of_node.append(number[t])
        uses[number[t]] += 1
    rep_nodes = [r for r in rep if r != NO_NODE]
    before, total = [], 0
    for r in rep_nodes:
        before.append(total)
        total += node_weight(nodes[r])
    return Shapes(
        tuple(of_node),
        tuple(rep),
        tuple(uses),
        sum(node_weight(n) for n in nodes),
        tuple(rep_nodes),
        tuple(before),
        deep is not None,
        # (Nav2's nodes tick their children there too, as the mission's own Controls do)
        any(n.kind in ("UserControl", "UserDecorator") or n.kind in NAV2_KINDS for n in nodes),
    )
