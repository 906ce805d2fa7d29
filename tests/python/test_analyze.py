"""`btgen analyze` on missions whose answers are known by hand (tests/analyze/*.xml say why)."""

from __future__ import annotations

import json
from pathlib import Path

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "tests" / "analyze"


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    rc = main(["analyze", *argv])
    out, err = capsys.readouterr()
    return rc, out, err


def _json(capsys, path: Path, *extra: str) -> dict:
    rc, out, _ = _run(capsys, "--json", str(path), *extra)
    assert rc == 0
    return json.loads(out)


def test_unreachable_children_and_constant_subtree_guards(capsys):
    path = CASES / "unreachable.xml"
    rc, out, err = _run(capsys, str(path))
    assert rc == 0
    lines = err.splitlines()
    assert (
        f'{path}:9:11: warning: `Act` "Never" can never be ticked: `Fallback` "Fallback" never gets past '
        '`AlwaysSuccess` "AlwaysSuccess" (line 8), which never returns FAILURE or SKIPPED'
    ) in lines
    assert any(
        line.startswith(f'{path}:19:7: warning: `Act` "Fire" can never be ticked (in SubTree instance `Disarmed`)')
        for line in lines
    )
    always = '`code` of `ScriptCondition` "ScriptCondition" is always'
    assert f"{path}:18:30: warning: {always} false in SubTree instance `Disarmed`" in lines
    assert len([line for line in lines if "can never be ticked" in line]) == 2
    doc = _json(capsys, path)
    assert doc["unreachable_nodes"] == 2  # Never, and Fire of the Disarmed instance
    # the Disarmed instance always fails, so the root Fallback always reaches Armed
    assert set(doc["root_outcomes"]) == {"SUCCESS", "FAILURE", "RUNNING"}


def test_worst_tick_is_composed_per_outcome(capsys):
    doc = _json(capsys, CASES / "cost.xml")
    assert doc["worst_tick"] == {"nodes_visited": 9, "leaf_hooks": 4, "script_evaluations": 2, "unbounded_by": None}
    # Repeat num_cycles=-1 never succeeds, so neither does the root Sequence
    assert set(doc["root_outcomes"]) == {"FAILURE", "RUNNING"}


def test_tick_budget_and_werror(capsys):
    rc, _, err = _run(capsys, "--tick-budget", "8", "--werror", str(CASES / "cost.xml"))
    assert rc == 1
    assert "a tick can take 9 nodes visited, over the budget of 8" in err
    assert "leaf hooks" not in err
    rc, _, err = _run(capsys, "--tick-budget", "9", str(CASES / "cost.xml"))
    assert rc == 0 and "budget" not in err


def test_blackboard_and_reactive_findings(capsys):
    path = CASES / "data.xml"
    rc, _, err = _run(capsys, str(path))
    assert rc == 0
    lines = err.splitlines()
    expected = [
        f'{path}:7:18: warning: blackboard entry `goal` is read by `Use` "Use" before anything can have written '
        'it: its first writer `Make` "Make" (line 8) runs later',
        f'{path}:8:32: warning: blackboard entry `log` is written by `Make` "Make" but never read by the mission',
        f'{path}:11:18: warning: blackboard entry `ext` is read by `Use` "Use" but no node of the mission writes '
        "it (the application must set it before the first tick)",
        f'{path}:10:22: warning: blackboard entry `count` is read as `int` by `UseInt` "UseInt" and as `string` '
        'by `UseText` "UseText" (line 20)',
    ]
    for line in expected:
        assert line in lines
    reactive = [line for line in lines if "can both return RUNNING" in line]
    assert len(reactive) == 1 and reactive[0].startswith(f'{path}:15:9: warning: `Make` "Slow2" and `Make` "Slow1"')
    rc, _, _ = _run(capsys, "--werror", str(path))
    assert rc == 1
    # an entry the application provides (--entry) has a value from the start
    rc, _, err = _run(capsys, "--entry", "ext=int", str(path))
    assert rc == 0 and "`ext`" not in err and "`goal` is read by" in err


