"""A suite's scenarios run on the real library from Python: `behaviortreepy` 0.1.4, the bindings
of BehaviorTree.CPP 4.8.2 (PyPI ships them; no registry ships the library's headers, so CI
cannot build the GoogleTest suite `btgen tests` writes, but it can run the same scenarios here).

    python -m btgen.tools.gtests.btpy MISSION.xml FILE.scenario... [--models FILE.xml] [--main-tree ID]

For each scenario the library loads the mission file, each user leaf the mission uses is
registered from Python (`register_simple_condition`: the next status of the leaf's name at
every tick; `register_simple_stateful_action`: the next status in onStart and onRunning:
the scripted leaves of the GoogleTest suite, support.hpp), the tree is ticked with
`tick_exactly_once` until the root completes or the scenario's ticks are spent, and every
status change, as the library's own StdCoutLogger prints it (node name, from, to;
transitions to IDLE included), and every root result are compared with btgen's interpreter.

What the bindings do not allow, and how this run handles it (docs/tests.md says the same):

- Leaves registered from Python have no ports (`register_simple_*` take none), and 4.8.2
  refuses an attribute that is no port of its node ("a port with name [x] is found in the
  XML ... but not in the providedPorts()"). A mission whose user leaves have port attributes
  is therefore loaded from a copy without them (only those attributes of those leaves;
  written to a temporary folder). The interpreter's expected trace is taken on the same copy,
  and that trace is checked equal to the one of the mission as written: a scripted leaf reads
  and writes no port, so removing them changes a run only where a port was the one thing that
  created an entry a script reads (then this says so and the scenario is not compared).
- No test clock (`Tree.sleep` waits on the wall clock): missions with Sleep, Delay or
  Timeout are refused, as by `btgen tests`.
- Control and Decorator nodes cannot be registered from Python with children of their own
  (`register_simple_decorator` has no child API): Nav2's PipelineSequence, RecoveryNode,
  RateController ... cannot run; only trees built from the library's own nodes and user leaves.
- The status changes are read from StdCoutLogger (names, no UIDs): the bindings' FileLogger
  (a .btlog with UIDs) writes from a thread of its own and loses the records still queued
  when it is destroyed (a run of two ticks gave a log with no record), so it is not used.
  Two nodes of one name are told apart by their order only.
- Version: 4.8.2 is neither of the releases btgen speaks. Its loader and script grammar are
  4.6.2's (every loading and grammar switch of lang/versions.py came in 4.8.4 or later) and its
  node semantics are 4.10.0's for the switches made in 4.7.0 (skipped_by_count,
  loop_end_never_skipped, retry_rereads_attempts, precondition_if_until_started,
  setblackboard_converts_to_entry_type, int_to_double_53_bits,
  reactive_sequence_child_checks). The expected trace is the interpreter's with the mission
  loaded as 4.6.2 and run with exactly those switches on (`versions.at_release("4.8.2")`);
  each result says whether the 4.6.2 trace differs from it for that scenario.
"""

from __future__ import annotations

import ctypes
import dataclasses
import os
import re
import sys
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.interp.engine import trace_text
from btgen.interp.scenario import Scenario
from btgen.lang import versions
from btgen.lang.model import Mission

VERSION = "4.8.2"


@dataclass
class Outcome:
    """One scenario on the library and on the interpreter."""

    name: str
    ok: bool
    library: list[str]  # the library's status changes and root results, as lines
    expected: list[str]  # the interpreter's
    differs_from_462: bool  # the 4.6.2 trace is not the 4.8.2 one (a 4.7.0 switch matters)
    stripped: list[str]  # the leaf port attributes removed so that the library loads it
    message: str = ""


def available() -> Optional[str]:
    """None when behaviortreepy can be imported, else why not."""
    try:
        import behaviortreepy  # noqa: F401
    except ImportError as e:
        return f"behaviortreepy is not installed ({e})"
    return None


def mission_at(mission: Mission, version: str) -> Mission:
    """The same mission run with the switches of `version` (versions.at_release)."""
    sem = versions.at_release(version)
    cls = type("MissionAt" + version.replace(".", "_"), (type(mission),), {"semantics": property(lambda self: sem)})
    return cls(**{f.name: getattr(mission, f.name) for f in dataclasses.fields(mission)})


_TRACE_LINE = re.compile(r'[0-9]+ \S+ "((?:[^"\\]|\\.)*)" (\S+) -> (\S+)\Z')


