"""`btgen analyze`: what a mission can and cannot do, found before the robot runs it.

The analysis works on the lowered program (ir/lower.py: the node table in
creation order, SubTrees expanded) and on the instances the data side loads
(ir/dataflow.py: one blackboard per SubTree instance). For every node it
computes, bottom up, the statuses one tick of it can return whatever the
user leaves return (Actions SUCCESS/FAILURE/RUNNING, Conditions
SUCCESS/FAILURE), and for each status the most work such a tick does:

- nodes visited (executeTick calls),
- leaf hooks called (onStart/onRunning of user Actions, tick of user Conditions),
- script evaluations (Script, ScriptCondition, Precondition `if`, pre- and
  post-conditions; `_onHalted` runs on halts and is not counted).

The semantics are BehaviorTree.CPP 4.6.2's, as the interpreter has them:
Repeat and RetryUntilSuccessful yield RUNNING after a cycle that started from
IDLE, so they tick their child at most twice per tick; nothing built in loops
without bound within one tick. A user Control or Decorator may tick its
children any number of times: the bound is then "unbounded" and names it.

Each node has two tables, for a tick that finds it IDLE and for one that finds
it RUNNING (a resumed Sequence skips the children before the running one; a
Repeat starts a second cycle in a tick only when it resumed the first). The
bounds are per outcome and composed along the tick's paths (a Sequence child
that only fails stops the count); they are reached when the leaves' results
are independent of each other, except for Parallel, whose count is an upper
bound. `btgen explore --no-merge` measures the most a tick does, and the tests
check on random missions that analyze is never below it, never calls a ticked
node unreachable and never calls a returned status impossible. With
`--btcpp 4.10.0` the switches of lang/versions.py that change what a tick
returns are followed; a node not modelled here (TryCatch) may return anything.

Scripts whose names are all SubTree constants never written by any node (or
no names at all) are evaluated once here: a constant `_skipIf`, `_while`,
`_successIf`, `_failureIf`, ScriptCondition or Precondition makes branches
unreachable, and the finding says which instance.
"""

from __future__ import annotations

import json
import struct
import sys
from dataclasses import dataclass, field
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.ir.data import records
from btgen.ir.data.resolve import Analysis as DataAnalysis
from btgen.ir.kinds import is_queue
from btgen.ir.lower import IRNode, Program
from btgen.lang import blackboard as bbmod
from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.model import Attr, Mission, SubTreeNode

S, F, R, K = "SUCCESS", "FAILURE", "RUNNING", "SKIPPED"
ORDER = (S, F, R, K)
UNBOUNDED = -1

Cost = tuple[int, int, int]  # visits, hooks, scripts (UNBOUNDED in any: no bound)
Outcomes = dict[str, Cost]


def _add(a: Cost, b: Cost) -> Cost:
    return tuple(UNBOUNDED if x == UNBOUNDED or y == UNBOUNDED else x + y for x, y in zip(a, b))  # type: ignore[return-value]


def _max(a: Optional[Cost], b: Cost) -> Cost:
    if a is None:
        return b
    return tuple(UNBOUNDED if x == UNBOUNDED or y == UNBOUNDED else max(x, y) for x, y in zip(a, b))  # type: ignore[return-value]


def _put(out: Outcomes, status: str, cost: Cost) -> None:
    out[status] = _max(out.get(status), cost)


ZERO: Cost = (0, 0, 0)
ONE: Cost = (1, 0, 0)


@dataclass
class Finding:
    loc: Loc
    category: str  # unreachable | budget | blackboard | reactive
    message: str

    def as_json(self) -> dict:
        return {
            "file": self.loc.path,
            "line": self.loc.line,
            "column": self.loc.col,
            "category": self.category,
            "message": self.message,
        }


@dataclass
class Analysis:
    program: Program
    outcomes: list[Outcomes]  # per node index: what one tick of it can return, and its most work
    reachable: list[bool]
    unbounded_by: Optional[int] = None  # index of the node that makes the tick unbounded
    findings: list[Finding] = field(default_factory=list)
    constants: dict = field(default_factory=dict)  # (node index, attr name) -> bool

    def worst(self) -> Cost:
        c: Cost = ZERO
        for v in self.outcomes[0].values():
            c = _max(c, v)
        return c


# ====================================================================== constants
def _owner_key(bb: bbmod.Blackboard, key: str) -> str:
    """The key of an entry on the blackboard that holds it (SubTree remaps followed)."""
    if key.startswith("@"):
        return key[1:]
    for _ in range(10000):
        if key in bb.local_keys() or bb.parent is None:
            return key
        remap = bb.remapping
        if key in remap:
            key = remap[key]
            if key.startswith("@"):
                return key[1:]
        elif not bb.autoremap:
            return key
        bb = bb.parent
    return key


