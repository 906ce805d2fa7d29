"""Nav2's Controls and Decorators that need only BehaviorTree.CPP (lang/nav2.py), as their
recorded traces show them (tests/conformance/nav2/, recorded from Nav2's own plugins).

Time is the run's virtual clock (`Runtime.now_ms`): RateController measures the time since it
started, or since its child last succeeded, in single-precision seconds, as Nav2's
`duration<float>` does, against the double period 1/hz."""

from __future__ import annotations

import struct

from btgen.interp.controls import ControlNode
from btgen.interp.decorators import DecoratorNode
from btgen.interp.tree import FAILURE, IDLE, MISSING, RUNNING, SKIPPED, SUCCESS, _run_error
from btgen.lang.nav2 import round_robin_wraps_always


def _f32(x: float) -> float:
    return struct.unpack("f", struct.pack("f", x))[0]


def elapsed_seconds_f32(elapsed_ms: int) -> float:
    """duration_cast<duration<float>> of a nanosecond duration: float(ns) / 1e9f in float."""
    return _f32(_f32(float(elapsed_ms * 1_000_000)) / _f32(1e9))


class PipelineSequenceNode(ControlNode):
    """Ticks its children in order on every tick; a RUNNING child at or after the furthest one
    reached so far ends the tick, earlier RUNNING children are passed over."""

    __slots__ = ("last",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.last = 0

    def halt(self) -> None:
        ControlNode.halt(self)
        self.last = 0

    def tick(self) -> int:
        skipped = 0
        children = self.children
        for i, child in enumerate(children):
            cs = child.execute_tick()
            if cs == FAILURE:
                self.reset_children()
                self.last = 0
                return FAILURE
            if cs == SKIPPED:
                skipped += 1
            elif cs == RUNNING:
                if i >= self.last:
                    self.last = i
                    return RUNNING
            elif cs != SUCCESS:
                raise self._child_idle_error()
        self.reset_children()
        self.last = 0
        return SKIPPED if skipped == len(children) else SUCCESS


class RecoveryNode(ControlNode):
    """Two children: the first; when it fails (and retries are left), the second, then the
    first again. `number_of_retries` is read on every tick (a failed read keeps the last)."""

    __slots__ = ("current", "retries", "count")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.current = 0
        self.retries = 1
        self.count = 0

    def halt(self) -> None:
        ControlNode.halt(self)
        self.count = 0
        self.current = 0

    def tick(self) -> int:
        value = self.get_input("number_of_retries", "int")
        if value is not MISSING:
            self.retries = value
        self.set_status(RUNNING)
        while self.current < 2 and self.count <= self.retries:
            cs = self.children[self.current].execute_tick()
            if self.current == 0:
                if cs == SKIPPED:
                    self.halt()
                    return SKIPPED
                if cs == SUCCESS:
                    self.halt_child(1)
                    self.halt()
                    return SUCCESS
                if cs == RUNNING:
                    return RUNNING
                if cs != FAILURE:
                    raise self._child_idle_error()
                if self.count < self.retries:
                    self.halt_child(0)
                    self.current = 1
                else:
                    self.halt()
                    return FAILURE
            else:
                if cs == SKIPPED:
                    self.current = 0
                    self.halt_child(1)
                    return FAILURE
                if cs == RUNNING:
                    return RUNNING
                if cs == SUCCESS:
                    self.halt_child(1)
                    self.count += 1
                    self.current = 0
                elif cs == FAILURE:
                    self.halt()
                    return FAILURE
                else:
                    raise self._child_idle_error()
        self.halt()
        return FAILURE


class RoundRobinNode(ControlNode):
    """Ticks one child per run, from the one after the last that completed; fails when every
    child failed in a row. Before lyrical (and with wrap_around) the round goes on from the last
    child to the first; without it a round ends at the last child, whatever that child answered."""

    __slots__ = ("idx", "failed", "wrap")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.failed = 0
        if round_robin_wraps_always(rt.mission.nav2):
            self.wrap = True
        else:  # read once, when the node is created
            value = self.get_input("wrap_around", "bool")
            self.wrap = bool(value) if value is not MISSING else False

    def halt(self) -> None:
        ControlNode.halt(self)
        self.idx = 0
        self.failed = 0

    def tick(self) -> int:
        children = self.children
        n = len(children)
        self.set_status(RUNNING)
        skipped = 0
        while self.failed + skipped < n:
            cs = children[self.idx].execute_tick()
            if cs != RUNNING:
                self.idx += 1
                if self.idx == n:
                    if self.wrap:
                        self.idx = 0
                    else:
                        if cs == SKIPPED:
                            skipped += 1
                        elif cs == FAILURE:
                            self.failed += 1
                        break
            if cs == SUCCESS:
                self.failed = 0
                self.reset_children()
                return SUCCESS
            if cs == FAILURE:
                self.failed += 1
            elif cs == SKIPPED:
                skipped += 1
            elif cs == RUNNING:
                return RUNNING
            else:
                raise self._child_idle_error()
        all_skipped = skipped == n
        self.halt()
        return SKIPPED if all_skipped else FAILURE


class NonblockingSequenceNode(ControlNode):
    """Ticks every child on every tick; fails at the first failure, succeeds when all succeed
    on one tick. A SKIPPED child is an error (Nav2 throws)."""

    __slots__ = ()

    def tick(self) -> int:
        all_success = True
        for child in self.children:
            cs = child.execute_tick()
            if cs == FAILURE:
                self.reset_children()
                return FAILURE
            if cs == RUNNING:
                all_success = False
            elif cs != SUCCESS:
                raise _run_error(
                    self.model.loc,
                    f'a child of `NonblockingSequence` "{self.name}" returned {_NAMES[cs]}, which Nav2 forbids',
                )
        if all_success:
            self.reset_children()
            return SUCCESS
        return RUNNING


_NAMES = {IDLE: "IDLE", SKIPPED: "SKIPPED", RUNNING: "RUNNING", SUCCESS: "SUCCESS", FAILURE: "FAILURE"}


class PersistentSequenceNode(ControlNode):
    """A sequence whose place is the `current_child_idx` entry: read on every tick, written
    after each child that completes (0 after a failure or the last child)."""

    __slots__ = ()

    def tick(self) -> int:
        idx = self.get_input("current_child_idx", "int")
        if idx is MISSING:
            raise _run_error(
                self.port_loc("current_child_idx"),
                f'`PersistentSequence` "{self.name}": cannot read `current_child_idx` (Nav2 throws); '
                f'set it first, e.g. <Script code="current_child_idx := 0"/>',
            )
        n = len(self.children)
        if idx < 0:
            raise _run_error(
                self.port_loc("current_child_idx"),
                f'`PersistentSequence` "{self.name}": `current_child_idx` is {idx}, not a child',
            )
        self.set_status(RUNNING)
        while idx < n:
            cs = self.children[idx].execute_tick()
            if cs == RUNNING:
                return RUNNING
            if cs == FAILURE:
                self.reset_children()
                self.set_output("current_child_idx", 0, "int")
                return FAILURE
            if cs not in (SUCCESS, SKIPPED):
                raise self._child_idle_error()
            idx += 1
            self.set_output("current_child_idx", idx, "int")
        self.reset_children()
        self.set_output("current_child_idx", 0, "int")
        return SUCCESS


class RateControllerNode(DecoratorNode):
    """Ticks the child when it starts (from IDLE), while the child is RUNNING, and when a period
    (1/hz s) has passed since it started or the child last succeeded; else answers RUNNING."""

    __slots__ = ("start", "period", "first")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.start = 0
        self.period = 1.0
        self.first = False

    def tick(self) -> int:
        if self.status == IDLE:
            hz = self.get_input("hz", "double")
            hz = 1.0 if hz is MISSING else float(hz)  # (a failed read keeps Nav2's local 1.0)
            self.period = 1.0 / hz if hz != 0.0 else float("inf")
            self.start = self.rt.now_ms
            self.first = True
        self.set_status(RUNNING)
        seconds = elapsed_seconds_f32(self.rt.now_ms - self.start)
        if self.first or self.child.status == RUNNING or seconds >= self.period:
            self.first = False
            cs = self.child.execute_tick()
            if cs == SUCCESS:
                self.start = self.rt.now_ms
            return cs
        return self.status


class SingleTriggerNode(DecoratorNode):
    """Ticks its child until it completes once; while the node stays active afterwards it fails."""

    __slots__ = ("first",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.first = True

    def tick(self) -> int:
        if self.status == IDLE:
            self.first = True
        self.set_status(RUNNING)
        if self.first:
            cs = self.child.execute_tick()
            if cs in (SUCCESS, FAILURE):
                self.first = False
            return cs
        return FAILURE


FACTORIES = {
    "PipelineSequence": PipelineSequenceNode,
    "RecoveryNode": RecoveryNode,
    "RoundRobin": RoundRobinNode,
    "NonblockingSequence": NonblockingSequenceNode,
    "PersistentSequence": PersistentSequenceNode,
    "RateController": RateControllerNode,
    "SingleTrigger": SingleTriggerNode,
}
