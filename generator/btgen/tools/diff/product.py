"""The product exploration behind `btgen diff`: two missions driven by the same leaf outcomes.

A *plan* is a scenario under construction: for each leaf name, the statuses its
calls return, in call order (the `leaf NAME S1 S2 ...` lines of a scenario file).
Both missions read the SAME plan, each with its own position per name, so the
k-th call of leaf X returns the same status in OLD and in NEW. A run replays a
plan on two fresh interpreters (interp/engine.py) tick by tick, OLD first, then
NEW, and stops at the first call the plan does not cover: a branch point, where
the search goes on with each possible result appended (SUCCESS or FAILURE for a
Condition, RUNNING too for an Action). The search is breadth first over the
plan's length, so the first difference found comes with a shortest scenario.

What is observed by default, per tick and in order: each leaf call (its name,
the values of its input ports when called, the result it was given), each write
of an entry of the main tree's blackboard (key and new value), a run-time error,
and the root's result. Control nodes, SubTree-private entries and the trace's
status lines are not observed: a tree reshaped without changing these is
equivalent. `observe` (OBSERVABLES, `--observe`) selects a subset, or adds every
node's status transitions.
NEW's events of a tick are compared with OLD's as they happen; the first one
that differs ends the run with a counterexample.

Repeats are cut as `btgen explore` cuts them (tools/explore/search.py's state hash),
on the pair: both engines' states (node statuses and members, blackboards,
clock, the chain of nodes being ticked), the results the plan holds that each
engine has not consumed yet, and OLD's events of the tick NEW has not matched
yet. A pair already reached at the same or an earlier tick is not explored
again. When every run ends (both roots completed alike, or a repeated pair)
the answer is exhaustive; when some run reached the tick bound, it holds up to
that bound; when the state budget runs out, the search was partial and proves
nothing (the command says so).
"""

from __future__ import annotations

import time
import weakref
from collections import deque
from dataclasses import dataclass, field
from typing import Callable, Optional

from btgen.diagnostics import UserError
from btgen.interp import actions as iactions
from btgen.interp.engine import Interpreter
from btgen.interp.nav2 import EnvInputDecorator
from btgen.interp.scenario import Scenario
from btgen.interp.tree import FAILURE, MISSING, RUNNING, SUCCESS, TreeNode
from btgen.lang import blackboard as bbmod
from btgen.lang.model import Mission
from btgen.tools.explore import NAMES, Explorer

# An event: ("call", leaf, ((port, value), ...), STATUS) | ("write", key, value)
#           | ("error", message) | ("result", STATUS) | ("transition", node, "FROM -> TO")
Event = tuple

# What can be observed (`--observe`): the leaf calls (name and result, in order), the values of
# their input ports, the root's result each tick, the writes of the main tree's blackboard,
# every node's status transitions (control nodes too: a reshaped tree then differs). A run-time
# error, and the end of a run (the root completing), are always observed.
OBSERVABLES = ("leaf-calls", "inputs", "root", "writes", "transitions")
DEFAULT_OBSERVE = frozenset(("leaf-calls", "inputs", "root", "writes"))


class _Branch(Exception):
    def __init__(self, name: str, options: tuple[int, ...]) -> None:
        self.name = name
        self.options = options


class _Stop(Exception):
    def __init__(self, reason: str) -> None:
        self.reason = reason


class _Differ(Exception):
    pass


def _show(value: object) -> str:
    if value is MISSING:
        return "<unset>"
    if value is None:
        return "<empty>"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return repr(value)
    return str(value)


def event_text(ev: Event) -> str:
    """One event as the traces print it."""
    if ev[0] == "call":
        args = ", ".join(f"{k}={v}" for k, v in ev[2])
        return f"{ev[1]}({args}) -> {ev[3]}"
    if ev[0] == "write":
        return f"write {ev[1]} = {ev[2]}"
    if ev[0] == "error":
        return f"error: {ev[1]}"
    if ev[0] == "transition":
        return f"{ev[1]}: {ev[2]}"
    return f"result {ev[1]}"


# ====================================================================== observing one engine
_HOOKED = "execute_tick"  # the method every visit goes through, wrapped while running
_CURRENT: Optional[_Recorder] = None  # the engine being ticked (the hooks report to it)


