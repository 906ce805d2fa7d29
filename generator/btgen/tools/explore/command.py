"""`btgen explore`'s command: scenario files, coverage lines, the options' checks, the report
and the progress line, over the search of `search.py` (the package's docstring says what the
search is)."""

from __future__ import annotations

import json
import os
import sys
import time
from typing import Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.fileio import Manifest, check_output, write_output
from btgen.interp.scenario import MAX_VALUE, format_scenario, leaf_locs, parse_scenario_text
from btgen.interp.tree import SUCCESS
from btgen.lang.model import Mission
from btgen.tools import obligations
from btgen.tools.explore.search import (
    BY_NAME,
    NAMES,
    Explorer,
    Path,
    parse_property,
)


# ====================================================================== scenario files
def scenario_text(path: Path, clock_ms: int, comment: str = "", where: Optional[dict[str, Loc]] = None) -> str:
    """The scenario file that replays a path: each leaf name's statuses in call order
    (interp.scenario.format_scenario: UserError at the leaf for a name the format cannot hold)."""
    per: dict[str, list[str]] = {}
    for name, st in path.picks:
        per.setdefault(name, []).append(NAMES[st])
    return format_scenario(path.ticks, list(per.items()), clock_ms, comment, where)


def coverage_lines(
    node_hits: int, node_goals: int, out_hits: int, out_goals: int, in_hits: int = 0, in_goals: int = 0
) -> list[str]:
    """The coverage lines `cover` and `explore` print, in one vocabulary: nodes ticked, outcomes
    (each status a node can return, as `btgen analyze` finds, seen at least once), and, when the
    mission has Nav2 Decorators with an input of the environment, inputs (each yes and no)."""

    def pct(hit: int, goal: int) -> str:
        return f"{100.0 * hit / goal if goal else 100.0:.1f}%"

    lines = [
        f"nodes:    {node_hits}/{node_goals} = {pct(node_hits, node_goals)} ticked",
        f"outcomes: {out_hits}/{out_goals} = {pct(out_hits, out_goals)} (each SUCCESS, FAILURE, RUNNING a node "
        "can return, seen)",
    ]
    if in_goals:
        lines.append(
            f"inputs:   {in_hits}/{in_goals} = {pct(in_hits, in_goals)} (each yes and no of a Nav2 Decorator's "
            "input, seen)"
        )
    return lines


def sync_actions(mission: Mission, args) -> frozenset[str]:
    """The IDs of `--sync`: user Actions implemented synchronously (a `tick()` hook, like
    BehaviorTree.CPP's SyncActionNode), which never return RUNNING; each must be one."""
    from btgen.diagnostics import did_you_mean

    wanted = tuple(getattr(args, "sync", None) or ())
    actions = {m.id for m in mission.models if m.kind == "Action"}
    for name in wanted:
        if name not in actions:
            guess = did_you_mean(name, actions)
            hint = f" (did you mean `{guess}`?)" if guess else ""
            raise cmdline.error(args, name, f"--sync {name}: the mission declares no Action `{name}`{hint}")
    return frozenset(wanted)


