"""`btgen explore`: every result the leaves can give, up to a bound, run on the interpreter.

Each run is a *plan*: the results chosen so far for the user leaves' calls, in
call order (Actions SUCCESS/FAILURE/RUNNING at each onStart/onRunning,
Conditions SUCCESS/FAILURE at each tick). A run plays its plan on the
interpreter (interp/engine.py, the executable semantics: scripts, timers and
the blackboard run as they do) and stops at the first call the plan does not
cover: that is a branch point, and the search goes on depth first with each
possible result appended. One interpreter serves every run: its state (each
node's members, the blackboards, the clock) is saved at each tick start, and a
plan is played on from the last tick start it shares with the plan before it
(depth first, that is most of it), restored there; building an interpreter per
run, or replaying from tick 1, gives the same search six times slower
(`test_explore.py` compares them; `bench/explore_speed.py` measures).
Scripted leaves share the results of their name, as scenario files do, so
every plan is a scenario file: the statuses each leaf name returned, in order.

Repeats are cut by a state hash taken at every branch point: each node's status
and members (counters, indices, flags), the blackboard values (update counters
only when an entry-update node reads them; the clock only when a timer node
exists), and the chain of nodes being ticked with the status each had when its
tick began (what the Python frames of the controls hold). A state already
reached at the same or an earlier tick is not explored again: what it leads to
was explored from there.

Coverage goals are each node ticked and each status each node can return (the
statuses `btgen analyze` finds possible). Every run that ends (root completed,
--ticks reached, --depth reached, state repeated) is a candidate, its goals kept
as the bits of an int; a greedy set cover of them, without the runs the others
make redundant, gives the scenario files written with -o.

Properties (--assert), checked at every node return (the root's is the end of a tick):

    never A STATUS                 A never returns STATUS
    never A STATUS before B STATUS A does not return STATUS while B has not yet
    at most one child of N RUNNING no two children of N are RUNNING at once

A, B and N are node names (the name attribute, else the ID) or `#UID`; a name
used by several nodes means any of them. STATUS is SUCCESS, FAILURE, RUNNING or
SKIPPED. The first violation stops the search (the other properties are then
undecided); its plan is the counterexample, printed with its trace in the report
and written as a scenario file with -o. With --keep-going the search goes on, each
property keeping its first violation. Each property's line says `holds (N states,
exhaustive)` when no run was cut by a bound, else which bound cut the search.

On a terminal, stderr shows a progress line while the search runs (goals covered,
states, states per second, elapsed); nothing when stderr is not a terminal.
"""

from __future__ import annotations

import re
import time
from collections import deque
from dataclasses import dataclass, field
from itertools import repeat
from operator import attrgetter
from typing import Callable, Optional

from btgen.diagnostics import UserError
from btgen.interp import actions as iactions
from btgen.interp.engine import Interpreter
from btgen.interp.nav2 import EnvInputDecorator
from btgen.interp.tree import FAILURE, IDLE, RUNNING, SKIPPED, SUCCESS, TreeNode
from btgen.lang import values
from btgen.lang.model import Mission
from btgen.tools import obligations


def _discard(_piece: tuple[str, str]) -> None:
    pass


NAMES = {IDLE: "IDLE", RUNNING: "RUNNING", SUCCESS: "SUCCESS", FAILURE: "FAILURE", SKIPPED: "SKIPPED"}
BY_NAME = {v: k for k, v in NAMES.items()}
# Node members that are not state: TreeNode's own (its status is hashed apart, the rest is
# identity and configuration) and the structure and configuration of its subclasses.
_NOT_STATE = frozenset(TreeNode.__slots__) | {
    "children",
    "child",
    "cursor",
    "default",
    "script",
    "key",
    "elem",
    "static_queue",
    "asynch",
    "result",
    "if_not_updated",
    "cases",
}
_TIMERS = {"Sleep", "Delay", "Timeout", "RateController"}  # nodes that read the clock
_HOOKED = "execute_tick"  # the method every visit goes through, wrapped while exploring
_ENTRY_NODES = {"WasEntryUpdated", "SkipUnlessUpdated", "WaitValueUpdate"}


