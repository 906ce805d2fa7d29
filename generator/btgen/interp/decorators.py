"""Decorator nodes as in BehaviorTree.CPP 4.6.2's ``src/decorators/``, plus the SubTree node."""

from __future__ import annotations

from typing import Optional

from btgen.interp.tree import (
    _TRANS,
    FAILURE,
    IDLE,
    MISSING,
    RUNNING,
    SKIPPED,
    SUCCESS,
    TreeNode,
    _entry_of,
    _run_error,
    _ScriptPort,
)
from btgen.lang import blackboard as bbmod
from btgen.lang import values

# The message of both engines (runtime/include/btgen/engine.hpp, Engine::not_idle).
_IDLE_RESULT = "{} is IDLE: a node may not set its own status to IDLE (BehaviorTree.CPP throws)"


class DecoratorNode(TreeNode):
    """4.6.2 ``DecoratorNode``: halt() resets the child (halting it when RUNNING), then itself;
    executeTick() resets a completed child after the decorator's own status is set."""

    __slots__ = ("child",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.child: TreeNode = None  # type: ignore[assignment]

    def halt(self) -> None:
        self.reset_child()
        self.reset_status()

    def reset_child(self) -> None:
        c = self.child
        if c.status == RUNNING:
            c.halt_node()
        c.reset_status()

    def execute_tick(self) -> int:
        # TreeNode::executeTick, inlined for speed, then DecoratorNode's child reset
        if self.conds:
            status = self._execute_tick_with_conditions()
        else:
            status = self.tick()
            if status != SKIPPED:
                if status == IDLE:  # setStatus(IDLE) throws even when the node is IDLE already
                    raise self._idle_error()
                prev = self.status
                if prev != status:
                    self.status = status
                    self.emit((self.prefix, _TRANS[prev][status]))
        c = self.child
        cs = c.status
        if cs in (SUCCESS, FAILURE):
            c.status = IDLE
            c.emit((c.prefix, _TRANS[cs][IDLE]))
        return status


class InverterNode(DecoratorNode):
    __slots__ = ()

    def tick(self) -> int:
        st = self.status
        if st != RUNNING:
            self.status = RUNNING
            self.emit((self.prefix, _TRANS[st][RUNNING]))
        c = self.child
        cs = c.execute_tick()
        if cs == SUCCESS:
            c.status = IDLE  # resetChild() of a completed child
            c.emit((c.prefix, _TRANS[SUCCESS][IDLE]))
            return FAILURE
        if cs == FAILURE:
            c.status = IDLE
            c.emit((c.prefix, _TRANS[FAILURE][IDLE]))
            return SUCCESS
        if cs == IDLE:
            raise _run_error(self.model.loc, f'the child of `Inverter` "{self.name}" returned IDLE')
        return cs

    def execute_tick(self) -> int:
        # executeTick + tick + DecoratorNode's child reset in one frame: a third of the nodes
        # of a big tree can be Inverters, and every call counts there
        if self.conds:
            return DecoratorNode.execute_tick(self)
        st = self.status
        if st != RUNNING:
            self.status = RUNNING
            self.emit((self.prefix, _TRANS[st][RUNNING]))
        c = self.child
        cs = c.execute_tick()
        if cs == SUCCESS:
            c.status = IDLE
            c.emit((c.prefix, _TRANS[SUCCESS][IDLE]))
            new = FAILURE
        elif cs == FAILURE:
            c.status = IDLE
            c.emit((c.prefix, _TRANS[FAILURE][IDLE]))
            new = SUCCESS
        elif cs == IDLE:
            raise _run_error(self.model.loc, f'the child of `Inverter` "{self.name}" returned IDLE')
        else:
            return cs  # RUNNING (already stored) or SKIPPED (never stored)
        self.status = new
        self.emit((self.prefix, _TRANS[RUNNING][new]))
        return new


class _ForceNode(DecoratorNode):
    """4.6.2 ``ForceSuccess`` and ``ForceFailure``: a finished child gives ``RESULT``."""

    __slots__ = ()
    RESULT = SUCCESS

    def tick(self) -> int:
        self.set_status(RUNNING)
        cs = self.child.execute_tick()
        if cs in (SUCCESS, FAILURE):
            self.reset_child()
            return self.RESULT
        return cs


class ForceSuccessNode(_ForceNode):
    __slots__ = ()
    RESULT = SUCCESS


class ForceFailureNode(_ForceNode):
    __slots__ = ()
    RESULT = FAILURE


class KeepRunningUntilFailureNode(DecoratorNode):
    """4.6.2: SUCCESS becomes RUNNING; a SKIPPED child leaves the node's own status (RUNNING)."""

    __slots__ = ()

    def tick(self) -> int:
        self.set_status(RUNNING)
        cs = self.child.execute_tick()
        if cs == FAILURE:
            self.reset_child()
            return FAILURE
        if cs == SUCCESS:
            self.reset_child()
            return RUNNING
        if cs == RUNNING:
            return RUNNING
        return self.status


class RepeatNode(DecoratorNode):
    """4.6.2 ``RepeatNode``: a child that succeeded from IDLE yields RUNNING before the next cycle.

    ``all_skipped`` is 4.6.2's flag: set when ticked from IDLE, cleared by any child result
    but SKIPPED. A count of 0 or below -1 never starts the loop, so the flag is still set and
    the node answers SKIPPED while staying RUNNING (docs/btcpp-4.6.2-edges.md, R1).
    From 4.7.0 the loop never ends SKIPPED (versions.py loop_end_never_skipped)."""

    __slots__ = ("count", "all_skipped")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.count = 0
        self.all_skipped = True

    def halt(self) -> None:
        self.count = 0
        DecoratorNode.halt(self)

    def tick(self) -> int:
        cycles = self.require_input("num_cycles", "int")
        do_loop = self.count < cycles or cycles == -1
        if self.status == IDLE:
            self.all_skipped = True
        self.set_status(RUNNING)
        while do_loop:
            prev = self.child.status
            cs = self.child.execute_tick()
            if cs != SKIPPED:
                self.all_skipped = False
            if cs == SUCCESS:
                self.count += 1
                do_loop = self.count < cycles or cycles == -1
                self.reset_child()
                if prev == IDLE and do_loop:
                    return RUNNING
            elif cs == FAILURE:
                self.count = 0
                self.reset_child()
                return FAILURE
            elif cs == RUNNING:
                return RUNNING
            elif cs == SKIPPED:
                self.reset_child()
                return SKIPPED
            else:
                raise _run_error(self.model.loc, f'the child of `Repeat` "{self.name}" returned IDLE')
        self.count = 0
        return SKIPPED if self.all_skipped and not self.rt.sem.loop_end_never_skipped else SUCCESS


class RetryNode(DecoratorNode):
    """4.6.2 ``RetryNode`` (RetryUntilSuccessful). From 4.7.0 num_attempts is read again after
    every failure (versions.py retry_rereads_attempts) and the loop never ends SKIPPED
    (loop_end_never_skipped)."""

    __slots__ = ("tries", "all_skipped")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.tries = 0
        self.all_skipped = True

    def halt(self) -> None:
        self.tries = 0
        DecoratorNode.halt(self)

    def tick(self) -> int:
        attempts = self.require_input("num_attempts", "int")
        do_loop = self.tries < attempts or attempts == -1
        if self.status == IDLE:
            self.all_skipped = True
        self.set_status(RUNNING)
        while do_loop:
            prev = self.child.status
            cs = self.child.execute_tick()
            if cs != SKIPPED:
                self.all_skipped = False
            if cs == SUCCESS:
                self.tries = 0
                self.reset_child()
                return SUCCESS
            if cs == FAILURE:
                self.tries += 1
                # 4.6.2 read num_attempts once, at the start of tick(); re-reading it after
                # every failure (#905) came with 4.7.0 (a failed read keeps the old value)
                if self.rt.sem.retry_rereads_attempts:
                    again = self.get_input("num_attempts", "int")
                    if again is not MISSING:
                        attempts = again
                do_loop = self.tries < attempts or attempts == -1
                self.reset_child()
                if prev == IDLE and do_loop:
                    return RUNNING
            elif cs == RUNNING:
                return RUNNING
            elif cs == SKIPPED:
                self.reset_child()
                return SKIPPED
            else:
                raise _run_error(self.model.loc, f'the child of `RetryUntilSuccessful` "{self.name}" returned IDLE')
        self.tries = 0
        return SKIPPED if self.all_skipped and not self.rt.sem.loop_end_never_skipped else FAILURE


class RunOnceNode(DecoratorNode):
    """4.6.2 ``RunOnceNode``: after the child completed once, SKIPPED (then_skip) or its status."""

    __slots__ = ("done", "returned")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.done = False
        self.returned = IDLE

    def tick(self) -> int:
        skip = True
        value = self.get_input("then_skip", "bool")
        if value is not MISSING:
            skip = bool(value)
        if self.done:
            return SKIPPED if skip else self.returned
        self.set_status(RUNNING)
        status = self.child.execute_tick()
        if status in (SUCCESS, FAILURE):
            self.done = True
            self.returned = status
            self.reset_child()
        return status


class PreconditionNode(DecoratorNode):
    """4.6.2 ``PreconditionNode``: `if` is evaluated on every tick; when false the node returns
    `else` without ticking (or halting) its child. (Later releases evaluate it once per run.)"""

    __slots__ = ("script", "children_running")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.script = _ScriptPort(self, "if")
        self.children_running = False

    def tick(self) -> int:
        self.script.load()
        else_status = self.status_input("else")
        if self.rt.sem.precondition_if_until_started:
            # 4.7.0: `if` only until the child has started; the flag survives a halt (a quirk
            # of the library: halt() does not clear it, docs/btcpp-versions.md)
            if not self.children_running:
                self.children_running = self.script.truth()
            if not self.children_running:
                return else_status
            cs = self.child.execute_tick()
            if cs in (SUCCESS, FAILURE):
                self.reset_child()
                self.children_running = False
            return cs
        if self.script.truth():
            cs = self.child.execute_tick()
            if cs in (SUCCESS, FAILURE):
                self.reset_child()
            return cs
        if else_status == IDLE:  # setStatus(IDLE) throws (edges table, L2)
            raise _run_error(self.model.loc, _IDLE_RESULT.format("the condition is false and `else`"))
        return else_status


class TimeoutNode(DecoratorNode):
    """4.6.2 ``TimeoutNode`` on the virtual clock: the timer that would halt the RUNNING child from
    another thread is a deadline, checked when the node is ticked (before the child)."""

    __slots__ = ("started", "deadline")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.started = False
        self.deadline: Optional[int] = None

    def halt(self) -> None:
        self.started = False
        self.deadline = None
        DecoratorNode.halt(self)

    def tick(self) -> int:
        msec = self.require_input("msec", "unsigned")
        if not self.started:
            self.started = True
            self.set_status(RUNNING)
            self.deadline = self.rt.now_ms + msec if msec > 0 else None
        elif self.deadline is not None and self.rt.now_ms >= self.deadline:
            # The timer fires once: it halts the child if that is RUNNING (haltChild(), then
            # FAILURE on this tick); otherwise it does nothing and is spent.
            self.deadline = None
            if self.child.status == RUNNING:
                self.reset_child()
                self.started = False
                return FAILURE
        cs = self.child.execute_tick()
        if cs in (SUCCESS, FAILURE):
            self.started = False
            self.deadline = None
            self.reset_child()
        return cs


class DelayNode(DecoratorNode):
    """4.6.2 ``DelayNode`` on the virtual clock: RUNNING until delay_msec have passed since the first
    tick, then the child is ticked (in the same tick when the delay is 0)."""

    __slots__ = ("started", "deadline")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.started = False
        self.deadline = 0

    def halt(self) -> None:
        self.started = False
        DecoratorNode.halt(self)

    def tick(self) -> int:
        msec = self.require_input("delay_msec", "unsigned")
        if not self.started:
            self.started = True
            self.set_status(RUNNING)
            self.deadline = self.rt.now_ms + msec
        if self.rt.now_ms >= self.deadline:
            cs = self.child.execute_tick()
            if cs in (SUCCESS, FAILURE):
                self.started = False
                self.reset_child()
            return cs
        return RUNNING


class LoopNode(DecoratorNode):
    """4.6.2 ``LoopNode<T>``: pops one element per run of the child into `value`.

    A literal queue is copied afresh each time the loop starts from IDLE
    (4.7.0 behaviour, as FORMAT.md asks; 4.6.2 consumed it for good)."""

    __slots__ = ("elem", "static_queue", "current", "child_running")

    def __init__(self, rt, model, bb, reg_id, ports, elem: str) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.elem = elem
        self.child_running = False
        self.current: Optional[values.Queue] = None
        self.static_queue: Optional[values.Queue] = None
        p = self.ports.get("queue")
        if p is not None and not bbmod.is_blackboard_pointer(p.raw):
            try:
                self.static_queue = values.convert_from_string(  # type: ignore[assignment]
                    f"queue<{elem}>", p.raw, double_from_chars=rt.sem.double_from_chars
                )
            except values.ConversionError as e:
                raise _run_error(self.port_loc("queue"), f'port `queue` of `{reg_id}` "{self.name}": {e}') from None

    def tick(self) -> int:
        done = self.pop_phase()
        if done is not None:
            return done
        if self.status == IDLE:
            self.set_status(RUNNING)
        cs = self.child.execute_tick()
        self.child_running = cs == RUNNING
        if cs in (SUCCESS, FAILURE):
            self.reset_child()
        if cs == FAILURE:
            return FAILURE
        return RUNNING

    def pop_phase(self) -> Optional[int]:
        """The part of tick() before the child: the next element into `value`; the status to
        return when the queue is empty (`if_empty`), None when the child is to be ticked.
        (btgen verify runs it on every blackboard, tools/verify/bbnodes.py.)"""
        popped = False
        if self.status == IDLE:
            self.child_running = False
            if self.rt.sem.loop_queue_untyped:
                self.current = None
            if self.static_queue is not None:
                self.current = values.Queue(self.elem, self.static_queue)
        if not self.child_running:
            if self.static_queue is None and self.rt.sem.loop_queue_untyped:
                q = self._queue_from_blackboard_410()
                if q is not None:
                    self.current = q
            elif self.static_queue is None:
                q = self._queue_from_blackboard()
                if q is not None:
                    self.current = q
            if self.current:
                value = self.current.popleft()
                popped = True
                self.set_output("value", value, self.elem)
        if not popped and not self.child_running:
            if_empty = self.status_input("if_empty")
            if if_empty == IDLE:  # setStatus(IDLE) throws (edges table, L1)
                raise _run_error(self.model.loc, _IDLE_RESULT.format("the queue is empty and `if_empty`"))
            return if_empty
        return None

    def _queue_from_blackboard_410(self):
        """4.9.1's getLockedPortContent("queue"): a queue of the element type is used (and
        consumed) in place; a string is converted into a private queue once per start of the
        loop (None: keep the one converted before); anything else, or no value, throws."""
        p = self.ports.get("queue")
        key = bbmod.remapped_key("queue", p.raw) if p is not None else None
        if key is None:
            return None
        entry = self.bb.get_entry(key)
        value = entry.value if entry is not None else None
        if isinstance(value, values.Queue) and value.element_type == self.elem:
            return value
        if self.current is not None:
            return None
        if isinstance(value, str):
            try:
                return values.convert_from_string(f"queue<{self.elem}>", value, double_from_chars=True)
            except values.ConversionError as e:
                raise _run_error(
                    self.port_loc("queue"), f'port `queue` of `{self.reg_id}` "{self.name}": {e}'
                ) from None
        what = "has no value" if value is None else f"holds {values.describe(value)}"
        raise _run_error(
            self.port_loc("queue"),
            f'port `queue` of `{self.reg_id}` "{self.name}" reads blackboard entry `{key}`, which {what}: '
            f"it must hold a queue<{self.elem}> or a string",
        )

    def _queue_from_blackboard(self):
        """getLockedPortContent("queue"): the entry's own queue (popping changes the entry), or
        None when there is no entry; an entry with no value or another type makes 4.6.2 throw."""
        p = self.ports.get("queue")
        key = bbmod.remapped_key("queue", p.raw) if p is not None else None
        if key is None:
            return None
        entry = self.bb.get_entry(key)
        if entry is None:
            return None
        if entry.value is None:
            raise _run_error(
                self.port_loc("queue"),
                f'port `queue` of `{self.reg_id}` "{self.name}" reads blackboard entry `{key}`, which has no value yet',
            )
        try:
            return values.cast(entry.value, f"queue<{self.elem}>")
        except values.ConversionError as e:
            raise _run_error(self.port_loc("queue"), f'port `queue` of `{self.reg_id}` "{self.name}": {e}') from None


class EntryUpdatedDecorator(TreeNode):
    """4.6.2 ``EntryUpdatedDecorator`` (SkipUnlessUpdated, WaitValueUpdate): the child runs only when
    the entry's update counter changed since this node last looked.

    4.6.2's halt() left a RUNNING child running; as FORMAT.md asks, btgen follows
    4.9.0, whose halt() halts the child like any decorator."""

    __slots__ = ("child", "key", "seen", "still_executing", "if_not_updated")

    def __init__(self, rt, model, bb, reg_id, ports, if_not_updated: int) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.child: TreeNode = None  # type: ignore[assignment]
        p = self.ports.get("entry")
        raw = p.raw if p is not None else ""
        self.key = bbmod.strip_blackboard_pointer(raw) or raw
        self.seen = 0
        self.still_executing = False
        self.if_not_updated = if_not_updated

    # the DecoratorNode parts
    def reset_child(self) -> None:
        c = self.child
        if c.status == RUNNING:
            c.halt_node()
        c.reset_status()

    def execute_tick(self) -> int:
        status = TreeNode.execute_tick(self)
        cs = self.child.status
        if cs in (SUCCESS, FAILURE):
            self.child.reset_status()
        return status

    def halt(self) -> None:
        self.still_executing = False
        self.reset_child()
        self.reset_status()

    def _entry(self):
        return _entry_of(self)

    def consume_update(self) -> bool:
        """The entry's update counter changed since this node last looked (it looks now)."""
        entry = self._entry()
        if entry is None:
            return False
        seq = entry.sequence_id
        previous = self.seen
        self.seen = seq
        return previous != seq

    def tick(self) -> int:
        if self.still_executing:
            status = self.child.execute_tick()
            self.still_executing = status == RUNNING
            return status
        if not self.consume_update():
            return self.if_not_updated
        status = self.child.execute_tick()
        self.still_executing = status == RUNNING
        return status


class SubTreeRunNode(DecoratorNode):
    """4.6.2 ``SubTreeNode``: RUNNING before its tree's root is ticked."""

    __slots__ = ()

    def tick(self) -> int:
        if self.status == IDLE:
            self.set_status(RUNNING)
        cs = self.child.execute_tick()
        if cs in (SUCCESS, FAILURE):
            self.reset_child()
        return cs


# ================================================================ leaves
