"""Step 4 of the data analysis: the capacity of every string and queue slot."""

from __future__ import annotations

from btgen.diagnostics import InternalError
from btgen.ir.data.queue_share import share_classes
from btgen.ir.data.records import WIDEN_AFTER
from btgen.ir.data.resolve import Analysis
from btgen.ir.kinds import DYN, STRING, is_numeric, is_queue, queue_kind


# ------------------------------------------------------------ 4. sizes
def size_slots(a: Analysis) -> None:
    cap = a.opt.string_capacity
    for s in a.slots:
        if s.kind in (STRING, DYN):
            s.capacity = 0
    # Queues first: a Loop's `value` is as long as the longest element of its queue (edges L3).
    for s in a.slots:
        if is_queue(s.kind):
            qcap = a.opt.queue_capacity
            s.capacity = max(s.queue_literals, default=0)
            if s.queue_unbounded or not s.queue_literals:
                s.capacity = max(s.capacity, qcap) if s.queue_unbounded else s.capacity
            s.capacity = max(s.capacity, 1)
            if s.kind == queue_kind(STRING):
                # literal elements are known: the slot holds the longest of them, whatever `cap`
                s.elem_capacity = max(s.elem_literals, default=0)
                if s.queue_unbounded:
                    s.elem_capacity = max(s.elem_capacity, cap)
    # Entries sharing one deque (queue_share.py) share one pool of queues: one capacity.
    for group in share_classes(a):
        cap_q = max(a.slots[i].capacity for i in group)
        cap_e = max(a.slots[i].elem_capacity for i in group)
        for i in group:
            a.slots[i].capacity, a.slots[i].elem_capacity = cap_q, cap_e
    # Capacities only grow. Robot code, whose bound is unknown, gets `cap`. A literal gets
    # its own length, and a computed value whose bound btgen knows (`'a' .. 1e300`: 318
    # bytes) its bound, even above `cap`, or the executor would fail where the library
    # succeeds (`cap` bounds what btgen cannot see, not what the mission spells out). A slot whose bound
    # depends on itself (`s := s .. 'x'`, possibly through other slots) grows a little
    # every round; after WIDEN_AFTER growths it is taken to grow without bound and gets
    # `cap` for good, so every slot changes at most WIDEN_AFTER + 1 times.
    growths = [0] * len(a.slots)
    changed = True
    rounds = 0
    while changed:
        changed = False
        rounds += 1
        for i, s in enumerate(a.slots):
            if s.kind not in (STRING, DYN) or growths[i] > WIDEN_AFTER:
                continue
            best = s.capacity
            for w in s.writes:
                if s.kind == DYN and is_numeric(w.kind()):
                    continue  # a dynamic slot holds numbers as numbers
                b = w.bound()
                b = cap if b is None else b
                best = max(best, b)
            if best > s.capacity:
                growths[i] += 1
                s.capacity = cap if growths[i] > WIDEN_AFTER else best
                changed = True
        if rounds > (WIDEN_AFTER + 2) * len(a.slots) + 2:
            raise InternalError("string capacities do not settle")
