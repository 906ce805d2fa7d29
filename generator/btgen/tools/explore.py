"""`btgen explore`: every result the leaves can give, up to a bound, run on the interpreter.

Each run is a *plan*: the results chosen so far for the user leaves' calls, in
call order (Actions SUCCESS/FAILURE/RUNNING at each onStart/onRunning,
Conditions SUCCESS/FAILURE at each tick). A run replays its plan on a fresh
interpreter (interp/engine.py, the executable semantics: scripts, timers and
the blackboard run as they do) and stops at the first call the plan does not
cover: that is a branch point, and the search goes on depth first with each
possible result appended. Scripted leaves share the results of their name, as
scenario files do, so every plan is a scenario file: the statuses each leaf name
returned, in order.

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
SKIPPED. A violation stops that run; its plan is written as a scenario file and
its trace printed.
"""

from __future__ import annotations

import json
import os
import re
import sys
import time
from dataclasses import dataclass, field
from typing import Callable, Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.fileio import Manifest, check_output, write_output
from btgen.interp import actions as iactions
from btgen.interp.engine import Interpreter
from btgen.interp.scenario import MAX_VALUE, format_scenario, leaf_locs, parse_scenario_text
from btgen.interp.tree import FAILURE, IDLE, RUNNING, SKIPPED, SUCCESS, TreeNode
from btgen.lang.model import Mission

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
_TIMERS = {"Sleep", "Delay", "Timeout"}
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


# ====================================================================== one run
class _Run:
    """A fresh interpreter replaying a plan, with the hooks the search needs."""

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
        self.interp = Interpreter(ex.mission, None)
        self.interp.rt.now_ms = 0
        for node in self.interp.nodes:
            if isinstance(node, (iactions.ScriptedAction, iactions.ScriptedCondition)):
                node.cursor = _Cursor(self, node)

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
        return v


class _Cursor:
    __slots__ = ("run", "node", "condition")

    def __init__(self, run: _Run, node: TreeNode) -> None:
        self.run = run
        self.node = node
        self.condition = isinstance(node, iactions.ScriptedCondition)

    def next(self) -> int:
        return self.run.pick(self.node, self.condition)


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
    ) -> None:
        self.merge = merge
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
        probe = Interpreter(mission, None)
        self.nodes = probe.nodes
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

    # -- state
    def state_key(self, run: _Run) -> tuple:
        parts: list = []
        for node in run.interp.nodes:
            parts.append(node.status)
            for f in self._fields[type(node)]:
                v = getattr(node, f, None)
                parts.append(v if isinstance(v, (int, str, bool, float, type(None))) else repr(v))
        bbs = {id(n.bb): n.bb for n in run.interp.nodes}
        for bb in bbs.values():
            for k in sorted(bb.local_keys()):
                e = bb.local_entry(k)
                assert e is not None
                parts.append((k, repr(e.value), e.sequence_id if self.use_seq else 0))
        if self.use_clock:
            parts.append(run.interp.rt.now_ms)
        parts.append(tuple((n.uid, st) for n, st in run.chain))
        parts.append(tuple(run.seen_return) if any(p.kind == "before" for p in self.properties) else ())
        return tuple(parts)

    # -- instrumentation: every execute_tick of the run's nodes
    def _install(self) -> Callable[[], None]:
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
                raise _Violation(p)
            if p.kind == "before":
                if result == p.b_status and node in self._nodes_of(run, p.b):
                    run.seen_return.add((p.b_status, id(p)))
                if (
                    result == p.a_status
                    and node in self._nodes_of(run, p.a)
                    and (p.b_status, id(p)) not in run.seen_return
                ):
                    raise _Violation(p)
            if p.kind == "one-running":
                for parent in self._nodes_of(run, p.a):
                    kids = getattr(parent, "children", None) or []
                    if sum(1 for c in kids if c.status == RUNNING) > 1:
                        raise _Violation(p)

    def _nodes_of(self, run: _Run, name: str) -> list[TreeNode]:
        return [run.interp.nodes[i] for i in self.by_name.get(name, ())]

    def run(self, plan: tuple[int, ...]) -> tuple[str, _Run, Optional[tuple[int, ...]]]:
        run = _Run(self, plan)
        self.current = run
        interp = run.interp
        try:
            for n in range(1, self.ticks + 1):
                run.tick_no = n
                if n > 1 and self.clock_ms:
                    interp.advance_clock(self.clock_ms)
                visits, hooks = run.visits, run.hooks
                status = interp.tick_once()
                self.max_visits = max(self.max_visits, run.visits - visits)
                self.max_hooks = max(self.max_hooks, run.hooks - hooks)
                interp.take_text()
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
        runs = 0
        truncated = False
        stack: list[tuple[int, ...]] = [()]
        try:
            while stack:
                if len(self.seen) >= self.max_states:
                    truncated = True
                    break
                plan = stack.pop()
                end, run, options = self.run(plan)
                runs += 1
                if options is not None:
                    for o in reversed(options):
                        stack.append(plan + (o,))
                    continue
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
                    continue
                # every finished run is a candidate for the cover (one per set of goals, the
                # shortest): kept as bits, 37,000 runs of the Lab Tour take a few megabytes
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
        return Result(
            goals,
            covered & goals,
            self._cover(list(candidates.values()), goals),
            runs,
            len(self.seen),
            seconds,
            truncated,
            violations,
            self.max_visits,
            self.max_hooks,
            errors,
        )

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
        out: set = set()
        for i, n in enumerate(self.nodes):
            if self.possible is not None and not self.possible.get(i):
                continue  # never ticked whatever the leaves return (btgen analyze says why)
            out.add(("node", n.uid))
            for st in self.possible.get(i, ()) if self.possible is not None else (SUCCESS, FAILURE, RUNNING):
                out.add(("outcome", n.uid, st))
        return out


