"""Scenario files (FORMAT.md): the parsed model, and every error with its exact message.

Errors must stop `btgen run` before any trace line: exit status 1, nothing on
stdout, `path:line:col: error: ...` on stderr. A `leaf` line naming no leaf
of the mission is only a warning.
"""

import dataclasses
import os
import subprocess
import sys

import pytest

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.scenario import (
    DEFAULT_TICKS,
    check_scenario,
    load_scenario,
    mission_leaves,
    parse_scenario,
    parse_scenario_text,
)
from conftest import ROOT

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <IsReady/>
      <Move name="MoveFast"/>
      <SubTree ID="Sub"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Sub">
    <Fallback>
      <IsReady name="ReadyAgain"/>
      <AlwaysSuccess name="Fine"/>
    </Fallback>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Move"/>
    <Condition ID="IsReady"/>
  </TreeNodesModel>
</root>
"""


@pytest.fixture
def mission_path(tmp_path):
    p = tmp_path / "m.xml"
    p.write_text(MISSION, encoding="utf-8")
    return p


def run_cli(tmp_path, scenario_text, mission="m.xml"):
    (tmp_path / "s.scenario").write_text(scenario_text, encoding="utf-8")
    return subprocess.run(
        [sys.executable, "-m", "btgen", "run", mission, "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONPATH": os.path.join(ROOT, "generator")},
        check=False,
    )


# ---------------------------------------------------------------- parsing
def test_defaults():
    s = parse_scenario_text("# nothing but a comment\n\n", "x.scenario")
    assert (s.ticks, s.default, s.leaves, s.clock_ms) == (DEFAULT_TICKS, "SUCCESS", (), 0)
    assert DEFAULT_TICKS == 100


def test_full_file_model():
    s = parse_scenario_text(
        "ticks 20   # most ticks\n"
        "default FAILURE\n"
        "\tleaf FindBall FAILURE SUCCESS # trailing comment\n"
        "leaf PickBall RUNNING RUNNING SUCCESS\r\n"
        "clock_ms 100\n",
        "x.scenario",
    )
    assert s.ticks == 20 and s.default == "FAILURE" and s.clock_ms == 100
    assert [(leaf.name, leaf.statuses) for leaf in s.leaves] == [
        ("FindBall", ("FAILURE", "SUCCESS")),
        ("PickBall", ("RUNNING", "RUNNING", "SUCCESS")),
    ]
    find = s.leaf("FindBall")
    assert (find.loc.line, find.loc.col) == (3, 7)
    assert [(loc.line, loc.col) for loc in find.status_locs] == [(3, 16), (3, 24)]
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.ticks = 3  # frozen


def test_hash_starts_a_comment_anywhere():
    s = parse_scenario_text("leaf A SUCCESS#FAILURE\n", "x.scenario")
    assert s.leaf("A").statuses == ("SUCCESS",)


ERRORS = [
    (
        "unknown keyword",
        "ticks 3\ntick 4\n",
        "s.scenario:2:1: error: unknown keyword `tick`: a line starts with ticks, default, leaf, clock_ms or queue "
        "(did you mean `ticks`?)",
    ),
    ("repeated ticks", "ticks 2\n\nticks 3\n", "s.scenario:3:1: error: `ticks` is given twice (first at line 1)"),
    (
        "repeated default",
        "default FAILURE\ndefault SUCCESS\n",
        "s.scenario:2:1: error: `default` is given twice (first at line 1)",
    ),
    (
        "repeated leaf",
        "leaf MoveFast RUNNING\nleaf MoveFast SUCCESS\n",
        "s.scenario:2:6: error: leaf `MoveFast` is listed twice (first at line 1)",
    ),
    (
        "leaf without status",
        "leaf MoveFast   # nothing\n",
        "s.scenario:1:6: error: leaf `MoveFast` has no status: list one or more of SUCCESS, FAILURE, RUNNING",
    ),
    ("leaf without name", "leaf\n", "s.scenario:1:1: error: `leaf` needs a leaf name and at least one status"),
    ("ticks zero", "ticks 0\n", "s.scenario:1:7: error: ticks must be at least 1, got 0"),
    ("ticks negative", "ticks -3\n", "s.scenario:1:7: error: ticks must be at least 1, got -3"),
    ("ticks not a number", "ticks many\n", "s.scenario:1:7: error: `ticks` needs a whole number, got `many`"),
    ("ticks missing", "ticks\n", "s.scenario:1:1: error: `ticks` needs a whole number (the most root ticks to send)"),
    ("ticks two numbers", "ticks 2 3\n", "s.scenario:1:9: error: `ticks` takes one number, found also `3`"),
    (
        "unknown status",
        "leaf MoveFast SUCCESS DONE\n",
        "s.scenario:1:23: error: unknown status `DONE`: use SUCCESS, FAILURE or RUNNING",
    ),
    (
        "lower-case status",
        "default success\n",
        "s.scenario:1:9: error: unknown status `success`: use SUCCESS, FAILURE or RUNNING (did you mean `SUCCESS`?)",
    ),
    (
        "SKIPPED is no leaf result",
        "leaf MoveFast SKIPPED\n",
        "s.scenario:1:15: error: `SKIPPED` cannot be scripted: a leaf returns SUCCESS, FAILURE or RUNNING",
    ),
    (
        "default without status",
        "default\n",
        "s.scenario:1:1: error: `default` needs a status: SUCCESS, FAILURE or RUNNING",
    ),
    ("negative clock", "clock_ms -1\n", "s.scenario:1:10: error: clock_ms cannot be negative, got -1"),
    (
        "repeated clock",
        "clock_ms 10\nclock_ms 20\n",
        "s.scenario:2:1: error: `clock_ms` is given twice (first at line 1)",
    ),
    (
        "scripted RUNNING Condition",
        "leaf IsReady SUCCESS RUNNING\n",
        "s.scenario:1:22: error: `IsReady` is a Condition and cannot return RUNNING (a Condition answers in one "
        "tick; its Condition node is at m.xml:4:7)",
    ),
    (
        "default RUNNING reaching Conditions",
        "ticks 3\ndefault RUNNING\n",
        "s.scenario:2:9: error: `default RUNNING` reaches the Conditions `IsReady` (m.xml:4:7), `ReadyAgain` "
        "(m.xml:11:7), which cannot return RUNNING; give each its own `leaf` line",
    ),
    (
        "default RUNNING reaching one Condition",
        "default RUNNING\nleaf IsReady FAILURE\n",
        "s.scenario:1:9: error: `default RUNNING` reaches the Condition `ReadyAgain` (m.xml:11:7), which cannot "
        "return RUNNING; give it its own `leaf` line",
    ),
]


@pytest.mark.parametrize("what,text,message", ERRORS, ids=[e[0] for e in ERRORS])
def test_error_stops_before_any_trace(tmp_path, mission_path, what, text, message):
    proc = run_cli(tmp_path, text)
    assert proc.returncode == 1, proc.stderr
    assert proc.stdout == ""
    assert proc.stderr.splitlines() == [message]


@pytest.mark.parametrize("what,text,message", ERRORS, ids=[e[0] for e in ERRORS])
def test_error_in_process(tmp_path, mission_path, what, text, message):
    path = tmp_path / "s.scenario"
    path.write_text(text, encoding="utf-8")
    mission = load_mission(str(mission_path))
    with pytest.raises(UserError) as e:
        load_scenario(str(path), mission)
    got = [str(d) for d in e.value.diagnostics]
    assert got == [message.replace("s.scenario", str(path)).replace("m.xml", str(mission_path))]


def test_all_errors_of_a_file_reported_together(tmp_path, mission_path):
    proc = run_cli(tmp_path, "ticks 0\nbogus 1\nleaf X\n")
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.splitlines() == [
        "s.scenario:1:7: error: ticks must be at least 1, got 0",
        "s.scenario:2:1: error: unknown keyword `bogus`: a line starts with ticks, default, leaf, clock_ms or queue",
        "s.scenario:3:6: error: leaf `X` has no status: list one or more of SUCCESS, FAILURE, RUNNING",
    ]


def test_unknown_leaf_is_only_a_warning(tmp_path, mission_path):
    proc = run_cli(tmp_path, "ticks 1\nleaf Movefast FAILURE\n")
    assert proc.returncode == 0
    assert proc.stderr.splitlines() == [
        "s.scenario:2:6: warning: leaf `Movefast` matches no Action or Condition of the mission; its line is "
        "ignored (did you mean `MoveFast`?)"
    ]
    assert proc.stdout.startswith('tick 1\n1 Sequence "Sequence" IDLE -> RUNNING\n')
    assert proc.stdout.endswith("result SUCCESS\n")  # MoveFast was not made to fail


def test_builtin_leaf_keeps_its_behaviour(tmp_path, mission_path):
    proc = run_cli(tmp_path, "ticks 1\nleaf Fine FAILURE\n")
    assert proc.returncode == 0
    assert proc.stderr.splitlines() == [
        "s.scenario:2:6: warning: `Fine` is a built-in node of BehaviorTree.CPP and keeps its built-in "
        "behaviour; its line is ignored"
    ]
    assert '6 AlwaysSuccess "Fine"' not in proc.stdout  # the Fallback stops at its first child
    assert proc.stdout.endswith("result SUCCESS\n")


def test_scripted_condition_failure_is_fine(tmp_path, mission_path):
    proc = run_cli(tmp_path, "ticks 2\nleaf IsReady FAILURE\n")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[-1] == "result FAILURE"


def test_missing_scenario_file(tmp_path, mission_path):
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "m.xml", "--scenario", "nope.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.splitlines() == ["nope.scenario:1:1: error: cannot read scenario: No such file or directory"]


def test_invalid_utf8(tmp_path, mission_path):
    (tmp_path / "s.scenario").write_bytes(b"ticks 2\nleaf Mo\xffve SUCCESS\n")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "m.xml", "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.splitlines() == ["s.scenario:2:8: error: invalid UTF-8 (byte 0xff); scenarios must be UTF-8"]


def test_mission_errors_come_first(tmp_path):
    (tmp_path / "bad.xml").write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><Nope/></BehaviorTree></root>')
    (tmp_path / "s.scenario").write_text("ticks 0\n")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "bad.xml", "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr.startswith("bad.xml:1:")


def test_leaves_of_the_mission(mission_path):
    mission = load_mission(str(mission_path))
    assert [(u.name, u.kind) for u in mission_leaves(mission)] == [
        ("IsReady", "Condition"),
        ("MoveFast", "Action"),
        ("ReadyAgain", "Condition"),
    ]


def test_parse_scenario_reads_files(tmp_path):
    p = tmp_path / "a.scenario"
    p.write_bytes(b"\xef\xbb\xbfticks 7\n")  # a BOM is tolerated
    assert parse_scenario(str(p)).ticks == 7


def test_check_returns_warnings(tmp_path, mission_path):
    mission = load_mission(str(mission_path))
    s = parse_scenario_text("leaf Ghost SUCCESS\nleaf MoveFast RUNNING\n", "x.scenario")
    assert [str(d) for d in check_scenario(s, mission)] == [
        "x.scenario:1:6: warning: leaf `Ghost` matches no Action or Condition of the mission; its line is ignored"
    ]


def test_leaf_of_a_tree_the_main_tree_does_not_run(tmp_path):
    (tmp_path / "m.xml").write_text(
        MISSION.replace("</root>", '  <BehaviorTree ID="Spare"><Move name="Dance"/></BehaviorTree>\n</root>')
    )
    proc = run_cli(tmp_path, "ticks 1\nleaf Dance RUNNING\n")
    assert proc.returncode == 0
    assert proc.stderr.splitlines() == [
        "s.scenario:2:6: warning: leaf `Dance` is only in BehaviorTree `Spare`, which the main tree `Main` does "
        "not run; its line is ignored"
    ]
