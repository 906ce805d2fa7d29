"""Per node, bottom up: the statuses one tick of a node can return and the most work that
tick does, for a tick that finds it IDLE and one that finds it RUNNING; which nodes can be
reached at all."""

from __future__ import annotations

from typing import Optional

from btgen.ir.data.records import PARALLEL_READS
from btgen.ir.lower import IRNode, Program
from btgen.lang import blackboard as bbmod
from btgen.lang.model import Mission
from btgen.tools.analyze.constants import _Data
from btgen.tools.analyze.results import (
    ONE,
    ORDER,
    UNBOUNDED,
    ZERO,
    Cost,
    F,
    Finding,
    K,
    Outcomes,
    R,
    S,
    _add,
    _max,
    _put,
)

_NAV2 = (
    "PipelineSequence",
    "RecoveryNode",
    "RoundRobin",
    "NonblockingSequence",
    "RateController",
    "SingleTrigger",
    "DistanceController",
    "SpeedController",
    "GoalUpdatedController",
    "PathLongerOnApproach",
    "GoalUpdater",
)


def _max_of(w: Outcomes) -> Cost:
    c: Cost = ZERO
    for v in w.values():
        c = _max(c, v)
    return c


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
        if n.kind == "Parallel" and n.params[2] & PARALLEL_READS:
            # thresholds read from the blackboard on every tick: any outcome, as far as known here
            for st in (S, F, R):
                out[st] = total
        elif n.kind == "Parallel":  # the thresholds are checked after every child (interp/controls.py)
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
            if const is not True and self.keyed(n, "else"):  # read from the blackboard on every tick
                for st in (R, S, F, K):
                    _put(out, st, (1, 0, 1))
            elif const is not True and else_status != "IDLE":  # IDLE: a run-time error (edge L1)
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
        elif kind in ("DistanceController", "SpeedController", "GoalUpdatedController"):
            out = {st: cost for st in can[0]}  # the input says no: RUNNING without ticking the child
            _put(out, R, ONE)
        elif kind == "PathLongerOnApproach":  # the input says no: SUCCESS without ticking the child
            out = {st: cost for st in can[0]}
            _put(out, S, ONE)
        elif kind == "GoalUpdater":
            out = {st: cost for st in can[0]}
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
        """The SubTree instances a node is in: `Tour/IV_VisitExhibit` ('' in the main tree)."""
        names = []
        j = self.p.nodes[i].parent
        while j >= 0:
            if self.p.nodes[j].kind == "SubTree":
                names.append(self.p.nodes[j].name)
            j = self.p.nodes[j].parent
        return "/".join(reversed(names))
