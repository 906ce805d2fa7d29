"""The mission's scripts in the Promela model: the blackboard as one finite variable.

Scripts (Script and ScriptCondition nodes, the _failureIf/_successIf/_skipIf/_while
pre-conditions, the _onSuccess/_onFailure/_post post-conditions) are not re-written in
Promela: they are run by the reference interpreter's own evaluator on every blackboard the
mission can reach, and the model gets their effect as tables. A *blackboard* is the value of
every entry of every blackboard of the tree (type and value; an update counter only as far
as an entry-update node compares it), with what is left of each Loop's queue
(`bbjobs.Members`). Starting from the blackboard the tree is
created with, every script is run on every blackboard found so far, until no new one comes:
the reachable blackboards are then a finite set (an over-approximation: a script is run on
blackboards it may never meet), numbered, and the model's variable `bb` holds the number.

When that closure passes MAX_BLACKBOARDS (a counter, `_onSuccess="i1 += 1"`, makes a new
value on every run) and the runs are bounded (--ticks N), the tables come instead from the
blackboards the runs reach: explore's search (tools/explore/search.py, the interpreter under
free leaves, N ticks) records every blackboard at the points where a table's job runs
(`_reachable`), and each job is run on each of those. Free leaves there are freer than in the
model (no contract, no running bound), so the set is an over-approximation still.

What cannot be translated is refused with a located error, never abstracted silently: more
than MAX_BLACKBOARDS blackboards with unbounded runs (an entry that counts without bound, a
double that keeps changing: the error names the script, the entries it changes, and --ticks),
more than MAX_REACHED reached ones under --ticks, a script that can fail at
run time on one of them, `_onHalted`, and scripts read from the blackboard (`code="{key}"`).
Free leaves never write the blackboard (a scenario gives them statuses only), so scripts and
the blackboard nodes (SetBlackboard, Loop ..., `bbjobs.py`, whose jobs run here too) are its
only writers.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from typing import Callable, Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.ir.lower import Program
from btgen.lang.model import Mission
from btgen.tools.verify.refusal import refuse

MAX_BLACKBOARDS = 250
MAX_REACHED = 5000  # with --ticks, blackboards the runs reach (the closure was too large)
MAX_EXPLORE_STATES = 50000  # explore's states for them (its search stops there: refused)
# A state past the reached ones (a script run on a reached blackboard where no run runs it) gets
# its own scripts run up to this many steps away. 0: the model runs a script only where a run of
# the interpreter does (it is the same semantics), at a point `_reachable` records, so such a
# state is never met; if it were, its rows are absent and the model's lookup asserts (a btgen
# bug, shown as a violation that does not replay, never a silent proof). The agreement with
# explore checks it: the assertion would stop SPIN's search short.
AFTER_REACHED = 0
IDLE, RUNNING, SUCCESS, FAILURE, SKIPPED = 0, 1, 2, 3, 4
HALT = 5  # a _while that turns false on a RUNNING node: halt it, SKIPPED
ERROR = 254  # the script fails at run time: the run ends there (the tree throws)
FREE = 253  # a contract's condition that cannot be evaluated on a blackboard: either status
NO_RESULT = 255  # the pre-conditions leave the tick to the node


def _value_key(v) -> tuple:
    try:
        hash(v)
        return (type(v).__name__, v)
    except TypeError:
        return (type(v).__name__, repr(v))


@dataclass
class Tables:
    """Per node index: each script's effect as {blackboard: (blackboard after, result)}."""

    count: int = 1  # blackboards (0: the initial one)
    script: dict[int, dict[int, tuple[int, int]]] = field(default_factory=dict)  # Script / ScriptCondition
    pre_idle: dict[int, dict[int, tuple[int, int]]] = field(default_factory=dict)  # result or NO_RESULT
    pre_running: dict[int, dict[int, tuple[int, int]]] = field(default_factory=dict)  # HALT or NO_RESULT
    post: dict[tuple[int, int], dict[int, tuple[int, int]]] = field(default_factory=dict)  # (node, status)
    cond: dict[int, dict[int, tuple[int, int]]] = field(default_factory=dict)  # contract: SUCCESS, FAILURE, FREE
    node: dict[tuple[int, str], dict[int, tuple[int, int]]] = field(default_factory=dict)  # bbnodes.py: (node, role)
    params: dict[int, list] = field(default_factory=dict)  # bbnodes.py: the counts a node reads, by index
    values: list[dict[str, object]] = field(default_factory=list)  # root blackboard's entries, per number
    warnings: list[Diagnostic] = field(default_factory=list)  # scripts that can fail at run time

    @property
    def used(self) -> bool:
        return bool(self.script or self.pre_idle or self.pre_running or self.post or self.cond or self.node)


