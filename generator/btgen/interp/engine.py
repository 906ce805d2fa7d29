"""The reference interpreter: runs a checked mission with BehaviorTree.CPP 4.6.2 semantics.

It builds one object per node, the way 4.6.2's ``XMLParser`` does (SubTrees
instantiated recursively, UIDs in creation order, one blackboard per tree
instance), and walks the tree with parents ticking and halting children as
4.6.2's node classes do. Every status change goes to an observer that writes
the trace lines of ``shared/conformance/FORMAT.md``.

Each class below follows one 4.6.2 source (named in its docstring); where
4.6.2 has a bug that later releases fixed and FORMAT.md says to follow the
later behaviour, the comment says so.

Leaves declared in TreeNodesModel take their results from a scenario: an
Action behaves as a ``StatefulActionNode`` (a result is taken in ``onStart``
and ``onRunning``), a Condition takes one every tick. Time (Sleep, Delay,
Timeout) comes from a virtual clock: 4.6.2's timer threads become deadlines
checked when the node is ticked, so a run never sleeps.

Statuses are kept as the small integers of ``NodeStatus`` (``.value``) inside
the hot paths and converted at the edges: a tick of a 10,000-node tree visits
every node, and an Enum hash per status change would cost seconds.

Nothing here is shared with the C++ back end: the interpreter walks the
model (model.py) directly.
"""
from __future__ import annotations

import sys
from typing import Callable, Optional

from btgen.lang import blackboard as bbmod
from btgen.lang import script as scriptmod
from btgen.lang import values
from btgen.lang.catalogue import BUILTINS, PortSpec
from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.lang.model import Attr, Mission, Node, SubTreeNode
from btgen.interp.scenario import Scenario
from btgen.lang.leaves import is_scripted_leaf, leaf_kind, user_node_kind, user_node_message
from btgen.lang.status import NodeStatus

# ---------------------------------------------------------------- statuses
IDLE = NodeStatus.IDLE.value
RUNNING = NodeStatus.RUNNING.value
SUCCESS = NodeStatus.SUCCESS.value
FAILURE = NodeStatus.FAILURE.value
SKIPPED = NodeStatus.SKIPPED.value
_BY_VALUE = {s.value: s for s in NodeStatus}
_NAMES = {s.value: s.name for s in NodeStatus}
# "FROM -> TO\n" for every pair, indexed [from][to]; a trace line is a node's prefix and one of these
_TRANS = tuple(tuple(f"{_NAMES.get(a, '?')} -> {_NAMES.get(b, '?')}\n" for b in range(5)) for a in range(5))
_STATUS_OF_TEXT = {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING}


def status_enum(value: int) -> NodeStatus:
    return _BY_VALUE[value]