def test_user_control_makes_the_tick_unbounded(capsys, tmp_path):
    mission = tmp_path / "user.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main">\n'
        "    <Sequence>\n"
        '      <Looper name="MyLoop"><Act/></Looper>\n'
        "    </Sequence>\n"
        "  </BehaviorTree>\n"
        '  <TreeNodesModel><Action ID="Act"/><Control ID="Looper"/></TreeNodesModel>\n'
        "</root>\n"
    )
    doc = _json(capsys, mission)
    assert doc["worst_tick"]["nodes_visited"] is None
    assert doc["worst_tick"]["unbounded_by"] == 2
    rc, out, err = _run(capsys, "--tick-budget", "100", str(mission))
    assert 'Looper "MyLoop" may tick its children any number of times' in err
    assert "unbounded" in out


def test_counts_read_from_the_blackboard_are_any_count(capsys, tmp_path):
    mission = tmp_path / "key.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>\n'
        '<Script code="n := 0"/><Repeat num_cycles="{n}"><Act name="A"/></Repeat>\n'
        '<Repeat name="Never" num_cycles="0"><Act name="B"/></Repeat>\n'
        '</Sequence></BehaviorTree><TreeNodesModel><Action ID="Act"/></TreeNodesModel></root>\n'
    )
    rc, _, err = _run(capsys, str(mission))
    assert rc == 0
    # a literal 0 never ticks its child; a {key} may hold any count, so A can run
    assert [line.split(": warning: ")[1][:22] for line in err.splitlines()] == ['`Act` "B" can never be']


def test_bad_mission_is_an_error_not_a_traceback(capsys, tmp_path):
    mission = tmp_path / "bad.xml"
    mission.write_text('<root BTCPP_format="4"><BehaviorTree ID="Main"><Nope/></BehaviorTree></root>\n')
    rc, _, err = _run(capsys, str(mission))
    assert rc == 1
    assert err.startswith(f"{mission}:1:") and ": error: " in err and "Traceback" not in err


def test_shipped_missions_have_no_findings(capsys):
    for name in ("LabTour.xml", "PickPlaceBall.xml", "Reception.xml"):
        rc, _, err = _run(capsys, "--werror", str(ROOT / "missions" / name))
        assert rc == 0, err


def test_memory_of_a_queue_entry(capsys, tmp_path):
    # a queue slot is sized from its capacity and element capacity; kinds are values (a
    # QueueKind, not the text "queue<int>"), and the estimate once called str methods on them
    mission = tmp_path / "queue.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>\n'
        '<SetBlackboard value="1;2;3" output_key="q"/>\n'
        '<LoopInt queue="{q}" value="{v}"><Act name="A"/></LoopInt>\n'
        '</Sequence></BehaviorTree><TreeNodesModel><Action ID="Act"/></TreeNodesModel></root>\n'
    )
    memory = _json(capsys, mission)["memory"]
    assert memory["blackboard_slots"] == 2
    # {v}: one int (16 bytes); {q}: a queue of ints, more than a scalar
    assert memory["blackboard_bytes_estimate"] > 2 * 16


def test_else_and_parallel_counts_read_from_the_blackboard_allow_what_the_library_returns(capsys):
    """A Precondition `else` or Parallel counts given as `{key}` (read on every tick): the root's
    outcomes include every result the library returned on the recorded runs of oracle-diff/."""
    folder = ROOT / "tests" / "conformance" / "oracle-diff"
    checked = 0
    for xml in sorted(folder.glob("*.xml")):
        if not xml.stem.startswith(("precondition_else_key_", "parallel_key_", "script_number_into_status")):
            continue
        outcomes = set(_json(capsys, xml)["root_outcomes"])
        for version in ("4.6.2", "4.10.0"):
            trace = (folder / version / (xml.stem + ".trace")).read_text(encoding="utf-8")
            results = {line.split()[1] for line in trace.splitlines() if line.startswith("result ")}
            assert results <= outcomes, (xml.stem, version, results, outcomes)
            checked += len(results)
    assert checked >= 6
