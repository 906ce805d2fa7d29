"""`btgen run --substitute`: BehaviorTree.CPP's JSON substitution rules on the interpreter."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from btgen.cli import main

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Find/>
      <SubTree ID="Arm" name="arm"/>
      <ScriptCondition name="Check" code="found == 1 &amp;&amp; calls == 2"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Arm">
    <Sequence>
      <Grab name="grab_left"/>
      <Grab name="grab_right"/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Find"/>
    <Action ID="Grab"/>
  </TreeNodesModel>
</root>
"""


def _run(capsys, tmp_path: Path, rules: str, scenario: str = "ticks 10\nclock_ms 100\n") -> tuple[int, str, str]:
    (tmp_path / "m.xml").write_text(MISSION)
    (tmp_path / "s.scenario").write_text(scenario)
    (tmp_path / "r.json").write_text(rules)
    rc = main(
        [
            "run",
            str(tmp_path / "m.xml"),
            "--scenario",
            str(tmp_path / "s.scenario"),
            "--substitute",
            str(tmp_path / "r.json"),
        ]
    )
    out, err = capsys.readouterr()
    return rc, out, err


RULES = """{
  "TestNodeConfigs": {
    "Slow": {"return_status": "SUCCESS", "async_delay": 250,
             "success_script": "found := 1", "post_script": "calls := 1"},
    "Quick": {"return_status": "SUCCESS", "post_script": "@calls := @calls + 1"}
  },
  "SubstitutionRules": {
    "Find": "Slow",
    "arm/grab_r*": "Quick",
    "Nothing": "AlwaysFailure"
  }
}
"""


def test_test_nodes_delay_and_scripts(capsys, tmp_path):
    rc, out, err = _run(capsys, tmp_path, RULES, "ticks 10\nclock_ms 100\nleaf grab_left SUCCESS\n")
    assert rc == 0, err
    lines = out.splitlines()
    # Find is RUNNING from tick 1 (t=0) until the first tick at or after 250 ms: tick 4 (t=300)
    assert lines[:4] == [
        "tick 1",
        '1 Sequence "Sequence" IDLE -> RUNNING',
        '2 Find "Find" IDLE -> RUNNING',
        "result RUNNING",
    ]
    assert lines.index("tick 4") < lines.index('2 Find "Find" RUNNING -> SUCCESS')
    # grab_right (path arm/grab_right) is the Quick TestNode: its post_script makes calls 2, so Check succeeds
    assert '7 ScriptCondition "Check" IDLE -> SUCCESS' in lines and lines[-1] == "result SUCCESS"
    assert f"{tmp_path / 'r.json'}:10:5: warning: the rule `Nothing` matches no node of the mission" in err


def test_rule_by_id_to_a_builtin(capsys, tmp_path):
    rules = '{"TestNodeConfigs": {}, "SubstitutionRules": {"Grab": "AlwaysFailure"}}'
    rc, out, _ = _run(capsys, tmp_path, rules, "ticks 3\n")
    assert rc == 0
    # the node keeps its registration ID and name in the trace, as setRegistrationID keeps them
    assert '5 Grab "grab_left" IDLE -> FAILURE' in out.splitlines()
    assert out.splitlines()[-1] == "result FAILURE"


def test_bad_rules_are_located(capsys, tmp_path):
    rc, _, err = _run(
        capsys, tmp_path, '{"TestNodeConfigs": {"A": {"return_status": "IDLE"}},\n "SubstitutionRules": {}}'
    )
    assert rc == 1 and err.startswith(f'{tmp_path / "r.json"}:1:45: error: `return_status` of `A` is "IDLE"')
    rc, _, err = _run(capsys, tmp_path, '{"TestNodeConfigs": {,}')
    assert rc == 1 and err.startswith(f"{tmp_path / 'r.json'}:1:22: error: invalid JSON: Expecting property name")
    rc, _, err = _run(capsys, tmp_path, '{"TestNodeConfigs": {}, "SubstitutionRules": {"Seq*": "AlwaysSuccess"}}')
    assert rc == 1 and 'matches `Sequence` "Sequence"' in err and "only leaves can be substituted" in err
    bad_script = (
        '{"TestNodeConfigs": {"B": {"return_status": "SUCCESS", "post_script": "x :="}}, "SubstitutionRules": {}}'
    )
    rc, _, err = _run(capsys, tmp_path, bad_script)
    assert rc == 1 and "`post_script` of `B`" in err and "Traceback" not in err