def lines_of_trace(text: str) -> list[str]:
    """`NAME from -> to` of every status change and `result S` of every tick of a trace (the
    library's logger names nodes, it gives no UID)."""
    out = []
    for line in text.splitlines():
        m = _TRACE_LINE.match(line)
        if m:
            name = re.sub(r"\\(.)", r"\1", m.group(1))
            out.append(f"{name} {m.group(2)} -> {m.group(3)}")
        elif line.startswith("result "):
            out.append(line)
    return out


def _leaf_elements(root: ET.Element, leaf_ids: set[str]):
    for tree in root.iter("BehaviorTree"):
        for el in tree.iter():
            ident = el.get("ID") if el.tag in ("Action", "Condition") else el.tag
            if ident in leaf_ids:
                yield el


def strip_leaf_ports(text: str, leaf_ids: set[str]) -> tuple[str, list[str]]:
    """The mission text without the port attributes of its user leaves (name, ID and the
    `_`-attributes kept), and what was removed; the text unchanged when nothing was."""
    root = ET.fromstring(text)
    removed: list[str] = []
    for el in _leaf_elements(root, leaf_ids):
        for key in list(el.attrib):
            if key in ("name", "ID") or key.startswith("_"):
                continue
            removed.append(f"{el.get('name') or el.get('ID') or el.tag}.{key}")
            del el.attrib[key]
    if not removed:
        return text, []
    return ET.tostring(root, encoding="unicode"), removed


class _Script:
    """What each leaf name returns, call by call (support.hpp's Script, FORMAT.md)."""

    def __init__(self, scenario: Scenario) -> None:
        self.lists = {s.name: list(s.statuses) for s in scenario.leaves}
        self.used: dict[str, int] = {}
        self.default = scenario.default

    def next(self, name: str) -> str:
        got = self.lists.get(name)
        if not got:
            return self.default
        k = self.used.get(name, 0)
        self.used[name] = k + 1
        return got[min(k, len(got) - 1)]


def run_on_library(path: str, leaves, scenario: Scenario, main_tree: Optional[str]) -> tuple[list[str], list[str]]:
    """The scenario on behaviortreepy: status changes (its StdCoutLogger) and root results."""
    import behaviortreepy as bt

    script = _Script(scenario)
    status = {
        "SUCCESS": bt.NodeStatus.SUCCESS,
        "FAILURE": bt.NodeStatus.FAILURE,
        "RUNNING": bt.NodeStatus.RUNNING,
    }
    factory = bt.BehaviorTreeFactory()
    for leaf in leaves:
        if leaf.condition:
            factory.register_simple_condition(leaf.id, lambda node: status[script.next(node.name())])
        else:
            factory.register_simple_stateful_action(
                leaf.id,
                lambda node: status[script.next(node.name())],
                lambda node: status[script.next(node.name())],
                lambda node: None,
            )
    if main_tree is None:
        tree = factory.create_tree_from_file(path)
    else:
        factory.register_behavior_tree_from_file(path)
        tree = factory.create_tree(main_tree)

    def ticks() -> list[str]:
        logger = bt.StdCoutLogger(tree)
        results = []
        for _ in range(scenario.ticks):
            st = tree.tick_exactly_once()
            results.append(st.name)
            if st.name in ("SUCCESS", "FAILURE"):
                break
        logger.flush()
        return results

    results, text = _stdout_of(ticks)
    changes = []
    for line in _ANSI.sub("", text).splitlines():
        m = _LOGGED.match(line)
        if m:
            changes.append(f"{m.group(1)} {m.group(2)} -> {m.group(3)}")
    return changes, results


# StdCoutLogger's line: `[seconds]: NAME (padded to 25) FROM -> TO`, statuses coloured
_ANSI = re.compile(r"\x1b\[[0-9;]*m")
_LOGGED = re.compile(
    r"\[[0-9.]+\]: (.*?) *(IDLE|RUNNING|SUCCESS|FAILURE|SKIPPED) -> (IDLE|RUNNING|SUCCESS|FAILURE|SKIPPED)\Z"
)


def _stdout_of(fn):
    """fn() with the process's standard output (file descriptor 1, where the library's
    StdCoutLogger writes, synchronously at each status change) captured: (result, text)."""
    sys.stdout.flush()
    libc = ctypes.CDLL(None)
    saved = os.dup(1)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 1)
        try:
            result = fn()
        finally:
            libc.fflush(None)
            os.dup2(saved, 1)
            os.close(saved)
        tmp.seek(0)
        return result, tmp.read().decode("utf-8", "replace")