class _Data:
    """The node instances of the data side, with the blackboard entries each reads and writes."""

    def __init__(self, mission: Mission, options: records.DataOptions) -> None:
        a = DataAnalysis(mission, options)
        a.load()
        self.insts = a.insts
        # entries the application sets before the first tick (--entry): written from the start
        self.provided = {eid for eid, i in a.slot_of_entry.items() if getattr(a.slots[i], "provided", False)}
        self.enums = dict(mission.enums)
        # id(entry) -> [(node index, loc, type or None)]
        self.reads: dict[int, list[tuple[int, Loc, Optional[str]]]] = {}
        self.writes: dict[int, list[tuple[int, Loc]]] = {}
        self.unsets: set[int] = set()
        self.entry_key: dict[int, str] = {}
        self.entries: dict[int, bbmod.Entry] = {}
        for inst in self.insts:
            self._collect(inst)

    def entry(self, bb: bbmod.Blackboard, key: str) -> Optional[bbmod.Entry]:
        try:
            e = bb.get_entry(key)
            if e is None:
                e = bb.create_entry(key, values.ANY)
        except (bbmod.BlackboardError, values.ConversionError):
            return None
        self.entry_key.setdefault(id(e), _owner_key(bb, key))
        self.entries[id(e)] = e
        return e

    def _read(self, inst, key: str, loc: Loc, type_name: Optional[str]) -> None:
        e = self.entry(inst.bb, key)
        if e is not None and not (key in self.enums and inst.bb.get_entry(key) is e and e.value is None):
            self.reads.setdefault(id(e), []).append((inst.index, loc, type_name))

    def _write(self, inst, key: str, loc: Loc) -> None:
        e = self.entry(inst.bb, key)
        if e is not None:
            self.writes.setdefault(id(e), []).append((inst.index, loc))

    def _script(self, inst, attr: Attr) -> None:
        script = attr.script
        if script is None:
            return
        for name in sc.variables_read(script):
            if name not in self.enums:
                self._read(inst, name, attr.value_loc, None)
        for name in sc.variables_written(script):
            self._write(inst, name, attr.value_loc)

    def _collect(self, inst) -> None:
        node = inst.node
        for attr in node.pre + node.post:
            self._script(inst, attr)
        if isinstance(node, SubTreeNode) or inst.spec is None:
            return
        nid = inst.reg_id
        if nid in ("Script", "ScriptCondition", "Precondition"):
            p = inst.ports.get("code" if nid != "Precondition" else "if")
            if p is not None and p.attr is not None:
                self._script(inst, p.attr)
            return
        if nid == "SetBlackboard":
            out, val = inst.ports.get("output_key"), inst.ports.get("value")
            if out is not None and not bbmod.is_blackboard_pointer(out.raw):
                self._write(inst, out.raw, out.loc_or or node.loc)
            if val is not None:
                key = bbmod.strip_blackboard_pointer(val.raw)
                if key is not None:
                    self._read(inst, key, val.loc_or or node.loc, None)
            return
        if nid == "UnsetBlackboard":
            p = inst.ports.get("key")
            if p is not None and not bbmod.is_blackboard_pointer(p.raw):
                e = self.entry(inst.bb, p.raw)
                if e is not None:
                    self.unsets.add(id(e))
            return
        for ps in inst.spec.ports:
            p = inst.ports.get(ps.name)
            if p is None:
                continue
            key = bbmod.remapped_key(ps.name, p.raw)
            if key is None:
                continue
            loc = p.loc_or or node.loc
            if nid in records.ENTRY_NODES:  # they read the update counter, not the value
                self._read(inst, key, loc, None)
                continue
            if ps.reads:
                self._read(inst, key, loc, ps.type if ps.type not in (values.ANY, "any") else None)
            if ps.writes:
                self._write(inst, key, loc)

    def constant(self, index: int, attr: Attr) -> Optional[bool]:
        """The value of a condition script that is the same whenever it runs, else None."""
        script = attr.script
        if script is None or sc.variables_written(script):
            return None
        inst = self.insts[index]
        for name in sc.variables_read(script):
            if name in self.enums:
                continue
            e = inst.bb.get_entry(name)
            if e is None or e.value is None or id(e) in self.writes or id(e) in self.unsets:
                return None
        try:
            return sc.script_truth(sc.evaluate(script, inst.bb, self.enums))
        except Exception:  # a script error whenever it runs: the run reports it, not us
            return None


# ====================================================================== per node
_CHAINS = {
    "Sequence": (F, S),
    "AsyncSequence": (F, S),
    "SequenceWithMemory": (F, S),
    "ReactiveSequence": (F, S),
    "Fallback": (S, F),
    "AsyncFallback": (S, F),
    "ReactiveFallback": (S, F),
}


def _union(a: Outcomes, b: Outcomes) -> Outcomes:
    out = dict(a)
    for st, c in b.items():
        _put(out, st, c)
    return out


def _switch(kids: list[Outcomes]) -> Outcomes:
    out: Outcomes = {}
    for k in kids:
        for st, c in k.items():
            _put(out, st, _add(ONE, c))
    return out


_PRE_OUTCOME = {"_failureIf": F, "_successIf": S, "_skipIf": K}
_ANY_COUNT = -(2**62)  # a Repeat/Retry count read from the blackboard: any value
_DECORATORS = {
    "Inverter",
    "ForceSuccess",
    "ForceFailure",
    "KeepRunningUntilFailure",
    "RunOnce",
    "Precondition",
    "Timeout",
    "Delay",
    "Loop",
    "SkipUnlessUpdated",
    "WaitValueUpdate",
    "SubTree",
}
_PRE_ORDER = ("_failureIf", "_successIf", "_skipIf", "_while")