class _Violation(Exception):
    def __init__(self, prop: Property) -> None:
        self.prop = prop


# ====================================================================== scenario files
def scenario_text(path: Path, clock_ms: int, comment: str = "", where: Optional[dict[str, Loc]] = None) -> str:
    """The scenario file that replays a path: each leaf name's statuses in call order
    (interp.scenario.format_scenario: UserError at the leaf for a name the format cannot hold)."""
    per: dict[str, list[str]] = {}
    for name, st in path.picks:
        per.setdefault(name, []).append(NAMES[st])
    return format_scenario(path.ticks, list(per.items()), clock_ms, comment, where)


def _possible(mission: Mission, args) -> Optional[dict[int, set[int]]]:
    """The statuses `btgen analyze` finds possible per node (None when the mission does not lower)."""
    from btgen import pipeline
    from btgen.ir.lower import lower
    from btgen.tools.analyze import analyze_program

    try:
        options = pipeline.options_from_args(args).data
        program = lower(mission, options)
    except UserError:
        return None
    result = analyze_program(mission, program, options)
    return {
        i: ({BY_NAME[s] for s in result.outcomes[i]} if result.reachable[i] else set())
        for i in range(len(program.nodes))
    }


def check_ticks(args) -> None:
    """`--ticks` of a command that writes scenarios: what a scenario's `ticks` can hold."""
    if args.ticks > MAX_VALUE:
        raise cmdline.error(
            args, "--ticks", f"--ticks {args.ticks} is larger than a scenario's ticks can be ({MAX_VALUE})"
        )


def check_clock_ms(args) -> None:
    """`--clock-ms` of a command that writes scenarios: what a scenario's clock_ms can hold."""
    if args.clock_ms < 0:
        raise cmdline.error(args, "--clock-ms", "--clock-ms cannot be negative")
    if args.clock_ms > MAX_VALUE:
        raise cmdline.error(
            args, "--clock-ms", f"--clock-ms {args.clock_ms} is larger than a scenario's clock_ms can be ({MAX_VALUE})"
        )


