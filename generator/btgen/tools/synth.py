"""Synthetic missions for measurements: balanced trees whose every tick visits every node.

:func:`balanced_mission` builds a mission of exactly ``n_nodes`` nodes from
Sequence, Fallback and Inverter over leaves, arranged so that one tick of
the root visits every node and the root succeeds:

- a subtree that must succeed is a leaf Action or Condition (the scenario's
  default SUCCESS), an ``Inverter`` over a subtree that must fail, or a
  ``Sequence`` whose children all succeed;
- a subtree that must fail is ``AlwaysFailure``, an ``Inverter`` over a
  leaf, or a ``Fallback`` whose children all fail.

Sequences and Fallbacks alternate level by level through Inverters, and the
nodes left are split evenly among ``branching`` children, so the tree is
balanced (depth about ``2 * log_branching(n)``). Every node changes status
twice per tick (to its result, then back to IDLE when its parent resets it),
so a traced run prints two lines per node per tick.

Variants with the same property (every tick visits every node, the root
succeeds, exactly ``n_nodes`` nodes with SubTrees expanded):

- :func:`reactive_mission`: ReactiveSequence and ReactiveFallback instead of
  Sequence and Fallback;
- :func:`subtree_mission`: the nodes spread over SubTrees two levels deep,
  each of the two shared trees instantiated four times per caller;
- :func:`script_mission`: the leaves are Script and ScriptCondition nodes
  and Actions with a pre-condition, over one blackboard entry.

Run as a script to print a mission: ``python -m btgen.tools.synth 10000 > big.xml``
(``--kind reactive|subtrees|scripts`` for the variants).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import Optional

from btgen import cmdline

SUCCESS_LEAVES = ("Work", "Ready")  # an Action and a Condition, both default SUCCESS
KINDS = ("balanced", "reactive", "subtrees", "scripts")

# The script variant: leaves that succeed, and one that fails, over entry `n`.
SUCCESS_LEAF_ELEMENTS = tuple(f"<{leaf}/>" for leaf in SUCCESS_LEAVES)
SCRIPT_SUCCESS_LEAVES = (
    '<Script code="n += 1"/>',
    '<ScriptCondition code="n &gt;= 0"/>',
    '<Work _failureIf="n &lt; 0"/>',
)
SCRIPT_FAILURE_LEAF = '<ScriptCondition code="n &lt; 0"/>'


def _body(
    n_nodes: int,
    branching: int,
    depth: int,
    *,
    sequence: str = "Sequence",
    fallback: str = "Fallback",
    success_leaves: Sequence[str] = SUCCESS_LEAF_ELEMENTS,
    failure_leaf: str = "<AlwaysFailure/>",
    name_prefix: str = "",
) -> list[str]:
    """The lines of a balanced subtree of `n_nodes` nodes that succeeds, indented for `depth`."""
    if n_nodes < 1:
        raise ValueError("a tree has at least one node")
    if branching < 2:
        raise ValueError("branching must be at least 2")
    out: list[str] = []
    counter = [0]

    def leaf() -> str:
        counter[0] += 1
        return success_leaves[counter[0] % len(success_leaves)]

    def emit(line: str, d: int) -> None:
        out.append("  " * (d + depth) + line)

    def split(total: int) -> list[int]:
        k = min(branching, total)
        base, extra = divmod(total, k)
        return [base + (1 if i < extra else 0) for i in range(k)]

    def succeed(n: int, d: int) -> None:
        if n == 1:
            emit(leaf(), d)
        elif n == 2:
            emit("<Inverter>", d)
            emit(failure_leaf, d + 1)
            emit("</Inverter>", d)
        else:
            emit(f'<{sequence} name="{name_prefix}S{len(out)}">', d)
            for m in split(n - 1):
                if m >= 3:
                    emit("<Inverter>", d + 1)
                    fail(m - 1, d + 2)
                    emit("</Inverter>", d + 1)
                else:
                    succeed(m, d + 1)
            emit(f"</{sequence}>", d)

    def fail(n: int, d: int) -> None:
        if n == 1:
            emit(failure_leaf, d)
        elif n == 2:
            emit("<Inverter>", d)
            emit(leaf(), d + 1)
            emit("</Inverter>", d)
        else:
            emit(f'<{fallback} name="{name_prefix}F{len(out)}">', d)
            for m in split(n - 1):
                if m >= 3:
                    emit("<Inverter>", d + 1)
                    succeed(m - 1, d + 2)
                    emit("</Inverter>", d + 1)
                else:
                    fail(m, d + 1)
            emit(f"</{fallback}>", d)

    succeed(n_nodes, 0)
    return out


def _document(main: str, trees: Sequence[tuple[str, list[str]]]) -> str:
    lines = ['<?xml version="1.0" encoding="UTF-8"?>', f'<root BTCPP_format="4" main_tree_to_execute="{main}">']
    for tree_id, body in trees:
        lines.append(f'  <BehaviorTree ID="{tree_id}">')
        lines.extend(body)
        lines.append("  </BehaviorTree>")
    lines += [
        "  <TreeNodesModel>",
        f'    <Action ID="{SUCCESS_LEAVES[0]}"/>',
        f'    <Condition ID="{SUCCESS_LEAVES[1]}"/>',
        "  </TreeNodesModel>",
        "</root>",
        "",
    ]
    return "\n".join(lines)


def balanced_mission(n_nodes: int, branching: int = 4, tree_id: str = "Main") -> str:
    """A valid BTCPP_format="4" mission of exactly `n_nodes` nodes (at least 1).

    With the scenario default SUCCESS, one root tick visits every node and
    returns SUCCESS.
    """
    return _document(tree_id, [(tree_id, _body(n_nodes, branching, 2))])


def reactive_mission(n_nodes: int, branching: int = 4) -> str:
    """As balanced_mission, with ReactiveSequence and ReactiveFallback."""
    return _document(
        "Main", [("Main", _body(n_nodes, branching, 2, sequence="ReactiveSequence", fallback="ReactiveFallback"))]
    )


def subtree_mission(n_nodes: int, branching: int = 4) -> str:
    """`n_nodes` nodes (SubTrees expanded, at least 46) over three trees:

        Main = Sequence( 4 x SubTree Part, balanced rest )
        Part = Sequence( 4 x SubTree Leg, balanced rest )
        Leg  = balanced tree

    with sizes chosen so the total is exact. One tick visits every node.
    """
    fan = 4
    part = (n_nodes - 2) // fan - 1  # nodes of one Part instance; Main's rest gets >= 1
    leg = (part - 2) // fan - 1  # nodes of one Leg instance; Part's rest gets >= 1
    if leg < 1:
        raise ValueError("a SubTree mission has at least 46 nodes")
    main_rest = n_nodes - 1 - fan * (1 + part)
    part_rest = part - 1 - fan * (1 + leg)

    def caller(callee: str, rest: int, prefix: str) -> list[str]:
        return (
            ['    <Sequence name="Calls">']
            + [f'      <SubTree ID="{callee}" name="{callee}{i}"/>' for i in range(fan)]
            + _body(rest, branching, 3, name_prefix=prefix)
            + ["    </Sequence>"]
        )

    return _document(
        "Main",
        [
            ("Main", caller("Part", main_rest, "M")),
            ("Part", caller("Leg", part_rest, "P")),
            ("Leg", _body(leg, branching, 2, name_prefix="L")),
        ],
    )


def script_mission(n_nodes: int, branching: int = 4) -> str:
    """`n_nodes` nodes (at least 3): `Sequence(Script n := 0, balanced tree)` whose
    leaves are scripts over the entry `n` (Script `n += 1`, ScriptCondition
    `n >= 0`, an Action with `_failureIf="n < 0"`; failing leaf: ScriptCondition
    `n < 0`). One tick visits every node."""
    if n_nodes < 3:
        raise ValueError("a script mission has at least 3 nodes")
    body = (
        ['    <Sequence name="Root">', '      <Script name="Init" code="n := 0"/>']
        + _body(n_nodes - 2, branching, 3, success_leaves=SCRIPT_SUCCESS_LEAVES, failure_leaf=SCRIPT_FAILURE_LEAF)
        + ["    </Sequence>"]
    )
    return _document("Main", [("Main", body)])


def mission(kind: str, n_nodes: int, branching: int = 4) -> str:
    """The synthetic mission of `kind` (one of KINDS) with `n_nodes` nodes."""
    makers = {
        "balanced": balanced_mission,
        "reactive": reactive_mission,
        "subtrees": subtree_mission,
        "scripts": script_mission,
    }
    if kind not in makers:
        raise ValueError(f"unknown kind {kind!r}; one of {', '.join(KINDS)}")
    return makers[kind](n_nodes, branching)


def count_nodes(xml_text: str) -> int:
    """The number of tree nodes in a mission produced by :func:`balanced_mission`
    (one BehaviorTree; SubTree missions: use the front end)."""
    inside = xml_text.split("<BehaviorTree", 1)[1].split("</BehaviorTree>", 1)[0]
    return sum(1 for part in inside.split("<")[1:] if part and part[0] not in "/!?")


def main(argv: Optional[list[str]] = None) -> int:
    p = cmdline.Parser(prog="python -m btgen.tools.synth", description=__doc__.splitlines()[0])
    p.add_argument("nodes", type=int)
    p.add_argument("branching", type=int, nargs="?", default=4)
    p.add_argument("--kind", choices=KINDS, default="balanced")
    args = p.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        sys.stdout.write(mission(args.kind, args.nodes, args.branching))
    except ValueError as e:
        print(f"{cmdline.loc_of(args.argv, None)}: error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