class _Analyzer:
    def __init__(self, mission: Mission, program: Program, data: _Data) -> None:
        self.m = mission
        self.p = program
        self.data = data
        n = len(program.nodes)
        self.out: list[Outcomes] = [{} for _ in range(n)]
        self.kid_reach: list[list[bool]] = [[] for _ in range(n)]  # per child: reachable from this node
        self.mark: list[list[bool]] = [[] for _ in range(n)]
        self.fr: list[Outcomes] = [{} for _ in range(n)]
        self.rs: list[Outcomes] = [{} for _ in range(n)]
        self.why: dict[int, str] = {}  # child index -> why its parent never ticks it
        self.gated: dict[int, str] = {}  # node -> why its own tick() never runs
        self.findings: list[Finding] = []
        self.constants: dict[tuple[int, str], bool] = {}
        self.unbounded_by: Optional[int] = None

    def model(self, i: int):
        return self.data.insts[i].node

    def label(self, i: int) -> str:
        n = self.p.nodes[i]
        return f'`{n.id}` "{n.name}"'

    # -- composition
    def run(self) -> None:
        for node in reversed(self.p.nodes):
            fr, rs = self.node(node)
            self.fr[node.index], self.rs[node.index] = fr, rs
            self.out[node.index] = _union(fr, rs)

    def node(self, n: IRNode) -> tuple[Outcomes, Outcomes]:
        """(fresh, resumed): the outcomes of a tick that finds the node IDLE, and of one that finds
        it RUNNING (empty when it can never be RUNNING)."""
        model = self.model(n.index)
        pre_scripts = 0
        pre_out: Outcomes = {}
        gate: Optional[tuple[str, str]] = None
        for attr in sorted(model.pre, key=lambda a: _PRE_ORDER.index(a.name)):  # 4.6.2 checks them so
            const = self.data.constant(n.index, attr)
            if const is not None:
                self.constants[(n.index, attr.name)] = const
            pre_scripts += 1
            cost = (1, 0, pre_scripts)
            if attr.name == "_while":
                if const is False:
                    gate = (K, f"its `_while` is always false ({attr.value!r})")
                    pre_out = {K: cost}
                    break
                if const is None:
                    _put(pre_out, K, cost)
                continue
            if const is True:
                gate = (_PRE_OUTCOME[attr.name], f"its `{attr.name}` is always true ({attr.value!r})")
                _put(pre_out, _PRE_OUTCOME[attr.name], cost)
                break
            if const is None:
                _put(pre_out, _PRE_OUTCOME[attr.name], cost)
        self.mark[n.index] = [False] * len(n.children)
        if gate is not None:
            self.gated[n.index] = gate[1]
            for c in n.children:
                self.why[c] = f"{self.label(n.index)} never ticks its children: {gate[1]}"
            bases: tuple[Outcomes, Outcomes] = ({}, {})
        else:
            bases = self.tick(n)
        self.kid_reach[n.index] = self.mark[n.index]
        post = {S: 0, F: 0}
        for attr in model.post:
            if attr.name == "_onSuccess":
                post[S] += 1
            elif attr.name == "_onFailure":
                post[F] += 1
            elif attr.name == "_post":
                post[S] += 1
                post[F] += 1
        result = []
        for which, base in enumerate(bases):
            out: Outcomes = {}
            for st, cost in base.items():
                _put(out, st, _add(cost, (0, 0, pre_scripts)))
            if which == 0:
                for st, cost in pre_out.items():
                    _put(out, st, cost)
            for st in (S, F):
                if st in out and post[st]:
                    out[st] = _add(out[st], (0, 0, post[st]))
            result.append(out)
        fresh, resumed = result
        if R not in fresh and R not in resumed:
            resumed = {}
        return fresh, resumed

    def tick(self, n: IRNode) -> tuple[Outcomes, Outcomes]:
        kind, nid = n.kind, n.id
        fr = [self.fr[c] for c in n.children]
        rs = [self.rs[c] for c in n.children]
        un = [self.out[c] for c in n.children]
        mark = self.mark[n.index]
        if kind not in _CHAINS and kind not in ("IfThenElse", "WhileDoElse"):
            mark[:] = [True] * len(mark)
        if kind == "Action":
            t = {S: (1, 1, 0), F: (1, 1, 0), R: (1, 1, 0)}
            return t, t
        if kind == "Condition":
            return {S: (1, 1, 0), F: (1, 1, 0)}, {}
        if kind in ("UserControl", "UserDecorator"):
            if self.unbounded_by is None:
                self.unbounded_by = n.index
            u: Cost = (UNBOUNDED, UNBOUNDED, UNBOUNDED)
            t = {S: u, F: u, R: u}
            return t, t
        if nid == "AlwaysSuccess":
            return {S: ONE}, {}
        if nid == "AlwaysFailure":
            return {F: ONE}, {}
        if nid == "Script":
            return {S: (1, 0, 1)}, {}
        if nid == "ScriptCondition":
            attr = self.model(n.index).port("code")
            const = self.data.constant(n.index, attr) if attr is not None else None
            if const is not None:
                self.constants[(n.index, "code")] = const
                return {S if const else F: (1, 0, 1)}, {}
            return {S: (1, 0, 1), F: (1, 0, 1)}, {}
        if nid == "SetBlackboard" and self.m.semantics.setblackboard_converts_to_entry_type:
            return {S: ONE, F: ONE}, {}  # 4.7.0 on: copying an empty entry fails
        if nid in ("SetBlackboard", "UnsetBlackboard"):
            return {S: ONE}, {}
        if nid == "WasEntryUpdated":
            return {S: ONE, F: ONE}, {}
        if nid == "Sleep":
            if n.params[0] == 0 and not self.keyed(n, "msec"):
                return {S: ONE}, {}
            return {S: ONE, R: ONE}, {S: ONE, R: ONE}
        if kind in _CHAINS:
            decides, goes_on = _CHAINS[kind]
            asynch = kind.startswith("Async")
            reactive = kind.startswith("Reactive")
            fresh = self.chain(n, [(t, asynch) for t in fr], decides, goes_on, 0)
            resumed: Outcomes = {}
            done: set[tuple[str, int]] = set()
            while True:  # until no new child is found ticked (a resumed tick may reach later ones)
                before = list(mark)
                for k in range(len(fr)):
                    if R not in un[k] or not mark[k] or ("run", k) in done:  # only a ticked child resumes
                        continue
                    done.add(("run", k))
                    if reactive:  # the others were halted: they start from IDLE
                        tables = [(rs[k] if j == k else fr[j], False) for j in range(len(fr))]
                        resumed = _union(resumed, self.chain(n, tables, decides, goes_on, 0))
                    else:
                        tables = [({}, False)] * k + [(rs[k], False)] + [(t, asynch) for t in fr[k + 1 :]]
                        resumed = _union(resumed, self.chain(n, tables, decides, goes_on, k))
                if asynch:  # resumed after a yield: the next child starts from IDLE
                    for k in range(1, len(fr)):
                        if goes_on in un[k - 1] and mark[k - 1] and ("yield", k) not in done:
                            done.add(("yield", k))
                            tables = [({}, False)] * k + [(t, asynch) for t in fr[k:]]
                            resumed = _union(resumed, self.chain(n, tables, decides, goes_on, k))
                if mark == before:
                    break
            return fresh, resumed
        if kind in ("Parallel", "ParallelAll"):
            return self.parallel(n, fr), self.parallel(n, un)
        if kind == "IfThenElse":
            fresh = self.if_then_else(n, fr[0], fr[1:])
            resumed = self.if_then_else(n, rs[0], fr[1:]) if rs[0] else {}
            for k, b in enumerate(rs[1:], start=1):
                for st, c in b.items() if mark[k] else ():
                    _put(resumed, st, _add(ONE, c))
            return fresh, resumed
        if kind == "WhileDoElse":
            return self.if_then_else(n, fr[0], fr[1:]), self.if_then_else(n, un[0], un[1:])
        if kind == "Switch":
            return _switch(fr), _switch(un)
        if kind in ("Repeat", "RetryUntilSuccessful"):
            return self.decorator(n, fr[0], fr[0], False), self.decorator(n, rs[0], fr[0], True)
        if kind in _NAV2:
            return self.nav2(n, fr), self.nav2(n, un)
        if kind not in _DECORATORS:  # a node this analysis does not model: anything, each child once
            total: Cost = ONE
            for w in un:
                most: Cost = ZERO
                for v in w.values():
                    most = _max(most, v)
                total = _add(total, most)
            anything = {st: total for st in ORDER}
            return anything, anything
        child_fr = fr[0] if fr else {}
        return self.decorator(n, child_fr, child_fr, False), self.decorator(n, un[0] if un else {}, {}, True)

    def chain(self, n: IRNode, kids: list[tuple[Outcomes, bool]], decides: str, goes_on: str, start: int) -> Outcomes:
        """Sequence-like nodes: children in order from `start` while they return `goes_on` (or
        SKIPPED); each child's table, and whether it yields after `goes_on` (the async variants)."""
        out: Outcomes = {}
        # a tick resumed at a later child: the ones before went on or were skipped in earlier ticks
        went: Optional[Cost] = ONE if start > 0 else None  # a path where some child went on
        skipped: Optional[Cost] = ONE  # a path where all children so far skipped
        last = len(kids) - 1
        mark = self.mark[n.index]
        for k in range(start, len(kids)):
            w, yields = kids[k]
            if went is None and skipped is None:
                prev = n.children[k - 1]
                self.why.setdefault(
                    n.children[k],
                    f"{self.label(n.index)} never gets past {self.label(prev)} (line {self.p.nodes[prev].loc.line}), "
                    f"which never returns {goes_on} or SKIPPED",
                )
                break
            mark[k] = True
            best = _max(went, skipped) if went is not None and skipped is not None else (went or skipped)
            assert best is not None
            for st, c in w.items():
                if st in (decides, R):
                    _put(out, st, _add(best, c))
                if st == goes_on and yields and k < last:
                    _put(out, R, _add(best, c))  # the async variants yield after a child that was IDLE
            g, s = w.get(goes_on), w.get(K)
            if yields and k < last:
                g = None  # ... so the next child is not ticked in this tick
            new_went: Optional[Cost] = None
            if g is not None:
                new_went = _add(best, g)
            if went is not None and s is not None:
                new_went = _max(new_went, _add(went, s))
            skipped = _add(skipped, s) if skipped is not None and s is not None else None
            went = new_went
        else:
            if went is not None:
                _put(out, goes_on, went)
            if skipped is not None and kids:
                _put(out, K, skipped)
        return out

    def parallel(self, n: IRNode, kids: list[Outcomes]) -> Outcomes:
        total: Cost = ONE
        for w in kids:
            c: Cost = ZERO
            for v in w.values():
                c = _max(c, v)
            total = _add(total, c)
        can = {st: sum(1 for w in kids if st in w) for st in ORDER}
        out: Outcomes = {}
        count = len(kids)
        if n.kind == "Parallel":  # the thresholds are checked after every child (interp/controls.py)
            need_s, need_f, negative = n.params
            if (can[S] + can[K] if negative else can[S]) >= need_s:
                out[S] = total
            if can[F] >= min(need_f, count - need_s + 1):
                out[F] = total
            if can[R] or can[K]:  # a child still RUNNING, or skipped ones that reach no threshold
                out[R] = total
        else:  # ParallelAll: decided when every child has completed or skipped
            need = n.params[0]
            must_fail = sum(1 for w in kids if set(w) == {F})
            if must_fail < need:
                out[S] = total
            if can[F] >= need:
                out[F] = total
            if can[R]:
                out[R] = total
        if kids and can[K] == len(kids):
            out[K] = total
        return out

    def if_then_else(self, n: IRNode, cond: Outcomes, branches: list[Outcomes]) -> Outcomes:
        out: Outcomes = {}
        mark = self.mark[n.index]
        if cond:
            mark[0] = True
        if R in cond:
            _put(out, R, _add(ONE, cond[R]))
        for branch, when in ((1, S), (2, F)):
            if when not in cond:
                if branch < len(n.children):
                    self.why.setdefault(
                        n.children[branch],
                        f"the condition {self.label(n.children[0])} of {self.label(n.index)} never returns {when}",
                    )
                continue
            if branch > len(branches):
                _put(out, F, _add(ONE, cond[when]))
                continue
            mark[branch] = True
            for st, c in branches[branch - 1].items():
                _put(out, st, _add(_add(ONE, cond[when]), c))
        return out

    def decorator(self, n: IRNode, w: Outcomes, w_fresh: Outcomes, resumed: bool) -> Outcomes:
        """One tick of a decorator whose child answers from `w`; a Repeat or Retry resumed from
        RUNNING may start the next cycle in the same tick, with the child fresh (`w_fresh`)."""
        kind = n.kind
        out: Outcomes = {}

        def through(mapping: dict[str, str], extra: Cost = ONE) -> None:
            for st, c in w.items():
                if st in mapping:
                    _put(out, mapping[st], _add(extra, c))

        same = {S: S, F: F, R: R, K: K}
        if kind == "Inverter":
            through({S: F, F: S, R: R, K: K})
        elif kind == "ForceSuccess":
            through({S: S, F: S, R: R, K: K})
        elif kind == "ForceFailure":
            through({S: F, F: F, R: R, K: K})
        elif kind == "KeepRunningUntilFailure":  # a SKIPPED child leaves its own status: RUNNING
            through({S: R, F: F, R: R, K: R})
        elif kind in ("Repeat", "RetryUntilSuccessful"):
            limit = n.params[0]
            again = S if kind == "Repeat" else F
            if self.keyed(n, "num_cycles" if kind == "Repeat" else "num_attempts"):
                limit = _ANY_COUNT  # read from the blackboard at every tick: any count
            # the loop never starts: SKIPPED (docs/btcpp-4.6.2-edges.md, R1)
            if limit != _ANY_COUNT and (limit == 0 or limit < -1):
                port = "num_cycles" if kind == "Repeat" else "num_attempts"
                self.never(n, f"{self.label(n.index)} has {port}={limit}")
                if self.m.semantics.loop_end_never_skipped:  # 4.7.0 on
                    return {S if kind == "Repeat" else F: ONE}
                return {K: ONE}
            final = S if kind == "Repeat" else F

            def single(st: str) -> list[str]:
                if st != again:
                    return [st]
                if limit == _ANY_COUNT:
                    return [R, final]
                return ([R] if limit == -1 or limit >= 2 else []) + ([final] if limit >= 1 else [])

            for st, c in w.items():
                for t in single(st):
                    _put(out, t, _add(ONE, c))
            if limit == _ANY_COUNT:  # a count of 0 never starts the loop
                _put(out, final if self.m.semantics.loop_end_never_skipped else K, ONE)
            # a cycle resumed from RUNNING that ends with `again` starts the next one in the same tick
            if resumed and again in w and (limit in (-1, _ANY_COUNT) or limit >= 2):
                first = _add(ONE, w[again])
                for st, c in w_fresh.items():
                    for t in single(st):
                        _put(out, t, _add(first, c))
        elif kind == "RunOnce":
            through(same)
            _put(out, K if n.params[0] == 1 else S, ONE)
            if n.params[0] != 1:
                _put(out, F, ONE)
        elif kind == "Precondition":
            attr = self.model(n.index).port("if")
            const = self.data.constant(n.index, attr) if attr is not None else None
            if const is not None:
                self.constants[(n.index, "if")] = const
            else_status = ("IDLE", R, S, F, K)[n.params[0]] if 0 <= n.params[0] <= 4 else F
            if const is not False:
                through(same, (1, 0, 1))
            else:
                self.never(n, f"the `if` of {self.label(n.index)} is always false ({attr.value if attr else ''!r})")
            if const is not True and else_status != "IDLE":  # IDLE: a run-time error (edge L1)
                _put(out, else_status, (1, 0, 1))
        elif kind == "Timeout":
            through(same)
            _put(out, F, ONE)
        elif kind == "Delay":
            through(same)
            _put(out, R, ONE)
        elif kind == "Loop":
            through({S: R, F: F, R: R, K: R})
            else_status = ("IDLE", R, S, F, K)[n.params[0]] if 0 <= n.params[0] <= 4 else S
            if else_status != "IDLE":  # IDLE: a run-time error (edge L1)
                _put(out, else_status, ONE)
        elif kind == "SkipUnlessUpdated":
            through(same)
            _put(out, K, ONE)
        elif kind == "WaitValueUpdate":
            through(same)
            _put(out, R, ONE)
        else:  # SubTree
            through(same)
        return out

    def nav2(self, n: IRNode, kids: list[Outcomes]) -> Outcomes:
        """One tick of a Nav2 node (interp/nav2.py): which statuses, and the most work. Each child
        is ticked at most once, but RecoveryNode's: the first up to number_of_retries + 1 times
        and the recovery up to number_of_retries times, while they answer at once."""
        most = [ZERO if not w else _max_of(w) for w in kids]
        can = [set(w) for w in kids]
        kind = n.kind
        out: Outcomes = {}
        if kind == "RecoveryNode":
            if self.keyed(n, "number_of_retries"):
                if self.unbounded_by is None:
                    self.unbounded_by = n.index
                u: Cost = (UNBOUNDED, UNBOUNDED, UNBOUNDED)
                return {st: u for st in ORDER}
            r = max(n.params[0], 0)
            cost = ONE
            for _ in range(r + 1):
                cost = _add(cost, most[0])
            for _ in range(r):
                cost = _add(cost, most[1])
            statuses = set()
            if S in can[0]:
                statuses.add(S)
            if F in can[0] or F in can[1] or K in can[1]:
                statuses.add(F)
            if R in can[0] or R in can[1]:
                statuses.add(R)
            if K in can[0]:
                statuses.add(K)
            return {st: cost for st in statuses}
        cost = ONE
        for c in most:
            cost = _add(cost, c)
        if kind == "PipelineSequence":
            if all(c & {S, K} for c in can):
                out[S] = cost
            if all(K in c for c in can):
                out[K] = cost
            if any(F in c for c in can):
                out[F] = cost
            if any(R in c for c in can):
                out[R] = cost
        elif kind == "RoundRobin":
            for st in (S, F, R):
                if any(st in c for c in can) or (st == F and any(K in c for c in can)):
                    out[st] = cost
            if all(K in c for c in can):
                out[K] = cost
        elif kind == "NonblockingSequence":
            if all(S in c for c in can):
                out[S] = cost
            if any(F in c for c in can) or any(K in c for c in can):  # (a SKIPPED child is an error)
                out[F] = cost
            if any(R in c for c in can):
                out[R] = cost
        elif kind == "RateController":  # a period not over yet: RUNNING without ticking the child
            out = {st: cost for st in can[0]}
            _put(out, R, ONE)
        elif kind == "SingleTrigger":  # its child done, it fails while it stays active
            out = {st: cost for st in can[0]}
            _put(out, F, ONE)
        return out

    def keyed(self, n: IRNode, port: str) -> bool:
        """Whether the node reads `port` from the blackboard (`{key}`), so its value is not known here."""
        attr = self.model(n.index).port(port)
        return attr is not None and bbmod.strip_blackboard_pointer(attr.value) is not None

    def never(self, n: IRNode, why: str) -> None:
        self.mark[n.index][:] = [False] * len(n.children)
        for c in n.children:
            self.why.setdefault(c, f"{why}: it never ticks its child")

    # -- what the results mean
    def reach(self) -> list[bool]:
        reach = [False] * len(self.p.nodes)
        reach[0] = True
        for n in self.p.nodes:  # parents before children
            if not reach[n.index]:
                continue
            for k, c in enumerate(n.children):
                ok = self.kid_reach[n.index][k] if k < len(self.kid_reach[n.index]) else True
                reach[c] = ok
        return reach

    def instance(self, i: int) -> str:
        """The SubTree instances a node is in: `Tour/IV. VisitExhibit` ('' in the main tree)."""
        names = []
        j = self.p.nodes[i].parent
        while j >= 0:
            if self.p.nodes[j].kind == "SubTree":
                names.append(self.p.nodes[j].name)
            j = self.p.nodes[j].parent
        return "/".join(reversed(names))