def _refuse(loc: Loc, message: str) -> UserError:
    return refuse(loc, message)


def build_tables(
    mission: Mission,
    program: Program,
    functions: tuple = (),
    params_from_bb: frozenset = frozenset(),
    ticks: Optional[int] = None,
    clock_ms: int = 100,
) -> Tables:
    """`functions`: (Condition name, success_if script, its place in the contract file);
    `params_from_bb`: the nodes whose count is read from the blackboard (bbjobs.py); `ticks`:
    the runs' bound (--ticks), which lets the tables come from the blackboards the runs reach
    when the closure over every script is too large (`_reachable`)."""
    try:
        return _build_tables(mission, program, functions, params_from_bb, None, clock_ms)
    except _TooMany as e:
        if ticks is None:
            raise _refuse(e.loc, e.message + _unbounded_hint(e)) from None
    try:
        return _build_tables(mission, program, functions, params_from_bb, ticks, clock_ms)
    except _TooMany as e:
        raise _refuse(e.loc, e.message + f" (in the runs of at most {ticks} ticks)") from None


class _TooMany(Exception):
    def __init__(self, loc: Loc, message: str, grows: list[str]) -> None:
        super().__init__(message)
        self.loc, self.message, self.grows = loc, message, grows


def _unbounded_hint(e: _TooMany) -> str:
    grows = ", ".join(f"`{k}`" for k in e.grows) if e.grows else "an entry"
    return (
        f"; {grows} takes a new value on every run of this script and the runs are unbounded: "
        "with --ticks N only the blackboards runs of N ticks reach are tabled"
    )


