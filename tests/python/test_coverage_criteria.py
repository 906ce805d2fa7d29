"""Coverage criteria (node, outcome, halt, condition, mcdc) in `explore`, `tests` and `cover`.

tests/coverage/Criteria.xml is small enough that every obligation's answer is known by hand:

- A and B (Conditions) set `a` and `b` by their post-conditions; `Mix` computes
  `c := a || (a && b)`; `Both` is `a && b`; `Other` has `_failureIf="false"`; Work (an Action
  under ReactiveSequence `Guarded`, after Condition `Safe`) has `_skipIf="c"`, `_onHalted`.
- halt: the nodes that can be RUNNING (the root aside) are Guarded and Work. Work is halted
  when Safe fails while it runs (reached); nothing halts Guarded (its parent is the root
  Sequence): unreachable. 1 of 2.
- pre: Work's _skipIf is `a`: true and false both reached; Other's `_failureIf="false"` is
  never true (unreachable): 3 of 4.
- post: A's and B's _onSuccess / _onFailure each run and not run (8), Work's _onHalted run
  (halted) and not run (completed): 10 of 10.
- mcdc: `a && b`: both operands shown, unique-cause ((T,T) vs (F,T) and (T,F)).
  `a || (a && b)`, three operands with the first two both `a`: operand 1 is shown only by the
  masking form ((T,T,F) -> true vs (F,F,F) -> false: operand 2 differs too, masked by `||`);
  operand 2 never decides the result while true (`a || ...` is then true anyway) and operand
  3 only while operand 2 is true and operand 1 false, which cannot happen: 3 of 5.
- bounded: with `--ticks 1` no node is halted (a halt needs a RUNNING node at an earlier tick):
  Work's halt is "not reached within the bound", not unreachable.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario
from btgen.ir.treexml import groot2_tree
from btgen.lang.script import parse_script
from btgen.tools import obligations
from btgen.tools.cover import trace_transitions

ROOT = Path(__file__).resolve().parents[2]
CRIT = ROOT / "tests" / "coverage" / "Criteria.xml"
PICK = ROOT / "missions" / "PickPlaceBall.xml"
NAV2 = ROOT / "tests" / "real_files" / "nav2"
CODES = {"IDLE": 0, "RUNNING": 1, "SUCCESS": 2, "FAILURE": 3, "SKIPPED": 4}
EXHAUSTIVE = "unreachable (exhaustive exploration)"
BOUNDED = "not reached within the bound"


def _explore(capsys, *args) -> dict:
    rc = main(["explore", *map(str, args), "--json"])
    report = json.loads(capsys.readouterr().out)
    assert rc == 0
    return report


def test_hand_known_answers(capsys):
    report = _explore(capsys, CRIT, "--coverage", "all")
    assert report["criteria"] == ["node", "outcome", "halt", "condition", "mcdc"]
    counts = report["obligations"]
    assert counts["node"] == [12, 12]
    assert counts["halt"] == [1, 2]
    assert counts["pre"] == [3, 4]
    assert counts["post"] == [10, 10]
    assert counts["mcdc"] == [3, 5]
    left = {(o["criterion"], o["node"], o["what"], o["answer"]) for o in report["uncovered_obligations"]}
    mix = "Main/Sequence/Mix"
    assert left == {
        ("halt", "Main/Sequence/Guarded", "halted while RUNNING", EXHAUSTIVE),
        ("condition", "Main/Sequence/Choose/Other", "_failureIf evaluated true", EXHAUSTIVE),
        ("mcdc", mix, "code operand 2 `a` shown to decide its `&&`/`||` (site 1)", EXHAUSTIVE),
        ("mcdc", mix, "code operand 3 `b` shown to decide its `&&`/`||` (site 1)", EXHAUSTIVE),
    }
    # located at the attribute (or the node) in the mission file
    where = {o["what"]: o["location"] for o in report["uncovered_obligations"]}
    assert where["_failureIf evaluated true"] == f"{CRIT}:14:37"
    assert where["halted while RUNNING"] == f"{CRIT}:16:7"


def test_bounded_is_not_unreachable(capsys):
    report = _explore(capsys, CRIT, "--coverage", "halt", "--ticks", "1")
    assert report["obligations"] == {"halt": [0, 2]}
    assert {(o["node"], o["answer"]) for o in report["uncovered_obligations"]} == {
        ("Main/Sequence/Guarded", BOUNDED),
        ("Main/Sequence/Guarded/Work", BOUNDED),
    }


def test_default_criteria_unchanged(capsys):
    report = _explore(capsys, PICK)
    assert report["criteria"] == ["node", "outcome"]
    assert set(report["obligations"]) == {"node", "outcome"}
    assert report["covered"] == report["goals"] == 28


def test_mcdc_pairs_by_hand():
    """`a || (a && b)` and `a && b` as sites: which evaluations show which operand, and how."""
    script = parse_script("a || (a && b)")
    ((expr, leaves),) = obligations._sites_of(script.statements)
    site = obligations.Site(1, "code", 0, expr, leaves, ["a", "a", "b"], None)
    coupled = {(v, site.value(v)) for v in [(True, True, True), (True, True, False), (False, False, True)]}
    coupled.add(((False, False, False), False))
    assert obligations.mcdc_pair(site, 0, coupled) == ((True, True, False), (False, False, False), False)
    assert obligations.mcdc_pair(site, 1, coupled) is None
    assert obligations.mcdc_pair(site, 2, coupled) is None
    # uncoupled operands (a third variable) show operand 2 unique-cause: (F,T,T) vs (F,F,T)
    free = coupled | {((False, True, True), True)}
    assert obligations.mcdc_pair(site, 1, free) == ((False, True, True), (False, False, True), True)
    both = parse_script("x > 1 && y")
    ((expr2, leaves2),) = obligations._sites_of(both.statements)
    s2 = obligations.Site(1, "code", 0, expr2, leaves2, ["x > 1", "y"], None)
    assert obligations.mcdc_pair(s2, 0, {((True, True), True), ((False, False), False)}) is None  # y masks
    assert obligations.mcdc_pair(s2, 0, {((True, True), True), ((False, True), False)})[2] is True


def test_cover_measures_the_same_on_scenarios_logs_and_traces(capsys, tmp_path):
    out = tmp_path / "sc"
    assert main(["explore", str(CRIT), "--coverage", "all", "-o", str(out)]) == 0
    capsys.readouterr()
    files = sorted(str(p) for p in out.glob("*.scenario"))
    assert main(["cover", str(CRIT), *files, "--coverage", "all", "--table"]) == 0
    text = capsys.readouterr().out
    for line in ("halts:    1/2 = 50.0%", "pre:      3/4 = 75.0%", "post:     10/10 = 100.0%", "mcdc:     3/5 = 60.0%"):
        assert line in text
    # uncovered obligations by node path and line; each shown MC/DC operand says its form
    assert f"uncovered halt: Main/Sequence/Guarded ({CRIT}:16:7): halted while RUNNING" in text
    assert f"uncovered condition: Main/Sequence/Choose/Other ({CRIT}:14:37): _failureIf evaluated true" in text
    assert "code operand 1 `a` shown to decide its `&&`/`||` (site 1): masking ((T, T, F) -> true" in text
    assert "Main/Sequence/Choose/Both" in text and "unique-cause ((T, T) -> true, (F, T) -> false)" in text
    # the same runs as .btlog files (replayed through scenario-from-log) and as traces
    mission = load_mission(str(CRIT))
    xml = groot2_tree(mission).xml.encode()
    logs, traces = [], []
    for k, f in enumerate(files):
        trace = trace_text(mission, parse_scenario(f))
        body = b"".join(
            struct.pack("<Q", 10 * i)[:6] + struct.pack("<HB", uid, CODES[to])
            for i, (uid, _, to) in enumerate(trace_transitions(trace))
        )
        log = tmp_path / f"run{k}.btlog"
        log.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + body)
        logs.append(str(log))
        t = tmp_path / f"run{k}.trace"
        t.write_text(trace)
        traces.append(str(t))
    assert main(["cover", str(CRIT), *logs, "--coverage", "all"]) == 0
    from_logs = capsys.readouterr().out
    for line in ("halts:    1/2", "pre:      3/4", "post:     10/10", "mcdc:     3/5"):
        assert line in from_logs
    assert main(["cover", str(CRIT), *traces, "--coverage", "halt,condition,mcdc"]) == 0
    from_traces = capsys.readouterr().out
    assert "halts:    1/2" in from_traces and "post:     10/10" in from_traces
    assert "outcomes:" not in from_traces  # the criteria asked for (and nodes, which --min reads)
    assert "pre and mcdc leave out 5 traces" in from_traces
    # a partial set: the scenario where Work is halted left out
    partial = [f for f in files if "Work RUNNING" not in Path(f).read_text()]
    assert len(partial) == len(files) - 1
    assert main(["cover", str(CRIT), *partial, "--coverage", "halt", "--uncovered"]) == 0
    text = capsys.readouterr().out
    assert "halts:    0/2" in text and "uncovered halt: Main/Sequence/Guarded/Work" in text


def test_tests_command_writes_the_criteria_scenarios(capsys, tmp_path):
    assert main(["tests", str(CRIT), "-o", str(tmp_path / "d"), "--coverage", "node,outcome"]) == 0
    few = capsys.readouterr().out
    assert main(["tests", str(CRIT), "-o", str(tmp_path / "a"), "--coverage", "all"]) == 0
    many = capsys.readouterr().out
    report = _explore(capsys, CRIT, "--coverage", "all")
    assert many.split(": ")[1].startswith(f"{report['scenarios']} tests")
    assert int(few.split(": ")[1].split()[0]) <= report["scenarios"]
    # the halt of Work is named in a test; each TEST's comment names the condition ways and the
    # MC/DC evaluations no earlier one reaches, and between them they are every one reached
    cpp = next((tmp_path / "a").glob("*_tests.cpp")).read_text()
    assert "WorkHaltedRunning" in cpp
    reaches = [line for line in cpp.splitlines() if line.startswith("// Reaches first: ")]
    assert "// Reaches first: `Work` _skipIf evaluated true" in reaches
    assert "// Reaches first: `Both` code: operands `a`, `b` = (T, T) -> true" in reaches
    assert "// Reaches first: `Mix` code: operands `a`, `a`, `b` = (T, T, F) -> true" in reaches
    assert sum("_onSuccess" in line or "_onFailure" in line for line in reaches) == 8
    assert sum("operands" in line for line in reaches) == 8  # Both: 4 vectors, Mix: 4 (a twice)
    assert len(reaches) == len(set(reaches))
    assert not any("_failureIf evaluated true" in line for line in reaches)  # never reached
    assert "Reaches first" not in next((tmp_path / "d").glob("*_tests.cpp")).read_text()


@pytest.mark.parametrize(
    "value, message",
    [
        ("nodes", "--coverage nodes: `nodes` is not a criterion (did you mean `node`?)"),
        ("node,", "--coverage node,: an empty name is not a criterion"),
        ("mcdc,halts", "`halts` is not a criterion (did you mean `halt`?)"),
    ],
)
def test_bad_criteria(capsys, tmp_path, value, message):
    for cmd in (["explore", str(CRIT)], ["cover", str(CRIT), str(CRIT)], ["tests", str(CRIT), "-o", str(tmp_path)]):
        assert main([*cmd, "--coverage", value]) == 1
        err = capsys.readouterr().err
        assert ": error: " in err and message in err and "Traceback" not in err
    assert not any(tmp_path.iterdir())


def test_rate_controller_keeps_the_clock_in_the_state(capsys):
    """RateController reads the clock: two states that differ only in the time are not the same
    (before, the search merged them and called ComputePathToPose's halt unreachable, exhaustive;
    it needs the 1 s period to pass, 11 ticks at 100 ms)."""
    tree = NAV2 / "navigate_w_replanning_time.xml"
    args = [tree, "--models", NAV2 / "nav2_tree_nodes.xml", "--coverage", "halt"]
    report = _explore(capsys, *args)
    answers = {o["node"].split("/")[-1]: o["answer"] for o in report["uncovered_obligations"]}
    assert answers["ComputePathToPose"] == BOUNDED
    report = _explore(capsys, *args, "--ticks", "12")
    covered = {o["node"].split("/")[-1] for o in report["uncovered_obligations"]}
    assert "ComputePathToPose" not in covered