def test_json_that_is_not_an_object(capsys, tmp_path):
    for text in ("[1, 2]", '{"TestNodeConfigs": [1], "SubstitutionRules": {}}', '{"SubstitutionRules": {"a": 3}}'):
        rc, _, err = _run(capsys, tmp_path, text)
        assert rc == 1 and ": error: " in err and "Traceback" not in err


def test_both_engines_agree(capsys, tmp_path):
    """The compiled test build (`compile --substitute`) runs the same trace as the interpreter."""
    (tmp_path / "m.xml").write_text(MISSION)
    (tmp_path / "s.scenario").write_text("ticks 10\nclock_ms 100\nleaf grab_left RUNNING SUCCESS\n")
    (tmp_path / "r.json").write_text(RULES)
    argv = [
        str(tmp_path / "m.xml"),
        "--scenario",
        str(tmp_path / "s.scenario"),
        "--substitute",
        str(tmp_path / "r.json"),
    ]
    assert main(["run", *argv]) == 0
    expected = capsys.readouterr().out
    assert '7 ScriptCondition "Check" IDLE -> SUCCESS' in expected
    got = subprocess.run(
        [sys.executable, "-m", "btgen", "run", *argv, "--engine", "cpp"], capture_output=True, text=True, check=False
    )
    assert got.returncode == 0, got.stderr
    assert got.stdout == expected
    assert (
        main(
            ["compile", str(tmp_path / "m.xml"), "-o", str(tmp_path / "out"), "--substitute", str(tmp_path / "r.json")]
        )
        == 0
    )
    header = (tmp_path / "out" / "m.hpp").read_text()
    assert "NodeKind::Sleep" in header and '"Find"' in header


def test_compile_refuses_what_it_cannot_build(capsys, tmp_path):
    (tmp_path / "m.xml").write_text(MISSION)
    (tmp_path / "r.json").write_text(
        '{"TestNodeConfigs": {"Late": {"return_status": "FAILURE", "async_delay": 5}},\n'
        ' "SubstitutionRules": {"Find": "Late"}}'
    )
    assert (
        main(
            ["compile", str(tmp_path / "m.xml"), "-o", str(tmp_path / "out"), "--substitute", str(tmp_path / "r.json")]
        )
        == 1
    )
    err = capsys.readouterr().err
    assert err.startswith(f"{tmp_path / 'r.json'}:2:24: error: `Late` fails after a delay")
    (tmp_path / "r.json").write_text('{"TestNodeConfigs": {}, "SubstitutionRules": {"arm/grab_left": "AlwaysFailure"}}')
    (tmp_path / "m2.xml").write_text(
        MISSION.replace(
            '<SubTree ID="Arm" name="arm"/>', '<SubTree ID="Arm" name="arm"/><SubTree ID="Arm" name="arm2"/>'
        )
    )
    assert (
        main(
            ["compile", str(tmp_path / "m2.xml"), "-o", str(tmp_path / "out"), "--substitute", str(tmp_path / "r.json")]
        )
        == 1
    )
    assert "is substituted in some SubTree instances and not in others" in capsys.readouterr().err


def test_provided_entries_exist_under_substitution(capsys, tmp_path):
    """The main tree's --entry entries are created (empty) with or without rules, as in a plain run."""
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">'
        '<Sequence><Find/><Script code="twice := timeout * 2"/></Sequence>'
        '</BehaviorTree><TreeNodesModel><Action ID="Find"/></TreeNodesModel></root>'
    )
    (tmp_path / "s.scenario").write_text("ticks 1\n")
    (tmp_path / "r.json").write_text('{"TestNodeConfigs": {}, "SubstitutionRules": {"Find": "AlwaysSuccess"}}')
    argv = ["run", str(tmp_path / "m.xml"), "--scenario", str(tmp_path / "s.scenario"), "--entry", "timeout=int"]
    assert main(argv) == 1
    plain = capsys.readouterr()
    assert "the left operand of `*` has no value" in plain.err
    assert main([*argv, "--substitute", str(tmp_path / "r.json")]) == 1
    assert capsys.readouterr() == plain
