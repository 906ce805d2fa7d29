"""`btgen diff`: known answers (equivalent refactorings, behavioural changes, version switches),
counterexamples replayed on both engines, bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario
from btgen.tools.diff.product import first_difference, observe

ROOT = Path(__file__).resolve().parents[2]
CONF_410 = ROOT / "tests" / "conformance" / "btcpp-4.10.0"

MODELS = """
  <TreeNodesModel>
    <Condition ID="IsBatteryOk"/>
    <Condition ID="IsDocked"/>
    <Action ID="MoveTo"><input_port name="goal" type="double"/></Action>
    <Action ID="Drive"><input_port name="goal" type="double"/></Action>
    <Action ID="Charge"/>
    <Action ID="Beep"/>
  </TreeNodesModel>
"""


def _mission(tmp_path: Path, name: str, body: str, main: str = "Main") -> str:
    path = tmp_path / f"{name}.xml"
    path.write_text(
        f'<root BTCPP_format="4" main_tree_to_execute="{main}">\n'
        f'  <BehaviorTree ID="{main}">\n{body}\n  </BehaviorTree>\n{MODELS}</root>\n'
    )
    return str(path)


def _diff(capsys, *argv: str) -> tuple[int, dict, str]:
    rc = main(["diff", "--format", "json", *argv])
    out, err = capsys.readouterr()
    return rc, json.loads(out) if out.strip() else {}, err


# ---------------------------------------------------------------- equivalent refactorings
EQUIVALENT = {
    "sequence of one child": (
        "<Sequence><MoveTo goal='1.5'/></Sequence>",
        "<MoveTo goal='1.5'/>",
    ),
    "inverter of inverter": (
        "<Sequence><IsBatteryOk/><MoveTo goal='2'/></Sequence>",
        "<Sequence><Inverter><Inverter><IsBatteryOk/></Inverter></Inverter>"
        "<Inverter><Inverter><MoveTo goal='2'/></Inverter></Inverter></Sequence>",
    ),
    "nested sequence flattened": (
        "<Sequence><IsBatteryOk/><Sequence><MoveTo goal='1'/><Charge/></Sequence><Beep/></Sequence>",
        "<Sequence><IsBatteryOk/><MoveTo goal='1'/><Charge/><Beep/></Sequence>",
    ),
    "reactive sequence wrapped": (
        "<ReactiveSequence><IsBatteryOk/><MoveTo goal='1.5'/></ReactiveSequence>",
        "<Sequence><ReactiveSequence><IsBatteryOk/><Inverter><Inverter><MoveTo goal='1.5'/></Inverter></Inverter>"
        "</ReactiveSequence></Sequence>",
    ),
    "script writes the same values": (
        "<Sequence><Script code=\"x := 1; y := 'a'\"/><MoveTo goal='{x}'/></Sequence>",
        "<Sequence><Script code='x := 1'/><Script code=\"y := 'a'\"/><MoveTo goal='{x}'/></Sequence>",
    ),
}


@pytest.mark.parametrize("case", sorted(EQUIVALENT))
def test_equivalent_refactorings(capsys, tmp_path, case):
    old_body, new_body = EQUIVALENT[case]
    old = _mission(tmp_path, "old", old_body)
    new = _mission(tmp_path, "new", new_body)
    rc, report, err = _diff(capsys, old, new)
    assert rc == 0, err
    assert report["equivalent"] is True
    assert report["exhaustive"] is True
    # and the other way round
    rc, report, _ = _diff(capsys, new, old)
    assert rc == 0 and report["exhaustive"] is True


def test_text_report_says_exhaustively(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Sequence><MoveTo goal='1.5'/></Sequence>")
    new = _mission(tmp_path, "new", "<MoveTo goal='1.5'/>")
    assert main(["diff", old, new]) == 0
    out = capsys.readouterr().out
    assert "equivalent (exhaustively)" in out


def test_bounded_when_runs_reach_the_tick_bound(capsys, tmp_path):
    # the clock grows with every tick, so no state repeats: the answer holds up to K ticks only
    body = "<Sequence><Sleep msec='1000'/><MoveTo goal='1'/></Sequence>"
    old = _mission(tmp_path, "old", body)
    new = _mission(tmp_path, "new", body)
    assert main(["diff", "--max-ticks", "4", old, new]) == 0
    assert "equivalent (up to 4 ticks)" in capsys.readouterr().out


def test_rename(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Sequence><IsBatteryOk/><MoveTo goal='3'/></Sequence>")
    new = _mission(tmp_path, "new", "<Sequence><IsBatteryOk/><Drive goal='3'/></Sequence>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1
    assert report["first_difference"] == {
        "tick": 1,
        "event": 2,
        "old": "MoveTo(goal=3.0) -> SUCCESS",
        "new": "Drive(goal=3.0) -> SUCCESS",
    }
    rc, report, _ = _diff(capsys, "--rename", "MoveTo=Drive", old, new)
    assert rc == 0 and report["exhaustive"] is True


# ---------------------------------------------------------------- behavioural changes
def test_reactive_sequence_to_sequence(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<ReactiveSequence><IsBatteryOk/><MoveTo goal='1.5'/></ReactiveSequence>")
    new = _mission(tmp_path, "new", "<Sequence><IsBatteryOk/><MoveTo goal='1.5'/></Sequence>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1
    # the reactive one checks the battery again on tick 2; the plain one goes on moving
    assert report["first_difference"] == {
        "tick": 2,
        "event": 1,
        "old": "IsBatteryOk() -> SUCCESS",
        "new": "MoveTo(goal=1.5) -> SUCCESS",
    }
    assert "leaf MoveTo RUNNING" in report["scenario"]


def test_fallback_children_swapped(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Fallback><IsDocked/><Charge/></Fallback>")
    new = _mission(tmp_path, "new", "<Fallback><Charge/><IsDocked/></Fallback>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1
    assert report["first_difference"]["tick"] == 1 and report["first_difference"]["event"] == 1
    # the shortest: one result for each leaf
    statuses = [line.split()[2:] for line in report["scenario"].splitlines() if line.startswith("leaf ")]
    assert sum(len(s) for s in statuses) == 2


def test_retry_count_changed(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<RetryUntilSuccessful num_attempts='2'><Charge/></RetryUntilSuccessful>")
    new = _mission(tmp_path, "new", "<RetryUntilSuccessful num_attempts='3'><Charge/></RetryUntilSuccessful>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1
    # two failures (a retry waits for the next tick): OLD gives up, NEW will try a third time
    assert "leaf Charge FAILURE FAILURE" in report["scenario"]
    assert report["first_difference"] == {"tick": 2, "event": 2, "old": "result FAILURE", "new": "result RUNNING"}


def test_force_success_is_not_a_refactoring(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<ReactiveSequence><IsBatteryOk/><MoveTo goal='1.5'/></ReactiveSequence>")
    forced = "<ForceSuccess><MoveTo goal='1.5'/></ForceSuccess>"
    new = _mission(tmp_path, "new", f"<ReactiveSequence><IsBatteryOk/>{forced}</ReactiveSequence>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1
    assert report["first_difference"] == {"tick": 1, "event": 3, "old": "result FAILURE", "new": "result SUCCESS"}


def test_port_value_changed(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<MoveTo goal='1.5'/>")
    new = _mission(tmp_path, "new", "<MoveTo goal='2.5'/>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1
    assert report["first_difference"]["old"] == "MoveTo(goal=1.5) -> SUCCESS"


def test_text_report_marks_the_first_difference(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Fallback><IsDocked/><Charge/></Fallback>")
    new = _mission(tmp_path, "new", "<Fallback><Charge/><IsDocked/></Fallback>")
    assert main(["diff", old, new]) == 1
    out = capsys.readouterr().out
    marked = [line for line in out.splitlines() if line.startswith("!")]
    assert len(marked) == 1 and "<- first difference" in marked[0]
    assert "IsDocked()" in marked[0] and "Charge()" in marked[0]
    assert main(["diff", "--format", "markdown", old, new]) == 1
    md = capsys.readouterr().out
    assert md.startswith("**btgen diff**") and "```text" in md


# ---------------------------------------------------------------- counterexamples on both engines
def _run(mission: str, scenario: str, engine: str, version: str = "4.6.2", extra: tuple = ()) -> str:
    got = subprocess.run(
        [sys.executable, "-m", "btgen", "run", mission, "--scenario", scenario, "--engine", engine, "--btcpp", version]
        + list(extra),
        capture_output=True,
        text=True,
        check=False,
    )
    assert got.returncode == 0, got.stderr
    return got.stdout


def _tick_of_first_difference(a: str, b: str) -> int:
    tick = 0
    for x, y in zip(a.splitlines(), b.splitlines()):
        if x.startswith("tick "):
            tick = int(x.split()[1])
        if x != y:
            return tick
    return tick + 1


def _replay_both_engines(old, new, cx: Path, v_old="4.6.2", v_new="4.6.2"):
    traces = {}
    for stem, mission, version in (("old", old, v_old), ("new", new, v_new)):
        sc = str(cx / f"{stem}.scenario")
        interp = _run(mission, sc, "interp", version)
        cpp = _run(mission, sc, "cpp", version)
        assert interp == cpp, f"{stem}: the two engines disagree"
        assert interp == (cx / f"{stem}.trace").read_text()
        traces[stem] = interp
    assert traces["old"] != traces["new"]
    return traces


def _replay_logs_on_both_engines(old, new, cx: Path, v_old="4.6.2", v_new="4.6.2", clock_ms=100):
    """Each .btlog through `btgen scenario-from-log`, the scenario got back run on the interpreter
    and on the generated C++: both give the written trace, and OLD's differs from NEW's."""
    traces = {}
    for stem, mission, version in (("old", old, v_old), ("new", new, v_new)):
        log = cx / f"{stem}.btlog"
        assert log.read_bytes().startswith(b"BTCPP4-FileLogger2\x01")
        back = cx.parent / f"{stem}-from-log.scenario"
        got = subprocess.run(
            [sys.executable, "-m", "btgen", "scenario-from-log", mission, str(log), "-o", str(back)]
            + ["--clock-ms", str(clock_ms), "--btcpp", version],
            capture_output=True,
            text=True,
            check=False,
        )
        assert got.returncode == 0, got.stderr
        interp = _run(mission, str(back), "interp", version)
        assert interp == _run(mission, str(back), "cpp", version), f"{stem}: the two engines disagree"
        assert interp == (cx / f"{stem}.trace").read_text()
        traces[stem] = interp
    assert traces["old"] != traces["new"]
    return traces


@pytest.mark.parametrize("case", ["reactive", "fallback"])
def test_counterexample_replays_on_both_engines(capsys, tmp_path, case):
    if case == "reactive":
        old_body = "<ReactiveSequence><IsBatteryOk/><MoveTo goal='1.5'/></ReactiveSequence>"
        new_body = "<Sequence><IsBatteryOk/><MoveTo goal='1.5'/></Sequence>"
    else:
        old_body = "<Fallback><IsDocked/><Charge/></Fallback>"
        new_body = "<Fallback><Charge/><IsDocked/></Fallback>"
    old, new = _mission(tmp_path, "old", old_body), _mission(tmp_path, "new", new_body)
    cx = tmp_path / "cx"
    rc, report, _ = _diff(capsys, "--counterexample", str(cx), old, new)
    assert rc == 1
    assert sorted(p.name for p in cx.iterdir()) == [
        "new.btlog",
        "new.scenario",
        "new.trace",
        "old.btlog",
        "old.scenario",
        "old.trace",
    ]
    _replay_both_engines(old, new, cx)
    _replay_logs_on_both_engines(old, new, cx)
    # the observable runs of the written scenario differ exactly where the report says
    at = first_difference(
        observe(load_mission(old, (), None), parse_scenario(str(cx / "old.scenario"))),
        observe(load_mission(new, (), None), parse_scenario(str(cx / "new.scenario"))),
    )
    assert at == (report["first_difference"]["tick"] - 1, report["first_difference"]["event"] - 1)


# ---------------------------------------------------------------- the same file across versions
def test_version_switch_that_matters(capsys, tmp_path):
    m = str(CONF_410 / "set_blackboard_always.xml")
    cx = tmp_path / "cx"
    rc, report, _ = _diff(capsys, m, m, "--btcpp-old", "4.6.2", "--btcpp-new", "4.10.0", "--counterexample", str(cx))
    assert rc == 1
    # 4.10.0's SetBlackboard converts a string into an untyped entry's type: it gets an empty value
    assert report["first_difference"] == {
        "tick": 1,
        "event": 1,
        "old": "write greeting = 'hello'",
        "new": "write greeting = <empty>",
    }
    traces = _replay_both_engines(m, m, cx, "4.6.2", "4.10.0")
    assert _replay_logs_on_both_engines(m, m, cx, "4.6.2", "4.10.0") == traces
    # the same tree under two versions: its traces are comparable line by line
    assert _tick_of_first_difference(traces["old"], traces["new"]) == report["first_difference"]["tick"]
    # and the recordings of the real library say the same
    assert (ROOT / "tests/conformance/btcpp-4.6.2/set_blackboard_always.trace").read_text() != (
        CONF_410 / "set_blackboard_always.trace"
    ).read_text()


@pytest.mark.parametrize("stem", ["seq_basic", "pick_and_place", "reactive_seq_halts"])
def test_version_switch_that_does_not_matter(capsys, stem):
    m = str(CONF_410 / f"{stem}.xml")
    rc, report, err = _diff(capsys, m, m, "--btcpp-old", "4.6.2", "--btcpp-new", "4.10.0")
    assert rc == 0, err
    assert report["exhaustive"] is True


def test_a_mission_is_equivalent_to_itself(capsys):
    m = str(CONF_410 / "robot_lab_tour.xml")
    rc, report, err = _diff(capsys, m, m, "--max-ticks", "4")
    assert rc == 0, err
    assert report["equivalent"] is True


# ---------------------------------------------------------------- bad input
def test_file_that_does_not_load(capsys, tmp_path):
    good = _mission(tmp_path, "good", "<MoveTo goal='1'/>")
    bad = tmp_path / "bad.xml"
    bad.write_text("<root BTCPP_format='4'>\n  <BehaviorTree ID='Main'>\n    <Nope/>\n")
    assert main(["diff", good, str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:" in err and "error:" in err and "Traceback" not in err


def test_both_files_reported(capsys, tmp_path):
    a = tmp_path / "a.xml"
    a.write_text("<root")
    b = tmp_path / "b.xml"
    b.write_text("<root")
    assert main(["diff", str(a), str(b)]) == 1
    err = capsys.readouterr().err
    assert f"{a}:" in err and f"{b}:" in err


def test_rename_of_an_unknown_leaf(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<MoveTo goal='1'/>")
    new = _mission(tmp_path, "new", "<Drive goal='1'/>")
    assert main(["diff", "--rename", "Move=Drive", old, new]) == 1
    err = capsys.readouterr().err
    assert "error: --rename `Move=Drive`: `Move` is no leaf of" in err
    assert main(["diff", "--rename", "MoveTo=Driv", old, new]) == 1
    assert "`Driv` is no leaf of" in capsys.readouterr().err
    assert main(["diff", "--rename", "MoveTo", old, new]) == 1
    assert "write OLD_ID=NEW_ID" in capsys.readouterr().err


def test_different_main_trees(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<MoveTo goal='1'/>", main="Main")
    new = _mission(tmp_path, "new", "<MoveTo goal='1'/>", main="Other")
    assert main(["diff", old, new]) == 1
    err = capsys.readouterr().err
    assert f"{new}:1:1: error: the main tree is `Other` here and `Main`" in err


def test_bad_option_values(capsys, tmp_path):
    m = _mission(tmp_path, "m", "<MoveTo goal='1'/>")
    for argv in (["--btcpp-new", "5.0"], ["--max-ticks", "0"], ["--format", "html"], ["--clock-ms", "-1"]):
        try:
            rc = main(["diff", *argv, m, m])
        except SystemExit as e:
            rc = e.code
        assert rc == 1
        assert "error:" in capsys.readouterr().err


def test_interp_trace_of_counterexample_is_the_written_one(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<RetryUntilSuccessful num_attempts='2'><Charge/></RetryUntilSuccessful>")
    new = _mission(tmp_path, "new", "<RetryUntilSuccessful num_attempts='3'><Charge/></RetryUntilSuccessful>")
    cx = tmp_path / "cx"
    assert main(["diff", "--counterexample", str(cx), old, new]) == 1
    capsys.readouterr()
    for stem, m in (("old", old), ("new", new)):
        text = trace_text(load_mission(m, (), None), parse_scenario(str(cx / f"{stem}.scenario")))
        assert text == (cx / f"{stem}.trace").read_text()


def test_state_budget_gives_no_proof(capsys):
    m = str(CONF_410 / "robot_lab_tour.xml")
    rc, report, _ = _diff(capsys, "--max-states", "20", m, m)
    assert rc == 0
    assert report["equivalent"] is None and report["exhaustive"] is False
    assert "not a proof" in report["verdict"]


def test_upgrade_that_refuses_the_file(capsys):
    # 4.8.4's name rules refuse a tree ID with a space: the upgrade stops the file from loading
    m = str(ROOT / "tests/real_files/btcpp/tests-4.10.0/gtest_name_validation_L177.xml")
    assert main(["diff", m, m, "--btcpp-new", "4.10.0"]) == 1
    err = capsys.readouterr().err
    assert f"{m}:2:7: error: BehaviorTree ID `Main Tree`" in err
    assert f"{m}:1:1: note: while loading NEW under BehaviorTree.CPP 4.10.0" in err
    assert "OLD" not in err


def test_condition_turned_action_is_found_both_ways(capsys, tmp_path):
    models = '<TreeNodesModel><{kind} ID="X"/><Action ID="Beep"/></TreeNodesModel>'
    paths = []
    for kind in ("Condition", "Action"):
        p = tmp_path / f"{kind}.xml"
        p.write_text(
            '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
            '  <BehaviorTree ID="Main"><Sequence><X/><Beep/></Sequence></BehaviorTree>\n'
            f"  {models.format(kind=kind)}\n</root>\n"
        )
        paths.append(str(p))
    for old, new in (paths, paths[::-1]):
        rc, report, _ = _diff(capsys, old, new)
        assert rc == 1
        assert "leaf X RUNNING" in report["scenario"]


def test_btcpp_is_the_default_of_both_sides(capsys):
    m = str(CONF_410 / "seq_basic.xml")
    rc, report, _ = _diff(capsys, "--btcpp", "4.10.0", m, m)
    assert rc == 0 and (report["btcpp_old"], report["btcpp_new"]) == ("4.10.0", "4.10.0")
    rc, report, _ = _diff(capsys, "--btcpp", "4.10.0", "--btcpp-old", "4.6.2", m, m)
    assert (report["btcpp_old"], report["btcpp_new"]) == ("4.6.2", "4.10.0")


def test_markdown_when_equivalent(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Sequence><MoveTo goal='1.5'/></Sequence>")
    new = _mission(tmp_path, "new", "<MoveTo goal='1.5'/>")
    assert main(["diff", "--format", "markdown", old, new]) == 0
    out = capsys.readouterr().out
    assert out.startswith("**btgen diff**") and "**equivalent (exhaustively)**" in out


def test_rename_onto_a_name_taken(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Sequence><MoveTo goal='1'/><Drive goal='1'/></Sequence>")
    new = _mission(tmp_path, "new", "<Sequence><Drive goal='1'/><MoveTo goal='1'/></Sequence>")
    assert main(["diff", "--rename", "MoveTo=Drive", old, new]) == 1
    assert "has a leaf `Drive` too; rename it as well" in capsys.readouterr().err
    assert main(["diff", "--rename", "MoveTo=Drive", "--rename", "Drive=Drive", old, new]) == 1
    assert "another leaf is renamed `Drive` already" in capsys.readouterr().err
    # a swap of names is a rename of both: the same calls, so equivalent
    rc, report, _ = _diff(capsys, "--rename", "MoveTo=Drive", "--rename", "Drive=MoveTo", old, new)
    assert rc == 0 and report["exhaustive"] is True


def test_product_states_are_keyed_by_each_sides_own_interpreter(capsys):
    """The state key of each side is read from that side's interpreter: keyed by the explorer's
    own (never ticked) interpreter, distinct states merged and the search stopped early (PickPlaceBall
    against itself gave 19 product states instead of 26), which could call missions equivalent
    on a search that never reached where they differ."""
    from btgen.cli import main

    pick = str(ROOT / "missions" / "PickPlaceBall.xml")
    assert main(["diff", pick, pick]) == 0
    out = capsys.readouterr().out
    assert "equivalent (exhaustively)" in out
    assert "79 runs, 26 product states" in out


# ---------------------------------------------------------------- what is observed (--observe)
def test_observe_transitions_sees_a_reshaped_tree(capsys, tmp_path):
    old = _mission(tmp_path, "old", EQUIVALENT["nested sequence flattened"][0])
    new = _mission(tmp_path, "new", EQUIVALENT["nested sequence flattened"][1])
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 0 and report["exhaustive"] is True  # by default control nodes are not observed
    rc, report, _ = _diff(capsys, "--observe", "transitions", old, new)
    assert rc == 1
    # OLD's inner Sequence starts where NEW has none: the first transition that differs
    first = report["first_difference"]
    assert (first["tick"], first["event"], first["old"]) == (1, 3, "Sequence: IDLE -> RUNNING")
    assert first["new"].startswith("MoveTo: IDLE -> ")
    # a mission against itself agrees on every transition
    rc, report, _ = _diff(capsys, "--observe", "default,transitions", old, old)
    assert rc == 0 and report["exhaustive"] is True


def test_observe_without_inputs_or_writes(capsys, tmp_path):
    old = _mission(tmp_path, "old", "<Sequence><Script code='x := 1'/><MoveTo goal='1'/></Sequence>")
    new = _mission(tmp_path, "new", "<Sequence><Script code='x := 2'/><MoveTo goal='2'/></Sequence>")
    rc, report, _ = _diff(capsys, old, new)
    assert rc == 1 and report["first_difference"]["old"] == "write x = 1"
    rc, report, _ = _diff(capsys, "--observe", "leaf-calls,inputs,root", old, new)
    assert rc == 1 and report["first_difference"]["old"] == "MoveTo(goal=1.0) -> SUCCESS"
    rc, report, _ = _diff(capsys, "--observe", "leaf-calls,root", old, new)
    assert rc == 0 and report["exhaustive"] is True
    # the root's result left out: a different result is not seen, a different end is
    a = _mission(tmp_path, "a", "<MoveTo goal='1'/>")
    b = _mission(tmp_path, "b", "<Inverter><MoveTo goal='1'/></Inverter>")
    rc, report, _ = _diff(capsys, "--observe", "leaf-calls", a, b)
    assert rc == 0
    rc, report, _ = _diff(capsys, "--observe", "leaf-calls,root", a, b)
    assert rc == 1 and report["first_difference"]["old"] == "result SUCCESS"
    # the end of a run is always observed: the same calls, but one run goes on sleeping
    c = _mission(tmp_path, "c", "<Sequence><MoveTo goal='1'/><Sleep msec='1000'/></Sequence>")
    rc, report, _ = _diff(capsys, "--observe", "leaf-calls", a, c)
    assert rc == 1 and report["first_difference"] == {"tick": 1, "event": 2, "old": "result completed", "new": None}


def test_observe_bad_values(capsys, tmp_path):
    m = _mission(tmp_path, "m", "<MoveTo goal='1'/>")
    assert main(["diff", "--observe", "leaf-cals", m, m]) == 1
    assert "did you mean `leaf-calls`?" in capsys.readouterr().err
    assert main(["diff", "--observe", ",", m, m]) == 1
    assert "error:" in capsys.readouterr().err


def test_resumed_runs_search_as_replayed_runs(tmp_path):
    """A run resumes from the tick where its parent plan branched (both interpreters restored by
    explore's core); played from the first tick instead, the search is the same: the same
    answer, runs, product states and counterexample."""
    from btgen.tools.diff.product import Differ

    pairs = [
        (str(ROOT / "missions" / "PickPlaceBall.xml"), str(ROOT / "missions" / "PickPlaceBall.xml")),
        (
            _mission(tmp_path, "a", "<ReactiveSequence><IsBatteryOk/><MoveTo goal='1.5'/></ReactiveSequence>"),
            _mission(tmp_path, "b", "<Sequence><IsBatteryOk/><MoveTo goal='1.5'/></Sequence>"),
        ),
        (
            _mission(tmp_path, "c", "<RetryUntilSuccessful num_attempts='2'><Charge/></RetryUntilSuccessful>"),
            _mission(tmp_path, "d", "<RetryUntilSuccessful num_attempts='3'><Charge/></RetryUntilSuccessful>"),
        ),
        (
            _mission(tmp_path, "e", "<Sequence><Sleep msec='250'/><MoveTo goal='1'/><Charge/></Sequence>"),
            _mission(tmp_path, "f", "<Sequence><Sleep msec='250'/><MoveTo goal='1'/><Charge/></Sequence>"),
        ),
    ]
    for old, new in pairs:
        got = []
        for resume, budget in ((True, None), (False, None), (True, 1)):  # 1: most runs replayed again
            d = Differ(load_mission(old, (), None), load_mission(new, (), None), max_ticks=6)
            d.resume = resume
            d.max_marks = budget or d.max_marks
            o = d.decide()
            got.append((o.equivalent, o.exhaustive, o.runs, o.states, o.plan, o.ticks))
        assert got[0] == got[1] == got[2], (old, new)


# ---------------------------------------------------------------- Nav2 distros (--models-old/--models-new)
def test_nav2_round_robin_from_jazzy_to_lyrical(capsys, tmp_path):
    """Nav2's rename table (lang/nav2.py RENAMES): RoundRobin always wrapped around before
    lyrical, where `wrap_around` defaults to false; written `wrap_around="true"` the tree keeps
    jazzy's behaviour. Lyrical's Spin also has a new input port (disable_collision_checks), so
    the calls compare without their inputs here."""
    models = ROOT / "tests" / "nav2_models"
    paths = []
    for k, wrap in enumerate(("", ' wrap_around="true"')):
        p = tmp_path / f"rr{k}.xml"
        p.write_text(
            '<root BTCPP_format="4" main_tree_to_execute="Main">\n  <BehaviorTree ID="Main">\n'
            f"    <RoundRobin{wrap}><Spin/><Wait/></RoundRobin>\n  </BehaviorTree>\n</root>\n"
        )
        paths.append(str(p))
    sides = ["--btcpp", "4.10.0", "--models-old", str(models / "jazzy" / "nav2_tree_nodes.xml")]
    sides += ["--models-new", str(models / "lyrical" / "nav2_tree_nodes.xml")]
    rc, report, _ = _diff(capsys, paths[0], paths[0], *sides)
    assert rc == 1 and "disable_collision_checks=false" in report["first_difference"]["new"]
    cx = tmp_path / "cx"
    rc, report, _ = _diff(
        capsys, paths[0], paths[0], *sides, "--observe", "leaf-calls,root,writes", "--counterexample", str(cx)
    )
    assert rc == 1
    assert report["first_difference"] == {"tick": 1, "event": 3, "old": "result SUCCESS", "new": "result FAILURE"}
    # the written scenario on both engines, each distro's models: jazzy succeeds, lyrical fails
    for stem, distro, result in (("old", "jazzy", "SUCCESS"), ("new", "lyrical", "FAILURE")):
        extra = ["--models", str(models / distro / "nav2_tree_nodes.xml")]
        interp = _run(paths[0], str(cx / f"{stem}.scenario"), "interp", "4.10.0", extra)
        assert interp == _run(paths[0], str(cx / f"{stem}.scenario"), "cpp", "4.10.0", extra)
        assert interp.rstrip().endswith(f"result {result}")
    rc, report, _ = _diff(capsys, paths[0], paths[1], *sides, "--observe", "leaf-calls,root,writes")
    assert rc == 0 and report["exhaustive"] is True