def explore_command(args) -> int:
    from btgen import pipeline
    from btgen.interp.engine import trace_text

    mission = pipeline.load(args.mission, pipeline.options_from_args(args))
    print_diagnostics(mission.warnings)
    try:
        props = tuple(parse_property(t) for t in args.asserts)
    except ValueError as e:
        raise cmdline.error(args, "--assert", f"--assert: {e}") from None
    check_clock_ms(args)
    check_ticks(args)
    possible = _possible(mission, args)
    try:
        ex = Explorer(
            mission, args.ticks, args.depth, args.clock_ms, args.max_states, props, possible, not args.no_merge
        )
    except ValueError as e:
        raise cmdline.error(args, "--assert", f"--assert: {e}") from None
    result = ex.explore()
    where = leaf_locs(mission)
    # Every text first (a name no scenario can hold is refused before any file is written),
    # then every file, then the manifest that lets the next run remove exactly these.
    covering = [
        scenario_text(path, args.clock_ms, f"btgen explore: {len(path.goals)} goals", where) for path in result.paths
    ]
    counterexamples = [
        scenario_text(path, args.clock_ms, f"counterexample of: {prop.text}", where) for prop, path in result.violations
    ]
    reaching = [scenario_text(path, args.clock_ms, f"reaches: {diag}", where) for diag, path in result.errors]
    files: list[str] = []
    cx_files: list[str] = []
    error_files: list[str] = []
    if args.output_dir:
        try:
            os.makedirs(args.output_dir, exist_ok=True)
        except OSError as e:
            raise UserError(
                Diagnostic(Loc(args.output_dir, 1, 1), f"cannot create the output folder: {e.strerror or e}")
            ) from None
        stem = os.path.splitext(os.path.basename(args.mission))[0]
        files = [os.path.join(args.output_dir, f"{stem}-{i:03d}.scenario") for i in range(1, len(covering) + 1)]
        cx_files = [
            os.path.join(args.output_dir, f"counterexample-{k}.scenario") for k in range(1, len(counterexamples) + 1)
        ]
        error_files = [os.path.join(args.output_dir, f"error-{k}.scenario") for k in range(1, len(reaching) + 1)]
        outputs = list(zip(files + cx_files + error_files, covering + counterexamples + reaching))
        manifest = Manifest(args.output_dir, stem, "explore")
        manifest.check(mission.files)
        for name, _ in outputs:
            check_output(name, mission.files)
        for name, text in outputs:
            write_output(name, text.encode("utf-8"), mission.files)
        # what an earlier exploration of this mission wrote and this one did not is stale: a
        # set of files that together cover the mission must not mix two explorations
        manifest.replace([name for name, _ in outputs], mission.files)
    status = 0
    for k, (prop, _) in enumerate(result.violations):
        status = 1
        text = counterexamples[k]
        print(f"{args.mission}: property violated: {prop.text}", file=sys.stderr)
        if args.output_dir:
            print(f"  counterexample: {cx_files[k]}", file=sys.stderr)
        print("  scenario:", file=sys.stderr)
        for line in text.splitlines():
            print(f"    {line}", file=sys.stderr)
        print("  trace:", file=sys.stderr)
        try:
            trace = trace_text(mission, parse_scenario_text(text, "<counterexample>"))
        except UserError as e:
            trace = "".join(str(d) + "\n" for d in e.diagnostics)
        for line in trace.splitlines():
            print(f"    {line}", file=sys.stderr)
    for k, (diag, _) in enumerate(result.errors):
        status = 1
        print(f"{diag}", file=sys.stderr)
        text = reaching[k]
        if args.output_dir:
            print(f"  a run that reaches it: {error_files[k]}", file=sys.stderr)
        else:
            print("  a run that reaches it:", file=sys.stderr)
            for line in text.splitlines():
                print(f"    {line}", file=sys.stderr)
    uncovered = sorted(result.goals - result.covered, key=lambda g: (g[1], g[2] if len(g) > 2 else -1))
    names = {n.uid: n for n in ex.nodes}
    impossible = []
    if possible is not None:
        for i, n in enumerate(ex.nodes):
            if not possible.get(i):
                impossible.append(f'{n.uid} {n.reg_id} "{n.name}": never ticked (see `btgen analyze`)')
    why = "not reached within the bounds"
    if result.truncated:
        why += f" (stopped at --max-states {args.max_states})"
    else:
        why += f" (--ticks {args.ticks}, --depth {args.depth})"
    report = {
        "mission": args.mission,
        "runs": result.runs,
        "states": result.states,
        "seconds": round(result.seconds, 3),
        "states_per_second": round(result.states / result.seconds) if result.seconds > 0 else None,
        "goals": len(result.goals),
        "covered": len(result.covered),
        "node_goals": sum(1 for g in result.goals if g[0] == "node"),
        "nodes_covered": sum(1 for g in result.covered if g[0] == "node"),
        "scenarios": len(result.paths),
        "files": files,
        "max_nodes_visited_per_tick": result.max_visits,
        "max_leaf_hooks_per_tick": result.max_hooks,
        "uncovered": [
            (f'{g[1]} {names[g[1]].reg_id} "{names[g[1]].name}"' + (f" {NAMES[g[2]]}" if len(g) > 2 else " ticked"))
            for g in uncovered
        ],
        "never_ticked": impossible,
        "violations": [p.text for p, _ in result.violations],
        "run_time_errors": [str(d) for d, _ in result.errors],
    }
    if args.json:
        json.dump(report, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return status
    pct = 100.0 * len(result.covered) / len(result.goals) if result.goals else 100.0
    print(f"{args.mission}:")
    print(
        f"  runs {result.runs}, states {result.states}, {result.seconds:.2f} s ({report['states_per_second']} states/s)"
    )
    print(
        f"  coverage: {report['nodes_covered']}/{report['node_goals']} nodes, "
        f"{len(result.covered)}/{len(result.goals)} goals (nodes and outcomes) = {pct:.1f}%"
    )
    print(f"  scenarios: {len(result.paths)}" + (f" written to {args.output_dir}" if args.output_dir else ""))
    print(f"  most per tick seen: {result.max_visits} nodes visited, {result.max_hooks} leaf hooks")
    for line in impossible:
        print(f"  impossible: {line}")
    for line in report["uncovered"]:
        print(f"  uncovered: {line}: {why}")
    return status