def _build_tables(
    mission: Mission,
    program: Program,
    functions: tuple,
    params_from_bb: frozenset,
    ticks: Optional[int],
    clock_ms: int,
) -> Tables:
    """With `ticks` None: every script run on every blackboard found (the closure). Otherwise the
    blackboards explore's search reaches in runs of `ticks` ticks (`_reachable`), and every script
    run on each of them and on what those runs make, up to AFTER_REACHED steps away."""
    from btgen.interp.engine import Interpreter
    from btgen.interp.tree import RunError
    from btgen.lang import script as scriptmod
    from btgen.tools.verify import bbjobs

    by_name = {name: (text, loc) for name, text, loc in functions}
    parsed = {}
    for name, (text, loc) in by_name.items():
        try:
            parsed[name] = scriptmod.parse_script(text, mission.semantics.script_grammar_49)
        except scriptmod.ScriptSyntaxError as e:
            raise _refuse(loc, f"`{name}`: success_if `{text}` is not a script: {e.message}") from None
    wanted = [
        n
        for n in program.nodes
        if n.kind in ("Script", "ScriptCondition")
        or n.scripts
        or (n.kind == "Condition" and n.name in by_name)
        or n.kind in bbjobs.BB_KINDS
        or n.index in params_from_bb
    ]
    tables = Tables()
    if not wanted:
        return tables
    explorer = None
    if ticks is not None:
        from btgen.tools.explore.search import Explorer

        explorer = Explorer(mission, ticks, 10**9, clock_ms, MAX_EXPLORE_STATES)
        interp = explorer.interp
    else:
        interp = Interpreter(mission)
    inodes = interp.nodes
    bbs = list({id(n.bb): n.bb for n in inodes}.values())
    root = interp.root_bb
    members = bbjobs.Members(inodes)  # the nodes' members the blackboard decides: the last item of a state

    def save() -> tuple:
        return (
            *(tuple((k, e, e.type_name, _copy(e.value), e.sequence_id) for k, e in bb._storage.items()) for bb in bbs),
            members.save(),
        )

    def key(state: tuple) -> tuple:
        return (
            *(tuple(sorted((k, t, _value_key(v)) for k, _e, t, v, _s in entries)) for entries in state[:-1]),
            members.key(state[-1]),
        )

    def restore(state: tuple) -> None:
        for bb, entries in zip(bbs, state):
            bb._storage.clear()
            for k, e, t, v, s in entries:
                e.type_name, e.value, e.sequence_id = t, _copy(v), s
                bb._storage[k] = e
        members.restore(state[-1])

    states: list[tuple] = [save()]
    numbers: dict[tuple, int] = {key(states[0]): 0}
    level = [0]  # per state: 0 reached by a run (or the closure), else steps past one
    limit = MAX_BLACKBOARDS
    if explorer is not None:
        limit = MAX_REACHED
        for st in _reachable(explorer, save, key, wanted[0].loc):
            k = key(st)
            if k not in numbers:
                if len(states) >= limit:
                    raise _TooMany(wanted[0].loc, f"the runs reach more than {limit} blackboards", [])
                numbers[k] = len(states)
                states.append(st)
                level.append(0)

    # Every script: (table, entry key, where, what to run on the interpreter's node).
    jobs: list[tuple[dict, object, Loc, Callable[[], int]]] = []
    for n in wanted:
        node = inodes[n.index]
        if node.uid != n.uid:  # pragma: no cover - the interpreter builds in creation order
            raise AssertionError("the interpreter's nodes are not in creation order")
        if node.on_halted is not None:  # haltNode: halt(), then the script (promela.Emitter.halt_node)
            job = partial(_run_on_halted, node)
            jobs.append((tables.node.setdefault((n.index, "halted"), {}), None, node.on_halted.value_loc, job))
        if n.kind in ("Script", "ScriptCondition"):
            port = node.script  # type: ignore[attr-defined]  # a Script or ScriptCondition node
            if not port.literal or port.attr is None:
                where = port.attr.value_loc if port.attr is not None else n.loc
                raise _refuse(
                    where, f'`{n.id}` "{n.name}" reads its script from the blackboard; btgen verify needs a literal'
                )
            run = _run_condition if n.kind == "ScriptCondition" else _run_script
            jobs.append((tables.script.setdefault(n.index, {}), None, port.attr.value_loc, partial(run, port)))
        if n.kind == "Condition" and n.name in by_name:
            job = partial(_contract_condition, node, parsed[n.name], interp)
            jobs.append((tables.cond.setdefault(n.index, {}), "pure", by_name[n.name][1], job))
        if node.pre:
            where = node.pre[0][1].value_loc
            jobs.append((tables.pre_idle.setdefault(n.index, {}), None, where, partial(_pre_idle, node)))
            for kind, attr in node.pre:
                if kind == "_while":
                    job = partial(_pre_running, node, attr)
                    jobs.append((tables.pre_running.setdefault(n.index, {}), None, attr.value_loc, job))
        for status in (SUCCESS, FAILURE):
            attrs = [a for a in (node.on_success if status == SUCCESS else node.on_failure, node.post_always) if a]
            if attrs:
                job = partial(_post, node, status)
                jobs.append((tables.post.setdefault((n.index, status), {}), None, attrs[0].value_loc, job))
        jobs.extend(bbjobs.node_jobs(n, node, tables, n.index in params_from_bb))

    failing: dict[Loc, str] = {}
    todo = list(range(len(states)))
    while todo:
        s = todo.pop()
        for table, _k, loc, job_run in jobs:
            restore(states[s])
            try:
                result = job_run()
            except (RunError, UserError) as e:
                table[s] = (s, ERROR)
                if loc not in failing:
                    failing[loc] = f"{e.diagnostics[0].message if e.diagnostics else e} (with " + (
                        describe_root(states[s], bbs, root) + ")"
                    )
                continue
            after = save()
            k = key(after)
            if _k == "pure" and k != key(states[s]):
                raise _refuse(loc, "a contract's success_if must not write the blackboard")
            if k not in numbers:
                if len(states) >= limit:
                    raise _TooMany(
                        loc,
                        f"the blackboard takes more than {limit} values: run on every blackboard found "
                        f"so far, this script keeps making new ones (e.g. {describe_root(after, bbs, root)}); "
                        "btgen verify needs entries of a finite domain (bool, enums, integers and strings that "
                        "take few values whatever the order the scripts run in)",
                        _changed(states[s], after, bbs, root),
                    )
                numbers[k] = len(states)
                states.append(after)
                level.append(0 if explorer is None else level[s] + 1)
                if level[-1] <= AFTER_REACHED:
                    todo.append(numbers[k])
            table[s] = (numbers[k], result)
    if failing:  # one warning: the blackboards are over-approximated, most failures never happen
        loc, first = next(iter(failing.items()))
        more = f" and {len(failing) - 1} more script(s)" if len(failing) > 1 else ""
        tables.warnings.append(
            Diagnostic(
                loc,
                f"this script{more} can fail at run time on some of the blackboards btgen verify considers, "
                f"which may not all be reachable (here: {first}); a run that gets there ends there, as the "
                "tree's exception ends it, and the properties are checked on what came before",
                severity="warning",
            )
        )
    if members.ahead:  # bbjobs._relation: an abstraction, said where
        node = members.ahead[0]
        p = node.ports.get("entry")
        where = p.attr.value_loc if p is not None and p.attr is not None else node.model.loc
        tables.warnings.append(Diagnostic(where, f'`{node.reg_id}` "{node.name}": {bbjobs.AHEAD_WARNING}', "warning"))
    tables.count = len(states)
    for st in states:
        restore(st)
        tables.values.append({k: e.value for k, e in root._storage.items()})
    restore(states[0])
    return tables


