"""`btgen cover` and `btgen scenario-from-log`.

`btgen cover MISSION.xml RUN...` measures node and outcome coverage of a set of runs: scenario
files (run on the interpreter), status traces (`btgen run` output) and Groot2 logs (.btlog,
from the robot or from `btgen::btlog::FileLogger`). A node is covered when some run moved it
out of IDLE; an outcome (SUCCESS, FAILURE, RUNNING) when some run showed the node entering it.
SKIPPED is never stored by BehaviorTree.CPP, so no trace or log can show it: it is not counted.
The goals are what `btgen analyze` finds possible: a node that can never be ticked, or a status
it can never return, is not a goal (the report lists the former). `--graph FILE.svg|.dot` draws
the mission with covered nodes green, partly covered ones (some possible outcome never seen)
orange, and nodes never ticked red.

`btgen scenario-from-log MISSION.xml RUN.btlog -o FILE.scenario` turns a log into the scenario
that replays it: the interpreter runs the mission and, at each call of a user leaf, takes the
result the log shows next for that node (a RUNNING leaf that the log does not show finishing
answers RUNNING again), checking every status change against the log's records in order. The
scenario then replays the same transitions on both engines (`btgen run`, `--engine cpp`).
A .btlog has no tick boundaries: the scenario has as many ticks as the run needs to use up the
log (or to complete: a scenario is one run of the tree, and records after the root completed
are a new run, left out with a warning), and `clock_ms` is `--clock-ms` (default 0): missions
whose Sleep, Delay or Timeout decide the course of the run replay only with the right clock step.
"""

from __future__ import annotations

import os
import re
import sys
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded
from btgen.fileio import check_output, write_output
from btgen.interp import actions as iactions
from btgen.interp.engine import Interpreter, run_ticks
from btgen.interp.nav2 import record_inputs
from btgen.interp.scenario import format_scenario, leaf_locs, parse_scenario
from btgen.interp.tree import FAILURE, RUNNING, SUCCESS
from btgen.lang.leaves import mission_leaves
from btgen.lang.model import Mission
from btgen.lang.nav2 import ENV_INPUTS
from btgen.tools import graph as g
from btgen.tools import obligations

STATUS_NAMES = g.STATUS_NAMES


def trace_transitions(text: str) -> list[tuple[int, str, str]]:
    """(uid, from, to) of every status line of a trace (the lines graph.read_trace takes)."""
    out = []
    for line in text.splitlines():
        words = line.split()
        if g.is_transition(words):
            out.append((int(words[0]), words[-3], words[-1]))
    return out