# ====================================================================== the checks
_NAV2 = ("PipelineSequence", "RecoveryNode", "RoundRobin", "NonblockingSequence", "RateController", "SingleTrigger")


def _max_of(w: Outcomes) -> Cost:
    c: Cost = ZERO
    for v in w.values():
        c = _max(c, v)
    return c


def rate_limits(program: Program) -> list[tuple[IRNode, Optional[float]]]:
    """Each Nav2 RateController and its hz (None: read from the blackboard when it starts): once
    its child has succeeded, the child is ticked again only after 1/hz seconds of the clock
    (while the child is RUNNING, on every tick)."""
    out: list[tuple[IRNode, Optional[float]]] = []
    for n in program.nodes:
        if n.kind == "RateController":
            out.append((n, None if n.params[1] else struct.unpack("<d", struct.pack("<q", n.params[0]))[0]))
    return out


def analyze_program(mission: Mission, program: Program, options: records.DataOptions) -> Analysis:
    data = _Data(mission, options)
    a = _Analyzer(mission, program, data)
    a.run()
    reach = a.reach()
    findings: list[Finding] = []
    seen: set[tuple[Loc, str]] = set()

    def add(loc: Loc, category: str, message: str) -> None:
        if (loc, message) not in seen:
            seen.add((loc, message))
            findings.append(Finding(loc, category, message))

    # unreachable: the first unreachable node of each branch
    for n in program.nodes:
        if reach[n.index] or (n.parent >= 0 and not reach[n.parent]):
            continue
        where = a.instance(n.index)
        inside = f" (in SubTree instance `{where}`)" if where else ""
        add(n.loc, "unreachable", f"{a.label(n.index)} can never be ticked{inside}: {a.why.get(n.index, '?')}")
    for (i, attr_name), value in sorted(a.constants.items()):
        if not reach[i]:
            continue
        n = program.nodes[i]
        model = data.insts[i].node
        attr = model.pre_condition(attr_name) or model.port(attr_name)
        loc = attr.value_loc if attr is not None else n.loc
        where = a.instance(i)
        inside = f" in SubTree instance `{where}`" if where else ""
        add(loc, "constant", f"`{attr_name}` of {a.label(i)} is always {'true' if value else 'false'}{inside}")

    # a completed tick's statuses the root can never return are findings of their own only when
    # the root can return nothing but RUNNING: the mission never ends
    root = a.out[0]
    if root and set(root) <= {R}:
        add(program.nodes[0].loc, "unreachable", "the main tree never returns SUCCESS or FAILURE")

    # reactive nodes: two children that can be RUNNING
    for n in program.nodes:
        if n.kind not in ("ReactiveSequence", "ReactiveFallback") or not reach[n.index]:
            continue
        running = [c for k, c in enumerate(n.children) if a.kid_reach[n.index][k] and R in a.out[c]]
        if len(running) >= 2:
            first, second = running[0], running[1]
            add(
                program.nodes[second].loc,
                "reactive",
                f"{a.label(second)} and {a.label(first)} (line {program.nodes[first].loc.line}) can both "
                f"return RUNNING under {a.label(n.index)}: the one RUNNING in a tick is halted (or has "
                f"completed) when the other is RUNNING in the next; BehaviorTree.CPP 4.6.2's "
                f"EnableException(true) check throws then",
            )

    _blackboard_findings(a, data, reach, add)
    return Analysis(program, a.out, reach, a.unbounded_by, findings, a.constants)