def quote_name(name: str) -> str:
    """A node name as the trace writes it, quotes included (FORMAT.md)."""
    out = ['"']
    for ch in name:
        o = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\r":
            out.append("\\r")
        elif ch == "\t":
            out.append("\\t")
        elif o < 0x20 or o == 0x7F:
            out.append(f"\\x{o:02x}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


MISSING = object()  # a port read that failed the way 4.6.2's getInput fails (no throw)


class RunError(UserError):
    """A problem found while running (a script error, a bad value in a port...)."""


def _run_error(loc: Loc, message: str) -> RunError:
    return RunError(Diagnostic(loc, message))


_FILE_LINES: dict[str, list[str]] = {}


def _raw_attr_value(value_loc: Loc) -> Optional[str]:
    """The attribute value as written in the file (entity references undecoded), for positions
    inside it; None when the file cannot be read again."""
    lines = _FILE_LINES.get(value_loc.path)
    if lines is None:
        try:
            with open(value_loc.path, encoding="utf-8-sig") as f:
                lines = f.read().split("\n")
        except (OSError, UnicodeDecodeError):
            return None
        _FILE_LINES[value_loc.path] = lines
    if not 1 <= value_loc.line <= len(lines):
        return None
    line = lines[value_loc.line - 1]
    start = value_loc.col - 1
    if start < 1 or start > len(line) or line[start - 1] not in "\"'":
        return None
    quote = line[start - 1]
    text = "\n".join([line[start:]] + lines[value_loc.line:])
    end = text.find(quote)
    return text[:end] if end >= 0 else None


# ---------------------------------------------------------------- the run context
class _Cursor:
    """The scripted results of one leaf name, shared by all its instances."""

    __slots__ = ("statuses", "i")

    def __init__(self, statuses: tuple[int, ...]) -> None:
        self.statuses = statuses
        self.i = 0

    def next(self) -> int:
        i = self.i
        if i < len(self.statuses):
            self.i = i + 1
            return self.statuses[i]
        return self.statuses[-1]


class Runtime:
    """What all nodes of one run share: the trace output, the clock, the scenario."""

    def __init__(self, mission: Mission, scenario: Optional[Scenario]) -> None:
        self.mission = mission
        self.enums = dict(mission.enums)  # registerScriptingEnum (enums.py)
        # The trace so far, as pieces: whole lines ("tick 3\n") or a node's prefix followed by its
        # "FROM -> TO\n". Pieces are cheaper to collect than joined lines, and a run of 10,000
        # nodes makes some 26,000 of them per tick.
        self.buf: list[str] = []
        self.emit: Callable[[tuple[str, str]], None] = self.buf.extend
        self.now_ms = 0
        self.default = _STATUS_OF_TEXT[scenario.default] if scenario else SUCCESS
        self.cursors: dict[str, _Cursor] = {}
        if scenario is not None:
            for s in scenario.leaves:
                self.cursors[s.name] = _Cursor(tuple(_STATUS_OF_TEXT[t] for t in s.statuses))
        self.uid = 0

    def write_line(self, line: str) -> None:
        self.buf.append(line + "\n")

    def take_text(self) -> str:
        text = "".join(self.buf)
        self.buf.clear()
        return text

    def cursor(self, name: str) -> Optional[_Cursor]:
        return self.cursors.get(name)

    def next_uid(self) -> int:
        self.uid += 1
        return self.uid


# ---------------------------------------------------------------- data access
class _Port:
    """A port of one node instance: the text written for it (or its default) and its spec."""

    __slots__ = ("name", "raw", "attr", "spec")

    def __init__(self, name: str, raw: str, attr: Optional[Attr], spec: Optional[PortSpec]) -> None:
        self.name = name
        self.raw = raw
        self.attr = attr
        self.spec = spec


class TreeNode:
    """4.6.2 ``TreeNode``: executeTick with pre/post conditions, setStatus, resetStatus, haltNode."""

    __slots__ = ("uid", "reg_id", "name", "status", "prefix", "emit", "rt", "model", "bb", "ports",
                 "conds", "pre", "on_halted", "on_success", "on_failure", "post_always")

    def __init__(self, rt: Runtime, model: Node, bb, reg_id: str, ports: Optional[dict] = None) -> None:
        self.uid = rt.next_uid()
        self.reg_id = reg_id
        self.name = model.display_name
        self.status = IDLE
        self.prefix = f"{self.uid} {reg_id} {quote_name(self.name)} "
        self.emit = rt.emit
        self.rt = rt
        self.model = model
        self.bb = bb
        self.ports: dict[str, _Port] = ports if ports is not None else {}
        # Pre-conditions in 4.6.2's PreCond order: _failureIf, _successIf, _skipIf, _while.
        pre = []
        for kind in ("_failureIf", "_successIf", "_skipIf", "_while"):
            a = model.pre_condition(kind)
            if a is not None:
                pre.append((kind, a))
        self.pre = tuple(pre)
        self.on_halted = model.post_condition("_onHalted")
        self.on_success = model.post_condition("_onSuccess")
        self.on_failure = model.post_condition("_onFailure")
        self.post_always = model.post_condition("_post")
        self.conds = bool(self.pre) or self.on_success is not None or self.on_failure is not None \
            or self.post_always is not None

    # -- status
    def set_status(self, new: int) -> None:
        prev = self.status
        if prev != new:
            self.status = new
            self.emit((self.prefix, _TRANS[prev][new]))

    def reset_status(self) -> None:
        prev = self.status
        if prev != IDLE:
            self.status = IDLE
            self.emit((self.prefix, _TRANS[prev][IDLE]))

    # -- ticking
    def execute_tick(self) -> int:
        """TreeNode::executeTick: pre-conditions may replace tick(); post-conditions on completion;
        a SKIPPED result is returned to the parent but never stored."""
        if self.conds:
            return self._execute_tick_with_conditions()
        new = self.tick()
        if new != SKIPPED:
            prev = self.status
            if prev != new:
                if new == IDLE:
                    raise self._idle_error()
                self.status = new
                self.emit((self.prefix, _TRANS[prev][new]))
        return new

    def _execute_tick_with_conditions(self) -> int:
        new = self._check_pre_conditions()
        if new is None:
            new = self.tick()
        if new == SUCCESS or new == FAILURE:
            self._check_post_conditions(new)
        if new != SKIPPED:
            if new == IDLE:
                raise self._idle_error()
            self.set_status(new)
        return new

    def _idle_error(self) -> RunError:
        return _run_error(self.model.loc, f"`{self.reg_id}` \"{self.name}\" returned IDLE, which "
                                          f"BehaviorTree.CPP forbids")

    def _check_pre_conditions(self) -> Optional[int]:
        """TreeNode::checkPreConditions (4.6.2): all of them when IDLE, only _while when RUNNING."""
        st = self.status
        if st == IDLE or st == SKIPPED:
            for kind, attr in self.pre:
                if self.truth(attr):
                    if kind == "_failureIf":
                        return FAILURE
                    if kind == "_successIf":
                        return SUCCESS
                    if kind == "_skipIf":
                        return SKIPPED
                elif kind == "_while":
                    return SKIPPED
        elif st == RUNNING:
            for kind, attr in self.pre:
                if kind == "_while" and not self.truth(attr):
                    self.halt_node()
                    return SKIPPED
        return None

    def _check_post_conditions(self, status: int) -> None:
        """TreeNode::checkPostConditions: _onSuccess or _onFailure, then _post."""
        if status == SUCCESS:
            if self.on_success is not None:
                self.run_script(self.on_success)
        elif status == FAILURE:
            if self.on_failure is not None:
                self.run_script(self.on_failure)
        if self.post_always is not None:
            self.run_script(self.post_always)

    def tick(self) -> int:  # pragma: no cover - every class overrides it
        raise NotImplementedError

    def halt(self) -> None:
        """Leaves that cannot be RUNNING (SyncActionNode, ConditionNode): just reset."""
        self.reset_status()

    def halt_node(self) -> None:
        """TreeNode::haltNode: halt(), then the _onHalted script."""
        self.halt()
        if self.on_halted is not None:
            self.run_script(self.on_halted)

    # -- scripts and ports (the data layer lives in blackboard.py, script.py, values.py)
    def run_script(self, attr: Attr, parsed=None, from_blackboard: bool = False):
        """Run the script of `attr` (or `parsed`, a script read at run time) on the node's blackboard."""
        code = parsed if parsed is not None else attr.script
        if code is None:
            code = self._parse_at_run_time(attr, attr.value)
            from_blackboard = True
        try:
            return scriptmod.evaluate(code, self.bb, self.rt.enums)
        except scriptmod.ScriptRuntimeError as e:
            raise self._script_error(attr, e.message, e.offset, from_blackboard) from None
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise self._script_error(attr, str(e), 0, True) from None

    def truth(self, attr: Attr, parsed=None, from_blackboard: bool = False) -> bool:
        """The script's result as a condition (4.6.2: ``cast<bool>()`` of it)."""
        value = self.run_script(attr, parsed, from_blackboard)
        try:
            return scriptmod.script_truth(value)
        except scriptmod.ScriptRuntimeError as e:
            raise self._script_error(attr, e.message, 0, True) from None

    def _script_error(self, attr: Attr, message: str, offset: int, at_start: bool) -> RunError:
        loc = attr.value_loc
        if not at_start and offset > 0:
            loc = scriptmod.script_error_loc(attr.value_loc, attr.value, offset, _raw_attr_value(attr.value_loc))
        return _run_error(loc, f"script error in `{attr.name}` of `{self.reg_id}` \"{self.name}\": {message}")

    def _parse_at_run_time(self, attr: Attr, text: str):
        try:
            return scriptmod.parse_script(text)
        except scriptmod.ScriptSyntaxError as e:
            raise _run_error(attr.value_loc, f"`{attr.name}` of `{self.reg_id}` \"{self.name}\" reads the script "
                                             f"`{text}`, which is invalid: {e.message}") from None

    def port_loc(self, name: str) -> Loc:
        p = self.ports.get(name)
        if p is not None and p.attr is not None:
            return p.attr.value_loc
        return self.model.loc

    def get_input(self, name: str, type_name: Optional[str] = None):
        """TreeNode::getInput<T>: the literal converted to the port's type, or the entry's value.

        Returns ``MISSING`` when 4.6.2's getInput would fail without
        throwing (no such port, entry missing or empty)."""
        p = self.ports.get(name)
        if p is None:
            return MISSING
        t = type_name or (p.spec.type if p.spec is not None else "any")
        try:
            return bbmod.get_input(self.bb, p.raw, t, port_name=name)
        except (values.ConversionError, bbmod.BlackboardError):
            return MISSING  # 4.6.2's getInput returns an error, it does not throw

    def require_input(self, name: str, type_name: Optional[str] = None):
        """getInput of a port the node cannot work without: 4.6.2 throws when it fails."""
        p = self.ports.get(name)
        if p is None:
            raise _run_error(self.model.loc, f"`{self.reg_id}` \"{self.name}\" needs port `{name}`")
        t = type_name or (p.spec.type if p.spec is not None else "any")
        try:
            return bbmod.get_input(self.bb, p.raw, t, port_name=name)
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(self.port_loc(name), f"`{self.reg_id}` \"{self.name}\": {e}") from None

    def set_output(self, name: str, value, type_name: Optional[str] = None) -> bool:
        """TreeNode::setOutput: a port not written, or written as a literal, is not set
        (4.6.2 returns an error that the built-in nodes ignore)."""
        p = self.ports.get(name)
        if p is None or bbmod.remapped_key(name, p.raw) is None:
            return False
        t = type_name or (p.spec.type if p.spec is not None else "any")
        try:
            bbmod.set_output(self.bb, p.raw, value, t, port_name=name)
            return True
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(self.port_loc(name), f"`{self.reg_id}` \"{self.name}\": {e}") from None

    def status_input(self, name: str) -> int:
        value = self.require_input(name, "NodeStatus")
        if isinstance(value, NodeStatus):
            return value.value
        raise _run_error(self.port_loc(name), f"port `{name}` of `{self.reg_id}` \"{self.name}\": "
                                              f"`{value}` is not a NodeStatus")


# ================================================================ controls
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
        return _run_error(self.model.loc, f"a child of `{self.reg_id}` \"{self.name}\" returned IDLE")


class SequenceNode(ControlNode):
    """4.6.2 ``SequenceNode`` (Sequence, and AsyncSequence with make_async).

    SKIPPED follows 4.6.2's member flag ``all_skipped_``: set when the node is ticked from
    IDLE, cleared by any child that does not return SKIPPED, never reset when the loop
    completes. (4.7.0 counts skipped children instead; the results differ when a child that
    was RUNNING is later skipped by ``_while``, and when a completed node is ticked again.)"""

    __slots__ = ("idx", "all_skipped", "asynch")

    def __init__(self, rt, model, bb, reg_id, ports, asynch: bool = False) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.all_skipped = True
        self.asynch = asynch

    def halt(self) -> None:
        self.idx = 0
        ControlNode.halt(self)

    def tick(self) -> int:
        children = self.children
        n = len(children)
        st = self.status
        if st == IDLE:
            self.all_skipped = True
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
            if cs == FAILURE:
                self.reset_children()
                self.idx = 0
                return FAILURE
            if cs == SUCCESS:
                idx += 1
                # every node has a wake-up signal in a Tree, so requiresWakeUp() holds
                if self.asynch and prev == IDLE and idx < n:
                    self.idx = idx
                    return RUNNING
            elif cs == SKIPPED:
                idx += 1
            else:
                self.idx = idx
                raise self._child_idle_error()
        self.idx = idx
        if idx == n:
            self.reset_children()
            self.idx = 0
        return SKIPPED if self.all_skipped else SUCCESS


class FallbackNode(ControlNode):
    """4.6.2 ``FallbackNode`` (Fallback, and AsyncFallback with make_asynch); SKIPPED as in
    SequenceNode (the ``all_skipped_`` flag)."""

    __slots__ = ("idx", "all_skipped", "asynch")

    def __init__(self, rt, model, bb, reg_id, ports, asynch: bool = False) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.all_skipped = True
        self.asynch = asynch

    def halt(self) -> None:
        self.idx = 0
        ControlNode.halt(self)

    def tick(self) -> int:
        children = self.children
        n = len(children)
        st = self.status
        if st == IDLE:
            self.all_skipped = True
        if st != RUNNING:
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
            if cs == SUCCESS:
                self.reset_children()
                self.idx = 0
                return SUCCESS
            if cs == FAILURE:
                idx += 1
                if self.asynch and prev == IDLE and idx < n:
                    self.idx = idx
                    return RUNNING
            elif cs == SKIPPED:
                idx += 1
            else:
                self.idx = idx
                raise self._child_idle_error()
        self.idx = idx
        if idx == n:
            self.reset_children()
            self.idx = 0
        return SKIPPED if self.all_skipped else FAILURE


class SequenceWithMemoryNode(ControlNode):
    """4.6.2 ``SequenceWithMemory``: a FAILURE halts the children from the current one on but
    keeps the index; halt() keeps it too. SKIPPED as in SequenceNode (``all_skipped_``)."""

    __slots__ = ("idx", "all_skipped")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.idx = 0
        self.all_skipped = True

    def tick(self) -> int:
        children = self.children
        n = len(children)
        if self.status == IDLE:
            self.all_skipped = True
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
            else:
                raise self._child_idle_error()
        if self.idx == n:
            self.reset_children()
            self.idx = 0
        return SKIPPED if self.all_skipped else SUCCESS


class ReactiveSequenceNode(ControlNode):
    """4.6.2 ``ReactiveSequence``: every child from the first, every tick; a RUNNING child halts
    all the others."""

    __slots__ = ()

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
            if cs == FAILURE:
                self.reset_children()
                return FAILURE
            if cs == SKIPPED:
                self.halt_child(index)
            elif cs != SUCCESS:
                raise self._child_idle_error()
        self.reset_children()
        return SKIPPED if all_skipped else SUCCESS


class ReactiveFallbackNode(ControlNode):
    """4.6.2 ``ReactiveFallback``."""

    __slots__ = ()

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
            if cs == SUCCESS:
                self.reset_children()
                return SUCCESS
            if cs == SKIPPED:
                self.halt_child(index)
            elif cs != FAILURE:
                raise self._child_idle_error()
        self.reset_children()
        return SKIPPED if all_skipped else FAILURE


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
            raise _run_error(self.port_loc("success_count"),
                             f"`Parallel` \"{self.name}\" needs {required_success} successes but has only "
                             f"{n} children: it can never succeed")
        if n < required_failure:
            raise _run_error(self.port_loc("failure_count"),
                             f"`Parallel` \"{self.name}\" fails after {required_failure} failures but has only "
                             f"{n} children: it can never fail")
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
                    success_threshold < 0 and self.success_count + skipped >= required_success):
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
            raise _run_error(self.port_loc("max_failures"),
                             f"`ParallelAll` \"{self.name}\" fails after {threshold} failures but has only "
                             f"{n} children: it can never fail")
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
    A SKIPPED condition makes 4.6.2 throw; btgen reports it as an error."""

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
            raise _skipped_condition_error(self, children[0])
        if status == RUNNING:
            return RUNNING
        self.reset_children()
        return status


def _skipped_condition_error(node: TreeNode, cond: TreeNode) -> RunError:
    return _run_error(cond.model.loc, f"the condition of `{node.reg_id}` \"{node.name}\" (`{cond.reg_id}` "
                                      f"\"{cond.name}\") was skipped; BehaviorTree.CPP 4.6.2 throws here, so a "
                                      f"condition child must not be skippable")


def _to_int_prefix(text: str) -> Optional[int]:
    """std::from_chars<int> as SwitchNode uses it: an optional '-', digits; the rest is ignored."""
    i = 0
    if i < len(text) and text[i] == "-":
        i += 1
    j = i
    while j < len(text) and "0" <= text[j] <= "9":
        j += 1
    if j == i:
        return None
    value = int(text[:j])
    if value < -2**31 or value > 2**31 - 1:
        return None
    return value


_FLOAT_RE = None


def _to_real_prefix(text: str) -> Optional[float]:
    """std::from_chars<double> (general format): the longest prefix that is a number, inf or nan."""
    global _FLOAT_RE
    if _FLOAT_RE is None:
        import re
        _FLOAT_RE = re.compile(r"-?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|inf(?:inity)?|nan(?:\([0-9A-Za-z_]*\))?)",
                               re.IGNORECASE)
    m = _FLOAT_RE.match(text)
    if not m:
        return None
    try:
        value = float(m.group(0))
    except ValueError:
        return None
    if value in (float("inf"), float("-inf")) and "inf" not in m.group(0).lower():
        return None  # out of range: from_chars reports an error
    return value


def switch_equal(v1: str, v2: str) -> bool:
    """SwitchNode's CheckStringEquality (4.6.2): as text, then as integers, then as reals."""
    if v1 == v2:
        return True
    i1, i2 = _to_int_prefix(v1), _to_int_prefix(v2)
    if i1 is not None and i2 is not None and i1 == i2:
        return True
    r1, r2 = _to_real_prefix(v1), _to_real_prefix(v2)
    if r1 is not None and r2 is not None and abs(r1 - r2) <= 1.1920928955078125e-07:
        return True
    return False


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

    def tick(self) -> int:
        match = self.cases
        variable = self.get_input("variable", "string")
        if variable is not MISSING:
            for index in range(self.cases):
                value = self.get_input(f"case_{index + 1}", "string")
                if value is not MISSING and switch_equal(variable, value):
                    match = index
                    break
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
                prev = self.status
                if prev != status:
                    if status == IDLE:
                        raise self._idle_error()
                    self.status = status
                    self.emit((self.prefix, _TRANS[prev][status]))
        c = self.child
        cs = c.status
        if cs == SUCCESS or cs == FAILURE:
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
            raise _run_error(self.model.loc, f"the child of `Inverter` \"{self.name}\" returned IDLE")
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
            raise _run_error(self.model.loc, f"the child of `Inverter` \"{self.name}\" returned IDLE")
        else:
            return cs  # RUNNING (already stored) or SKIPPED (never stored)
        self.status = new
        self.emit((self.prefix, _TRANS[RUNNING][new]))
        return new