class _Recorder:
    """One engine's observer: the events of the tick being run."""

    def __init__(
        self,
        mission: Mission,
        key_of: Callable[[str], str],
        scenario: Optional[Scenario] = None,
        observe: frozenset = DEFAULT_OBSERVE,
        interp: Optional[Interpreter] = None,
    ) -> None:
        if interp is None:
            interp = Interpreter(mission, scenario)
            interp.rt.now_ms = 0
        self.interp = interp
        self.key_of = key_of
        self.events: list[Event] = []
        self.chain: list[tuple[TreeNode, int]] = []
        self.seen_return: set = set()  # Explorer.state_key reads it (no properties here)
        self.root_bb = self.interp.root_bb
        self.calls = "leaf-calls" in observe or "inputs" in observe
        self.inputs = "inputs" in observe
        self.root = "root" in observe
        self.writes = "writes" in observe
        if "transitions" in observe:
            for node in self.interp.nodes:
                node.emit = self._transition_emitter(node)

    def _transition_emitter(self, node: TreeNode) -> Callable[[tuple[str, str]], None]:
        out = self.interp.rt.buf.extend
        name = self.key_of(node.name) if isinstance(node, _SCRIPTED) else node.name

        def emit(piece: tuple[str, str]) -> None:
            out(piece)
            self.emit(("transition", name, piece[1].rstrip("\n")))

        return emit

    def emit(self, ev: Event) -> None:
        self.events.append(ev)

    def on_write(self, entry: bbmod.Entry) -> None:
        if not self.writes:
            return
        bb = self.root_bb
        for k in bb.local_keys():
            if bb.local_entry(k) is entry:
                self.emit(("write", k, _show(entry.value)))
                return

    def leaf_call(self, node: TreeNode, key: str, condition: bool) -> int:  # pragma: no cover
        raise NotImplementedError

    def call_event(self, node: TreeNode, key: str, status: int) -> None:
        if not self.calls:
            return
        inputs = []
        for name in sorted(node.ports) if self.inputs else ():
            p = node.ports[name]
            if p.spec is not None and p.spec.direction == "output":
                continue
            inputs.append((name, _show(node.get_input(name))))
        self.emit(("call", key, tuple(inputs), NAMES[status]))

    def tick(self, n: int, clock_ms: int) -> bool:
        """Tick n; False when the run of this engine is over (root completed, or an error)."""
        global _CURRENT
        if n > 1 and clock_ms:
            self.interp.advance_clock(clock_ms)
        _CURRENT = self
        try:
            status = self.interp.tick_once()
        except UserError as e:
            d = e.diagnostics[0] if e.diagnostics else None
            self.emit(("error", d.message if d is not None else "run-time error"))
            return False
        finally:
            _CURRENT = None
            self.interp.take_text()
        going = status.name not in ("SUCCESS", "FAILURE")
        if self.root:
            self.emit(("result", status.name))
        elif not going:
            self.emit(("result", "completed"))  # the end of the run, without its status
        return going


def _state(ex: Explorer, rec: _Recorder) -> tuple:
    """explore's state key of one side's own interpreter (Explorer.key_of_interpreter: the
    explorer keeps an interpreter of its own), with the tick's chain of calls in progress."""
    return ex.key_of_interpreter(rec.interp) + (tuple((n.uid, st) for n, st in rec.chain),)


# The nodes whose results a scenario scripts: user leaves, and the inputs of Nav2's Decorators
# that read ROS 2 (answered as a Condition's).
_SCRIPTED = (iactions.ScriptedAction, iactions.ScriptedCondition, EnvInputDecorator)


class _LeafHook:
    """Stands for a scripted leaf's scenario cursor: asks the engine's recorder."""

    __slots__ = ("rec", "node", "key", "condition")

    def __init__(self, rec: _Recorder, node: TreeNode) -> None:
        self.rec = rec
        self.node = node
        self.key = rec.key_of(node.name)
        self.condition = isinstance(node, (iactions.ScriptedCondition, EnvInputDecorator))

    def next(self) -> int:
        return self.rec.leaf_call(self.node, self.key, self.condition)


class _Slot:
    """The side of the run being played on one explorer's interpreter (its leaves' hooks ask it)."""

    __slots__ = ("side",)

    def __init__(self) -> None:
        self.side: Optional[_Side] = None