def _loops_between(program: Program, i: int, j: int) -> bool:
    """Whether a node on the path from the common ancestor of i and j re-ticks earlier children
    (so j's write may come before i's read in a later tick)."""
    anc_i = []
    k = i
    while k >= 0:
        anc_i.append(k)
        k = program.nodes[k].parent
    anc_j = set()
    k = j
    while k >= 0:
        anc_j.add(k)
        k = program.nodes[k].parent
    loopers = {
        "Repeat",
        "RetryUntilSuccessful",
        "KeepRunningUntilFailure",
        "Loop",
        "ReactiveSequence",
        "ReactiveFallback",
        "WhileDoElse",
        "UserControl",
        "UserDecorator",
    }
    for k in anc_i:
        if k in anc_j:  # the common ancestor and the ones above it
            while k >= 0:
                if program.nodes[k].kind in loopers:
                    return True
                k = program.nodes[k].parent
            return False
    return False


def _blackboard_findings(a: _Analyzer, data: _Data, reach: list[bool], add) -> None:
    program = a.p
    for eid, reads in data.reads.items():
        entry = data.entries[eid]
        key = data.entry_key.get(eid, "?")
        if entry.value is not None or eid in data.provided:  # a value from the start (constant, --entry)
            continue
        reads = [r for r in reads if reach[r[0]]]
        if not reads:
            continue
        writes = [w for w in data.writes.get(eid, []) if reach[w[0]]]
        first = min(reads, key=lambda r: r[0])
        if not writes:
            add(
                first[1],
                "blackboard",
                f"blackboard entry `{key}` is read by {a.label(first[0])} but no node of the mission "
                f"writes it (the application must set it before the first tick)",
            )
            continue
        if all(w[0] > first[0] for w in writes) and not any(_loops_between(program, first[0], w[0]) for w in writes):
            w = min(writes)
            add(
                first[1],
                "blackboard",
                f"blackboard entry `{key}` is read by {a.label(first[0])} before anything can have written "
                f"it: its first writer {a.label(w[0])} (line {w[1].line}) runs later",
            )
    for eid, writes in data.writes.items():
        writes = [w for w in writes if reach[w[0]]]
        if not writes or data.reads.get(eid):
            continue
        key = data.entry_key.get(eid, "?")
        w = min(writes)
        add(
            w[1],
            "blackboard",
            f"blackboard entry `{key}` is written by {a.label(w[0])} but never read by the mission",
        )
    for eid, reads in data.reads.items():
        typed: dict[str, tuple[int, Loc]] = {}
        for idx, loc, t in reads:
            if t is not None and reach[idx]:
                typed.setdefault(t, (idx, loc))
        if len(typed) > 1:
            (t1, (i1, l1)), (t2, (i2, l2)) = sorted(typed.items(), key=lambda x: x[1][0])[:2]
            key = data.entry_key.get(eid, "?")
            add(
                l2,
                "blackboard",
                f"blackboard entry `{key}` is read as `{t2}` by {a.label(i2)} and as `{t1}` by "
                f"{a.label(i1)} (line {l1.line})",
            )