def _changed(before: tuple, after: tuple, bbs: list, root) -> list[str]:
    """The root blackboard's entries a script changed (the error names them)."""
    if root not in bbs:
        return []
    i = bbs.index(root)
    old = {k: _value_key(v) for k, _e, _t, v, _s in before[i]}
    return sorted(k for k, _e, _t, v, _s in after[i] if old.get(k) != _value_key(v))


def _reachable(explorer, save: Callable[[], tuple], key: Callable[[tuple], tuple], loc: Loc) -> list[tuple]:
    """Every blackboard (build_tables' `save`) explore's search meets in its runs: at the start
    and the end of every node's executeTick (its pre-conditions run at the start), of its
    tick() (the body: its post-conditions run at the end) and of every halt, the points where
    a table's job runs. explore merges repeated states (what follows one was recorded where it
    was first reached); --ticks ends a run."""
    from btgen.interp.tree import TreeNode

    found: dict[tuple, tuple] = {}

    def record() -> None:
        st = save()
        found.setdefault(key(st), st)

    classes = {k for n in explorer.nodes for k in type(n).__mro__ if issubclass(k, TreeNode)}
    patched: list[tuple[type, str, object]] = []

    def wrap(original):
        def hooked(node, *a):
            record()
            try:
                return original(node, *a)
            finally:
                record()

        return hooked

    install = explorer._install

    def install_both():
        restore = install()
        for cls in classes:
            for name in ("execute_tick", "tick", "halt"):
                if name in cls.__dict__:
                    original = cls.__dict__[name]
                    patched.append((cls, name, original))
                    setattr(cls, name, wrap(original))

        def restore_both() -> None:
            for cls, name, original in reversed(patched):
                setattr(cls, name, original)
            restore()

        return restore_both

    explorer._install = install_both
    record()
    result = explorer.explore()
    explorer._restore(explorer._initial)
    if result.truncated:
        raise _TooMany(
            loc,
            f"explore's search of the runs stopped at {explorer.max_states} states",
            [],
        )
    return list(found.values())