class _Branch(Exception):
    def __init__(self, options: tuple[int, ...]) -> None:
        self.options = options


class _Stop(Exception):
    def __init__(self, reason: str) -> None:
        self.reason = reason


@dataclass
class Property:
    text: str
    kind: str  # never | before | one-running
    a: str = ""
    a_status: int = 0
    b: str = ""
    b_status: int = 0


_PROP_RES = (
    (re.compile(r"never\s+(\S+)\s+(\w+)\s+before\s+(\S+)\s+(\w+)"), "before"),
    (re.compile(r"never\s+(\S+)\s+(\w+)"), "never"),
    (re.compile(r"at\s+most\s+one\s+child\s+of\s+(\S+)\s+RUNNING"), "one-running"),
)


def parse_property(text: str) -> Property:
    """One --assert property; UserError-free: raises ValueError with the reason."""
    t = text.strip()
    for rx, kind in _PROP_RES:
        m = rx.fullmatch(t)
        if not m:
            continue
        g = m.groups()
        statuses = [g[i] for i in (1, 3) if i < len(g)]
        for s in statuses:
            if s not in ("SUCCESS", "FAILURE", "RUNNING", "SKIPPED"):
                raise ValueError(f"`{s}` is not a status (SUCCESS, FAILURE, RUNNING or SKIPPED)")
        if kind == "before":
            return Property(t, kind, g[0], BY_NAME[g[1]], g[2], BY_NAME[g[3]])
        if kind == "never":
            return Property(t, kind, g[0], BY_NAME[g[1]])
        return Property(t, kind, g[0])
    raise ValueError(
        "unknown property: use `never A STATUS`, `never A STATUS before B STATUS` or `at most one child of N RUNNING`"
    )


@dataclass
class Path:
    plan: tuple[int, ...]
    picks: tuple[tuple[str, int], ...]  # (leaf name, status) in call order
    ticks: int
    goals: frozenset
    end: str
    mask: int = 0  # the goals as bits (Explorer.bit)


@dataclass
class Result:
    goals: set  # every goal: ("node", uid) and ("outcome", uid, status)
    covered: set
    paths: list[Path]  # the covering set
    runs: int
    states: int
    seconds: float
    truncated: bool
    violations: list[tuple[Property, Path]] = field(default_factory=list)
    max_visits: int = 0  # most nodes visited in one tick, over every run
    max_hooks: int = 0
    errors: list = field(default_factory=list)  # (Diagnostic, Path): run-time errors some run meets
    bounded_by: tuple[str, ...] = ()  # "ticks", "depth": some run was cut there (else exhaustive)
    stopped_at_violation: bool = False  # the search ended at the first violation (no --keep-going)


# ====================================================================== one run
class _Run:
    """One plan played on the explorer's interpreter (restored to where the plan starts to
    differ from the last one played: Explorer.run), with the record the search needs."""

    def __init__(self, ex: Explorer, plan: tuple[int, ...]) -> None:
        self.ex = ex
        self.plan = plan
        self.pos = 0
        self.picks: list[tuple[str, int]] = []
        self.goals: set = set()
        self.chain: list[tuple[TreeNode, int]] = []
        self.tick_no = 0
        self.seen_return: set[tuple[int, int]] = set()
        self.visits = 0
        self.hooks = 0
        self.interp = ex.interp

    def pick(self, node: TreeNode, condition: bool) -> int:
        self.hooks += 1
        if self.pos < len(self.plan):
            v = self.plan[self.pos]
        else:
            if self.pos >= self.ex.depth:
                raise _Stop("depth")
            if self.ex.merge:
                key = self.ex.state_key(self)
                best = self.ex.seen.get(key)
                if best is not None and best <= self.tick_no:
                    raise _Stop("repeat")
                self.ex.seen[key] = self.tick_no
            else:
                self.ex.seen[(len(self.ex.seen),)] = self.tick_no
            raise _Branch((SUCCESS, FAILURE) if condition else (SUCCESS, FAILURE, RUNNING))
        self.pos += 1
        self.picks.append((node.name, v))
        if isinstance(node, EnvInputDecorator):
            self.goals.add(("input", node.uid, v))
        return v


