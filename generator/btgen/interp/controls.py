"""Control nodes as in BehaviorTree.CPP 4.6.2's ``src/controls/``: sequences, fallbacks,
Parallel, IfThenElse, WhileDoElse and Switch."""

from __future__ import annotations

from typing import Optional

from btgen.interp.tree import _TRANS, FAILURE, IDLE, MISSING, RUNNING, SKIPPED, SUCCESS, RunError, TreeNode, _run_error


class ControlNode(TreeNode):
    """4.6.2 ``ControlNode``: halt() resets the children (halting the RUNNING ones), then itself."""

    __slots__ = ("children",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.children: list[TreeNode] = []

    def halt(self) -> None:
        self.reset_children()
        self.reset_status()

    def reset_children(self) -> None:
        for c in self.children:
            st = c.status
            if st == RUNNING:
                c.halt_node()
                c.reset_status()
            elif st != IDLE:  # resetStatus(), inlined: this is the hottest loop of a run
                c.status = IDLE
                c.emit((c.prefix, _TRANS[st][IDLE]))

    def halt_child(self, i: int) -> None:
        c = self.children[i]
        if c.status == RUNNING:
            c.halt_node()
        c.reset_status()

    def _child_idle_error(self) -> RunError:
        return _run_error(self.model.loc, f'a child of `{self.reg_id}` "{self.name}" returned IDLE')


class _FirstDecidingChildNode(ControlNode):
    """The loop 4.6.2's ``SequenceNode`` and ``FallbackNode`` share, with the roles of SUCCESS
    and FAILURE swapped: children are ticked in order from the current one; a child returning
    ``DECIDES`` ends the node with that status (children reset), ``GOES_ON`` moves to the
    next child, and the node returns ``GOES_ON`` when all have.

    The Async variants (``make_async``) return RUNNING after a child that was IDLE completes,
    so the next child runs on the next tick. SKIPPED follows 4.6.2's member flag
    ``all_skipped_``: set when the node is ticked from IDLE, cleared by any child that does not
    return SKIPPED, never reset when the loop completes. (4.7.0 counts skipped children
    instead; the results differ when a child that was RUNNING is later skipped by ``_while``,
    and when a completed node is ticked again.)"""

    __slots__ = ("idx", "all_skipped", "asynch", "by_count", "skipped")
    DECIDES = FAILURE
    GOES_ON = SUCCESS

    def __init__(self, rt, model, bb, reg_id, ports, asynch: bool = False) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.all_skipped = True
        self.asynch = asynch
        # versions.py skipped_by_count: SKIPPED when every child was skipped in this run
        self.by_count = rt.sem.skipped_by_count
        self.skipped = 0

    def halt(self) -> None:
        self.idx = 0
        self.skipped = 0
        ControlNode.halt(self)

    def tick(self) -> int:
        decides, goes_on = self.DECIDES, self.GOES_ON
        children = self.children
        n = len(children)
        st = self.status
        if st == IDLE:
            self.all_skipped = True
            self.skipped = 0
        if st != RUNNING:  # setStatus(RUNNING)
            self.status = RUNNING
            self.emit((self.prefix, _TRANS[st][RUNNING]))
        idx = self.idx
        while idx < n:
            child = children[idx]
            prev = child.status
            cs = child.execute_tick()
            if cs != SKIPPED:
                self.all_skipped = False
            if cs == RUNNING:
                self.idx = idx
                return RUNNING
            if cs == decides:
                self.reset_children()
                self.idx = 0
                return decides
            if cs == goes_on:
                idx += 1
                # every node has a wake-up signal in a Tree, so requiresWakeUp() holds
                if self.asynch and prev == IDLE and idx < n:
                    self.idx = idx
                    return RUNNING
            elif cs == SKIPPED:
                idx += 1
                self.skipped += 1
            else:
                self.idx = idx
                raise self._child_idle_error()
        self.idx = idx
        all_skipped = self.skipped == n if self.by_count else self.all_skipped
        if idx == n:
            self.reset_children()
            self.idx = 0
            self.skipped = 0
        return SKIPPED if all_skipped else goes_on


class SequenceNode(_FirstDecidingChildNode):
    """4.6.2 ``SequenceNode`` (Sequence, and AsyncSequence): the first FAILURE decides."""

    __slots__ = ()
    DECIDES = FAILURE
    GOES_ON = SUCCESS


class FallbackNode(_FirstDecidingChildNode):
    """4.6.2 ``FallbackNode`` (Fallback, and AsyncFallback): the first SUCCESS decides."""

    __slots__ = ()
    DECIDES = SUCCESS
    GOES_ON = FAILURE


class SequenceWithMemoryNode(ControlNode):
    """4.6.2 ``SequenceWithMemory``: a FAILURE halts the children from the current one on but
    keeps the index; halt() keeps it too. SKIPPED as in SequenceNode (``all_skipped_``)."""

    __slots__ = ("idx", "all_skipped", "by_count", "skipped")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.all_skipped = True
        self.by_count = rt.sem.skipped_by_count
        self.skipped = 0

    def tick(self) -> int:
        children = self.children
        n = len(children)
        if self.status == IDLE:
            self.all_skipped = True
            self.skipped = 0
        self.set_status(RUNNING)
        while self.idx < n:
            child = children[self.idx]
            prev = child.status
            cs = child.execute_tick()
            if cs != SKIPPED:
                self.all_skipped = False
            if cs == RUNNING:
                return RUNNING
            if cs == FAILURE:
                for i in range(self.idx, n):
                    self.halt_child(i)
                return FAILURE
            if cs == SUCCESS:
                self.idx += 1
                if prev == IDLE and self.idx < n:  # wake-up rule
                    return RUNNING
            elif cs == SKIPPED:
                self.idx += 1
                self.skipped += 1
            else:
                raise self._child_idle_error()
        all_skipped = self.skipped == n if self.by_count else self.all_skipped
        if self.idx == n:
            self.reset_children()
            self.idx = 0
            self.skipped = 0
        return SKIPPED if all_skipped else SUCCESS


class TryCatchNode(ControlNode):
    """4.9.0 ``TryCatchNode`` (versions.py trycatch): the children but the last run as a
    Sequence; on a FAILURE they are reset and the last (catch) child runs until it completes,
    then the node returns FAILURE. With ``catch_on_halt`` a halt in the try block ticks the
    catch child once (halting it if RUNNING)."""

    __slots__ = ("idx", "skipped", "in_catch")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.skipped = 0
        self.in_catch = False

    def halt(self) -> None:
        catch_on_halt = self.get_input("catch_on_halt", "bool")
        n = len(self.children)
        if catch_on_halt is True and not self.in_catch and self.status == RUNNING and n >= 2:
            for i in range(n - 1):
                self.halt_child(i)
            if self.children[-1].execute_tick() == RUNNING:
                self.halt_child(n - 1)
        self.idx = 0
        self.skipped = 0
        self.in_catch = False
        ControlNode.halt(self)

    def tick(self) -> int:
        children = self.children
        n = len(children)
        if self.status == IDLE:
            self.skipped = 0
            self.in_catch = False
        self.set_status(RUNNING)
        while True:
            if self.in_catch:
                cs = children[-1].execute_tick()
                if cs == RUNNING:
                    return RUNNING
                self.reset_children()
                self.idx = 0
                self.in_catch = False
                return FAILURE
            tries = n - 1
            while self.idx < tries:
                cs = children[self.idx].execute_tick()
                if cs == RUNNING:
                    return RUNNING
                if cs == FAILURE:
                    self.reset_children()
                    self.idx = 0
                    self.in_catch = True
                    break
                if cs == SUCCESS:
                    self.idx += 1
                elif cs == SKIPPED:
                    self.idx += 1
                    self.skipped += 1
                else:
                    raise self._child_idle_error()
            else:
                all_skipped = self.skipped == tries
                self.reset_children()
                self.idx = 0
                self.skipped = 0
                return SKIPPED if all_skipped else SUCCESS


class _ReactiveNode(ControlNode):
    """4.6.2 ``ReactiveSequence`` and ``ReactiveFallback``: every child from the first, every
    tick; a RUNNING child halts all the others; the first child that returns ``DECIDES``
    decides, and when none does the node returns ``OTHERWISE``."""

    __slots__ = ()
    DECIDES = FAILURE
    OTHERWISE = SUCCESS

    def tick(self) -> int:
        all_skipped = True
        self.set_status(RUNNING)
        children = self.children
        n = len(children)
        for index in range(n):
            cs = children[index].execute_tick()
            if cs != SKIPPED:
                all_skipped = False
            if cs == RUNNING:
                for i in range(n):
                    if i != index:
                        self.halt_child(i)
                return RUNNING
            if cs == self.DECIDES:
                self.reset_children()
                return cs
            if cs == SKIPPED:
                self.halt_child(index)
            elif cs != self.OTHERWISE:
                raise self._child_idle_error()
        self.reset_children()
        return SKIPPED if all_skipped else self.OTHERWISE


class ReactiveSequenceNode(_ReactiveNode):
    """4.6.2 ``ReactiveSequence``: a FAILURE decides."""

    __slots__ = ()
    DECIDES = FAILURE
    OTHERWISE = SUCCESS


class ReactiveFallbackNode(_ReactiveNode):
    """4.6.2 ``ReactiveFallback``: a SUCCESS decides."""

    __slots__ = ()
    DECIDES = SUCCESS
    OTHERWISE = FAILURE


def _threshold(value: int, n: int) -> int:
    """ParallelNode::successThreshold / failureThreshold: negative counts from the number of children."""
    return max(n + value + 1, 0) if value < 0 else value


class ParallelNode(ControlNode):
    """4.6.2 ``ParallelNode``: finished children are not ticked again; the thresholds are checked
    after every child."""

    __slots__ = ("completed", "success_count", "failure_count")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.completed: set[int] = set()
        self.success_count = 0
        self.failure_count = 0

    def clear(self) -> None:
        self.completed.clear()
        self.success_count = 0
        self.failure_count = 0

    def halt(self) -> None:
        self.clear()
        ControlNode.halt(self)

    def tick(self) -> int:
        success_threshold = self.require_input("success_count", "int")
        failure_threshold = self.require_input("failure_count", "int")
        children = self.children
        n = len(children)
        required_success = _threshold(success_threshold, n)
        required_failure = _threshold(failure_threshold, n)
        if n < required_success:
            raise _run_error(
                self.port_loc("success_count"),
                f'`Parallel` "{self.name}" needs {required_success} successes but has only '
                f"{n} children: it can never succeed",
            )
        if n < required_failure:
            raise _run_error(
                self.port_loc("failure_count"),
                f'`Parallel` "{self.name}" fails after {required_failure} failures but has only '
                f"{n} children: it can never fail",
            )
        self.set_status(RUNNING)
        skipped = 0
        completed = self.completed
        for i in range(n):
            if i not in completed:
                cs = children[i].execute_tick()
                if cs == SKIPPED:
                    skipped += 1
                elif cs == SUCCESS:
                    completed.add(i)
                    self.success_count += 1
                elif cs == FAILURE:
                    completed.add(i)
                    self.failure_count += 1
                elif cs != RUNNING:
                    raise self._child_idle_error()
            if self.success_count >= required_success or (
                success_threshold < 0 and self.success_count + skipped >= required_success
            ):
                self.clear()
                self.reset_children()
                return SUCCESS
            if n - self.failure_count < required_success or self.failure_count == required_failure:
                self.clear()
                self.reset_children()
                return FAILURE
        return SKIPPED if skipped == n else RUNNING


class ParallelAllNode(ControlNode):
    """4.6.2 ``ParallelAllNode``: waits for every child; FAILURE when failures reach max_failures."""

    __slots__ = ("completed", "failure_count")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.completed: set[int] = set()
        self.failure_count = 0

    def halt(self) -> None:
        self.completed.clear()
        self.failure_count = 0
        ControlNode.halt(self)

    def tick(self) -> int:
        max_failures = self.require_input("max_failures", "int")
        children = self.children
        n = len(children)
        threshold = _threshold(max_failures, n)
        if n < threshold:
            raise _run_error(
                self.port_loc("max_failures"),
                f'`ParallelAll` "{self.name}" fails after {threshold} failures but has only '
                f"{n} children: it can never fail",
            )
        skipped = 0
        self.set_status(RUNNING)
        completed = self.completed
        for i in range(n):
            if i in completed:
                continue
            cs = children[i].execute_tick()
            if cs == SUCCESS:
                completed.add(i)
            elif cs == FAILURE:
                completed.add(i)
                self.failure_count += 1
            elif cs == SKIPPED:
                skipped += 1
            elif cs != RUNNING:
                raise self._child_idle_error()
        if skipped == n:
            return SKIPPED
        if skipped + len(completed) >= n:
            for i in range(n):
                self.halt_child(i)
            completed.clear()
            status = FAILURE if self.failure_count >= threshold else SUCCESS
            self.failure_count = 0
            return status
        return RUNNING


class IfThenElseNode(ControlNode):
    """4.6.2 ``IfThenElseNode``: the condition is not re-evaluated while a branch is RUNNING.
    A SKIPPED condition makes the library throw; btgen reports it as a run-time error."""

    __slots__ = ("child_idx",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.child_idx = 0

    def halt(self) -> None:
        self.child_idx = 0
        ControlNode.halt(self)

    def tick(self) -> int:
        children = self.children
        n = len(children)
        self.set_status(RUNNING)
        if self.child_idx == 0:
            cond = children[0].execute_tick()
            if cond == RUNNING:
                return RUNNING
            if cond == SUCCESS:
                self.child_idx = 1
            elif cond == FAILURE:
                if n == 3:
                    self.child_idx = 2
                else:
                    return FAILURE
            else:
                raise _skipped_condition_error(self, children[0])
        status = children[self.child_idx].execute_tick()
        if status == RUNNING:
            return RUNNING
        self.reset_children()
        self.child_idx = 0
        return status


class WhileDoElseNode(ControlNode):
    """4.6.2 ``WhileDoElseNode``: the condition every tick; switching branch halts the other one."""

    __slots__ = ()

    def tick(self) -> int:
        children = self.children
        n = len(children)
        self.set_status(RUNNING)
        cond = children[0].execute_tick()
        if cond == RUNNING:
            return RUNNING
        if cond == SUCCESS:
            if n == 3:
                self.halt_child(2)
            status = children[1].execute_tick()
        elif cond == FAILURE:
            if n == 3:
                self.halt_child(1)
                status = children[2].execute_tick()
            else:
                status = FAILURE
        else:
            # The library resets the children, then throws (its status would become IDLE).
            self.reset_children()
            raise _skipped_condition_error(self, children[0])
        if status == RUNNING:
            return RUNNING
        self.reset_children()
        return status


def _skipped_condition_error(node: TreeNode, cond: TreeNode) -> RunError:
    return _run_error(
        cond.model.loc,
        f"the condition of this `{node.reg_id}` returned SKIPPED, which makes BehaviorTree.CPP throw "
        f"(a condition child must not be skippable)",
    )


def _to_int_prefix(text: str, whole: bool = False) -> Optional[int]:
    """std::from_chars<int> as SwitchNode uses it: an optional '-', digits; the rest is ignored
    (``whole``: 4.10.0 needs the digits to be the whole text)."""
    i = 0
    if i < len(text) and text[i] == "-":
        i += 1
    j = i
    while j < len(text) and "0" <= text[j] <= "9":
        j += 1
    if j == i or (whole and j != len(text)):
        return None
    value = int(text[:j])
    if value < -(2**31) or value > 2**31 - 1:
        return None
    return value


_FLOAT_RE = None


def _to_real_prefix(text: str, whole: bool = False) -> Optional[float]:
    """std::from_chars<double> (general format): the longest prefix that is a number, inf or nan."""
    global _FLOAT_RE
    if _FLOAT_RE is None:
        import re

        _FLOAT_RE = re.compile(
            r"-?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|inf(?:inity)?|nan(?:\([0-9A-Za-z_]*\))?)",
            re.IGNORECASE,
        )
    m = _FLOAT_RE.match(text)
    if not m or (whole and m.end() != len(text)):
        return None
    try:
        value = float(m.group(0))
    except ValueError:
        return None
    if value in (float("inf"), float("-inf")) and "inf" not in m.group(0).lower():
        return None  # out of range: from_chars reports an error
    return value


def switch_equal(v1: str, v2: str, whole: bool = False) -> bool:
    """SwitchNode's CheckStringEquality: as text, then as integers, then as reals; 4.6.2 reads
    a number from the start of the text, 4.10.0 (``whole``, versions.py switch_whole_parse)
    only from the whole of it."""
    if v1 == v2:
        return True
    i1, i2 = _to_int_prefix(v1, whole), _to_int_prefix(v2, whole)
    if i1 is not None and i2 is not None and i1 == i2:
        return True
    r1, r2 = _to_real_prefix(v1, whole), _to_real_prefix(v2, whole)
    return bool(r1 is not None and r2 is not None and abs(r1 - r2) <= 1.1920928955078125e-07)


class SwitchNode(ControlNode):
    """4.6.2 ``SwitchNode<N>``: no RUNNING before the selected child is ticked; a change of case halts
    the one that was running."""

    __slots__ = ("cases", "running_child")

    def __init__(self, rt, model, bb, reg_id, ports, cases: int) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.cases = cases
        self.running_child = -1

    def halt(self) -> None:
        self.running_child = -1
        ControlNode.halt(self)

    def select(self) -> int:
        """The child to tick: the first case equal to `variable`, else the default (the last)."""
        match = self.cases
        variable = self.get_input("variable", "string")
        if variable is not MISSING:
            for index in range(self.cases):
                value = self.get_input(f"case_{index + 1}", "string")
                if value is not MISSING and switch_equal(variable, value, self.rt.sem.switch_whole_parse):
                    match = index
                    break
        return match

    def tick(self) -> int:
        match = self.select()
        if self.running_child != -1 and self.running_child != match:
            self.halt_child(self.running_child)
        ret = self.children[match].execute_tick()
        if ret == SKIPPED:
            self.running_child = -1
            return SKIPPED
        if ret == RUNNING:
            self.running_child = match
        else:
            self.reset_children()
            self.running_child = -1
        return ret


# ================================================================ decorators
