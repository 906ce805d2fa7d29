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

Run as a script to print a mission: ``python -m btgen.synth 10000 > big.xml``.
"""
from __future__ import annotations

import sys
from typing import Optional

SUCCESS_LEAVES = ("Work", "Ready")  # an Action and a Condition, both default SUCCESS


def balanced_mission(n_nodes: int, branching: int = 4, tree_id: str = "Main") -> str:
    """A valid BTCPP_format="4" mission of exactly `n_nodes` nodes (at least 1).

    With the scenario default SUCCESS, one root tick visits every node and
    returns SUCCESS.
    """
    if n_nodes < 1:
        raise ValueError("a mission has at least one node")
    if branching < 2:
        raise ValueError("branching must be at least 2")
    out: list[str] = []
    counter = [0]

    def leaf() -> str:
        counter[0] += 1
        return SUCCESS_LEAVES[counter[0] % 2]

    def emit(line: str, depth: int) -> None:
        out.append("  " * (depth + 2) + line)

    def split(total: int) -> list[int]:
        k = min(branching, total)
        base, extra = divmod(total, k)
        return [base + (1 if i < extra else 0) for i in range(k)]

    def succeed(n: int, depth: int) -> None:
        if n == 1:
            emit(f"<{leaf()}/>", depth)
        elif n == 2:
            emit("<Inverter>", depth)
            emit("<AlwaysFailure/>", depth + 1)
            emit("</Inverter>", depth)
        else:
            emit(f'<Sequence name="S{len(out)}">', depth)
            for m in split(n - 1):
                if m >= 3:
                    emit("<Inverter>", depth + 1)
                    fail(m - 1, depth + 2)
                    emit("</Inverter>", depth + 1)
                else:
                    succeed(m, depth + 1)
            emit("</Sequence>", depth)

    def fail(n: int, depth: int) -> None:
        if n == 1:
            emit("<AlwaysFailure/>", depth)
        elif n == 2:
            emit("<Inverter>", depth)
            emit(f"<{leaf()}/>", depth + 1)
            emit("</Inverter>", depth)
        else:
            emit(f'<Fallback name="F{len(out)}">', depth)
            for m in split(n - 1):
                if m >= 3:
                    emit("<Inverter>", depth + 1)
                    succeed(m - 1, depth + 2)
                    emit("</Inverter>", depth + 1)
                else:
                    fail(m, depth + 1)
            emit("</Fallback>", depth)

    succeed(n_nodes, 0)
    return "\n".join([
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<root BTCPP_format="4" main_tree_to_execute="{tree_id}">',
        f'  <BehaviorTree ID="{tree_id}">',
        *out,
        "  </BehaviorTree>",
        "  <TreeNodesModel>",
        f'    <Action ID="{SUCCESS_LEAVES[0]}"/>',
        f'    <Condition ID="{SUCCESS_LEAVES[1]}"/>',
        "  </TreeNodesModel>",
        "</root>",
        "",
    ])


def count_nodes(xml_text: str) -> int:
    """The number of tree nodes in a mission produced by :func:`balanced_mission`."""
    inside = xml_text.split("<BehaviorTree", 1)[1].split("</BehaviorTree>", 1)[0]
    return sum(1 for part in inside.split("<")[1:] if part and part[0] not in "/!?")


def main(argv: Optional[list[str]] = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if not args or not args[0].isdigit():
        print("usage: python -m btgen.synth N_NODES [BRANCHING]", file=sys.stderr)
        return 2
    branching = int(args[1]) if len(args) > 1 else 4
    sys.stdout.write(balanced_mission(int(args[0]), branching))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