class ForceSuccessNode(DecoratorNode):
    __slots__ = ()

    def tick(self) -> int:
        self.set_status(RUNNING)
        cs = self.child.execute_tick()
        if cs == SUCCESS or cs == FAILURE:
            self.reset_child()
            return SUCCESS
        return cs


class ForceFailureNode(DecoratorNode):
    __slots__ = ()

    def tick(self) -> int:
        self.set_status(RUNNING)
        cs = self.child.execute_tick()
        if cs == SUCCESS or cs == FAILURE:
            self.reset_child()
            return FAILURE
        return cs


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
    """4.6.2 ``RepeatNode``: a child that succeeded from IDLE yields RUNNING before the next cycle."""

    __slots__ = ("count",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.count = 0

    def halt(self) -> None:
        self.count = 0
        DecoratorNode.halt(self)

    def tick(self) -> int:
        cycles = self.require_input("num_cycles", "int")
        do_loop = self.count < cycles or cycles == -1
        self.set_status(RUNNING)
        while do_loop:
            prev = self.child.status
            cs = self.child.execute_tick()
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
                raise _run_error(self.model.loc, f"the child of `Repeat` \"{self.name}\" returned IDLE")
        self.count = 0
        return SUCCESS


class RetryNode(DecoratorNode):
    """4.6.2 ``RetryNode`` (RetryUntilSuccessful)."""

    __slots__ = ("tries",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.tries = 0

    def halt(self) -> None:
        self.tries = 0
        DecoratorNode.halt(self)

    def tick(self) -> int:
        attempts = self.require_input("num_attempts", "int")
        do_loop = self.tries < attempts or attempts == -1
        self.set_status(RUNNING)
        while do_loop:
            prev = self.child.status
            cs = self.child.execute_tick()
            if cs == SUCCESS:
                self.tries = 0
                self.reset_child()
                return SUCCESS
            if cs == FAILURE:
                self.tries += 1
                # 4.6.2 read num_attempts once, at the start of tick(); re-reading it after
                # every failure (#905) came with 4.7.0
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
                raise _run_error(self.model.loc, f"the child of `RetryUntilSuccessful` \"{self.name}\" "
                                                 f"returned IDLE")
        self.tries = 0
        return FAILURE


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
        if status == SUCCESS or status == FAILURE:
            self.done = True
            self.returned = status
            self.reset_child()
        return status


class _ScriptPort:
    """A port holding a script (`code`, `if`): parsed once when written literally; read and
    parsed again when it changes if it names a blackboard entry (4.6.2 loadExecutor)."""

    __slots__ = ("node", "name", "attr", "parsed", "text", "literal")

    def __init__(self, node: TreeNode, name: str) -> None:
        self.node = node
        self.name = name
        p = node.ports.get(name)
        self.attr = p.attr if p is not None else None
        self.literal = self.attr is not None and self.attr.script is not None \
            and not bbmod.is_blackboard_pointer(self.attr.value)
        self.parsed = self.attr.script if self.literal else None
        self.text = self.attr.value if self.literal else None

    def load(self):
        if not self.literal:
            text = self.node.require_input(self.name, "string")
            if text != self.text:
                self.parsed = self.node._parse_at_run_time(self.attr, text)
                self.text = text
        return self.parsed

    def run(self):
        return self.node.run_script(self.attr, self.load(), not self.literal)

    def truth(self) -> bool:
        return self.node.truth(self.attr, self.load(), not self.literal)


class PreconditionNode(DecoratorNode):
    """4.6.2 ``PreconditionNode``: `if` is evaluated on every tick; when false the node returns
    `else` without ticking (or halting) its child. (Later releases evaluate it once per run.)"""

    __slots__ = ("script",)

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.script = _ScriptPort(self, "if")

    def tick(self) -> int:
        self.script.load()
        else_status = self.status_input("else")
        if self.script.truth():
            cs = self.child.execute_tick()
            if cs == SUCCESS or cs == FAILURE:
                self.reset_child()
            return cs
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
        if cs == SUCCESS or cs == FAILURE:
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
            if cs == SUCCESS or cs == FAILURE:
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
                self.static_queue = values.convert_from_string(f"queue<{elem}>", p.raw)  # type: ignore
            except values.ConversionError as e:
                raise _run_error(self.port_loc("queue"), f"port `queue` of `{reg_id}` \"{self.name}\": {e}") \
                    from None

    def tick(self) -> int:
        popped = False
        if self.status == IDLE:
            self.child_running = False
            if self.static_queue is not None:
                self.current = values.Queue(self.elem, self.static_queue)
        if not self.child_running:
            if self.static_queue is None:
                q = self._queue_from_blackboard()
                if q is not None:
                    self.current = q
            if self.current:
                value = self.current.popleft()
                popped = True
                self.set_output("value", value, self.elem)
        if not popped and not self.child_running:
            return self.status_input("if_empty")
        if self.status == IDLE:
            self.set_status(RUNNING)
        cs = self.child.execute_tick()
        self.child_running = cs == RUNNING
        if cs == SUCCESS or cs == FAILURE:
            self.reset_child()
        if cs == FAILURE:
            return FAILURE
        return RUNNING

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
            raise _run_error(self.port_loc("queue"), f"port `queue` of `{self.reg_id}` \"{self.name}\" reads "
                                                     f"blackboard entry `{key}`, which has no value yet")
        try:
            return values.cast(entry.value, f"queue<{self.elem}>")
        except values.ConversionError as e:
            raise _run_error(self.port_loc("queue"), f"port `queue` of `{self.reg_id}` \"{self.name}\": {e}") \
                from None


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
        if cs == SUCCESS or cs == FAILURE:
            self.child.reset_status()
        return status

    def halt(self) -> None:
        self.still_executing = False
        self.reset_child()
        self.reset_status()

    def _entry(self):
        return _entry_of(self)

    def tick(self) -> int:
        if self.still_executing:
            status = self.child.execute_tick()
            self.still_executing = status == RUNNING
            return status
        entry = self._entry()
        if entry is None:
            return self.if_not_updated
        seq = entry.sequence_id
        previous = self.seen
        self.seen = seq
        if previous == seq:
            return self.if_not_updated
        status = self.child.execute_tick()
        self.still_executing = status == RUNNING
        return status


def _entry_of(node):
    """The entry `key` names from the node's blackboard (getEntry); a bad key is an error."""
    try:
        return node.bb.get_entry(node.key)
    except bbmod.BlackboardError as e:
        raise _run_error(node.port_loc("entry"), f"`{node.reg_id}` \"{node.name}\": {e}") from None


class SubTreeRunNode(DecoratorNode):
    """4.6.2 ``SubTreeNode``: RUNNING before its tree's root is ticked."""

    __slots__ = ()

    def tick(self) -> int:
        if self.status == IDLE:
            self.set_status(RUNNING)
        cs = self.child.execute_tick()
        if cs == SUCCESS or cs == FAILURE:
            self.reset_child()
        return cs


# ================================================================ leaves
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
            raise _run_error(self.model.loc, f"`SetBlackboard` \"{self.name}\" needs port `value`")
        try:
            ok = bbmod.set_blackboard(self.bb, str(key), p.raw)
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(self.port_loc("value"), f"`SetBlackboard` \"{self.name}\": {e}") from None
        return SUCCESS if ok is not False else FAILURE


class UnsetBlackboardNode(TreeNode):
    """``UnsetBlackboardNode``: removes `key`; SUCCESS also when it did not exist."""

    __slots__ = ()

    def tick(self) -> int:
        key = self.require_input("key", "string")
        try:
            self.bb.unset(str(key))
        except bbmod.BlackboardError as e:
            raise _run_error(self.port_loc("key"), f"`UnsetBlackboard` \"{self.name}\": {e}") from None
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


class ScriptedAction(StatefulActionNode):
    """A user Action: every onStart/onRunning takes the next scripted result."""

    __slots__ = ("cursor", "default")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.cursor = rt.cursor(self.name)
        self.default = rt.default

    def on_start(self) -> int:
        c = self.cursor
        return c.next() if c is not None else self.default

    on_running = on_start

    def execute_tick(self) -> int:
        # TreeNode::executeTick + StatefulActionNode::tick, inlined for speed
        if self.conds:
            return self._execute_tick_with_conditions()
        prev = self.status
        if prev == IDLE or prev == RUNNING:
            c = self.cursor
            new = c.next() if c is not None else self.default
            if new != prev:
                self.status = new
                self.emit((self.prefix, _TRANS[prev][new]))
            return new
        return prev


class ScriptedCondition(TreeNode):
    """A user Condition: every tick takes the next scripted result."""

    __slots__ = ("cursor", "default")

    def __init__(self, rt, model, bb, reg_id, ports) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.cursor = rt.cursor(self.name)
        self.default = rt.default
        if self.cursor is None and self.default == RUNNING:
            raise _run_error(model.loc, f"Condition `{self.name}` would return RUNNING (the scenario's default)")

    def tick(self) -> int:
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


# ================================================================ building the tree
_BUILTIN_FACTORIES = {
    "Sequence": lambda rt, m, bb, r, p: SequenceNode(rt, m, bb, r, p, False),
    "AsyncSequence": lambda rt, m, bb, r, p: SequenceNode(rt, m, bb, r, p, True),
    "SequenceWithMemory": SequenceWithMemoryNode,
    "ReactiveSequence": ReactiveSequenceNode,
    "Fallback": lambda rt, m, bb, r, p: FallbackNode(rt, m, bb, r, p, False),
    "AsyncFallback": lambda rt, m, bb, r, p: FallbackNode(rt, m, bb, r, p, True),
    "ReactiveFallback": ReactiveFallbackNode,
    "Parallel": ParallelNode,
    "ParallelAll": ParallelAllNode,
    "IfThenElse": IfThenElseNode,
    "WhileDoElse": WhileDoElseNode,
    "Switch2": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 2),
    "Switch3": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 3),
    "Switch4": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 4),
    "Switch5": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 5),
    "Switch6": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 6),
    "Inverter": InverterNode,
    "ForceSuccess": ForceSuccessNode,
    "ForceFailure": ForceFailureNode,
    "KeepRunningUntilFailure": KeepRunningUntilFailureNode,
    "Repeat": RepeatNode,
    "RetryUntilSuccessful": RetryNode,
    "RunOnce": RunOnceNode,
    "Precondition": PreconditionNode,
    "Timeout": TimeoutNode,
    "Delay": DelayNode,
    "LoopInt": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "int"),
    "LoopBool": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "bool"),
    "LoopDouble": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "double"),
    "LoopString": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "string"),
    "SkipUnlessUpdated": lambda rt, m, bb, r, p: EntryUpdatedDecorator(rt, m, bb, r, p, SKIPPED),
    "WaitValueUpdate": lambda rt, m, bb, r, p: EntryUpdatedDecorator(rt, m, bb, r, p, RUNNING),
    "AlwaysSuccess": lambda rt, m, bb, r, p: AlwaysNode(rt, m, bb, r, p, SUCCESS),
    "AlwaysFailure": lambda rt, m, bb, r, p: AlwaysNode(rt, m, bb, r, p, FAILURE),
    "Script": ScriptNode,
    "ScriptCondition": ScriptConditionNode,
    "SetBlackboard": SetBlackboardNode,
    "UnsetBlackboard": UnsetBlackboardNode,
    "Sleep": SleepNode,
    "WasEntryUpdated": WasEntryUpdatedNode,
}