class _SharedHook:
    """A scripted leaf's cursor on an explorer's interpreter, installed once: the run being
    played answers (through the side's slot)."""

    __slots__ = ("slot", "node", "key", "condition")

    def __init__(self, slot: _Slot, node: TreeNode, key: str) -> None:
        self.slot = slot
        self.node = node
        self.key = key
        self.condition = isinstance(node, (iactions.ScriptedCondition, EnvInputDecorator))

    def next(self) -> int:
        side = self.slot.side
        assert side is not None
        return side.leaf_call(self.node, self.key, self.condition)


def _hook_leaves(rec: _Recorder) -> None:
    for node in rec.interp.nodes:
        if isinstance(node, _SCRIPTED):
            node.cursor = _LeafHook(rec, node)


def _install(nodes: list[TreeNode]) -> Callable[[], None]:
    """Wrap execute_tick of every node class (the chain being ticked, for the state hash) and
    Entry.bump (every blackboard write); returns the undo."""
    classes = {k for n in nodes for k in type(n).__mro__ if issubclass(k, TreeNode)}
    patched: list[tuple[type, str, object]] = []

    def wrap(original):
        def execute_tick(node):
            rec = _CURRENT
            if rec is None or (rec.chain and rec.chain[-1][0] is node):
                return original(node)
            rec.chain.append((node, node.status))
            try:
                return original(node)
            finally:
                rec.chain.pop()

        return execute_tick

    for cls in classes:
        if "execute_tick" in cls.__dict__:
            original = cls.__dict__["execute_tick"]
            patched.append((cls, _HOOKED, original))
            setattr(cls, _HOOKED, wrap(original))
    bump = bbmod.Entry.bump

    def bump_and_report(entry):
        bump(entry)
        rec = _CURRENT
        if rec is not None:
            rec.on_write(entry)

    patched.append((bbmod.Entry, "bump", bump))
    bbmod.Entry.bump = bump_and_report  # type: ignore[method-assign]

    def restore() -> None:
        for cls, name, original in reversed(patched):
            setattr(cls, name, original)

    return restore


# ====================================================================== the product search
class _Side(_Recorder):
    """One engine of a product run, fed by the shared plan: the side's explorer's interpreter
    (explore's core), restored to its initial state (building an interpreter per run cost
    about 70% of the search), its leaves answering through the side's slot."""

    def __init__(self, run: _Run, index: int, mission: Mission, key_of: Callable[[str], str]) -> None:
        ex = run.d.ex_old if index == 0 else run.d.ex_new  # restored by Differ._run
        super().__init__(mission, key_of, None, run.d.observe, ex.interp)
        self.run = run
        self.index = index
        self.pos: dict[str, int] = {}
        run.d.slots[index].side = self

    def emit(self, ev: Event) -> None:
        self.events.append(ev)
        if self.index == 1:  # NEW: compared with OLD's tick as it happens
            old = self.run.sides[0].events
            i = len(self.events) - 1
            if i >= len(old) or old[i] != ev:
                raise _Differ()

    def leaf_call(self, node: TreeNode, key: str, condition: bool) -> int:
        run = self.run
        q = run.plan.get(key, ())
        i = self.pos.get(key, 0)
        if i >= len(q):
            run.branch_point(self)
            # RUNNING is a possible result when the leaf is an Action in EITHER mission (a leaf
            # turned from Condition into Action must not hide behind the side that asks first)
            running = not condition or key in run.d.actions
            raise _Branch(key, (SUCCESS, FAILURE, RUNNING) if running else (SUCCESS, FAILURE))
        self.pos[key] = i + 1
        v = q[i]
        self.call_event(node, key, v)
        return v


MARK_BUDGET = 4_000_000  # saved node states held at once by the marks of queued plans (memory)


class _Mark:
    """Both interpreters (Explorer._save) and both sides' plan positions at a tick's start."""

    __slots__ = ("tick", "old", "new", "pos_old", "pos_new", "__weakref__")

    def __init__(self, tick: int, old: tuple, new: tuple, pos_old: dict, pos_new: dict) -> None:
        self.tick = tick
        self.old = old
        self.new = new
        self.pos_old = pos_old
        self.pos_new = pos_new


def _dec(live: list) -> None:
    live[0] -= 1


