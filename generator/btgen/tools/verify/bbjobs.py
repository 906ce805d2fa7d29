"""The tables of the blackboard nodes (`bbnodes.py` has their Promela): what each runs of the
interpreter's own node code on every reachable blackboard (`blackboard.build_tables` runs the
jobs), and the members of those nodes that belong to the blackboard state (`Members`)."""

from __future__ import annotations

from typing import Any, Callable

from btgen.diagnostics import Loc
from btgen.ir.lower import IRNode

IDLE, RUNNING, SUCCESS, FAILURE, SKIPPED = 0, 1, 2, 3, 4
POPPED = 1  # a Loop's pop_phase: the child is to be ticked (a status is 16 x status: never 1)
KEEP = 252  # a Retry's re-read of num_attempts found no value: the count read before stays

BB_KINDS = frozenset(
    {
        "SetBlackboard",
        "UnsetBlackboard",
        "WasEntryUpdated",
        "Switch",
        "Precondition",
        "Loop",
        "SkipUnlessUpdated",
        "WaitValueUpdate",
    }
)
PARAM_FROM_BB = frozenset({"Repeat", "RetryUntilSuccessful", "RunOnce", "TryCatch", "RecoveryNode"})  # read from it
_PARAM_PORT = {"Repeat": "num_cycles", "RetryUntilSuccessful": "num_attempts"}


Job = tuple[dict, object, Loc, Callable[[], int]]  # (table, None, place, what to run on the interpreter's node)


def node_jobs(n: IRNode, node, tables: Any, param_from_bb: bool) -> list[Job]:
    """The tables node n needs."""
    k, i = n.kind, n.index
    out: list[Job] = []

    def job(role: str, run: Callable[[], int], port: str = "") -> None:
        p = node.ports.get(port) if port else None
        where = p.attr.value_loc if p is not None and p.attr is not None else n.loc
        out.append((tables.node.setdefault((i, role), {}), None, where, run))

    if k in ("SetBlackboard", "UnsetBlackboard", "WasEntryUpdated"):
        port = {"SetBlackboard": "value", "UnsetBlackboard": "key", "WasEntryUpdated": "entry"}[k]
        job("tick", node.tick, port)
    elif k == "Switch":
        job("case", node.select, "variable")
    elif k == "Precondition":
        job("if", lambda: _precondition(node), "if")
        if node.rt.sem.precondition_if_until_started:
            job("else", lambda: 16 * node.status_input("else"), "else")
    elif k == "Loop":
        job("idle", lambda: _pop(node, IDLE), "queue")
        job("cont", lambda: _pop(node, RUNNING), "queue")
    elif k in ("SkipUnlessUpdated", "WaitValueUpdate"):
        job("upd", lambda: 1 if node.consume_update() else 0, "entry")
    elif k == "RunOnce" and param_from_bb:  # then_skip, read every tick (no value: true)
        values = tables.params.setdefault(i, [])
        job("param", lambda: _index(values, _then_skip(node)), "then_skip")
    elif k == "RecoveryNode" and param_from_bb:  # Nav2: read every tick (no value: the last one stays)
        values = tables.params.setdefault(i, [])
        job("param", lambda: _reread(values, node, "number_of_retries"), "number_of_retries")
    elif k == "TryCatch" and param_from_bb:  # catch_on_halt, read in halt() (no value: false)
        values = tables.params.setdefault(i, [])
        job("param", lambda: _index(values, node.get_input("catch_on_halt", "bool") is True), "catch_on_halt")
    elif k in PARAM_FROM_BB and param_from_bb:
        port = _PARAM_PORT[k]
        values = tables.params.setdefault(i, [])
        job("param", lambda: _index(values, node.require_input(port, "int")), port)
        if k == "RetryUntilSuccessful" and node.rt.sem.retry_rereads_attempts:
            job("reread", lambda: _reread(values, node, port), port)
    return out


def _index(values: list, v) -> int:
    if v not in values:
        values.append(v)
    return values.index(v)


def _reread(values: list, node, port: str) -> int:
    from btgen.interp.tree import MISSING

    v = node.get_input(port, "int")
    return KEEP if v is MISSING else _index(values, v)


def _then_skip(node) -> bool:
    from btgen.interp.tree import MISSING

    v = node.get_input("then_skip", "bool")
    return True if v is MISSING else bool(v)


def _precondition(node) -> int:
    """PreconditionNode.tick up to the child: `else` read, then the `if` script's truth."""
    node.script.load()
    else_status = node.status_input("else")
    truth = node.script.truth()
    if not truth and else_status == IDLE:  # returned, IDLE throws: a table's error (and its warning)
        raise node._idle_error()
    return 16 * else_status + (1 if truth else 0)


def _pop(node, status: int) -> int:
    node.status = status
    node.child_running = False
    r = node.pop_phase()
    return POPPED if r is None else 16 * r


class Members:
    """The members of the interpreter's nodes that belong to the blackboard state."""

    def __init__(self, inodes: list) -> None:
        from btgen.interp.actions import WasEntryUpdatedNode
        from btgen.interp.decorators import EntryUpdatedDecorator, LoopNode

        self.loops = [n for n in inodes if isinstance(n, LoopNode)]
        self.updates = [n for n in inodes if isinstance(n, (EntryUpdatedDecorator, WasEntryUpdatedNode))]
        self.ahead: list = []  # the entry-update nodes found ahead of their entry's counter (a warning)

    def save(self) -> tuple:
        from btgen.interp.tree import RunError, _entry_of
        from btgen.lang import values

        loops = tuple(None if q is None else values.Queue(q.element_type, q) for q in (n.current for n in self.loops))
        ups = []
        for u in self.updates:
            try:
                e = _entry_of(u)
            except RunError:  # a bad key: the node fails at run time whatever it saw
                e = None
            rel = _relation(u.seen, e)
            if rel == ("ahead",) and u not in self.ahead:
                self.ahead.append(u)
            ups.append((u.seen, rel))
        return (loops, tuple(ups))

    @staticmethod
    def key(saved: tuple) -> tuple:
        loops, ups = saved
        return (tuple(None if q is None else repr(q) for q in loops), tuple(k for _s, k in ups))

    def restore(self, saved: tuple) -> None:
        from btgen.lang import values

        for n, q in zip(self.loops, saved[0]):
            n.current = None if q is None else values.Queue(q.element_type, q)
        for u, (seen, _k) in zip(self.updates, saved[1]):
            u.seen = seen


def _relation(seen: int, entry) -> tuple:
    """What an entry-update node's last seen counter decides: equal to the entry's (not
    updated), behind it (updated, and it stays so: counters only grow), or ahead of it. Ahead
    happens when the entry was unset and made again (it counts from 0): the node sees an update
    until the new counter comes back to `seen`, and then not. Keeping by how much would make the
    over-approximated blackboards grow, so ahead is one state (abstracted, with a warning:
    blackboard.build_tables)."""
    if entry is None:
        return ("missing", seen)
    seq = entry.sequence_id
    if seen == seq:
        return ("fresh",)
    return ("behind",) if seen < seq else ("ahead",)


AHEAD_WARNING = (
    "its entry may be unset and made again, and the new entry's update counter may come back to "
    "the one this node saw last: then BehaviorTree.CPP sees no update where btgen verify may see "
    "one (btgen verify keeps whether the counter is ahead, not by how much)"
)
