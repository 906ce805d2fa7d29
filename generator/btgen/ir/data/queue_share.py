"""Queue entries that SetBlackboard copies connect: one deque shared between entries.

BehaviorTree.CPP keeps a queue entry as a shared pointer, and SetBlackboard value="{q}"
output_key="r" copies the pointer (4.6.2 and 4.10.0): `r` and `q` are one deque until either is
set anew. The C++ back end gives such connected entries (of one queue kind) one pool of queues
(btgen::QueuePool in runtime/include/btgen/queue_view.hpp): each entry holds the number of its
queue, a copy shares it, a new queue takes a free one. Sizing (size.py) gives the class one
capacity; operations.py checks that nothing else writes its entries.
"""

from __future__ import annotations

from btgen.ir.data.resolve import Analysis
from btgen.ir.data.state import SetCopyUse
from btgen.ir.kinds import is_queue

# What may write an entry of a shared class: a user leaf's queue port, a SetBlackboard copy.
SHARED_WRITES = ("port", "copy")


def share_classes(a: Analysis) -> list[list[int]]:
    """The classes (sorted) that queue copies connect, in slot order (one slot: copied into itself)."""
    parent: dict[int, int] = {}

    def find(i: int) -> int:
        while parent.setdefault(i, i) != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for _, op in a.node_ops:
        if not isinstance(op, SetCopyUse):
            continue
        d, s = a.slots[op.dst], a.slots[op.src]
        if is_queue(s.kind) and d.kind == s.kind:
            parent[find(op.dst)] = find(op.src)  # (a copy into itself: a class of one)
    groups: dict[int, list[int]] = {}
    for i in sorted(parent):
        groups.setdefault(find(i), []).append(i)
    return sorted(groups.values(), key=lambda g: g[0])