# ====================================================================== memory
def memory(program: Program) -> dict:
    """The compiled executor's sizes from the tables (runtime/include/btgen/engine.hpp: statuses are
    bytes, counters int32, timers uint64; the blackboard as data_cpp.py spells its slots)."""
    n = len(program.nodes)
    bb = 0
    if program.data is not None:
        for s in program.data.slots:
            if s.kind == "string":
                bb += s.capacity + 8
            elif is_queue(s.kind):
                bb += s.capacity * max(s.elem_capacity + 8, 8) + 16
            elif s.kind == "bool":
                bb += 2
            else:
                bb += 16
    return {
        "nodes": n,
        "stack_depth": program.max_depth,
        "counters": program.counter_count,
        "timers": program.timer_count,
        "state_bytes": n + 4 * program.counter_count + 8 * program.timer_count,
        "blackboard_slots": len(program.data.slots) if program.data is not None else 0,
        "blackboard_bytes_estimate": bb,
    }


# ====================================================================== command
def stop_quietly_on_broken_pipe(command, args) -> int:
    """Run a command whose reader may go away (`btgen explore ... | head`): stop quietly, exit 1."""
    import os

    try:
        return command(args)
    except BrokenPipeError:
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 1


def _fmt(v: int) -> str:
    return "unbounded" if v == UNBOUNDED else str(v)