def btlog_records(path: str, nodes: list[g.GNode]) -> list[tuple[int, int, str, str]]:
    """(microseconds, uid, from, to) of every record of a .btlog (checked against the mission
    by graph.py)."""
    g.btlog_statuses(path, None, nodes)  # the checks and their path:line:col errors
    data = read_bounded(path, g.MAX_LOG_BYTES, "log", cannot="cannot read the log")
    size = int.from_bytes(data[19:23], "little", signed=True)
    body = data[23 + size + 8 :]
    status: dict[int, str] = {}
    out = []
    for k in range(len(body) // 9):
        usec = int.from_bytes(body[9 * k : 9 * k + 6], "little")
        uid = int.from_bytes(body[9 * k + 6 : 9 * k + 8], "little")
        to = STATUS_NAMES[body[9 * k + 8]]
        out.append((usec, uid, status.get(uid, "IDLE"), to))
        status[uid] = to
    return out


def btlog_transitions(path: str, nodes: list[g.GNode]) -> list[tuple[int, str, str]]:
    """(uid, from, to) of every record of a .btlog (checked against the mission by graph.py)."""
    return [(uid, before, to) for _, uid, before, to in btlog_records(path, nodes)]


def _possible(mission: Mission, args) -> tuple[dict[int, set[str]], dict[int, bool]]:
    from btgen import pipeline
    from btgen.tools.analyze import analyze_program
    from btgen.tools.explore import sync_actions

    opts = pipeline.options_from_args(args)
    options = opts.data
    program = pipeline.program(mission, opts)
    result = analyze_program(mission, program, options)
    sync = sync_actions(mission, args)  # their RUNNING is no goal: they never return it
    possible = {
        n.uid: {s for s in result.outcomes[n.index] if s != "SKIPPED" and not (s == "RUNNING" and n.id in sync)}
        for n in program.nodes
    }
    reach = {n.uid: result.reachable[n.index] for n in program.nodes}
    return possible, reach


def cover_command(args) -> int:
    from btgen import pipeline
    from btgen.tools.explore import coverage_lines, criteria_of

    mission = pipeline.load(args.mission, pipeline.options_from_args(args))
    nodes, clusters = g.walk(mission)
    criteria = criteria_of(args)
    possible, reach = _possible(mission, args)
    extra = Extra(mission, args, criteria)
    seen: dict[int, set[str]] = {}
    ticked: set[int] = set()
    inputs: set[tuple[int, int]] = set()  # (uid, SUCCESS or FAILURE): a Nav2 Decorator's input seen
    input_uids = [n.uid for n in nodes if mission.nav2 is not None and n.id in ENV_INPUTS]
    for run in args.runs:
        ext = os.path.splitext(run)[1].lower()
        if ext == ".btlog":
            moves = btlog_transitions(run, nodes)
        elif ext == ".scenario":
            scenario = parse_scenario(run)
            interp = Interpreter(mission, scenario)
            record_inputs(interp.nodes, inputs)
            parts: list[str] = []
            run_ticks(interp, scenario, parts.append)
            moves = trace_transitions("".join(parts))
        else:
            moves = [(uid, before, to) for _, uid, before, to in g.read_trace(run, nodes).moves]
        for uid, _, to in moves:
            if to != "IDLE":
                ticked.add(uid)
                seen.setdefault(uid, set()).add(to)
        extra.add_run(run, ext, moves)
    rows = []
    node_goals = node_hits = out_goals = out_hits = 0
    state: dict[int, str] = {}
    for n in nodes:
        if not reach.get(n.uid, True):
            rows.append((n, "never ticked (btgen analyze)", "", ""))
            continue
        node_goals += 1
        want = possible.get(n.uid, set())
        got = seen.get(n.uid, set()) & want
        out_goals += len(want)
        out_hits += len(got)
        if n.uid in ticked:
            node_hits += 1
        missing = sorted(want - got)
        state[n.uid] = "full" if n.uid in ticked and not missing else ("part" if n.uid in ticked else "none")
        rows.append((n, "yes" if n.uid in ticked else "NO", ",".join(sorted(got)), ",".join(missing)))
    pct_n = 100.0 * node_hits / node_goals if node_goals else 100.0
    pct_o = 100.0 * out_hits / out_goals if out_goals else 100.0
    runs = f"{len(args.runs)} run{'' if len(args.runs) == 1 else 's'}"
    print(f"{args.mission}: {runs}")
    in_goals = [(uid, st) for uid in input_uids if reach.get(uid, True) for st in (SUCCESS, FAILURE)]
    in_hits = sum(1 for goal in in_goals if goal in inputs)
    lines = coverage_lines(node_hits, node_goals, out_hits, out_goals, in_hits, len(in_goals))
    for line in lines if "outcome" in criteria else lines[:1]:
        print(f"  {line}")
    extra.report(args.table or args.uncovered, args.table)
    if args.table or args.uncovered:
        print(f"  {'uid':>5}  {'node':40}  {'ticked':8}  {'seen':30}  missing")
        for n, tick, got_s, miss in rows:
            if args.uncovered and tick == "yes" and not miss:
                continue
            label = f'{n.id} "{n.name}"' if n.name != n.id else n.id
            print(f"  {n.uid:>5}  {label[:40]:40}  {tick:8}  {got_s:30}  {miss}")
    if args.graph:
        fill = {"full": "SUCCESS", "part": "RUNNING", "none": "FAILURE"}
        status = {uid: fill[s] for uid, s in state.items()}
        caption = f"{mission.path}: coverage of {runs}: {pct_n:.1f}% of nodes, {pct_o:.1f}% of outcomes"
        text = g.dot_text(mission, nodes, clusters, status, caption)
        legend = (
            '  legend [shape=plaintext, label=<<table border="0" cellborder="1" cellspacing="0"><tr>'
            f'<td bgcolor="{g.FILL["SUCCESS"]}">covered</td>'
            f'<td bgcolor="{g.FILL["RUNNING"]}">ticked, some outcome never seen</td>'
            f'<td bgcolor="{g.FILL["FAILURE"]}">never ticked</td>'
            f'<td bgcolor="{g.FILL["IDLE"]}">cannot be ticked</td></tr></table>>];'
        )
        text = re.sub(r"  legend \[.*\];", lambda _: legend, text)
        if _write_graph(args.graph, text, (*mission.files, *args.runs)) != 0:
            return 1
    if args.min is not None and pct_n < args.min:
        from btgen import cmdline

        loc = cmdline.loc_of(args.argv if getattr(args, "argv", None) is not None else sys.argv[1:], "--min")
        print(
            f"{loc}: error: node coverage {pct_n:.1f}% is below --min {args.min:g}%: {node_goals - node_hits} of "
            f"{node_goals} nodes never ticked by the {runs} (`--uncovered` lists them)",
            file=sys.stderr,
        )
        return 1
    return 0


class Extra:
    """The criteria beyond nodes and outcomes (tools/obligations.py) over a set of runs: halts
    and post-conditions from the status changes of every run; pre-conditions and MC/DC by
    replaying scenario files (and .btlog files, through `scenario-from-log`): a trace shows no
    script evaluation, so those criteria leave traces out, and say how many."""

    def __init__(self, mission: Mission, args, criteria: tuple[str, ...]) -> None:
        from btgen.tools.explore import Explorer, Places, _possible

        self.mission = mission
        self.criteria = criteria
        self.kinds = obligations.kinds_of(criteria) - {"node", "outcome"}
        self.reached: set = set()
        self.unreplayed: list[str] = []
        self.ex = None
        if not self.kinds:
            return
        self.ex = ex = Explorer(mission, possible=_possible(mission, args), criteria=criteria)
        self.ob = ex.obligations
        self.places = Places(mission, ex.nodes)

    def add_run(self, run: str, ext: str, moves: list[tuple[int, str, str]]) -> None:
        if self.ex is None:
            return
        got: set[tuple] = {("halt", uid) for uid, before, to in moves if before == "RUNNING" and to == "IDLE"}
        got |= {("outcome", uid, _STATUS[to]) for uid, _, to in moves if to in _STATUS}
        self.reached |= got | obligations.derived(self.ob, got)
        if not self.kinds & {"pre", "mcdc"}:
            return
        if ext == ".scenario":
            self.reached |= self.ex.replay(parse_scenario(run))
        elif ext == ".btlog":
            from btgen.interp.scenario import parse_scenario_text

            self.reached |= self.ex.replay(parse_scenario_text(scenario_from_log(self.mission, run), run))
        else:
            self.unreplayed.append(run)

    def report(self, uncovered: bool, table: bool) -> None:
        if self.ex is None:
            return
        from btgen.tools.explore import criteria_lines

        goals = self.ob.all_goals
        shown = obligations.mcdc_shown(self.ob, self.reached)
        covered = (self.reached & goals) | set(shown)
        extra = tuple(c for c in self.criteria if c not in ("node", "outcome"))
        for line in criteria_lines(extra, goals, covered):
            print(f"  {line}")
        if self.unreplayed and self.kinds & {"pre", "mcdc"}:
            n = len(self.unreplayed)
            print(
                f"  pre and mcdc leave out {n} trace{'' if n == 1 else 's'}: a trace shows no script evaluation "
                "(give the scenario or the .btlog instead)"
            )
        if not uncovered:
            return
        rows = sorted(goals - covered, key=lambda g: (g[1], str(g)))
        for goal in rows:
            where = f"{self.places.path(goal[1])} ({self.places.loc(goal)})"
            print(f"  uncovered {obligations.criterion_of(goal)}: {where}: {obligations.describe(goal, self.ob)}")
        if table:
            for goal, (a, b, unique) in sorted(shown.items(), key=lambda kv: str(kv[0])):
                where = f"{self.places.path(goal[1])} ({self.places.loc(goal)})"
                form = "unique-cause" if unique else "masking"
                pair = f"{_bits(a)} -> {'true' if self.ob.site(goal).value(a) else 'false'}, " + (
                    f"{_bits(b)} -> {'true' if self.ob.site(goal).value(b) else 'false'}"
                )
                print(f"  shown mcdc: {where}: {obligations.describe(goal, self.ob)}: {form} ({pair})")


_STATUS = {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING}


def _bits(vals: tuple[bool, ...]) -> str:
    return "(" + ", ".join("T" if v else "F" for v in vals) + ")"


def _write_graph(output: str, text: str, inputs: tuple[str, ...]) -> int:
    import shutil
    import subprocess

    ext = os.path.splitext(output)[1].lower()
    if ext == ".dot":
        g._write(output, text.encode("utf-8"), inputs)
        return 0
    if ext != ".svg":
        print(f"btgen: error: --graph {output}: the output is a .svg or a .dot file", file=sys.stderr)
        return 1
    dot = shutil.which("dot")
    if dot is None:
        print("btgen: error: Graphviz `dot` is not installed; write a .dot file instead", file=sys.stderr)
        return 1
    proc = subprocess.run([dot, "-Tsvg"], input=text.encode("utf-8"), capture_output=True, timeout=600, check=False)
    if proc.returncode != 0:
        print(f"btgen: error: dot failed: {proc.stderr.decode('utf-8', 'replace').strip()}", file=sys.stderr)
        return 1
    g._write(output, proc.stdout, inputs)
    return 0


# ====================================================================== scenario-from-log
class _Mismatch(Exception):
    pass


class _Replay:
    def __init__(self, mission: Mission, records: list[tuple[int, str, str]]) -> None:
        self.records = records
        self.pos = 0
        self.interp = Interpreter(mission, None)
        self.picks: list[tuple[str, str]] = []
        for node in self.interp.nodes:
            if isinstance(node, (iactions.ScriptedAction, iactions.ScriptedCondition)):
                node.cursor = _LogCursor(self, node)

    def sync(self) -> None:
        """Match the status changes the interpreter made since the last call against the log."""
        for uid, before, to in trace_transitions(self.interp.take_text()):
            if self.pos >= len(self.records):
                raise _Mismatch(f"the run changes node {uid} from {before} to {to} after the log has ended")
            want = self.records[self.pos]
            if (uid, to) != (want[0], want[2]):
                raise _Mismatch(
                    f"record {self.pos + 1}: the log has node {want[0]} -> {want[2]}, "
                    f"the mission changes node {uid} -> {to}"
                )
            self.pos += 1

    def pick(self, node) -> int:
        self.sync()
        cur = node.status
        if self.pos < len(self.records) and self.records[self.pos][0] == node.uid:
            to = self.records[self.pos][2]
            if to in ("SUCCESS", "FAILURE", "RUNNING"):
                self.picks.append((node.name, to))
                return {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING}[to]
        if cur in (SUCCESS, FAILURE, RUNNING):  # no change shown: it answered as before
            name = {SUCCESS: "SUCCESS", FAILURE: "FAILURE", RUNNING: "RUNNING"}[cur]
            self.picks.append((node.name, name))
            return cur
        want = self.records[self.pos] if self.pos < len(self.records) else None
        raise _Mismatch(
            f"record {self.pos + 1}: leaf {node.uid} `{node.name}` is ticked, but the log shows "
            + (f"node {want[0]} -> {want[2]} next" if want else "nothing more")
        )


class _LogCursor:
    __slots__ = ("replay", "node")

    def __init__(self, replay: _Replay, node) -> None:
        self.replay = replay
        self.node = node

    def next(self) -> int:
        return self.replay.pick(self.node)


MAX_ANSWERS = 1_000_000  # leaf answers in a replayed scenario (about 8 MB of scenario text)
MAX_TICKS = 1_000_000


def halt_start(records: list[tuple[int, int, str, str]]) -> Optional[int]:
    """Where a log ends with the halt of a run that had not completed (`--max-ticks`, an
    operator's stop): the first of the trailing `-> IDLE` records, when they take the root
    from RUNNING to IDLE; None otherwise."""
    h = len(records)
    while h > 0 and records[h - 1][3] == "IDLE":
        h -= 1
    tail = records[h:]
    if any(uid == 1 and before == "RUNNING" for _, uid, before, _ in tail):
        return h
    return None


def scenario_from_log(mission: Mission, log: str, clock_ms: int = 0) -> str:
    """The scenario that replays the log. The replay is bounded by the log: a tick that uses
    no record of it is allowed only while the mission's clock (`clock_ms` a tick) has not
    passed the log's time of its next record (from its first) (with no clock, nothing can change
    without a record: the replay stops there), and the ticks and answers written are at
    most MAX_TICKS and MAX_ANSWERS. A log that ends with the halt of an unfinished run is replayed up to the
    halt (a scenario sends no halt)."""
    nodes, _ = g.walk(mission)
    timed = btlog_records(log, nodes)
    if mission.nav2 is not None:
        for use in mission_leaves(mission):
            if use.node.id in ENV_INPUTS:
                raise UserError(
                    Diagnostic(
                        use.node.loc,
                        f"`btgen scenario-from-log` cannot recover the input of Nav2's `{use.node.id}` "
                        f'"{use.name}" (whether {ENV_INPUTS[use.node.id]}): a log has no record of it; '
                        f"write its `leaf {use.name} ...` line by hand, or use `btgen explore`",
                    )
                )
    halt = halt_start(timed)
    if halt is not None and halt < len(timed):
        print(
            f"{log}:1:1: warning: the run was halted before it completed (records {halt + 1} to {len(timed)} "
            "reset the running nodes); the scenario replays it up to the halt",
            file=sys.stderr,
        )
        timed = timed[:halt]
    records = [(uid, before, to) for _, uid, before, to in timed]
    r = _Replay(mission, records)
    ticks = 0
    try:
        while r.pos < len(records):
            ticks += 1
            if ticks > 1 and clock_ms:
                r.interp.advance_clock(clock_ms)
            before = r.pos
            status = r.interp.tick_once()
            r.sync()
            if len(r.picks) > MAX_ANSWERS:
                raise _Mismatch(f"the replay needs more than {MAX_ANSWERS} leaf answers")
            if status.name in ("SUCCESS", "FAILURE") and r.pos < len(records):
                # a robot ticks the tree again after it completes; a scenario is one run
                rest = len(records) - r.pos
                print(
                    f"{log}:1:1: warning: the mission completed at record {r.pos}; the {rest} records after "
                    "it are a new run of the tree, which this scenario does not replay",
                    file=sys.stderr,
                )
                break
            if r.pos > before:
                continue
            # a tick that used no record: only time can make the next one differ, and the
            # mission's clock may not run past the log's time of its next record
            log_ms = (timed[r.pos][0] - timed[0][0]) // 1000
            if not clock_ms or (ticks - 1) * clock_ms > log_ms + clock_ms or ticks >= MAX_TICKS:
                raise _Mismatch(
                    f"record {r.pos + 1}: a tick changes nothing the log shows"
                    + (
                        ""
                        if not clock_ms
                        else f" (the mission's clock is at {(ticks - 1) * clock_ms} ms, the log's next record "
                        f"at {log_ms} ms)"
                    )
                )
    except _Mismatch as e:
        raise UserError(Diagnostic(Loc(log, 1, 1), f"the log is not a run of this mission: {e}")) from None
    per: dict[str, list[str]] = {}
    for name, st in r.picks:
        per.setdefault(name, []).append(st)
    return format_scenario(
        max(ticks, 1),
        list(per.items()),
        clock_ms,
        f"replays {os.path.basename(log)} (records 1 to {r.pos})",
        leaf_locs(mission),
    )


def scenario_from_log_command(args) -> int:
    from btgen import pipeline
    from btgen.tools.explore import check_clock_ms

    check_clock_ms(args)
    mission = pipeline.load(args.mission, pipeline.options_from_args(args))
    inputs = (*mission.files, args.log)
    if args.output not in (None, "-"):
        check_output(args.output, inputs)  # before the replay: a slip costs nothing
    text = scenario_from_log(mission, args.log, args.clock_ms)
    if args.output in (None, "-"):
        sys.stdout.write(text)
        return 0
    write_output(args.output, text.encode("utf-8"), inputs)
    return 0