class _Cursor:
    """A scripted leaf's results: the plan of the run being played."""

    __slots__ = ("ex", "node", "condition")

    def __init__(self, ex: Explorer, node: TreeNode) -> None:
        self.ex = ex
        self.node = node
        # a Condition, or an Action implemented synchronously (--sync): SUCCESS or FAILURE only
        self.condition = isinstance(node, (iactions.ScriptedCondition, EnvInputDecorator)) or node.reg_id in ex.sync

    def next(self) -> int:
        run = self.ex.current
        assert run is not None
        return run.pick(self.node, self.condition)


_IMMUTABLE = frozenset({int, str, bool, float, type(None), tuple, frozenset})


def _copied(v, memo: dict):
    """A value of the interpreter's state, copied when it is mutated in place (a Parallel's set
    of completed children, a Loop's queue). One object held in two places (a queue a Loop pops
    that is also an entry's value, an entry copied into another) is copied once (`memo`), so
    the copies are shared as the originals were."""
    if type(v) in _IMMUTABLE:
        return v
    if not isinstance(v, (values.Queue, set, list, dict)):
        return v
    c = memo.get(id(v))
    if c is None:
        c = values.Queue(v.element_type, v) if isinstance(v, values.Queue) else type(v)(v)
        memo[id(v)] = c
    return c


_UNSET = object()
_KEY_SCALAR = frozenset({int, str, bool, float})
_KEY_PLAIN = frozenset({int, str, bool, float, type(None)})


@dataclass
class _Mark:
    """The interpreter and the run's record at the start of a tick, after `pos` picks: every
    plan that begins with those picks passes here, so it is played on from here."""

    tick: int
    pos: int
    state: tuple
    picks: tuple
    goals: frozenset
    seen_return: frozenset