def analyze_command(args) -> int:
    from btgen import pipeline
    from btgen.ir.lower import lower

    opts = pipeline.options_from_args(args)
    options = opts.data
    status = 0
    reports = []
    for path in args.missions:
        try:
            mission = pipeline.load(path, opts)
            print_diagnostics(mission.warnings)
            program = lower(mission, options)
        except UserError as e:
            print_diagnostics(e.diagnostics)
            status = 1
            continue
        result = analyze_program(mission, program, options)
        worst = result.worst()
        if args.tick_budget is not None:
            for name, v in zip(("nodes visited", "leaf hooks called", "script evaluations"), worst):
                if v == UNBOUNDED or v > args.tick_budget:
                    culprit = ""
                    if v == UNBOUNDED and result.unbounded_by is not None:
                        u = program.nodes[result.unbounded_by]
                        culprit = f' ({u.id} "{u.name}" may tick its children any number of times)'
                    result.findings.append(
                        Finding(
                            program.nodes[0].loc,
                            "budget",
                            f"a tick can take {_fmt(v)} {name}, over the budget of {args.tick_budget}{culprit}",
                        )
                    )
        mem = memory(program)
        reports.append((path, result, worst, mem))
        if args.json:
            continue
        print_diagnostics([Diagnostic(f.loc, f.message, "warning") for f in result.findings])
        if result.findings and args.werror:
            status = 1
    if args.json:
        doc = []
        for path, result, worst, mem in reports:
            unb = result.unbounded_by
            doc.append(
                {
                    "mission": path,
                    "findings": [f.as_json() for f in result.findings],
                    "worst_tick": {
                        "nodes_visited": None if worst[0] == UNBOUNDED else worst[0],
                        "leaf_hooks": None if worst[1] == UNBOUNDED else worst[1],
                        "script_evaluations": None if worst[2] == UNBOUNDED else worst[2],
                        "unbounded_by": None if unb is None else result.program.nodes[unb].uid,
                    },
                    "root_outcomes": {st: list(c) for st, c in result.outcomes[0].items()},
                    "unreachable_nodes": sum(1 for r in result.reachable if not r),
                    "rate_limits": [{"uid": n.uid, "name": n.name, "hz": hz} for n, hz in rate_limits(result.program)],
                    "memory": mem,
                }
            )
            if result.findings and args.werror:
                status = 1
        json.dump(doc if len(doc) != 1 else doc[0], sys.stdout, indent=2)
        sys.stdout.write("\n")
        return status
    for path, result, worst, mem in reports:
        counts: dict[str, int] = {}
        for f in result.findings:
            counts[f.category] = counts.get(f.category, 0) + 1
        unreachable = sum(1 for r in result.reachable if not r)
        rows = [
            ("nodes (SubTrees expanded)", str(mem["nodes"])),
            ("unreachable nodes", str(unreachable)),
            ("worst tick: nodes visited", _fmt(worst[0])),
            ("worst tick: leaf hooks called", _fmt(worst[1])),
            ("worst tick: script evaluations", _fmt(worst[2])),
            ("root can return", ", ".join(st for st in ORDER if st in result.outcomes[0]) or "-"),
            ("stack depth", str(mem["stack_depth"])),
            ("state (statuses, counters, timers)", f"{mem['state_bytes']} bytes"),
            ("blackboard", f"{mem['blackboard_slots']} entries, ~{mem['blackboard_bytes_estimate']} bytes"),
            ("findings", ", ".join(f"{v} {k}" for k, v in sorted(counts.items())) or "none"),
        ]
        if result.unbounded_by is not None:
            n = result.program.nodes[result.unbounded_by]
            rows.insert(5, ("unbounded because of", f'{n.id} "{n.name}" ({n.loc})'))
        for n, hz in rate_limits(result.program):
            how = (
                "as often a second as its `hz` entry says when the node starts"
                if hz is None
                else f"at most {hz:g} times a second (every {1.0 / hz if hz else float('inf'):g} s of the clock"
                "; ticked on every tick while RUNNING)"
            )
            rows.append(("rate limit", f'RateController "{n.name}": its child starts again {how}'))
        width = max(len(r[0]) for r in rows)
        print(f"{path}:")
        for label, text in rows:
            print(f"  {label.ljust(width)}  {text}")
    return status
