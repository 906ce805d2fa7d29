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


class EnvInputDecorator(DecoratorNode):
    """A Nav2 Decorator whose code reads ROS 2 for one yes-or-no fact (lang/nav2.py ENV_INPUTS):
    the scenario scripts it under the node's name as a Condition's results (SUCCESS: yes), one
    result each time the node consults it; explore branches on it as on a Condition."""

    __slots__ = ("cursor", "default")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.cursor = rt.cursor(self.name)
        self.default = rt.default

    def env(self) -> bool:
        c = self.cursor
        st = c.next() if c is not None else self.default
        if st == RUNNING:
            raise _run_error(
                self.model.loc,
                f'the input of `{self.reg_id}` "{self.name}" is yes (SUCCESS) or no (FAILURE), not RUNNING',
            )
        return st == SUCCESS


class InputsSeen:
    """A cursor that records each answer an EnvInputDecorator's input gives: (uid, status) into
    `seen` (cover counts them)."""

    __slots__ = ("inner", "node", "seen")

    def __init__(self, node: EnvInputDecorator, seen: set) -> None:
        self.inner = node.cursor
        self.node = node
        self.seen = seen

    def next(self) -> int:
        st = self.inner.next() if self.inner is not None else self.node.default
        self.seen.add((self.node.uid, st))
        return st


def record_inputs(nodes, seen: set) -> None:
    """Make every EnvInputDecorator of `nodes` record its answers into `seen`."""
    for node in nodes:
        if isinstance(node, EnvInputDecorator):
            node.cursor = InputsSeen(node, seen)


class DistanceControllerNode(EnvInputDecorator):
    """Nav2's DistanceController: on every tick the input says whether the robot is `distance`
    or more from where it was when the run started or the child last succeeded; the child is
    ticked on the first tick of a run, while it is RUNNING, and when the input says yes; else
    the node answers RUNNING. (The robot's pose is always available here: Nav2 fails when tf2
    has none.)"""

    __slots__ = ("first",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.first = False

    def tick(self) -> int:
        if self.status in (IDLE, SKIPPED):  # !isStatusActive(status())
            self.first = True
        self.set_status(RUNNING)
        far = self.env()
        if self.first or self.child.status == RUNNING or far:
            self.first = False
            return self.child.execute_tick()
        return self.status


class SpeedControllerNode(DistanceControllerNode):
    """Nav2's SpeedController: as DistanceController, the input (every tick) saying whether the
    period (1/rate, the rate set by the robot's speed between min_rate and max_rate) has passed
    since the child was last ticked for it, or the goal changed."""

    __slots__ = ()


class GoalUpdatedControllerNode(EnvInputDecorator):
    """Nav2's GoalUpdatedController: the input (every tick) says whether the goal changed; the
    child is ticked on the first tick of a run, while it is RUNNING, and when it did; else the
    node answers RUNNING."""

    __slots__ = ()

    def tick(self) -> int:
        updated = self.status in (IDLE, SKIPPED)
        self.set_status(RUNNING)
        if self.env():
            updated = True
        if self.child.status == RUNNING or updated:
            return self.child.execute_tick()
        return self.status


class PathLongerOnApproachNode(EnvInputDecorator):
    """Nav2's PathLongerOnApproach: the input (every tick) says whether a new path came that is
    much longer near the goal; then the child is ticked (a completed child is reset), except on
    the node's very first tick; otherwise the node succeeds, leaving a RUNNING child as it is."""

    __slots__ = ("first",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.first = True  # Nav2's first_time_: the node has never been ticked

    def tick(self) -> int:
        self.set_status(RUNNING)
        if self.env() and not self.first:
            cs = self.child.execute_tick()
            if cs in (SUCCESS, FAILURE):
                self.reset_child()
            return cs
        self.first = False
        return SUCCESS


class GoalUpdaterNode(DecoratorNode):
    """Nav2's GoalUpdater: ticks its child and answers as it does. No goal arrives on its topic
    in a scenario, so Nav2 would write input_goal to output_goal: btgen writes nothing there
    (a goal is a ROS message, which neither engine holds without `--type`; docs/nav2.md)."""

    __slots__ = ()

    def tick(self) -> int:
        return self.child.execute_tick()


FACTORIES = {
    "DistanceController": DistanceControllerNode,
    "SpeedController": SpeedControllerNode,
    "GoalUpdatedController": GoalUpdatedControllerNode,
    "PathLongerOnApproach": PathLongerOnApproachNode,
    "GoalUpdater": GoalUpdaterNode,
    "PipelineSequence": PipelineSequenceNode,
    "RecoveryNode": RecoveryNode,
    "RoundRobin": RoundRobinNode,
    "NonblockingSequence": NonblockingSequenceNode,
    "PersistentSequence": PersistentSequenceNode,
    "RateController": RateControllerNode,
    "SingleTrigger": SingleTriggerNode,
}