def _copy(value):
    """A queue is a mutable value (a Loop pops it in place): each state keeps its own."""
    from btgen.lang import values

    return values.Queue(value.element_type, value) if isinstance(value, values.Queue) else value


def _run_on_halted(node) -> int:
    node.run_script(node.on_halted)
    return SUCCESS


def _run_script(port) -> int:
    port.run()
    return SUCCESS


def _run_condition(port) -> int:
    return SUCCESS if port.truth() else FAILURE


def _contract_condition(node, parsed, interp) -> int:
    """SUCCESS when the contract's script is true on the node's blackboard; FREE when it cannot
    be evaluated there (an entry without a value)."""
    from btgen.lang import script as scriptmod
    from btgen.lang import values

    try:
        value = scriptmod.evaluate(parsed, node.bb, interp.rt.enums, interp.rt.sem.int_to_double_53_bits)
        return SUCCESS if scriptmod.script_truth(value) else FAILURE
    except (scriptmod.ScriptRuntimeError, values.ConversionError):
        return FREE
    except Exception as e:  # a blackboard error: the same as an entry without value
        if type(e).__name__ == "BlackboardError":
            return FREE
        raise


def _pre_idle(node) -> int:
    """checkPreConditions of an IDLE node: a result, or NO_RESULT (tick it)."""
    node.status = IDLE
    r = node._check_pre_conditions()
    return NO_RESULT if r is None else r


def _pre_running(node, attr) -> int:
    """checkPreConditions of a RUNNING node: its _while false halts it."""
    return NO_RESULT if node.truth(attr) else HALT


def _post(node, status: int) -> int:
    node._check_post_conditions(status)
    return status


def compare_entry(values: dict, key: tuple) -> bool:
    """("bb", ENTRY, OP, VALUE) on the root blackboard's entries: False when the entry has no
    value, or when a number is compared with a string (then `!=` is True)."""
    _bb, name, op, want = key
    if name not in values or values[name] is None:
        return False
    have = values[name]
    if isinstance(have, bool):
        have = int(have)
    numbers = isinstance(have, (int, float)) and isinstance(want, (int, float))
    if not numbers and not (isinstance(have, str) and isinstance(want, str)):
        return op == "!="
    return {
        "==": have == want,
        "!=": have != want,
        "<": have < want,
        "<=": have <= want,
        ">": have > want,
        ">=": have >= want,
    }[op]


def entries_of(tables: Tables) -> dict[str, str]:
    """The root blackboard's entries some reachable blackboard gives a value."""
    out: dict[str, str] = {}
    for values in tables.values:
        for k, v in values.items():
            if v is not None:
                out.setdefault(k, type(v).__name__)
    return out


def describe_root(state: tuple, bbs: list, root) -> str:
    entries = state[bbs.index(root)] if root in bbs else ()
    shown = ", ".join(f"{k}={v!r}" for k, _e, _t, v, _s in sorted(entries, key=lambda x: x[0])[:6])
    return shown or "no entries"


def lookup(table: dict[int, tuple[int, int]], on_result: Callable[[int], str], var: str = "bb") -> list[str]:
    """`if :: bb == S -> bb = S'; <on_result(result)> ... fi` over a table."""
    out = ["if"]
    for s, (after, result) in sorted(table.items()):
        if result == ERROR:
            out.append(f":: {var} == {s} -> goto Error")
            continue
        move = f"{var} = {after}; " if after != s else ""
        out.append(f":: {var} == {s} -> {move}{on_result(result)}")
    out.append(":: else -> assert(false)  /* a blackboard the tables do not know: a btgen bug */")
    out.append("fi;")
    return out


def result_is(name: str) -> Callable[[int], str]:
    return lambda r: f"{name} = {r}"
