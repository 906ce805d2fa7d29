"""Leaf nodes: 4.6.2's built-in actions and conditions (``src/actions/``) and the
scenario-scripted leaves that stand for the robot's own."""

from __future__ import annotations

from typing import Optional

from btgen.interp.tree import _TRANS, FAILURE, IDLE, RUNNING, SUCCESS, TreeNode, _entry_of, _run_error, _ScriptPort
from btgen.lang import blackboard as bbmod
from btgen.lang import values


class AlwaysNode(TreeNode):
    __slots__ = ("result",)

    def __init__(self, rt, model, bb, reg_id, ports, result: int) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.result = result

    def tick(self) -> int:
        return self.result

    def execute_tick(self) -> int:
        if self.conds:
            return self._execute_tick_with_conditions()
        new = self.result
        prev = self.status
        if prev != new:
            self.status = new
            self.emit((self.prefix, _TRANS[prev][new]))
        return new


class ScriptNode(TreeNode):
    """4.6.2 ``ScriptNode``: runs `code`, SUCCESS."""

    __slots__ = ("script",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.script = _ScriptPort(self, "code")

    def tick(self) -> int:
        self.script.run()
        return SUCCESS


class ScriptConditionNode(TreeNode):
    """4.6.2 ``ScriptCondition``: SUCCESS when `code` is true."""

    __slots__ = ("script",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.script = _ScriptPort(self, "code")

    def tick(self) -> int:
        return SUCCESS if self.script.truth() else FAILURE


class SetBlackboardNode(TreeNode):
    """``SetBlackboardNode``: writes `value` (a literal, or a copy of {key}) into `output_key`.
    A copy counts as an update (4.7.0 behaviour, as FORMAT.md asks)."""

    __slots__ = ()

    def tick(self) -> int:
        key = self.require_input("output_key", "string")
        p = self.ports.get("value")
        if p is None:
            raise _run_error(self.model.loc, f'`SetBlackboard` "{self.name}" needs port `value`')
        try:
            if self.rt.sem.setblackboard_converts_to_entry_type:
                ok = bbmod.set_blackboard_410(self.bb, str(key), p.raw)
            else:
                ok = bbmod.set_blackboard(self.bb, str(key), p.raw)
        except (values.ConversionError, bbmod.BlackboardError) as e:
            if isinstance(e, bbmod.BlackboardError) and e.stdout:
                for line in e.stdout.splitlines():  # (the library prints before it throws)
                    self.rt.write_line(line)
            raise _run_error(self.port_loc("value"), f'`SetBlackboard` "{self.name}": {e}') from None
        return SUCCESS if ok is not False else FAILURE


class UnsetBlackboardNode(TreeNode):
    """``UnsetBlackboardNode``: removes `key`; SUCCESS also when it did not exist."""

    __slots__ = ()

    def tick(self) -> int:
        key = self.require_input("key", "string")
        try:
            self.bb.unset(str(key))
        except bbmod.BlackboardError as e:
            raise _run_error(self.port_loc("key"), f'`UnsetBlackboard` "{self.name}": {e}') from None
        return SUCCESS


class WasEntryUpdatedNode(TreeNode):
    """``EntryUpdatedAction`` (WasEntryUpdated): SUCCESS when the entry's update counter changed
    since this node last looked; FAILURE otherwise or when the entry does not exist."""

    __slots__ = ("key", "seen")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        p = self.ports.get("entry")
        raw = p.raw if p is not None else ""
        self.key = bbmod.strip_blackboard_pointer(raw) or raw
        self.seen = 0

    def tick(self) -> int:
        entry = _entry_of(self)
        if entry is None:
            return FAILURE
        seq = entry.sequence_id
        previous = self.seen
        self.seen = seq
        return SUCCESS if previous != seq else FAILURE


class StatefulActionNode(TreeNode):
    """4.6.2 ``StatefulActionNode``: onStart when IDLE, onRunning when RUNNING; ticked while
    SUCCESS/FAILURE it returns that status again; halt() calls onHalted when RUNNING."""

    __slots__ = ()

    def tick(self) -> int:
        st = self.status
        if st == IDLE:
            return self.on_start()
        if st == RUNNING:
            return self.on_running()
        return st

    def halt(self) -> None:
        if self.status == RUNNING:
            self.on_halted_action()
        self.reset_status()

    def on_start(self) -> int:  # pragma: no cover
        raise NotImplementedError

    def on_running(self) -> int:  # pragma: no cover
        raise NotImplementedError

    def on_halted_action(self) -> None:
        pass


def fill_queues(node: TreeNode, fills: list[tuple[str, tuple[str, ...]]]) -> None:
    """A scenario's `queue` lines for a leaf: setOutput of a new SharedQueue<T> of the items
    into each queue port (the scenario check made sure each converts to T)."""
    for port, items in fills:
        p = node.ports.get(port)
        if p is None or p.spec is None:
            continue
        elem = values.queue_element_type(p.spec.type)
        if elem is None:
            continue
        dfc = node.rt.sem.double_from_chars
        queue = values.Queue(elem, (values.convert_from_string(elem, x, double_from_chars=dfc) for x in items))
        node.set_output(port, queue)


class ScriptedAction(StatefulActionNode):
    """A user Action: every onStart/onRunning takes the next scripted result (after setting
    the queue ports its `queue` lines name)."""

    __slots__ = ("cursor", "default", "fills")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.cursor = rt.cursor(self.name)
        self.default = rt.default
        self.fills = rt.fills.get(self.name)

    def on_start(self) -> int:
        if self.fills:
            fill_queues(self, self.fills)
        c = self.cursor
        return c.next() if c is not None else self.default

    on_running = on_start

    def execute_tick(self) -> int:
        # TreeNode::executeTick + StatefulActionNode::tick, inlined for speed
        if self.conds:
            return self._execute_tick_with_conditions()
        prev = self.status
        if prev in (IDLE, RUNNING):
            if self.fills:
                fill_queues(self, self.fills)
            c = self.cursor
            new = c.next() if c is not None else self.default
            if new != prev:
                self.status = new
                self.emit((self.prefix, _TRANS[prev][new]))
            return new
        return prev


class ScriptedCondition(TreeNode):
    """A user Condition: every tick takes the next scripted result."""

    __slots__ = ("cursor", "default", "fills")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.cursor = rt.cursor(self.name)
        self.default = rt.default
        self.fills = rt.fills.get(self.name)
        if self.cursor is None and self.default == RUNNING:
            raise _run_error(model.loc, f"Condition `{self.name}` would return RUNNING (the scenario's default)")

    def tick(self) -> int:
        if self.fills:
            fill_queues(self, self.fills)
        c = self.cursor
        st = c.next() if c is not None else self.default
        if st == RUNNING:
            raise _run_error(self.model.loc, f"Condition `{self.name}` cannot return RUNNING")
        return st

    def execute_tick(self) -> int:
        if self.conds:
            return self._execute_tick_with_conditions()
        new = self.tick()
        prev = self.status
        if new != prev:
            self.status = new
            self.emit((self.prefix, _TRANS[prev][new]))
        return new


class SleepNode(StatefulActionNode):
    """4.6.2 ``SleepNode`` on the virtual clock: SUCCESS at once for 0 ms, else RUNNING until msec
    have passed since onStart."""

    __slots__ = ("deadline",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.deadline: Optional[int] = None

    def on_start(self) -> int:
        msec = self.require_input("msec", "unsigned")
        if msec <= 0:
            return SUCCESS
        self.set_status(RUNNING)
        self.deadline = self.rt.now_ms + msec
        return RUNNING

    def on_running(self) -> int:
        if self.deadline is not None and self.rt.now_ms < self.deadline:
            return RUNNING
        self.deadline = None
        return SUCCESS

    def on_halted_action(self) -> None:
        self.deadline = None