# ====================================================================== the search
class Explorer:
    def __init__(
        self,
        mission: Mission,
        ticks: int = 8,
        depth: int = 200,
        clock_ms: int = 100,
        max_states: int = 200000,
        properties: tuple[Property, ...] = (),
        possible: Optional[dict[int, set[int]]] = None,
        merge: bool = True,
        sync: frozenset[str] = frozenset(),
        criteria: tuple[str, ...] = obligations.DEFAULT,
    ) -> None:
        self.merge = merge
        self.sync = sync
        self.keep_going = False  # go on after a property's first violation
        self.kept: list[tuple[Property, Path]] = []  # with keep_going: each property's first violation
        self.resume = True  # play a plan on from the last tick start it shares (False: from tick 1)
        # called about ten times a second while exploring: (states, goals covered, goals)
        self.on_progress: Optional[Callable[[int, int, int], None]] = None
        self.max_visits = 0
        self.max_hooks = 0
        self.mission = mission
        self.ticks = ticks
        self.depth = depth
        self.clock_ms = clock_ms
        self.max_states = max_states
        self.properties = properties
        self.seen: dict[tuple, int] = {}
        self.current: Optional[_Run] = None
        # One interpreter for every run: building one costs more than most runs (a name
        # quoted, ports resolved, entries created per node), so each run restores the state
        # it starts from instead (_Mark; `_initial` before the first tick).
        self.interp = probe = Interpreter(mission, None)
        probe.rt.now_ms = 0
        for node in probe.nodes:
            node.emit = _discard  # the search reads no trace; a counterexample is re-run for one
            if isinstance(node, (iactions.ScriptedAction, iactions.ScriptedCondition, EnvInputDecorator)):
                node.cursor = _Cursor(self, node)
        self.marks: list[_Mark] = []
        self.last_plan: tuple[int, ...] = ()
        self.nodes = probe.nodes
        self.criteria = criteria
        self.shown: dict[tuple, tuple] = {}  # MC/DC obligation -> its pair (A, B, unique)
        # the goals of the criteria beyond nodes and outcomes (tools/obligations.py)
        self.obligations = obligations.build(probe.nodes, possible, obligations.kinds_of(criteria))
        if self.obligations.halt_uids:
            for node in probe.nodes:
                node.emit = obligations.halt_emit(node, _discard, self._sink)
        ids = {n.reg_id for n in probe.nodes}
        self.use_clock = bool(ids & _TIMERS)
        self.use_seq = bool(ids & _ENTRY_NODES)
        self.possible = possible
        self._fields: dict[type, tuple[str, ...]] = {}
        for node in probe.nodes:
            cls = type(node)
            if cls not in self._fields:
                names: list[str] = []
                for k in cls.__mro__:
                    for s in getattr(k, "__slots__", ()):
                        if s not in _NOT_STATE and s not in names:
                            names.append(s)
                self._fields[cls] = tuple(names)
        self._state_slots = [(node, ("status", *self._fields[type(node)])) for node in probe.nodes]
        # state_key's reading of each node: status and fields at once; `check` when a field
        # may hold something other than a number or a string (a set, a queue, None for now)
        self._key_getters: list[tuple[TreeNode, Callable, bool]] = []
        for node, slots in self._state_slots:
            get = attrgetter(*slots) if len(slots) > 1 else (lambda n: (n.status,))
            initial = tuple(getattr(node, s, None) for s in slots)
            self._key_getters.append((node, get, any(type(v) not in _KEY_SCALAR for v in initial)))
        self._bbs = list({id(n.bb): n.bb for n in probe.nodes}.values())
        self._initial = self._save()
        self.bit: dict[tuple, int] = {}  # goal -> its bit in Path.mask
        self.reached: set = set()
        self.by_name: dict[str, list[int]] = {}
        for i, n in enumerate(probe.nodes):
            self.by_name.setdefault(n.name, []).append(i)
            self.by_name.setdefault(f"#{n.uid}", []).append(i)
        for p in properties:
            for name in (p.a, p.b):
                if name and name not in self.by_name:
                    raise ValueError(f"property `{p.text}`: no node is named `{name}`")

    # -- the interpreter's whole state, saved and restored
    def _save(self) -> tuple:
        """(per node: its state slots' values, and whether any needs copying or is unset),
        the blackboards' entries, the clock. Most values are ints and strings: restoring
        them is one setattr each, done by map() (_restore)."""
        memo: dict = {}
        nodes = []
        for n, names in self._state_slots:
            saved = tuple(getattr(n, s, _UNSET) for s in names)
            plain = all(type(v) in _IMMUTABLE for v in saved)
            nodes.append((n, names, saved if plain else tuple(_copied(v, memo) for v in saved), plain))
        bbs = tuple(
            tuple((k, e, e.type_name, _copied(e.value, memo), e.sequence_id) for k, e in bb._storage.items())
            for bb in self._bbs
        )
        return tuple(nodes), bbs, self.interp.rt.now_ms

    def _restore(self, state: tuple) -> None:
        nodes, bbs, now = state
        memo: dict = {}
        for node, names, saved, plain in nodes:
            if plain:
                deque(map(setattr, repeat(node, len(names)), names, saved), 0)
                continue
            for name, v in zip(names, saved):
                if v is _UNSET:
                    if hasattr(node, name):
                        delattr(node, name)
                else:
                    setattr(node, name, _copied(v, memo))
        for bb, entries in zip(self._bbs, bbs):
            storage = bb._storage
            storage.clear()
            for k, e, type_name, value, seq in entries:
                e.type_name, e.value, e.sequence_id = type_name, _copied(value, memo), seq
                storage[k] = e
        self.interp.rt.now_ms = now
        self.interp.rt.buf.clear()

    # -- state
    def state_key(self, run: _Run) -> tuple:
        """What decides the rest of a run from a branch point (see the module's docstring)."""
        parts: list = []
        for node, getter, check in self._key_getters:
            t = getter(node)
            if check:
                t = tuple(v if type(v) in _KEY_PLAIN else repr(v) for v in t)
            parts.append(t)
        use_seq = self.use_seq
        for bb in self._bbs:
            for k, e in sorted(bb._storage.items()):
                v = e.value
                # the type is part of the value: 1, 1.0, True and "1" are different entries
                parts.append((k, type(v), v if type(v) in _KEY_PLAIN else repr(v), e.sequence_id if use_seq else 0))
        if self.use_clock:
            parts.append(run.interp.rt.now_ms)
        parts.append(tuple((n.uid, st) for n, st in run.chain))
        parts.append(tuple(run.seen_return) if any(p.kind == "before" for p in self.properties) else ())
        return tuple(parts)

    def key_of_interpreter(self, interp: Interpreter) -> tuple:
        """`state_key` at a tick boundary of another interpreter of the same mission (its nodes
        in this explorer's order): what `btgen verify --probabilities` keys its chain by."""
        own = interp is self.interp  # `btgen diff` plays its runs on the explorer's interpreter
        index = None if own else {id(n): i for i, n in enumerate(self.nodes)}
        parts: list = []
        for node, getter, check in self._key_getters:
            t = getter(node if index is None else interp.nodes[index[id(node)]])
            if check:
                t = tuple(v if type(v) in _KEY_PLAIN else repr(v) for v in t)
            parts.append(t)
        for bb in self._bbs if own else {id(n.bb): n.bb for n in interp.nodes}.values():
            for k, e in sorted(bb._storage.items()):
                v = e.value
                parts.append(
                    (k, type(v), v if type(v) in _KEY_PLAIN else repr(v), e.sequence_id if self.use_seq else 0)
                )
        if self.use_clock:
            parts.append(interp.rt.now_ms)
        return tuple(parts)

    def _sink(self) -> Optional[set]:
        run = self.current
        return run.goals if run is not None else None

    # -- instrumentation: every execute_tick of the run's nodes
    def _install(self) -> Callable[[], None]:
        restore_hooks = obligations.Hooks(self.obligations, self._sink).install()
        restore_ticks = self._install_ticks()

        def restore() -> None:
            restore_ticks()
            restore_hooks()

        return restore

    def _install_ticks(self) -> Callable[[], None]:
        classes = {k for n in self.nodes for k in type(n).__mro__ if issubclass(k, TreeNode)}
        patched: list[tuple[type, object]] = []
        ex = self

        def wrap(original):
            def execute_tick(node):
                run = ex.current
                if run is None or (run.chain and run.chain[-1][0] is node):
                    return original(node)
                run.visits += 1
                run.goals.add(("node", node.uid))
                run.chain.append((node, node.status))
                try:
                    result = original(node)
                finally:
                    run.chain.pop()
                run.goals.add(("outcome", node.uid, result))
                ex.check(run, node, result)
                return result

            return execute_tick

        for cls in classes:
            if "execute_tick" in cls.__dict__:
                original = cls.__dict__["execute_tick"]
                patched.append((cls, original))
                setattr(cls, _HOOKED, wrap(original))

        def restore() -> None:
            for cls, original in patched:
                setattr(cls, _HOOKED, original)

        return restore

    def check(self, run: _Run, node: TreeNode, result: int) -> None:
        for p in self.properties:
            if p.kind == "never" and result == p.a_status and node in self._nodes_of(run, p.a):
                self._violated(run, p)
            if p.kind == "before":
                if result == p.b_status and node in self._nodes_of(run, p.b):
                    run.seen_return.add((p.b_status, id(p)))
                if (
                    result == p.a_status
                    and node in self._nodes_of(run, p.a)
                    and (p.b_status, id(p)) not in run.seen_return
                ):
                    self._violated(run, p)
            if p.kind == "one-running":
                for parent in self._nodes_of(run, p.a):
                    kids = getattr(parent, "children", None) or []
                    if sum(1 for c in kids if c.status == RUNNING) > 1:
                        self._violated(run, p)

    def _violated(self, run: _Run, prop: Property) -> None:
        """A property fails here: the run stops (its plan is the counterexample), or, with
        --keep-going, the first violation of each property is kept and the run goes on (what
        only a violating run reaches is reached)."""
        if not self.keep_going:
            raise _Violation(prop)
        if all(p is not prop for p, _ in self.kept):
            picks = tuple(run.picks)
            self.kept.append((prop, Path(run.plan[: run.pos], picks, max(run.tick_no, 1), frozenset(), "violation")))

    def _nodes_of(self, run: _Run, name: str) -> list[TreeNode]:
        return [run.interp.nodes[i] for i in self.by_name.get(name, ())]

    def run(self, plan: tuple[int, ...]) -> tuple[str, _Run, Optional[tuple[int, ...]]]:
        """Play `plan`: from the latest tick start the last plan played passed with a prefix
        of this one's picks (the search is depth first, so that is most of the plan)."""
        run = _Run(self, plan)
        last = self.last_plan
        same = 0
        for a, b in zip(plan, last):
            if a != b:
                break
            same += 1
        marks = self.marks
        if not self.resume:
            marks.clear()
        while marks and marks[-1].pos > same:
            marks.pop()
        if marks:
            mark = marks[-1]
            self._restore(mark.state)
            run.pos = mark.pos
            run.picks = list(mark.picks)
            run.goals = set(mark.goals)
            run.seen_return = set(mark.seen_return)
            first = mark.tick
        else:
            self._restore(self._initial)
            first = 1
        self.last_plan = plan
        self.current = run
        interp = run.interp
        try:
            for n in range(first, self.ticks + 1):
                run.tick_no = n
                if not marks or marks[-1].tick < n:
                    marks.append(
                        _Mark(
                            n,
                            run.pos,
                            self._save(),
                            tuple(run.picks),
                            frozenset(run.goals),
                            frozenset(run.seen_return),
                        )
                    )
                if n > 1 and self.clock_ms:
                    interp.advance_clock(self.clock_ms)
                visits, hooks = run.visits, run.hooks
                status = interp.tick_once()
                self.max_visits = max(self.max_visits, run.visits - visits)
                self.max_hooks = max(self.max_hooks, run.hooks - hooks)
                if status.name in ("SUCCESS", "FAILURE"):
                    return "done", run, None
            return "ticks", run, None
        except _Branch as b:
            return "branch", run, b.options
        except _Stop as s:
            return s.reason, run, None
        except _Violation as v:
            run.violation = v.prop  # type: ignore[attr-defined]
            return "violation", run, None
        except UserError as e:  # a run-time error (a script, a port): a finding of its own
            run.error = e.diagnostics[0] if e.diagnostics else None  # type: ignore[attr-defined]
            return "error", run, None
        finally:
            self.current = None

    def explore(self) -> Result:
        self.max_visits = self.max_hooks = 0
        restore = self._install()
        t0 = time.perf_counter()
        candidates: dict[int, Path] = {}
        covered: set = set()
        violations: list[tuple[Property, Path]] = []
        errors: list[tuple[object, Path]] = []
        self.kept = violations  # with keep_going, _violated adds to it
        runs = 0
        truncated = stopped = False
        cut: set[str] = set()
        goal_set = self.goals() if self.on_progress is not None else set()
        next_report = t0 + 0.1
        stack: list[tuple[int, ...]] = [()]
        try:
            while stack:
                if len(self.seen) >= self.max_states:
                    truncated = True
                    break
                plan = stack.pop()
                end, run, options = self.run(plan)
                runs += 1
                if self.on_progress is not None and runs % 16 == 0:
                    now = time.perf_counter()
                    if now >= next_report:
                        next_report = now + 0.1
                        self.on_progress(len(self.seen), len(covered & goal_set), len(goal_set))
                if end in ("ticks", "depth"):
                    cut.add(end)
                if options is not None:
                    for o in reversed(options):
                        stack.append(plan + (o,))
                    continue
                if self.obligations.post:
                    run.goals |= obligations.derived(self.obligations, run.goals)
                mask = 0
                for goal in run.goals:
                    b = self.bit.get(goal)
                    if b is None:
                        b = self.bit[goal] = len(self.bit)
                    mask |= 1 << b
                path = Path(plan, tuple(run.picks), max(run.tick_no, 1), frozenset(run.goals), end, mask)
                if end == "error" and len(errors) < 5:
                    diag = run.error  # type: ignore[attr-defined]
                    if diag is not None and all(str(diag) != str(d) for d, _ in errors):
                        errors.append((diag, path))
                if end == "violation":
                    prop = run.violation  # type: ignore[attr-defined]
                    if not any(p is prop for p, _ in violations):
                        violations.append((prop, path))
                    if not self.keep_going:
                        stopped = bool(stack)
                        stack.clear()
                # every finished run (a violating one too: what it reached, it reached) is a
                # candidate for the cover (one per set of goals, the shortest): kept as bits,
                # 37,000 runs of the Lab Tour take a few megabytes
                if not path.goals <= covered:
                    covered |= path.goals
                old = candidates.get(mask)
                if old is None or len(path.picks) < len(old.picks):
                    candidates[mask] = Path(plan, path.picks, path.ticks, frozenset(), end, mask)
        finally:
            restore()
        seconds = time.perf_counter() - t0
        self.reached = covered  # every goal a run reached, possible or not (tests check analyze with it)
        goals = self.goals()
        # MC/DC: an obligation is shown by a pair of evaluations; the pair's two evaluations
        # are what the covering set must reach (one run may reach both)
        self.shown = obligations.mcdc_shown(self.obligations, covered)
        wanted = set(goals)
        for goal, (a, b, _) in self.shown.items():
            site = self.obligations.site(goal)
            wanted |= {obligations.eval_goal(site, a), obligations.eval_goal(site, b)}
        return Result(
            goals | set(self.obligations.mcdc),
            (covered & goals) | set(self.shown),
            self._cover(list(candidates.values()), wanted),
            runs,
            len(self.seen),
            seconds,
            truncated,
            violations,
            self.max_visits,
            self.max_hooks,
            errors,
            tuple(sorted(cut)),
            stopped,
        )

    def replay(self, scenario) -> set:
        """The goals one scenario reaches (every kind, and the MC/DC evaluations), on an
        interpreter of its own with this explorer's hooks: what `btgen cover` measures."""
        interp = Interpreter(self.mission, scenario)
        run = _Run(self, ())
        run.interp = interp
        for node in interp.nodes:
            node.emit = obligations.halt_emit(node, _discard, self._sink)
        restore = self._install()
        self.current = run
        try:
            for n in range(1, scenario.ticks + 1):
                if n > 1 and scenario.clock_ms:
                    interp.advance_clock(scenario.clock_ms)
                status = interp.tick_once()
                if status.name in ("SUCCESS", "FAILURE"):
                    break
        except UserError:
            pass  # a run-time error ends the run; what it reached, it reached
        finally:
            self.current = None
            restore()
        return run.goals | obligations.derived(self.obligations, run.goals)

    def _cover(self, paths: list[Path], goals: set) -> list[Path]:
        """Greedy set cover (the run adding most goals first, the shorter on a tie), then each
        chosen run whose goals the others cover is dropped."""
        want = 0
        for goal in goals:
            if goal in self.bit:
                want |= 1 << self.bit[goal]
        left = want
        chosen: list[Path] = []
        while left:
            best = max(paths, key=lambda p: ((p.mask & left).bit_count(), -len(p.picks)))
            if not best.mask & left:
                break
            chosen.append(best)
            left &= ~best.mask
        for p in list(chosen):
            others = 0
            for q in chosen:
                if q is not p:
                    others |= q.mask
            if (p.mask & want) & ~others == 0:
                chosen.remove(p)
        names = {b: g for g, b in self.bit.items()}
        return [
            Path(
                p.plan,
                p.picks,
                p.ticks,
                frozenset(names[b] for b in range(len(names)) if p.mask >> b & 1),
                p.end,
                p.mask,
            )
            for p in chosen
        ]

    def goals(self) -> set:
        """The goals of the selected criteria but MC/DC's (each shown by a pair of runs)."""
        out: set = set(self.obligations.goals)
        if "node" not in self.criteria and "outcome" not in self.criteria:
            return out
        for i, n in enumerate(self.nodes):
            if self.possible is not None and not self.possible.get(i):
                continue  # never ticked whatever the leaves return (btgen analyze says why)
            if "node" in self.criteria:
                out.add(("node", n.uid))
            if "outcome" not in self.criteria:
                continue
            for st in self.possible.get(i, ()) if self.possible is not None else (SUCCESS, FAILURE, RUNNING):
                out.add(("outcome", n.uid, st))
            if isinstance(n, EnvInputDecorator):  # its input of the environment: yes and no
                out.add(("input", n.uid, SUCCESS))
                out.add(("input", n.uid, FAILURE))
        return out


class _Violation(Exception):
    def __init__(self, prop: Property) -> None:
        self.prop = prop