def _possible(mission: Mission, args) -> Optional[dict[int, set[int]]]:
    """The statuses `btgen analyze` finds possible per node (None when the mission does not lower)."""
    from btgen import pipeline
    from btgen.tools.analyze import analyze_program

    try:
        opts = pipeline.options_from_args(args)
        options = opts.data
        program = pipeline.program(mission, opts)
    except UserError:
        return None
    result = analyze_program(mission, program, options)
    sync = sync_actions(mission, args)
    return {
        i: (
            {BY_NAME[s] for s in result.outcomes[i] if not (s == "RUNNING" and program.nodes[i].id in sync)}
            if result.reachable[i]
            else set()
        )
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


def criteria_of(args) -> tuple[str, ...]:
    """`--coverage` of a command (default: node,outcome)."""
    text = getattr(args, "coverage", None)
    if text is None:
        return obligations.DEFAULT
    try:
        return obligations.parse_criteria(text)
    except ValueError as e:
        raise cmdline.error(args, "--coverage", f"--coverage {text}: {e}") from None


def _goal_order(g: tuple) -> tuple:
    order = ("node", "outcome", "halt", "pre", "post", "mcdc")
    return (g[1], order.index(g[0]) if g[0] in order else 9, str(g[2:]))


def _uncovered_text(g: tuple, names: dict, ob) -> str:
    n = names[g[1]]
    head = f'{g[1]} {n.reg_id} "{n.name}"'
    if g[0] == "node":
        return head + " ticked"
    if g[0] == "outcome":
        return f"{head} {NAMES[g[2]]}"
    if g[0] == "input":
        return f"{head} input {'yes' if g[2] == SUCCESS else 'no'}"
    return f"{head} {obligations.describe(g, ob)}"


def obligation_counts(goals: set, covered: set) -> dict[str, list[int]]:
    """Per goal kind: [covered, goals]."""
    out: dict[str, list[int]] = {}
    for g in goals:
        row = out.setdefault(g[0], [0, 0])
        row[1] += 1
        if g in covered:
            row[0] += 1
    return out


def criteria_lines(criteria: tuple[str, ...], goals: set, covered: set) -> list[str]:
    """One line per goal kind of the criteria, `nodes:` and `outcomes:` as before."""
    counts = obligation_counts(goals, covered)

    def get(kind: str) -> tuple[int, int]:
        hit, total = counts.get(kind, [0, 0])
        return hit, total

    lines: list[str] = []
    if "node" in criteria or "outcome" in criteria:
        both = coverage_lines(*get("node"), *get("outcome"), *get("input"))
        lines += [both[0]] if "node" in criteria else []
        lines += both[1:] if "outcome" in criteria else []  # (the inputs line with the outcomes)
    what = {
        "halt": "each node that can be RUNNING, halted while RUNNING",
        "pre": "each _failureIf/_successIf/_skipIf/_while evaluated true and false",
        "post": "each _onSuccess/_onFailure/_post/_onHalted decided each way",
        "mcdc": "each operand of each && and || shown to decide the result (masking MC/DC)",
    }
    for kind in ("halt", "pre", "post", "mcdc"):
        if kind not in obligations.kinds_of(criteria):
            continue
        hit, total = get(kind)
        pct = f"{100.0 * hit / total if total else 100.0:.1f}%"
        label = {"halt": "halts:", "pre": "pre:", "post": "post:", "mcdc": "mcdc:"}[kind]
        lines.append(f"{label:9} {hit}/{total} = {pct} ({what[kind]})")
    return lines


class Places:
    """Where a goal is: the node's path from the root (names, SubTrees followed) and the line
    of the node, or of the attribute the goal is about."""

    def __init__(self, mission: Mission, nodes: list) -> None:
        from btgen.tools import graph as g

        gnodes, _ = g.walk(mission)
        self.by_uid = {n.uid: n for n in gnodes}
        self.interp = {n.uid: n for n in nodes}
        self.main = mission.main_tree

    def path(self, uid: int) -> str:
        parts = []
        n = self.by_uid.get(uid)
        while n is not None:
            parts.append(n.name)
            n = self.by_uid.get(n.parent)
        return "/".join([self.main, *reversed(parts)])

    def loc(self, goal: tuple) -> Loc:
        node = self.interp[goal[1]]
        if goal[0] in ("pre", "post", "mcdc"):
            model = node.model
            for attr in (*model.ports, *model.pre, *model.post):
                if attr.name == goal[2]:
                    return attr.loc
        return node.model.loc


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
    criteria = criteria_of(args)
    possible = _possible(mission, args)
    try:
        ex = Explorer(
            mission,
            args.ticks,
            args.depth,
            args.clock_ms,
            args.max_states,
            props,
            possible,
            not args.no_merge,
            sync_actions(mission, args),
            criteria,
        )
    except ValueError as e:
        raise cmdline.error(args, "--assert", f"--assert: {e}") from None
    ex.keep_going = args.keep_going
    progress = _Progress(sys.stderr) if sys.stderr.isatty() else None
    if progress is not None:
        ex.on_progress = progress.update
    try:
        result = ex.explore()
    finally:
        if progress is not None:
            progress.clear()
    where = leaf_locs(mission)
    # Every text first (a name no scenario can hold is refused before any file is written),
    # then every file, then the manifest that lets the next run remove exactly these.
    covering = [
        scenario_text(path, args.clock_ms, f"btgen explore: {len(path.goals)} goals", where) for path in result.paths
    ]
    cx_texts = [
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
        cx_files = [os.path.join(args.output_dir, f"counterexample-{k}.scenario") for k in range(1, len(cx_texts) + 1)]
        error_files = [os.path.join(args.output_dir, f"error-{k}.scenario") for k in range(1, len(reaching) + 1)]
        outputs = list(zip(files + cx_files + error_files, covering + cx_texts + reaching))
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
    # each property: holds (how far the search went), violated (its counterexample), or undecided
    if result.stopped_at_violation:
        bound = "not decided: the search stopped at the first violation (--keep-going goes on)"
    elif result.truncated:
        bound = f"bounded by --max-states {args.max_states}"
    elif result.bounded_by:
        bound = "bounded by " + " and ".join(
            f"--ticks {args.ticks}" if b == "ticks" else f"--depth {args.depth}" for b in result.bounded_by
        )
    else:
        bound = "exhaustive"
    properties = []
    for prop in props:
        found = next((path for p, path in result.violations if p is prop), None)
        entry: dict = {"property": prop.text}
        if found is None:
            decided = not result.stopped_at_violation
            entry["result"] = "holds" if decided else "undecided"
            entry["line"] = f"holds ({result.states} states, {bound})" if decided else bound
        else:
            status = 1
            k = next(i for i, (p, _) in enumerate(result.violations) if p is prop)
            text = cx_texts[k]
            try:
                trace = trace_text(mission, parse_scenario_text(text, "<counterexample>"))
            except UserError as e:
                trace = "".join(str(d) + "\n" for d in e.diagnostics)
            entry.update(result="violated", line="violated (counterexample below)", scenario=text, trace=trace)
            if args.output_dir:
                entry["file"] = cx_files[k]
        properties.append(entry)
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
    uncovered = sorted(result.goals - result.covered, key=_goal_order)
    names = {n.uid: n for n in ex.nodes}
    impossible = []
    if possible is not None:
        for i, n in enumerate(ex.nodes):
            if not possible.get(i):
                impossible.append(f'{n.uid} {n.reg_id} "{n.name}": never ticked (see `btgen analyze`)')
    if result.stopped_at_violation:
        why = "not explored: the search stopped at the first violation (--keep-going explores on)"
        answer = "not explored"
    elif result.truncated:
        why = f"not reached within the bounds (stopped at --max-states {args.max_states})"
        answer = "not reached within the bound"
    elif result.bounded_by:
        why = f"not reached within the bounds (--ticks {args.ticks}, --depth {args.depth})"
        answer = "not reached within the bound"
    else:
        why = "never reached, and the search was exhaustive: no run of the leaves gets there"
        answer = "unreachable (exhaustive exploration)"
    places = Places(mission, ex.nodes)
    report = {
        "mission": args.mission,
        "runs": result.runs,
        "states": result.states,
        "seconds": round(result.seconds, 3),
        "states_per_second": round(result.states / result.seconds) if result.seconds > 0 else None,
        "search": "stopped at the first violation" if result.stopped_at_violation else bound,
        "goals": len(result.goals),
        "covered": len(result.covered),
        "node_goals": sum(1 for g in result.goals if g[0] == "node"),
        "nodes_covered": sum(1 for g in result.covered if g[0] == "node"),
        "outcome_goals": sum(1 for g in result.goals if g[0] == "outcome"),
        "outcomes_covered": sum(1 for g in result.covered if g[0] == "outcome"),
        "scenarios": len(result.paths),
        "files": files,
        "max_nodes_visited_per_tick": result.max_visits,
        "max_leaf_hooks_per_tick": result.max_hooks,
        "criteria": list(criteria),
        "obligations": obligation_counts(result.goals, result.covered),
        "input_goals": sum(1 for g in result.goals if g[0] == "input"),
        "inputs_covered": sum(1 for g in result.covered if g[0] == "input"),
        "uncovered": [_uncovered_text(g, names, ex.obligations) for g in uncovered],
        "uncovered_obligations": [
            {
                "criterion": obligations.criterion_of(g),
                "node": places.path(g[1]),
                "location": str(places.loc(g)),
                "what": obligations.describe(g, ex.obligations),
                "answer": answer,
            }
            for g in uncovered
        ],
        "never_ticked": impossible,
        "properties": [{k: v for k, v in p.items() if k != "line"} for p in properties],
        "violations": [p.text for p, _ in result.violations],
        "run_time_errors": [str(d) for d, _ in result.errors],
    }
    if args.json:
        json.dump(report, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return status
    print(f"{args.mission}:")
    rate = report["states_per_second"]
    print(f"  runs {result.runs}, states {result.states}, {result.seconds:.2f} s ({rate} states/s)")
    for line in criteria_lines(criteria, result.goals, result.covered):
        print(f"  {line}")
    for entry in properties:
        print(f"  assert `{entry['property']}`: {entry['line']}")
    print(f"  scenarios: {len(result.paths)}" + (f" written to {args.output_dir}" if args.output_dir else ""))
    print(f"  most per tick seen: {result.max_visits} nodes visited, {result.max_hooks} leaf hooks")
    for line in impossible:
        print(f"  impossible: {line}")
    if result.stopped_at_violation and uncovered:
        print(f"  uncovered: {len(uncovered)} goals: {why}")
    else:
        for g, line in zip(uncovered, report["uncovered"]):
            print(f"  uncovered: {line}: {why}")
            if g[0] not in ("node", "outcome"):
                print(f"    at {places.path(g[1])} ({places.loc(g)})")
    for entry in properties:
        if entry["result"] != "violated":
            continue
        print(f"  counterexample of `{entry['property']}`" + (f": {entry['file']}" if "file" in entry else ""))
        print("    scenario:")
        for line in entry["scenario"].splitlines():
            print(f"      {line}")
        print("    trace:")
        for line in entry["trace"].splitlines():
            print(f"      {line}")
    return status


class _Progress:
    """One line on a terminal, redrawn: a bar of the goals covered, states, rate, elapsed."""

    WIDTH = 24

    def __init__(self, stream) -> None:
        self.stream = stream
        self.t0 = time.perf_counter()

    def update(self, states: int, covered: int, goals: int) -> None:
        elapsed = time.perf_counter() - self.t0
        filled = self.WIDTH * covered // goals if goals else self.WIDTH
        bar = "#" * filled + "-" * (self.WIDTH - filled)
        rate = states / elapsed if elapsed > 0 else 0.0
        minutes, seconds = divmod(int(elapsed), 60)
        self.stream.write(
            f"\rexplore [{bar}] {covered}/{goals} goals, {states} states, {rate:.0f} states/s, "
            f"{minutes}:{seconds:02d}\033[K"
        )
        self.stream.flush()

    def clear(self) -> None:
        self.stream.write("\r\033[K")
        self.stream.flush()