def compare(mission_path: str, scenarios: list[tuple[str, Scenario]], options) -> list[Outcome]:
    """Every scenario on the library and on the interpreter (4.8.2's switches)."""
    from btgen import pipeline
    from btgen.tools.gtests import mission_leaves

    mission = pipeline.load(mission_path, options)
    leaves = mission_leaves(mission)
    with open(mission_path, encoding="utf-8") as f:
        text = f.read()
    copy_text, removed = strip_leaf_ports(text, {leaf.id for leaf in leaves})
    out: list[Outcome] = []
    with tempfile.TemporaryDirectory(prefix="btgen-btpy-mission-") as tmp:
        path = mission_path
        run_mission = mission
        if removed:
            path = os.path.join(tmp, os.path.basename(mission_path))
            with open(path, "w", encoding="utf-8") as f:
                f.write(copy_text)
            run_mission = pipeline.load(path, options)
        at = mission_at(run_mission, VERSION)
        as_written = mission_at(mission, VERSION)
        for name, sc in scenarios:
            expected = lines_of_trace(trace_text(at, sc))
            old = lines_of_trace(trace_text(run_mission, sc))
            if removed and lines_of_trace(trace_text(as_written, sc)) != expected:
                out.append(
                    Outcome(
                        name,
                        False,
                        [],
                        expected,
                        old != expected,
                        removed,
                        "removing the leaves' ports changes the run",
                    )
                )
                continue
            try:
                changes, results = run_on_library(path, leaves, sc, options.main_tree)
            except RuntimeError as e:  # the library refuses the mission (its own message)
                hint = ""
                if "Node not recognized" in str(e):
                    hint = " (a Control or Decorator cannot be registered from Python: only the library's own)"
                raise UserError(
                    Diagnostic(
                        Loc(mission_path, 1, 1), f"BehaviorTree.CPP {VERSION} (behaviortreepy) refuses it: {e}{hint}"
                    )
                ) from None
            # the expected lines hold the root results in tick order, after each tick's changes;
            # the log has no tick boundaries: compare the changes, then the results
            exp_changes = [line for line in expected if not line.startswith("result ")]
            exp_results = [line.split()[1] for line in expected if line.startswith("result ")]
            ok = changes == exp_changes and results == exp_results
            message = ""
            if not ok:
                k = next((i for i, (a, b) in enumerate(zip(changes, exp_changes)) if a != b), None)
                if k is None and changes != exp_changes:
                    k = min(len(changes), len(exp_changes))
                if k is not None:
                    got = changes[k] if k < len(changes) else "(nothing)"
                    want = exp_changes[k] if k < len(exp_changes) else "(nothing)"
                    message = f"status change {k + 1}: library {got}, interpreter {want}"
                else:
                    message = f"root results: library {results}, interpreter {exp_results}"
            out.append(
                Outcome(
                    name, ok, changes + [f"result {r}" for r in results], expected, old != expected, removed, message
                )
            )
    return out


def main(argv: Optional[list[str]] = None) -> int:
    from btgen import cmdline, pipeline
    from btgen.diagnostics import print_diagnostics
    from btgen.interp.scenario import load_scenario

    p = cmdline.Parser(prog="python -m btgen.tools.gtests.btpy", description=__doc__.split("\n\n")[0])
    p.add_argument("mission", metavar="MISSION.xml", help="the mission the scenarios run")
    p.add_argument("scenarios", nargs="+", metavar="FILE.scenario", help="the scenarios to run on the library")
    p.add_argument("--models", action="append", default=[], metavar="FILE.xml", help="a models file")
    p.add_argument("--main-tree", metavar="ID", help="the tree to run")
    args = p.parse_args(argv)
    why = available()
    if why is not None:
        print(f"btgen: error: {why}", file=sys.stderr)
        return 1
    options = pipeline.CompileOptions(models=tuple(args.models), main_tree=args.main_tree)
    try:
        mission = pipeline.load(args.mission, options)
        scenarios = []
        for s in args.scenarios:
            sc, _ = load_scenario(s, mission)
            scenarios.append((s, sc))
        outcomes = compare(args.mission, scenarios, options)
    except UserError as e:
        print_diagnostics(e.diagnostics)
        return 1
    bad = [o for o in outcomes if not o.ok]
    for o in outcomes:
        print(f"{o.name}: {'same' if o.ok else 'DIFFERENT: ' + o.message}")
    print(f"{len(outcomes) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
