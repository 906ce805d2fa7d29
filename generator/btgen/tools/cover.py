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

from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded
from btgen.interp import actions as iactions
from btgen.interp.engine import Interpreter, trace_text
from btgen.interp.scenario import parse_scenario
from btgen.interp.tree import FAILURE, RUNNING, SUCCESS
from btgen.lang.model import Mission
from btgen.tools import graph as g

STATUS_NAMES = g.STATUS_NAMES
_LINE = re.compile(
    r"([0-9]{1,9}) (\S+) .* (IDLE|RUNNING|SUCCESS|FAILURE|SKIPPED) -> (IDLE|RUNNING|SUCCESS|FAILURE|SKIPPED)\Z"
)


def trace_transitions(text: str) -> list[tuple[int, str, str]]:
    """(uid, from, to) of every status line of a trace."""
    out = []
    for line in text.splitlines():
        m = _LINE.match(line)
        if m:
            out.append((int(m.group(1)), m.group(3), m.group(4)))
    return out


def btlog_transitions(path: str, nodes: list[g.GNode]) -> list[tuple[int, str, str]]:
    """(uid, from, to) of every record of a .btlog (checked against the mission by graph.py)."""
    g.btlog_statuses(path, None, nodes)  # the checks and their path:line:col errors
    data = read_bounded(path, g.MAX_LOG_BYTES, "log", cannot="cannot read the log")
    size = int.from_bytes(data[19:23], "little", signed=True)
    body = data[23 + size + 8 :]
    status: dict[int, str] = {}
    out = []
    for k in range(len(body) // 9):
        uid = int.from_bytes(body[9 * k + 6 : 9 * k + 8], "little")
        to = STATUS_NAMES[body[9 * k + 8]]
        out.append((uid, status.get(uid, "IDLE"), to))
        status[uid] = to
    return out


def _possible(mission: Mission, args) -> tuple[dict[int, set[str]], dict[int, bool]]:
    from btgen import pipeline
    from btgen.ir.lower import lower
    from btgen.tools.analyze import analyze_program
    from btgen.tools.explore import sync_actions

    options = pipeline.options_from_args(args).data
    program = lower(mission, options)
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

    mission = pipeline.load(args.mission, pipeline.options_from_args(args))
    nodes, clusters = g.walk(mission)
    possible, reach = _possible(mission, args)
    seen: dict[int, set[str]] = {}
    ticked: set[int] = set()
    for run in args.runs:
        ext = os.path.splitext(run)[1].lower()
        if ext == ".btlog":
            moves = btlog_transitions(run, nodes)
        elif ext == ".scenario":
            moves = trace_transitions(trace_text(mission, parse_scenario(run)))
        else:
            g.trace_statuses(run, None, nodes)  # the checks and their errors
            moves = trace_transitions(read_bounded(run, g.MAX_LOG_BYTES, "trace", cannot="cannot read").decode())
        for uid, _, to in moves:
            if to != "IDLE":
                ticked.add(uid)
                seen.setdefault(uid, set()).add(to)
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
    for line in coverage_lines(node_hits, node_goals, out_hits, out_goals):
        print(f"  {line}")
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
        if _write_graph(args.graph, text) != 0:
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


def coverage_lines(node_hits: int, node_goals: int, out_hits: int, out_goals: int) -> list[str]:
    """The two coverage lines `cover` and `explore` print, in one vocabulary: nodes ticked, and
    outcomes (each status a node can return, as `btgen analyze` finds, seen at least once)."""

    def pct(hit: int, goal: int) -> str:
        return f"{100.0 * hit / goal if goal else 100.0:.1f}%"

    return [
        f"nodes:    {node_hits}/{node_goals} = {pct(node_hits, node_goals)} ticked",
        f"outcomes: {out_hits}/{out_goals} = {pct(out_hits, out_goals)} (each SUCCESS, FAILURE, RUNNING a node "
        "can return, seen)",
    ]


def _write_graph(output: str, text: str) -> int:
    import shutil
    import subprocess

    ext = os.path.splitext(output)[1].lower()
    if ext == ".dot":
        g._write(output, text.encode("utf-8"))
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
    g._write(output, proc.stdout)
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


def scenario_from_log(mission: Mission, log: str, clock_ms: int = 0, max_ticks: int = 1_000_000) -> str:
    nodes, _ = g.walk(mission)
    records = btlog_transitions(log, nodes)
    r = _Replay(mission, records)
    ticks = 0
    try:
        while r.pos < len(records):
            if ticks >= max_ticks:
                raise _Mismatch(f"{max_ticks} ticks did not use up the log")
            ticks += 1
            if ticks > 1 and clock_ms:
                r.interp.advance_clock(clock_ms)
            before = r.pos
            status = r.interp.tick_once()
            r.sync()
            if status.name in ("SUCCESS", "FAILURE") and r.pos < len(records):
                # a robot ticks the tree again after it completes; a scenario is one run
                rest = len(records) - r.pos
                print(
                    f"{log}:1:1: warning: the mission completed at record {r.pos}; the {rest} records after "
                    "it are a new run of the tree, which this scenario does not replay",
                    file=sys.stderr,
                )
                break
            if r.pos == before and not r.picks:
                raise _Mismatch(f"record {r.pos + 1}: a tick changes nothing the log shows")
    except _Mismatch as e:
        raise UserError(Diagnostic(Loc(log, 1, 1), f"the log is not a run of this mission: {e}")) from None
    per: dict[str, list[str]] = {}
    for name, st in r.picks:
        per.setdefault(name, []).append(st)
    lines = [f"# replays {os.path.basename(log)} (records 1 to {r.pos})", f"ticks {max(ticks, 1)}"]
    if clock_ms:
        lines.append(f"clock_ms {clock_ms}")
    lines += [f"leaf {name} {' '.join(sts)}" for name, sts in per.items()]
    return "\n".join(lines) + "\n"


def scenario_from_log_command(args) -> int:
    from btgen import pipeline

    mission = pipeline.load(args.mission, pipeline.options_from_args(args))
    text = scenario_from_log(mission, args.log, args.clock_ms)
    if args.output in (None, "-"):
        sys.stdout.write(text)
        return 0
    g._write(args.output, text.encode("utf-8"))
    return 0
