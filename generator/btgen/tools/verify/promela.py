"""The lowered program as a Promela model: one root tick is a sequence of steps of one process.

The model follows the node table of `ir.lower.Program` (creation order, SubTrees expanded,
the selected BehaviorTree.CPP version's switches) and mirrors, node kind by node kind, the
executable semantics of the reference interpreter (`interp/controls.py`, `decorators.py`,
`actions.py`): the same members (a Sequence's current child, a Repeat's count, a Parallel's
completed children ...), the same order of ticks, halts and status resets. What the
interpreter keeps but never reads again is not kept (a counter of an endless Repeat), so the
model's states are the interpreter's states without what cannot matter.

Leaves are free: each run of an Action's code (onStart, onRunning) answers SUCCESS, FAILURE or
RUNNING, each tick of a Condition SUCCESS or FAILURE, as far as the leaf contract allows; an
Action's RUNNING answers in a row can be bounded (`running_bound`). Every such choice prints
`@C <node> <status>` so a SPIN trail replays as the scenario that makes the same choices.

Scripts and pre/post conditions are tables over the reachable blackboards (`blackboard.py`),
Nav2's nodes are in `nav2.py`, the blackboard nodes (SetBlackboard, Switch, Loop ...) in
`bbnodes.py`. What the model does not translate is refused with a located
error (`Refusal`): user Controls and Decorators, most parameters read from the blackboard
(bbnodes.py reads a Repeat's and a Retry's count). Nothing is abstracted silently.

A subtree with few paths through a tick (`ModelOptions.atomic_paths`) is one atomic step:
SPIN stores no state inside it (`Emitter.atomic_root`).

Atoms are evaluated at the end of each tick: the model copies them into observation bits in
one `d_step`, so a never claim sees one value per tick (every LTL formula without X is
stutter-invariant, and X is refused). After the root returns SUCCESS or FAILURE the run ends
(as a scenario run does; so does a run that reaches --ticks): then no node is ticked or
returns any more, the statuses stay, and that observation stays for ever.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass, field
from typing import Optional

from btgen.diagnostics import Loc
from btgen.ir.lower import IRNode, Program
from btgen.lang import blackboard as bbmod
from btgen.lang.model import Mission
from btgen.lang.versions import Semantics
from btgen.tools.verify.bbjobs import BB_KINDS, PARAM_FROM_BB
from btgen.tools.verify.bbnodes import _OPEN as _HALT_TICK
from btgen.tools.verify.bbnodes import BlackboardNodeTicks, unique_labels
from btgen.tools.verify.blackboard import FREE, HALT, NO_RESULT, build_tables, lookup, result_is
from btgen.tools.verify.decorators import NONE, DecoratorTicks
from btgen.tools.verify.nav2 import NAV2_KINDS, Nav2Ticks, rate_ticks
from btgen.tools.verify.packing import pack, widths
from btgen.tools.verify.refusal import Refusal, refuse

__all__ = ["Refusal", "Emitter", "ModelOptions", "Observe", "emit_model"]

IDLE, RUNNING, SUCCESS, FAILURE, SKIPPED = 0, 1, 2, 3, 4
STATUS = {"IDLE": IDLE, "RUNNING": RUNNING, "SUCCESS": SUCCESS, "FAILURE": FAILURE, "SKIPPED": SKIPPED}
STATUS_NAME = {v: k for k, v in STATUS.items()}
MAX_PARALLEL = 30  # children of a Parallel (their completed set is a bit mask)
MAX_TIMER_TICKS = 250
D_STEP_LINES = 120  # the longest halt emitted as one d_step (SPIN refuses a few hundred statements)

SUPPORTED_KINDS = frozenset(
    {
        "Sequence",
        "AsyncSequence",
        "Fallback",
        "AsyncFallback",
        "SequenceWithMemory",
        "ReactiveSequence",
        "ReactiveFallback",
        "Parallel",
        "ParallelAll",
        "IfThenElse",
        "WhileDoElse",
        "Inverter",
        "ForceSuccess",
        "ForceFailure",
        "Repeat",
        "RetryUntilSuccessful",
        "KeepRunningUntilFailure",
        "RunOnce",
        "Timeout",
        "Delay",
        "SubTree",
        "AlwaysSuccess",
        "AlwaysFailure",
        "Sleep",
        "Action",
        "Condition",
        "TryCatch",
        "Script",
        "ScriptCondition",
        *NAV2_KINDS,
        *BB_KINDS,
    }
)
_WHY_NOT = {
    "UserControl": "a Control of the mission's own (its tick() is robot code; no contract for it)",
    "UserDecorator": "a Decorator of the mission's own (its tick() is robot code; no contract for it)",
}
_SEQUENCES = {"Sequence": (FAILURE, SUCCESS, False), "AsyncSequence": (FAILURE, SUCCESS, True)}
_SEQUENCES.update({"Fallback": (SUCCESS, FAILURE, False), "AsyncFallback": (SUCCESS, FAILURE, True)})
_REACTIVE = {"ReactiveSequence": (FAILURE, SUCCESS), "ReactiveFallback": (SUCCESS, FAILURE)}
_PARAM_PORTS = {
    "Parallel": ("success_count", "failure_count"),
    "ParallelAll": ("max_failures",),
    "Repeat": ("num_cycles",),
    "RetryUntilSuccessful": ("num_attempts",),
    "RunOnce": ("then_skip",),
    "Timeout": ("msec",),
    "Delay": ("delay_msec",),
    "Sleep": ("msec",),
    "TryCatch": ("catch_on_halt",),
    "RecoveryNode": ("number_of_retries",),
    "RateController": ("hz",),
    "RoundRobin": ("wrap_around",),
}


_refuse = refuse


@dataclass
class Observe:
    """What the properties need observed: per-node tick and return records, and the atoms."""

    ticked: set[int] = field(default_factory=set)
    returned: set[int] = field(default_factory=set)
    atoms: list[str] = field(default_factory=list)  # Promela expressions over the records, end of tick
    bb_values: list[dict] = field(default_factory=list)  # the root blackboard's entries, per `bb` number

    def atom(self, expr: str) -> str:
        """The observation bit of `expr` (one per distinct expression)."""
        if expr not in self.atoms:
            self.atoms.append(expr)
        return f"o{self.atoms.index(expr)}"


@dataclass(frozen=True)
class ModelOptions:
    running_bound: Optional[int] = None  # most RUNNING answers of an Action in a row
    ticks: Optional[int] = None  # most root ticks (None: unbounded)
    clock_ms: int = 100  # virtual time per tick (Sleep, Delay, Timeout)
    contract: tuple[tuple[str, tuple[int, ...]], ...] = ()  # leaf name -> allowed statuses
    print_states: bool = False  # `@S` line of every node's status at every tick end (agreement)
    failure_bound: Optional[int] = None  # most FAILURE answers of a leaf in a row (a fairness)
    atomic_paths: int = 64  # a subtree with at most this many paths through a tick runs atomically
    functions: tuple[tuple[str, str, Loc], ...] = ()  # Condition name -> success_if script (its place)
    pack: bool = True  # statuses and counters as bit fields (packing.py)


def _double(bits: int) -> float:
    """A double parameter of the lowered program (kept as its IEEE bits)."""
    return struct.unpack("<d", struct.pack("<q", bits))[0]


def timer_ticks(msec: int, clock_ms: int) -> Optional[int]:
    """Ticks after the start at which `msec` have passed (None: never, the clock stands still)."""
    if msec <= 0:
        return 0
    if clock_ms <= 0:
        return None
    return math.ceil(msec / clock_ms)


def _steppable(body: list[str]) -> bool:
    """A halt that can be one `d_step`: no jump out of it (a script's `goto Error`) and no choice
    in it (TryCatch catch_on_halt ticks its catch child, whose leaves choose; a d_step would take
    the first choice only)."""
    return not any("goto " in s or _HALT_TICK in s for s in body)


class Emitter(BlackboardNodeTicks, DecoratorTicks, Nav2Ticks):
    def __init__(
        self, mission: Mission, program: Program, options: ModelOptions, observe: Optional[Observe] = None
    ) -> None:
        self.m = mission
        self.p = program
        self.nodes = program.nodes
        self.o = options
        self.obs = observe or Observe()
        self.sem: Semantics = mission.semantics
        self.contract = dict(options.contract)
        self.globals: list[str] = []
        self.temps: list[str] = []  # reset at every tick end
        self.node_temps: dict[int, list[str]] = {}  # reset when the node returns: paths merge sooner
        self.timers: list[tuple[int, int]] = []  # (node, ticks) of every timer that counts
        self._paths: Optional[list[int]] = None
        self.params_from_bb: set[int] = set()  # a Repeat's or Retry's count read from the blackboard (bbnodes.py)

        self.parent = [0] * len(self.nodes)
        for n in self.nodes:
            for c in n.children:
                self.parent[c] = n.index
        self.check()
        # after check(): the nodes it refuses come first
        self.bbt = build_tables(
            mission, program, options.functions, frozenset(self.params_from_bb), options.ticks, options.clock_ms
        )

    # ------------------------------------------------------------ what is translated
    def check(self) -> None:
        for n in self.nodes:
            if n.kind not in SUPPORTED_KINDS:
                why = _WHY_NOT.get(n.kind, f"a `{n.kind}` node")
                raise _refuse(n.loc, f'`{n.id}` "{n.name}": btgen verify does not translate {why}')
            if n.kind in ("Parallel", "ParallelAll") and len(n.children) > MAX_PARALLEL:
                raise _refuse(
                    n.loc,
                    f'`{n.id}` "{n.name}" has {len(n.children)} children; btgen verify takes at most {MAX_PARALLEL}',
                )
        if self.p.data is not None:
            for index in self.p.data.params:
                n = self.nodes[index]
                if n.kind in PARAM_FROM_BB:
                    self.params_from_bb.add(index)
                elif n.kind in _PARAM_PORTS:
                    raise _refuse(
                        n.loc,
                        f'`{n.id}` "{n.name}" reads a parameter from the blackboard; btgen verify needs a literal',
                    )
        from btgen.ir.numbering import number_nodes

        for entry in number_nodes(self.m):
            n = self.nodes[entry.index]
            for port in _PARAM_PORTS.get(n.kind, ()):
                attr = entry.node.port(port)
                if attr is not None and bbmod.is_blackboard_pointer(attr.value):
                    if n.kind in PARAM_FROM_BB:  # read from the blackboard by the model (bbnodes.py)
                        self.params_from_bb.add(n.index)
                        continue
                    raise _refuse(
                        attr.value_loc,
                        f'port `{port}` of `{n.id}` "{n.name}" reads the blackboard; btgen verify needs a literal',
                    )
        for n in self.nodes:
            if n.kind == "RateController":
                hz = _double(n.params[0])
                if not hz > 0.0 or rate_ticks(hz, self.o.clock_ms, MAX_TIMER_TICKS) is None:
                    raise _refuse(
                        n.loc,
                        f'`{n.id}` "{n.name}": hz="{hz}" with --clock-ms {self.o.clock_ms}: btgen verify counts '
                        f"a period of 1 to {MAX_TIMER_TICKS} ticks",
                    )
            if n.kind in ("Sleep", "Delay", "Timeout") and n.params[0] > 0:
                k = timer_ticks(n.params[0], self.o.clock_ms)
                if k is not None and k > MAX_TIMER_TICKS:
                    raise _refuse(
                        n.loc,
                        f'`{n.id}` "{n.name}" waits {n.params[0]} ms, {k} ticks of --clock-ms {self.o.clock_ms}; '
                        f"btgen verify counts at most {MAX_TIMER_TICKS} (raise --clock-ms)",
                    )

    def check_scenario_names(self) -> None:
        """A counterexample is a scenario: leaf names must be scenario words, and a name an Action
        and a Condition share must not be given RUNNING (FORMAT.md rejects that scenario)."""
        kinds: dict[str, set[str]] = {}
        for n in self.nodes:
            if n.kind in ("Action", "Condition"):
                kinds.setdefault(n.name, set()).add(n.kind)
                if not n.name or any(c.isspace() or c == "#" for c in n.name):
                    raise _refuse(
                        n.loc,
                        f'`{n.id}` "{n.name}": a counterexample is a scenario, which names a leaf by one word '
                        "(no blank, no `#`): give the leaf such a name",
                    )
        for n in self.nodes:
            if n.kind == "Condition" and len(kinds[n.name]) > 1 and RUNNING in self.allowed_action(n.name):
                raise _refuse(
                    n.loc,
                    f'Condition "{n.name}" shares its name with an Action: a scenario (a counterexample) gives '
                    "both the same answers, and a Condition cannot answer RUNNING; rename one, or give the name a "
                    "contract without RUNNING",
                )

    def allowed_action(self, name: str) -> tuple[int, ...]:
        base = (SUCCESS, FAILURE, RUNNING)
        return tuple(s for s in base if s in self.contract[name]) if name in self.contract else base

    def running_bounded(self, n: IRNode) -> bool:
        """The RUNNING answers of an Action in a row are counted (never when it has no other answer)."""
        a = self.allowed(n)
        return n.kind == "Action" and self.o.running_bound is not None and RUNNING in a and len(a) > 1

    def failure_bounded(self, n: IRNode) -> bool:
        """The FAILURE answers of a leaf in a row are counted (only when it can answer SUCCESS)."""
        a = self.allowed(n)
        return n.kind in ("Action", "Condition") and self.o.failure_bound is not None and FAILURE in a and SUCCESS in a

    def allowed(self, n: IRNode) -> tuple[int, ...]:
        base = (SUCCESS, FAILURE) if n.kind == "Condition" else (SUCCESS, FAILURE, RUNNING)
        if n.name in self.contract:
            return tuple(s for s in base if s in self.contract[n.name])
        return base

    # ------------------------------------------------------------ variables
    def var(self, decl: str, temp: bool = False) -> None:
        self.globals.append(decl)
        if temp:
            name = decl.split()[1].split("=")[0]
            self.temps.append(name)
            digits = name.lstrip("abcdefghijklmnopqrstuvwxyz")
            if digits.isdigit() and not name.startswith(("tk", "rt")):
                self.node_temps.setdefault(int(digits), []).append(name)

    def declare(self) -> None:
        for n in self.nodes:
            i, k = n.index, n.kind
            if k in _SEQUENCES or k == "SequenceWithMemory":
                self.var(f"byte idx{i}")
                if self.sem.skipped_by_count:
                    self.var(f"byte skp{i}")
                else:
                    self.var(f"bit als{i}")
                self.var(f"byte cs{i}", True)
                self.var(f"byte prv{i}", True)
                self.var(f"bit tmp{i}", True)
            elif k in _REACTIVE:
                self.var(f"byte cs{i}", True)
                self.var(f"byte k{i}", True)
                self.var(f"byte j{i}", True)
                self.var(f"bit tmp{i}", True)
            elif k == "Parallel":
                self.var(f"int cm{i}")
                self.var(f"byte sc{i}")
                self.var(f"byte fc{i}")
                self.var(f"byte cs{i}", True)
                self.var(f"byte k{i}", True)
                self.var(f"byte sk{i}", True)
            elif k == "ParallelAll":
                self.var(f"int cm{i}")
                self.var(f"byte nc{i}")
                self.var(f"byte fc{i}")
                self.var(f"byte cs{i}", True)
                self.var(f"byte k{i}", True)
                self.var(f"byte sk{i}", True)
            elif k == "IfThenElse":
                self.var(f"byte cidx{i}")
                self.var(f"byte cs{i}", True)
            elif k == "WhileDoElse":
                self.var(f"byte cs{i}", True)
            elif k in ("Repeat", "RetryUntilSuccessful"):
                if n.params[0] != -1:
                    self.var(f"int cnt{i}")
                if not self.sem.loop_end_never_skipped:
                    self.var(f"bit als{i}")
                self.var(f"byte cs{i}", True)
                self.var(f"byte prv{i}", True)
            elif k == "RunOnce":
                self.var(f"bit done{i}")
                self.var(f"byte ret{i}")
            elif k in ("Timeout", "Delay"):
                self.var(f"bit started{i}")
                self.var(f"byte el{i} = {NONE}")
                self.var(f"byte cs{i}", True)
                self.timers.append((i, self.ticks_of(n)))
            elif k == "Sleep":
                self.var(f"byte el{i} = {NONE}")
                self.timers.append((i, self.ticks_of(n)))
            elif k == "TryCatch":
                self.var(f"byte idx{i}")
                self.var(f"byte skp{i}")
                self.var(f"bit inc{i}")
                self.var(f"byte cs{i}", True)
            elif k in ("Inverter", "ForceSuccess", "ForceFailure", "KeepRunningUntilFailure", "SubTree"):
                self.var(f"byte cs{i}", True)
            elif k == "PipelineSequence":
                self.var(f"byte last{i}")
                self.var(f"byte cs{i}", True)
                self.var(f"byte k{i}", True)
                self.var(f"byte sk{i}", True)
            elif k == "RecoveryNode":
                self.var(f"byte rcur{i}")
                self.var(f"int rcnt{i}")
                self.var(f"byte cs{i}", True)
            elif k == "RoundRobin":
                self.var(f"byte ix{i}")
                self.var(f"byte fl{i}")
                self.var(f"byte cs{i}", True)
                self.var(f"byte sk{i}", True)
                self.var(f"bit tmp{i}", True)
            elif k == "RateController":
                self.var(f"bit first{i}")
                self.var(f"byte el{i} = {NONE}")
                self.timers.append((i, self.ticks_of(n)))
            if self.running_bounded(n):
                self.var(f"byte rc{i}")
            if self.failure_bounded(n):
                self.var(f"byte fb{i}")
            self.declare_bb(n)
        for i in sorted(self.obs.ticked):
            self.var(f"bit tk{i}", True)
        for i in sorted(self.obs.returned):
            self.var(f"byte rt{i}", True)

    def ticks_of(self, n: IRNode) -> int:
        if n.kind == "RateController":
            r = rate_ticks(_double(n.params[0]), self.o.clock_ms, MAX_TIMER_TICKS)
            return MAX_TIMER_TICKS + 1 if r is None else r
        k = timer_ticks(n.params[0], self.o.clock_ms)
        return MAX_TIMER_TICKS + 1 if k is None else k  # never reached: the counter stops below

    # ------------------------------------------------------------ halting
    def halt_node(self, c: int) -> list[str]:
        """Node c's haltNode: halt(), then its _onHalted script (bbnodes.py); in `d_step`s."""
        return self._stepped(self._halt(c), lambda: self._halt_parts(c))

    def reset_child(self, c: int) -> list[str]:
        """haltChild / resetChildren for one child: halt it when RUNNING, then IDLE; in `d_step`s."""
        return self._stepped(self._reset(c), lambda: self._reset_parts(c))

    def reset_children(self, n: IRNode) -> list[str]:
        return self._stepped(
            [s for ch in n.children for s in self._reset(ch)],
            lambda: [s for ch in n.children for s in self.reset_child(ch)],
        )

    def _stepped(self, body: list[str], parts) -> list[str]:
        """A halt is deterministic and never blocks (every `if` has an `else`): one `d_step`, which
        pan compiles as one transition (a smaller verifier, no state stored inside). SPIN takes a
        d_step of a few hundred statements at most: a longer halt is one d_step per child."""
        if len(body) <= 1:
            return body
        if len(body) > D_STEP_LINES or not _steppable(body):
            return parts()
        return [
            "atomic { d_step {  /* atomic: a jump (`break`) may end at it, which SPIN refuses for a d_step */",
            *("   " + s for s in body),
            "} };",
        ]

    def _halt_parts(self, c: int) -> list[str]:
        return [
            *self._halt_own(c),
            *(s for ch in self._halted_children(c) for s in self.reset_child(ch)),
            f"st[{c}] = IDLE;",
            *self.on_halted(c),
        ]

    def _halted_children(self, c: int) -> list[int]:
        n = self.nodes[c]
        return list(n.children[:1] if self.is_decorator(n) else n.children)

    def _reset_parts(self, c: int) -> list[str]:
        return [
            f"if :: st[{c}] == RUNNING ->",
            *("  " + s for s in self._halt_parts(c)),
            f"   :: else -> st[{c}] = IDLE fi;",
        ]

    def _halt(self, c: int) -> list[str]:
        return [
            *self._halt_own(c),
            *(s for ch in self._halted_children(c) for s in self._reset(ch)),
            f"st[{c}] = IDLE;",
            *self.on_halted(c),
        ]

    def _halt_own(self, c: int) -> list[str]:
        """What halt() clears beside the children and the status (and a TryCatch's catch tick)."""
        n = self.nodes[c]
        k = n.kind
        out: list[str] = []
        if k in _SEQUENCES:
            out.append(f"idx{c} = 0;")
            if self.sem.skipped_by_count:
                out.append(f"skp{c} = 0;")
        elif k == "Parallel":
            out.append(f"cm{c} = 0; sc{c} = 0; fc{c} = 0;")
        elif k == "ParallelAll":
            out.append(f"cm{c} = 0; nc{c} = 0; fc{c} = 0;")
        elif k == "IfThenElse":
            out.append(f"cidx{c} = 0;")
        elif k == "TryCatch":
            out.extend(self.catch_on_halt(n))
            out.append(f"idx{c} = 0; skp{c} = 0; inc{c} = 0;")
        elif k in ("Repeat", "RetryUntilSuccessful") and n.params[0] != -1:
            out.append(f"cnt{c} = 0;")
        elif k in ("Timeout", "Delay"):
            out.append(f"started{c} = 0; el{c} = {NONE};")
        elif k == "Sleep":
            out.append(f"el{c} = {NONE};")
        elif k == "PipelineSequence":
            out.append(f"last{c} = 0;")
        elif k == "RecoveryNode":
            out.append(f"rcnt{c} = 0; rcur{c} = 0;")
        elif k == "RoundRobin":
            out.append(f"ix{c} = 0; fl{c} = 0;")
        elif k == "RateController":  # its start is taken again from IDLE: forgotten, so states merge
            out.append(f"el{c} = {NONE}; first{c} = 0;")
        out.extend(self.halt_bb(n))
        return out

    def _reset(self, c: int) -> list[str]:
        inner = self._halt(c)
        if inner == [f"st[{c}] = IDLE;"]:  # nothing else to halt: IDLE either way
            return inner
        return [
            f"if :: st[{c}] == RUNNING ->",
            *("  " + s for s in inner),
            f"   :: else -> st[{c}] = IDLE fi;",
        ]

    def dispatch(self, var: str, n: IRNode, body, positions: Optional[list[int]] = None) -> list[str]:
        """`if :: var == 0 -> body(child 0) :: ... fi` over the children (positions)."""
        out = ["if"]
        for pos in positions if positions is not None else range(len(n.children)):
            lines = body(pos, n.children[pos])
            out.append(f":: {var} == {pos} ->")
            out.extend("   " + s for s in (lines or ["skip;"]))
        out.append(":: else -> skip")
        out.append("fi;")
        return out

    @staticmethod
    def is_decorator(n: IRNode) -> bool:
        return n.kind in (
            "Inverter",
            "ForceSuccess",
            "ForceFailure",
            "Repeat",
            "RetryUntilSuccessful",
            "KeepRunningUntilFailure",
            "RunOnce",
            "Timeout",
            "Delay",
            "SubTree",
            "RateController",
            "Precondition",
            "Loop",
            "SkipUnlessUpdated",
            "WaitValueUpdate",
        )

    # ------------------------------------------------------------ ticking
    def paths(self, i: int) -> int:
        """A bound on the paths a tick of node i can take (its leaves' choices); capped."""
        if self._paths is None:
            cap = 1 << 20
            memo: list[int] = [1] * len(self.nodes)
            for n in reversed(self.nodes):  # creation order: children after their parent
                if n.kind in ("Action", "Condition"):
                    v = len(self.allowed(n))
                else:
                    v = 1
                    for c in n.children:
                        v = min(cap, v * memo[c])
                    if n.kind in ("Repeat", "RetryUntilSuccessful", "RecoveryNode", "RoundRobin"):  # loops
                        v = cap if n.params[0] < 0 or v > 1 else v
                memo[n.index] = v
            self._paths = memo
        return self._paths[i]

    def atomic_root(self, i: int) -> bool:
        """Node i's tick is one atomic step of the model (no state stored inside it): its paths
        are few (so the search loses little by not merging them) and its parent's are not.
        Atomic or not, the model's runs are the same; only what SPIN stores differs."""
        k = self.o.atomic_paths
        if k <= 0 or self.paths(i) > k:
            return False
        return i == 0 or self.paths(self.parent[i]) > k

    def tick(self, i: int) -> list[str]:
        """execute_tick of node i: its result in `rv`."""
        if self.atomic_root(i):
            return ["atomic {", *("   " + s for s in self.tick_body(i)), "};"]
        return self.tick_body(i)

    def tick_body(self, i: int) -> list[str]:
        n = self.nodes[i]
        out = [f"/* {n.uid} {n.id} {n.name!r} */"]
        if i in self.obs.ticked:
            out.append(f"tk{i} = 1;")
        body = getattr(self, "k_" + n.kind)(n)
        t = self.bbt
        if i in t.pre_idle:  # TreeNode::checkPreConditions: all when IDLE, _while when RUNNING
            out.append(f"if :: st[{i}] == IDLE ->")
            out.extend("   " + s for s in lookup(t.pre_idle[i], result_is("pr")))
            out.append(f":: st[{i}] == RUNNING ->")
            running = lookup(t.pre_running[i], result_is("pr")) if i in t.pre_running else [f"pr = {NO_RESULT};"]
            out.extend("   " + s for s in running)
            out.append(f":: else -> pr = {NO_RESULT} fi;")
            out.append(f"if :: pr == {NO_RESULT} ->")
            out.extend("   " + s for s in body)
            out.append(f":: pr == {HALT} ->")
            out.extend("   " + s for s in self.halt_node(i))
            out.append("   rv = SKIPPED")
            out.append(":: else -> rv = pr fi;")
        else:
            out.extend(body)
        out.append(f"E{i}: if :: rv != SKIPPED -> st[{i}] = rv :: else -> skip fi;")
        for status, name in ((SUCCESS, "SUCCESS"), (FAILURE, "FAILURE")):
            if (i, status) in t.post:  # checkPostConditions (the status is set after it: no matter)
                out.append(f"if :: rv == {name} ->")
                out.extend("   " + s for s in lookup(t.post[(i, status)], lambda r: "skip"))
                out.append(":: else -> skip fi;")
        if self.node_temps.get(i):
            out.append(" ".join(f"{t} = 0;" for t in self.node_temps[i]))
        if self.is_decorator(n):
            c = n.children[0]
            out.append(f"if :: st[{c}] == SUCCESS || st[{c}] == FAILURE -> st[{c}] = IDLE :: else -> skip fi;")
        if i in self.obs.returned:
            out.append(f"rt{i} = rt{i} | (1 << rv);")
        return out

    def child_tick(self, c: int) -> list[str]:
        return self.tick(c)

    def leave(self, i: int, value: str) -> str:
        return f"rv = {value}; goto E{i}"

    # leaves
    def k_AlwaysSuccess(self, n: IRNode) -> list[str]:
        return ["rv = SUCCESS;"]

    def k_AlwaysFailure(self, n: IRNode) -> list[str]:
        return ["rv = FAILURE;"]

    def choice(self, n: IRNode) -> list[str]:
        i = n.index
        allowed = self.allowed(n)
        if not allowed:
            raise _refuse(n.loc, f'the leaf contract leaves `{n.id}` "{n.name}" no status to return')
        if i in self.bbt.cond:  # the contract makes it a function of the blackboard
            free = "if :: rv = SUCCESS :: rv = FAILURE fi"
            out = lookup(self.bbt.cond[i], lambda r: free if r == FREE else f"rv = {r}")
            return [*out, f'printf("@C {i} %d\\n", rv);']
        bounded = self.running_bounded(n)
        fair = self.failure_bounded(n)
        opts = []
        for s in allowed:
            if s == RUNNING and bounded:
                opts.append(f":: rc{i} < {self.o.running_bound} -> rv = RUNNING; rc{i}++")
            elif s == FAILURE and fair:
                opts.append(f":: fb{i} < {self.o.failure_bound} -> rv = FAILURE; fb{i}++")
            elif s == SUCCESS and fair:
                opts.append(f":: rv = SUCCESS; fb{i} = 0")
            else:
                opts.append(f":: rv = {STATUS_NAME[s]}")
        out = ["if", *opts, "fi;", f'printf("@C {i} %d\\n", rv);']
        if bounded:
            out = [f"if :: st[{i}] == IDLE -> rc{i} = 0 :: else -> skip fi;", *out]
        return out

    def k_Action(self, n: IRNode) -> list[str]:
        i = n.index
        return [
            f"if :: st[{i}] == IDLE || st[{i}] == RUNNING ->",
            *("   " + s for s in self.choice(n)),
            f":: else -> rv = st[{i}]",
            "fi;",
        ]

    def k_Condition(self, n: IRNode) -> list[str]:
        return self.choice(n)

    def k_Script(self, n: IRNode) -> list[str]:
        return lookup(self.bbt.script[n.index], result_is("rv"))

    def k_ScriptCondition(self, n: IRNode) -> list[str]:
        return lookup(self.bbt.script[n.index], result_is("rv"))

    def k_Sleep(self, n: IRNode) -> list[str]:
        i, msec = n.index, n.params[0]
        start = "rv = SUCCESS" if msec <= 0 else f"el{i} = 0; rv = RUNNING"
        return [
            f"if :: st[{i}] == IDLE -> {start}",
            f"   :: st[{i}] == RUNNING ->",
            f"      if :: el{i} != {NONE} && el{i} < {self.ticks_of(n)} -> rv = RUNNING",
            f"         :: else -> el{i} = {NONE}; rv = SUCCESS fi",
            f"   :: else -> rv = st[{i}] fi;",
        ]

    # controls
    def k_sequence(self, n: IRNode, decides: int, goes_on: int, asynch: bool, memory: bool) -> list[str]:
        i, nn = n.index, len(n.children)
        d, g = STATUS_NAME[decides], STATUS_NAME[goes_on]
        by_count = self.sem.skipped_by_count
        start = f"skp{i} = 0" if by_count else f"als{i} = 1"
        out = [
            f"if :: st[{i}] == IDLE -> {start} :: else -> skip fi;",
            f"st[{i}] = RUNNING;",
            "do",
            f":: idx{i} < {nn} ->",
        ]
        body = self.dispatch(f"idx{i}", n, lambda pos, c: [f"prv{i} = st[{c}];", *self.child_tick(c)])
        out.extend("   " + s for s in body)
        out.append(f"   cs{i} = rv;")
        if not by_count:
            out.append(f"   if :: cs{i} != SKIPPED -> als{i} = 0 :: else -> skip fi;")
        out.append("   if")
        out.append(f"   :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        if memory:  # a FAILURE halts the children from the current one on, the index is kept
            out.append(f"   :: cs{i} == FAILURE ->")
            for pos, c in enumerate(n.children):
                out.append(f"      if :: idx{i} <= {pos} ->")
                out.extend("         " + s for s in self.reset_child(c))
                out.append("         :: else -> skip fi;")
            out.append(f"      {self.leave(i, 'FAILURE')}")
        else:
            out.append(f"   :: cs{i} == {d} ->")
            out.extend("      " + s for s in self.reset_children(n))
            out.append(f"      idx{i} = 0; {self.leave(i, d)}")
        out.append(f"   :: cs{i} == {g} -> idx{i}++;")
        if asynch or memory:
            out.append(f"      if :: prv{i} == IDLE && idx{i} < {nn} -> {self.leave(i, 'RUNNING')} :: else -> skip fi")
        skipped = f"idx{i}++; skp{i}++" if by_count else f"idx{i}++"
        out.append(f"   :: else -> {skipped}")
        out.append("   fi")
        out.append(":: else -> break")
        out.append("od;")
        cond = f"skp{i} == {nn}" if by_count else f"als{i} == 1"
        out.append(f"if :: {cond} -> tmp{i} = 1 :: else -> tmp{i} = 0 fi;")
        out.extend(self.reset_children(n))
        out.append(f"idx{i} = 0;" + (f" skp{i} = 0;" if by_count else ""))
        out.append(f"if :: tmp{i} -> rv = SKIPPED :: else -> rv = {g} fi;")
        return out

    def k_Sequence(self, n: IRNode) -> list[str]:
        return self.k_sequence(n, FAILURE, SUCCESS, False, False)

    def k_AsyncSequence(self, n: IRNode) -> list[str]:
        return self.k_sequence(n, FAILURE, SUCCESS, True, False)

    def k_Fallback(self, n: IRNode) -> list[str]:
        return self.k_sequence(n, SUCCESS, FAILURE, False, False)

    def k_AsyncFallback(self, n: IRNode) -> list[str]:
        return self.k_sequence(n, SUCCESS, FAILURE, True, False)

    def k_SequenceWithMemory(self, n: IRNode) -> list[str]:
        return self.k_sequence(n, FAILURE, SUCCESS, False, True)

    def k_reactive(self, n: IRNode, decides: int, otherwise: int) -> list[str]:
        i, nn = n.index, len(n.children)
        d, o = STATUS_NAME[decides], STATUS_NAME[otherwise]
        out = [f"tmp{i} = 1; st[{i}] = RUNNING; k{i} = 0;", "do", f":: k{i} < {nn} ->"]
        out.extend("   " + s for s in self.dispatch(f"k{i}", n, lambda pos, c: self.child_tick(c)))
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: cs{i} != SKIPPED -> tmp{i} = 0 :: else -> skip fi;")
        out.append("   if")
        out.append(f"   :: cs{i} == RUNNING -> j{i} = 0;")
        out.append("      do")
        out.append(f"      :: j{i} < {nn} ->")
        others = ["if"]
        for pos, c in enumerate(n.children):
            others.append(f":: j{i} == {pos} && k{i} != {pos} ->")
            others.extend("   " + s for s in self.reset_child(c))
        others.extend([":: else -> skip", "fi;"])
        out.extend("         " + s for s in others)
        out.append(f"         j{i}++")
        out.append("      :: else -> break")
        out.append("      od;")
        out.append(f"      {self.leave(i, 'RUNNING')}")
        out.append(f"   :: cs{i} == {d} ->")
        out.extend("      " + s for s in self.reset_children(n))
        out.append(f"      {self.leave(i, d)}")
        out.append(f"   :: cs{i} == SKIPPED ->")
        out.extend("      " + s for s in self.dispatch(f"k{i}", n, lambda pos, c: self.reset_child(c)))
        out.append("   :: else -> skip")
        out.append("   fi;")
        out.append(f"   k{i}++")
        out.append(":: else -> break")
        out.append("od;")
        out.extend(self.reset_children(n))
        out.append(f"if :: tmp{i} -> rv = SKIPPED :: else -> rv = {o} fi;")
        return out

    def k_ReactiveSequence(self, n: IRNode) -> list[str]:
        return self.k_reactive(n, FAILURE, SUCCESS)

    def k_ReactiveFallback(self, n: IRNode) -> list[str]:
        return self.k_reactive(n, SUCCESS, FAILURE)

    def k_Parallel(self, n: IRNode) -> list[str]:
        i, nn = n.index, len(n.children)
        rs, rf, neg = n.params
        out = [f"st[{i}] = RUNNING; sk{i} = 0; k{i} = 0;", "do", f":: k{i} < {nn} ->"]
        out.append(f"   if :: ((cm{i} >> k{i}) & 1) == 0 ->")
        out.extend("      " + s for s in self.dispatch(f"k{i}", n, lambda pos, c: self.child_tick(c)))
        out.append(f"      cs{i} = rv;")
        out.append(
            f"      if :: cs{i} == SKIPPED -> sk{i}++ :: cs{i} == SUCCESS -> cm{i} = cm{i} | (1 << k{i}); sc{i}++"
            f" :: cs{i} == FAILURE -> cm{i} = cm{i} | (1 << k{i}); fc{i}++ :: else -> skip fi"
        )
        out.append("   :: else -> skip fi;")
        won = f"sc{i} >= {rs}" + (f" || sc{i} + sk{i} >= {rs}" if neg else "")
        out.append(f"   if :: {won} -> cm{i} = 0; sc{i} = 0; fc{i} = 0;")
        out.extend("      " + s for s in self.reset_children(n))
        out.append(f"      {self.leave(i, 'SUCCESS')}")
        out.append("   :: else -> skip fi;")
        out.append(f"   if :: {nn} - fc{i} < {rs} || fc{i} == {rf} -> cm{i} = 0; sc{i} = 0; fc{i} = 0;")
        out.extend("      " + s for s in self.reset_children(n))
        out.append(f"      {self.leave(i, 'FAILURE')}")
        out.append("   :: else -> skip fi;")
        out.append(f"   k{i}++")
        out.append(":: else -> break")
        out.append("od;")
        out.append(f"if :: sk{i} == {nn} -> rv = SKIPPED :: else -> rv = RUNNING fi;")
        return out

    def k_ParallelAll(self, n: IRNode) -> list[str]:
        i, nn = n.index, len(n.children)
        th = n.params[0]
        out = [f"sk{i} = 0; st[{i}] = RUNNING; k{i} = 0;", "do", f":: k{i} < {nn} ->"]
        out.append(f"   if :: ((cm{i} >> k{i}) & 1) == 0 ->")
        out.extend("      " + s for s in self.dispatch(f"k{i}", n, lambda pos, c: self.child_tick(c)))
        out.append(f"      cs{i} = rv;")
        out.append(
            f"      if :: cs{i} == SUCCESS -> cm{i} = cm{i} | (1 << k{i}); nc{i}++"
            f" :: cs{i} == FAILURE -> cm{i} = cm{i} | (1 << k{i}); nc{i}++; fc{i}++"
            f" :: cs{i} == SKIPPED -> sk{i}++ :: else -> skip fi"
        )
        out.append("   :: else -> skip fi;")
        out.append(f"   k{i}++")
        out.append(":: else -> break")
        out.append("od;")
        out.append(f"if :: sk{i} == {nn} -> {self.leave(i, 'SKIPPED')} :: else -> skip fi;")
        out.append(f"if :: sk{i} + nc{i} >= {nn} ->")
        for c in n.children:
            out.extend("   " + s for s in self.reset_child(c))
        out.append(f"   cm{i} = 0; nc{i} = 0;")
        out.append(f"   if :: fc{i} >= {th} -> rv = FAILURE :: else -> rv = SUCCESS fi; fc{i} = 0")
        out.append(":: else -> rv = RUNNING fi;")
        return out

    def k_IfThenElse(self, n: IRNode) -> list[str]:
        i, nn = n.index, len(n.children)
        out = [f"st[{i}] = RUNNING;", f"if :: cidx{i} == 0 ->"]
        out.extend("   " + s for s in self.child_tick(n.children[0]))
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        out.append(f"      :: cs{i} == SUCCESS -> cidx{i} = 1")
        if nn == 3:
            out.append(f"      :: cs{i} == FAILURE -> cidx{i} = 2")
        else:
            out.append(f"      :: cs{i} == FAILURE -> {self.leave(i, 'FAILURE')}")
        out.append("      :: else -> goto Error fi  /* a skipped condition: the library throws */")
        out.append(":: else -> skip fi;")
        out.extend(self.dispatch(f"cidx{i}", n, lambda pos, c: self.child_tick(c), list(range(1, nn))))
        out.append(f"cs{i} = rv;")
        out.append(f"if :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')} :: else -> skip fi;")
        out.extend(self.reset_children(n))
        out.append(f"cidx{i} = 0; rv = cs{i};")
        return out

    def k_WhileDoElse(self, n: IRNode) -> list[str]:
        i, nn = n.index, len(n.children)
        ch = n.children
        out = [f"st[{i}] = RUNNING;", *self.child_tick(ch[0]), f"cs{i} = rv;"]
        out.append(f"if :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        out.append(f":: cs{i} == SUCCESS ->")
        if nn == 3:
            out.extend("   " + s for s in self.reset_child(ch[2]))
        out.extend("   " + s for s in self.child_tick(ch[1]))
        out.append(f"   cs{i} = rv")
        out.append(f":: cs{i} == FAILURE ->")
        if nn == 3:
            out.extend("   " + s for s in self.reset_child(ch[1]))
            out.extend("   " + s for s in self.child_tick(ch[2]))
            out.append(f"   cs{i} = rv")
        else:
            out.append("   skip")
        out.append(":: else -> goto Error fi;  /* a skipped condition: the library throws */")
        out.append(f"if :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')} :: else -> skip fi;")
        out.extend(self.reset_children(n))
        out.append(f"rv = cs{i};")
        return out

    def k_TryCatch(self, n: IRNode) -> list[str]:
        i, nn = n.index, len(n.children)
        tries, last = nn - 1, n.children[-1]
        out = [f"if :: st[{i}] == IDLE -> skp{i} = 0; inc{i} = 0 :: else -> skip fi;", f"st[{i}] = RUNNING;"]
        out.append(f"TC{i}: if :: inc{i} ->")
        out.extend("   " + s for s in self.child_tick(last))
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')} :: else -> skip fi;")
        out.extend("   " + s for s in self.reset_children(n))
        out.append(f"   idx{i} = 0; inc{i} = 0; {self.leave(i, 'FAILURE')}")
        out.append(":: else -> skip fi;")
        out.append("do")
        out.append(f":: idx{i} < {tries} ->")
        out.extend(
            "   " + s for s in self.dispatch(f"idx{i}", n, lambda pos, c: self.child_tick(c), list(range(tries)))
        )
        out.append(f"   cs{i} = rv;")
        out.append(f"   if :: cs{i} == RUNNING -> {self.leave(i, 'RUNNING')}")
        out.append(f"   :: cs{i} == FAILURE ->")
        out.extend("      " + s for s in self.reset_children(n))
        out.append(f"      idx{i} = 0; inc{i} = 1; goto TC{i}")
        out.append(f"   :: cs{i} == SUCCESS -> idx{i}++")
        out.append(f"   :: else -> idx{i}++; skp{i}++")
        out.append("   fi")
        out.append(":: else -> break")
        out.append("od;")
        out.append(f"if :: skp{i} == {tries} -> cs{i} = SKIPPED :: else -> cs{i} = SUCCESS fi;")
        out.extend(self.reset_children(n))
        out.append(f"idx{i} = 0; skp{i} = 0; rv = cs{i};")
        return out

    # ------------------------------------------------------------ the model
    def emit(self, ltl: list[tuple[str, str]]) -> str:
        self.declare()
        body = unique_labels(self.tick(0))
        n = len(self.nodes)
        head = [
            "/* generated by btgen verify from " + self.p.mission_path.replace("*/", "* /") + " */",
            "#define IDLE 0",
            "#define RUNNING 1",
            "#define SUCCESS 2",
            "#define FAILURE 3",
            "#define SKIPPED 4",
            f"byte st[{n}];",
            "byte rv;",
            "byte rootr;",
        ]
        if self.bbt.used:
            head.append(f"byte bb;  /* the blackboard: one of {self.bbt.count} (blackboard.py) */")
            head.append("byte pr;  /* the pre-conditions' verdict */")
        if self.o.ticks is not None:
            head.append("int ticks;")
        head += [d + ";" for d in self.globals]
        head += [f"bit o{k};  /* {a} */" for k, a in enumerate(self.obs.atoms)]
        for name, formula in ltl:
            head.append(f"ltl {name} {{ {formula} }}")
        clear = [f"tk{i} = 0;" for i in sorted(self.obs.ticked)] + [f"rt{i} = 0;" for i in sorted(self.obs.returned)]
        observe = [f"o{k} = ({a});" for k, a in enumerate(self.obs.atoms)]
        timers = [
            f"if :: el{i} != {NONE} && el{i} < {min(k, MAX_TIMER_TICKS + 1)} -> el{i}++ :: else -> skip fi;"
            for i, k in self.timers
            if self.o.clock_ms > 0
        ]
        temps = [f"{t} = 0;" for t in self.temps if not t.startswith(("tk", "rt"))]
        end = [*observe, *clear, *temps, *timers, "rv = 0;", *(["pr = 0;"] if self.bbt.used else [])]
        if self.o.ticks is not None:
            end.append("ticks++;")
        if self.o.print_states:
            end.append('printf("@S");')
            for k in range(0, n, 8):  # eight statuses a printf
                part = range(k, min(n, k + 8))
                end.append(f'printf("{" %d" * len(part)}", {", ".join(f"st[{j}]" for j in part)});')
            end.append('printf("\\n");')
        end.append('printf("@T\\n");')
        bound = f"ticks < {self.o.ticks}" if self.o.ticks is not None else "true"
        proc = [
            "active proctype tree() {",
            "do",
            f":: {bound} ->",
            *("   " + s for s in body),
            "   rootr = rv;",
            "   if :: rv == SUCCESS || rv == FAILURE -> st[0] = IDLE :: else -> skip fi;",
            "   d_step {",
            *("      " + s for s in end),
            "   };",
            "   if :: rootr == SUCCESS || rootr == FAILURE -> break :: else -> skip fi",
            ":: else -> break",
            "od;",
            "skip;",
            "/* the run has ended: no node is ticked any more (this observation stays for ever) */",
            "d_step {",
            "   rootr = 255;",
            *("   " + s for s in observe),
            "}",
            "Error: skip  /* a script failed at run time (blackboard.py): the run ends there */",
            "}",
        ]
        text = "\n".join(head + proc) + "\n"
        if not self.o.pack:
            return text
        rc = {i.index: self.o.running_bound or 0 for i in self.nodes if self.running_bounded(i)}
        fb = {i.index: self.o.failure_bound or 0 for i in self.nodes if self.failure_bounded(i)}
        return pack(text, widths(self.nodes, rc, fb, self.params_from_bb), self.o.ticks)


def emit_model(
    mission: Mission,
    program: Program,
    options: ModelOptions,
    observe: Optional[Observe] = None,
    ltl: Optional[list[tuple[str, str]]] = None,
) -> str:
    """The Promela text; Refusal (a located error) for what is not translated."""
    return Emitter(mission, program, options, observe).emit(ltl or [])