class _Builder:
    """Instantiates the main tree as 4.6.2's XMLParser::instantiateTree does."""

    def __init__(self, rt: Runtime, mission: Mission) -> None:
        self.rt = rt
        self.mission = mission
        self.trees = {t.id: t for t in mission.trees}
        self.nodes: list[TreeNode] = []

    def build(self, root_bb) -> TreeNode:
        return self._node(self.trees[self.mission.main_tree].root, root_bb)

    def _ports_of(self, model: Node) -> dict[str, _Port]:
        try:
            spec = self.mission.spec(model.id)
        except KeyError:
            spec = None
        ports: dict[str, _Port] = {}
        for a in model.ports:
            ps = spec.port(a.name) if spec is not None else None
            raw = a.value
            if raw == "" and ps is not None and ps.default is not None and ps.type not in ("string", "any") \
                    and not values.is_opaque_type(ps.type):
                raw = ps.default  # TreeNode::getInput: an empty value reads the model's (non-string) default
            ports[a.name] = _Port(a.name, raw, a, ps)
        if spec is not None:
            # createNodeFromXML: a port not written takes the model's default, an input port any
            # default, an output port only a `{key}` one
            for ps in spec.ports:
                if ps.name in ports or ps.default is None:
                    continue
                if ps.direction != "output" or bbmod.is_blackboard_pointer(ps.default):
                    ports[ps.name] = _Port(ps.name, ps.default, None, ps)
        return ports

    def _node(self, model: Node, bb) -> TreeNode:
        rt = self.rt
        if isinstance(model, SubTreeNode):
            node = SubTreeRunNode(rt, model, bb, "SubTree", {})
            self.nodes.append(node)
            child_bb = self._subtree_blackboard(model, bb)
            node.child = self._node(self.trees[model.target].root, child_bb)
            return node
        ports = self._ports_of(model)
        self._create_entries(model, ports, bb)
        if model.id in _BUILTIN_FACTORIES and model.id in BUILTINS:
            factory = _BUILTIN_FACTORIES[model.id]
            node = factory(rt, model, bb, model.id, ports)
        elif is_scripted_leaf(self.mission, model):
            cls = ScriptedCondition if leaf_kind(self.mission, model) == "Condition" else ScriptedAction
            node = cls(rt, model, bb, model.id, ports)
        else:
            raise _run_error(model.loc, user_node_message(model.id, user_node_kind(self.mission, model)
                                                          or "node"))
        self.nodes.append(node)
        kids = [self._node(c, bb) for c in model.children]
        if isinstance(node, ControlNode):
            node.children = kids
        elif isinstance(node, (DecoratorNode, EntryUpdatedDecorator)):
            if len(kids) != 1:
                raise _run_error(model.loc, f"`{model.id}` needs exactly one child")
            node.child = kids[0]
        elif kids:
            raise _run_error(model.loc, f"`{model.id}` takes no children")
        return node

    def _create_entries(self, model: Node, ports: dict[str, _Port], bb) -> None:
        """Load time: every {key} port creates its entry (with the port's type) when missing."""
        for p in ports.values():
            if p.attr is None:
                continue
            try:
                bbmod.create_port_entry(bb, p.raw, p.spec.type if p.spec is not None else "any", p.name)
            except (values.ConversionError, bbmod.BlackboardError) as e:
                raise _run_error(p.attr.value_loc, f"port `{p.name}` of `{model.id}`: {e}") from None

    def _subtree_blackboard(self, model: SubTreeNode, parent_bb):
        """recursivelyCreateSubtree: a child blackboard with the SubTree's remappings."""
        model_spec = next((m for m in self.mission.models if m.id == model.target and m.kind == "SubTree"), None)
        remap = [(a.name, a.value, a) for a in model.ports]
        if model_spec is not None and not model.autoremap:
            given = {a.name for a in model.ports}
            for ps in model_spec.ports:
                if ps.name not in given:
                    if ps.default is None:
                        raise _run_error(model.loc, f"SubTree `{model.target}` declares port `{ps.name}` "
                                                    f"without a default, and this instance does not remap it")
                    remap.append((ps.name, ps.default, None))
        try:
            return bbmod.Blackboard.for_subtree(parent_bb, [(n, v) for n, v, _ in remap], model.autoremap)
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(model.loc, f"SubTree `{model.target}`: {e}") from None