class _Run:
    def __init__(self, d: Differ, plan: dict[str, tuple[int, ...]]) -> None:
        self.d = d
        self.plan = plan
        self.mark: Optional[_Mark] = None
        self.tick_no = 0
        self.sides: list[_Side] = []
        self.sides.append(_Side(self, 0, d.old, lambda n: d.rename.get(n, n)))
        self.sides.append(_Side(self, 1, d.new, lambda n: n))

    def branch_point(self, side: _Side) -> None:
        d = self.d
        if len(d.seen) >= d.max_states:
            raise _Stop("states")
        old, new = self.sides
        left = []
        for s in self.sides:
            for name in sorted(self.plan):
                rest = self.plan[name][s.pos.get(name, 0) :]
                if rest:
                    left.append((s.index, name, rest))
        pending = tuple(old.events) if side is old else tuple(old.events[len(new.events) :])
        key = (side.index, _state(d.ex_old, old), _state(d.ex_new, new), tuple(left), pending)
        best = d.seen.get(key)
        if best is not None and best <= self.tick_no:
            raise _Stop("repeat")
        d.seen[key] = self.tick_no


@dataclass
class Outcome:
    equivalent: bool
    exhaustive: bool  # the product state space was exhausted (else: up to `bound` ticks)
    bound: int  # the tick bound that held (the --max-ticks asked, or where the budget stopped)
    runs: int
    states: int
    seconds: float
    plan: dict[str, tuple[int, ...]] = field(default_factory=dict)  # the counterexample (NEW's names)
    ticks: int = 0  # its length in ticks
    why_bounded: str = ""  # "ticks" | "states" | ""


