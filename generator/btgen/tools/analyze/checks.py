"""The findings: nodes never ticked, unbounded or over-budget ticks, blackboard entries read
before any write or never read, reactive nodes with two RUNNING children."""

from __future__ import annotations

from btgen.diagnostics import Diagnostic, Loc
from btgen.ir.data import records
from btgen.ir.lower import Program
from btgen.lang.model import Mission
from btgen.tools.analyze.constants import _Data
from btgen.tools.analyze.results import Analysis, Finding, R
from btgen.tools.analyze.ticks import _Analyzer


def unwritten_script_reads(mission: Mission, options: records.DataOptions) -> list[Diagnostic]:
    """A warning for each blackboard entry a script reads that nothing writes: no node, no
    literal, not the application (--entry). The script fails when it runs (the entry does not
    exist), so `validate` says so; most often an `--entry` / CMake ENTRIES is missing."""
    data = _Data(mission, options)
    out = []
    for eid, reads in data.script_reads.items():
        entry = data.entries[eid]
        if entry.value is not None or eid in data.provided or data.writes.get(eid):
            continue
        index, loc = min(reads, key=lambda r: (r[1].line, r[1].col, r[0]))
        key = data.entry_key.get(eid, "?")
        node = data.insts[index].node
        label = f"`{node.id}`" + (f' "{node.name}"' if node.name and node.name != node.id else "")
        name = key.rsplit("/", 1)[-1].lstrip("@")
        out.append(
            Diagnostic(
                loc,
                f"the script of {label} reads the blackboard entry `{key}`, which nothing writes: it fails "
                f"when it runs unless the application sets the entry (`--entry {name}=TYPE`, CMake "
                f"`ENTRIES {name}=TYPE`)",
                "warning",
            )
        )
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