# ================================================================ running
def expanded_depth(mission: Mission) -> int:
    """The depth of the main tree with its SubTrees expanded (a SubTree node counts as a level)."""
    trees = {t.id: t for t in mission.trees}
    memo: dict[str, int] = {}

    def tree_depth(tree_id: str) -> int:
        if tree_id in memo:
            return memo[tree_id]
        memo[tree_id] = 0  # the front end rejects recursive SubTrees; never loop here anyway
        best = 0
        stack = [(trees[tree_id].root, 1)]
        while stack:
            node, d = stack.pop()
            if isinstance(node, SubTreeNode):
                d += tree_depth(node.target) if node.target in trees else 0
            best = max(best, d)
            stack.extend((c, d + 1) for c in node.children)
        memo[tree_id] = best
        return best

    return tree_depth(mission.main_tree) if mission.main_tree in trees else 0


def _ensure_recursion_depth(depth: int) -> None:
    """Ticking and halting recurse about three Python frames per tree level; a tree nested deeper
    than the default limit allows gets a higher limit (Python 3.11+ keeps such frames off the C
    stack)."""
    needed = 4 * depth + 200
    if sys.getrecursionlimit() < needed:
        sys.setrecursionlimit(needed)


class Interpreter:
    """A mission instantiated for running: `tick_once()` is BehaviorTree.CPP's tickExactlyOnce."""

    def __init__(self, mission: Mission, scenario: Optional[Scenario] = None) -> None:
        self.mission = mission
        self.scenario = scenario
        _ensure_recursion_depth(expanded_depth(mission))
        self.rt = Runtime(mission, scenario)
        self.root_bb = bbmod.Blackboard()
        builder = _Builder(self.rt, mission)
        self.root = builder.build(self.root_bb)
        self.nodes = builder.nodes
        self.ticks_sent = 0

    def take_text(self) -> str:
        """The trace lines produced since the last call, as text."""
        return self.rt.take_text()

    def take_lines(self) -> list[str]:
        """The trace lines produced since the last call."""
        return self.rt.take_text().splitlines()

    def advance_clock(self, ms: int) -> None:
        self.rt.now_ms += ms

    def tick_once(self) -> NodeStatus:
        """Tree::tickRoot(EXACTLY_ONCE): one executeTick of the root; a completed root is reset."""
        self.ticks_sent += 1
        status = self.root.execute_tick()
        if status == SUCCESS or status == FAILURE:
            self.root.reset_status()
        return _BY_VALUE[status]


def run_trace(mission: Mission, scenario: Scenario, write: Callable[[str], object]) -> NodeStatus:
    """Run as FORMAT.md says and write the trace through `write` (one call per tick).

    Returns the last root status. A run-time error raises RunError after the
    lines of the failing tick so far have been written."""
    interp = Interpreter(mission, scenario)
    last = NodeStatus.IDLE
    for n in range(1, scenario.ticks + 1):
        if n > 1 and scenario.clock_ms:
            interp.advance_clock(scenario.clock_ms)
        interp.rt.write_line(f"tick {n}")
        try:
            last = interp.tick_once()
        except UserError:
            write(interp.take_text())
            raise
        interp.rt.write_line(f"result {last.name}")
        write(interp.take_text())
        if last is NodeStatus.SUCCESS or last is NodeStatus.FAILURE:
            break
    return last


def trace_text(mission: Mission, scenario: Scenario) -> str:
    """The whole trace as one string (for tests and tools)."""
    parts: list[str] = []
    run_trace(mission, scenario, parts.append)
    return "".join(parts)