class Differ:
    def __init__(
        self,
        old: Mission,
        new: Mission,
        rename: Optional[dict[str, str]] = None,
        max_ticks: int = 10,
        clock_ms: int = 100,
        max_states: int = 200000,
        observe: Optional[frozenset] = None,
    ) -> None:
        self.observe = DEFAULT_OBSERVE if observe is None else frozenset(observe)
        self.old = old
        self.new = new
        self.rename = dict(rename or {})
        self.max_ticks = max_ticks
        self.clock_ms = clock_ms
        self.max_states = max_states
        self.ex_old = Explorer(old, max_ticks, clock_ms=clock_ms)
        self.ex_new = Explorer(new, max_ticks, clock_ms=clock_ms)
        self.seen: dict[tuple, int] = {}
        self.actions: set[str] = set()  # leaf names (NEW's) that are an Action in either mission
        for ex, renames in ((self.ex_old, self.rename), (self.ex_new, {})):
            for node in ex.nodes:
                if isinstance(node, iactions.ScriptedAction):
                    self.actions.add(renames.get(node.name, node.name))
        # each side plays its runs on its explorer's interpreter; its leaves ask the side's slot
        # runs resume from the start of the tick where their parent branched (`_Mark`: both
        # interpreters saved by explore's core), at most `max_marks` saved at once
        self.resume = True
        self.max_marks = max(64, MARK_BUDGET // max(1, len(self.ex_old.nodes) + len(self.ex_new.nodes)))
        self._live = [0]
        self.slots = (_Slot(), _Slot())
        for slot, ex, renames in ((self.slots[0], self.ex_old, self.rename), (self.slots[1], self.ex_new, {})):
            for node in ex.nodes:
                if isinstance(node, _SCRIPTED):
                    node.cursor = _SharedHook(slot, node, renames.get(node.name, node.name))

    def _mark(self, n: int, old: _Side, new: _Side) -> Optional[_Mark]:
        """Both interpreters and both plan positions at the start of tick n (None past the budget
        of saved states: those runs are replayed from the first tick)."""
        if self._live[0] >= self.max_marks:
            return None
        m = _Mark(n, self.ex_old._save(), self.ex_new._save(), dict(old.pos), dict(new.pos))
        self._live[0] += 1
        weakref.finalize(m, _dec, self._live)
        return m

    def _run(
        self, plan: dict[str, tuple[int, ...]], mark: Optional[_Mark] = None
    ) -> tuple[str, _Run, Optional[_Branch]]:
        """Play `plan` from tick 1, or on from `mark` (the start of the tick where its parent plan
        branched: every earlier tick of the two runs is the parent's)."""
        run = _Run(self, plan)
        old, new = run.sides
        going = [True, True]
        start = 1
        if mark is not None:
            self.ex_old._restore(mark.old)
            self.ex_new._restore(mark.new)
            old.pos, new.pos = dict(mark.pos_old), dict(mark.pos_new)
            start = mark.tick
        else:
            self.ex_old._restore(self.ex_old._initial)
            self.ex_new._restore(self.ex_new._initial)
        run.mark = mark
        try:
            for n in range(start, self.max_ticks + 1):
                run.tick_no = n
                if n != start or mark is None:
                    run.mark = self._mark(n, old, new) if self.resume else None
                old.events = []
                new.events = []
                going[0] = old.tick(n, self.clock_ms)
                going[1] = new.tick(n, self.clock_ms)
                if len(new.events) != len(old.events):
                    raise _Differ()
                if not going[0]:  # both over alike (the same last event)
                    return "done", run, None
            return "ticks", run, None
        except _Branch as b:
            return "branch", run, b
        except _Stop as s:
            return s.reason, run, None
        except _Differ:
            return "differ", run, None

    def decide(self) -> Outcome:
        t0 = time.perf_counter()
        restore = _install(self.ex_old.nodes + self.ex_new.nodes)
        runs = 0
        why = ""
        queue: deque[tuple[dict[str, tuple[int, ...]], Optional[_Mark]]] = deque([({}, None)])
        try:
            while queue:
                plan, mark = queue.popleft()
                end, run, branch = self._run(plan, mark)
                runs += 1
                if end == "differ":
                    return Outcome(
                        False, False, self.max_ticks, runs, len(self.seen), time.perf_counter() - t0, plan, run.tick_no
                    )
                if branch is not None:
                    for o in branch.options:
                        ext = dict(plan)
                        ext[branch.name] = plan.get(branch.name, ()) + (o,)
                        queue.append((ext, run.mark))
                elif end == "ticks" and not why:
                    why = "ticks"
                elif end == "states":
                    why = "states"
                    break
        finally:
            restore()
        return Outcome(
            True,
            not why,
            self.max_ticks,
            runs,
            len(self.seen),
            time.perf_counter() - t0,
            why_bounded=why,
        )


# ====================================================================== replaying a scenario
class _Replayer(_Recorder):
    """An engine run on a scenario file's cursors, its observable events kept per tick."""

    def __init__(self, mission: Mission, scenario: Scenario, key_of: Callable[[str], str], observe: frozenset) -> None:
        super().__init__(mission, key_of, scenario, observe)
        self.real = {}
        for node in self.interp.nodes:
            if isinstance(node, _SCRIPTED):
                self.real[id(node)] = node.cursor
        _hook_leaves(self)

    def leaf_call(self, node: TreeNode, key: str, condition: bool) -> int:
        cur = self.real[id(node)]
        v = cur.next() if cur is not None else self.interp.rt.default
        self.call_event(node, key, v)
        return v


def observe(
    mission: Mission,
    scenario: Scenario,
    key_of: Callable[[str], str] = lambda n: n,
    observables: Optional[frozenset] = None,
) -> list[list[Event]]:
    """The observable events of each tick of a scenario's run (what `btgen diff` compares)."""
    rec = _Replayer(mission, scenario, key_of, DEFAULT_OBSERVE if observables is None else observables)
    restore = _install(rec.interp.nodes)
    ticks: list[list[Event]] = []
    try:
        for n in range(1, scenario.ticks + 1):
            rec.events = []
            going = rec.tick(n, scenario.clock_ms)
            ticks.append(rec.events)
            if not going:
                break
    finally:
        restore()
    return ticks


def first_difference(a: list[list[Event]], b: list[list[Event]]) -> Optional[tuple[int, int]]:
    """(tick index, event index) of the first difference of two observed runs, None when equal."""
    for t in range(max(len(a), len(b))):
        ea = a[t] if t < len(a) else []
        eb = b[t] if t < len(b) else []
        for i in range(max(len(ea), len(eb))):
            if i >= len(ea) or i >= len(eb) or ea[i] != eb[i]:
                return t, i
    return None


def difference_record(a: list[list[Event]], b: list[list[Event]], at: tuple[int, int]) -> dict:
    """The first difference `at` of two observed runs, for reports: tick and event (from 1) and
    each side's event as the traces print it (None where that side has no such event)."""
    t, i = at
    ea = a[t][i] if t < len(a) and i < len(a[t]) else None
    eb = b[t][i] if t < len(b) and i < len(b[t]) else None
    return {
        "tick": t + 1,
        "event": i + 1,
        "old": event_text(ea) if ea else None,
        "new": event_text(eb) if eb else None,
    }
