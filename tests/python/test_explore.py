"""`btgen explore`: the scenarios it writes reach the coverage it claims, on both engines; its
most-per-tick matches `btgen analyze`'s bound; properties give counterexamples that replay."""

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

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "tests" / "analyze"
PICK = ROOT / "missions" / "PickPlaceBall.xml"


def _explore(capsys, *argv: str) -> tuple[int, dict, str]:
    rc = main(["explore", "--json", *argv])
    out, err = capsys.readouterr()
    return rc, json.loads(out), err


def _analyze(capsys, mission: Path) -> dict:
    assert main(["analyze", "--json", str(mission)]) == 0
    return json.loads(capsys.readouterr().out)


def _trace_coverage(trace: str) -> set:
    """Nodes and statuses a trace shows (SKIPPED is never stored, so it never shows)."""
    seen: set = set()
    for line in trace.splitlines():
        parts = line.split()
        if len(parts) >= 4 and parts[0].isdigit() and parts[-2] == "->" and parts[-1] != "IDLE":
            seen.add(("node", int(parts[0])))
            seen.add(("outcome", int(parts[0]), parts[-1]))
    return seen


@pytest.mark.parametrize("mission", ["cost.xml", "unreachable.xml", "data.xml"])
def test_most_per_tick_reached_is_the_analyze_bound(capsys, mission):
    path = CASES / mission
    bound = _analyze(capsys, path)["worst_tick"]
    rc, report, _ = _explore(capsys, "--no-merge", "--ticks", "4", str(path))
    assert rc == 0
    assert report["max_nodes_visited_per_tick"] == bound["nodes_visited"]
    assert report["max_leaf_hooks_per_tick"] == bound["leaf_hooks"]
    assert report["covered"] == report["goals"]


def _check_scenarios(capsys, mission: Path, tmp_path: Path) -> tuple[dict, list[Path]]:
    out = tmp_path / "scenarios"
    rc, report, _ = _explore(capsys, "--ticks", "6", "-o", str(out), str(mission))
    assert rc == 0 and report["covered"] == report["goals"] and not report["uncovered"]
    files = sorted(out.glob("*.scenario"))
    assert len(files) == report["scenarios"] >= 1
    return report, files


def test_scenarios_cover_every_node_on_the_interpreter(capsys, tmp_path):
    for mission in (CASES / "cost.xml", CASES / "data.xml", CASES / "unreachable.xml"):
        report, files = _check_scenarios(capsys, mission, tmp_path / mission.stem)
        m = load_mission(str(mission), (), None)
        covered: set = set()
        for f in files:
            covered |= _trace_coverage(trace_text(m, parse_scenario(str(f))))
        ticked = {g[1] for g in covered if g[0] == "node"}
        assert len(ticked) == report["nodes_covered"] == report["node_goals"]


def test_scenarios_replay_identically_on_the_cpp_engine(capsys, tmp_path):
    report, files = _check_scenarios(capsys, PICK, tmp_path)
    m = load_mission(str(PICK), (), None)
    covered: set = set()
    for f in files:
        expected = trace_text(m, parse_scenario(str(f)))
        got = subprocess.run(
            [sys.executable, "-m", "btgen", "run", str(PICK), "--scenario", str(f), "--engine", "cpp"],
            capture_output=True,
            text=True,
            check=False,
        )
        assert got.returncode == 0, got.stderr
        assert got.stdout == expected
        covered |= _trace_coverage(got.stdout)
    assert len({g[1] for g in covered if g[0] == "node"}) == 7
    # every status of every node (none of this mission's nodes can be SKIPPED)
    assert len([g for g in covered if g[0] == "outcome"]) == report["goals"] - 7


def test_property_counterexample_replays(capsys, tmp_path):
    out = tmp_path / "cx"
    rc, report, err = _explore(
        capsys, "--assert", "never PlaceBall SUCCESS before FindBall FAILURE", "-o", str(out), str(PICK)
    )
    assert rc == 1
    assert report["violations"] == ["never PlaceBall SUCCESS before FindBall FAILURE"]
    cx = out / "counterexample-1.scenario"
    trace = trace_text(load_mission(str(PICK), (), None), parse_scenario(str(cx)))
    assert '7 PlaceBall "PlaceBall" IDLE -> SUCCESS' in trace
    assert "FindBall IDLE -> FAILURE" not in trace.replace('"FindBall" ', "")
    assert err == ""  # the counterexample is in the report (stdout), not mixed with warnings
    [prop] = report["properties"]
    assert prop["result"] == "violated" and prop["file"] == str(cx)
    assert prop["scenario"] == cx.read_text() and '7 PlaceBall "PlaceBall" IDLE -> SUCCESS' in prop["trace"]
    # a property that holds
    rc, report, _ = _explore(capsys, "--assert", "never PickBall SUCCESS before FindBall SUCCESS", str(PICK))
    assert rc == 0 and report["violations"] == []
    rc, report, _ = _explore(capsys, "--assert", "at most one child of PickMovePlace RUNNING", str(PICK))
    assert rc == 0 and report["violations"] == []


def test_output_folder(capsys, tmp_path):
    out = tmp_path / "sc"
    out.mkdir()
    # a file named as explore names its own, which no exploration wrote: the user's, kept
    (out / "PickPlaceBall-099.scenario").write_text("ticks 1\n")
    (out / "mine.scenario").write_text("ticks 1\n")
    rc, _, _ = _explore(
        capsys, "-o", str(out), "--assert", "never PlaceBall SUCCESS before FindBall FAILURE", str(PICK)
    )
    assert rc == 1 and (out / "counterexample-1.scenario").is_file()
    # a later exploration removes exactly what the earlier one wrote and it does not (its manifest)
    rc, report, _ = _explore(capsys, "-o", str(out), str(PICK))
    assert rc == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(
        [f"PickPlaceBall-{i:03d}.scenario" for i in range(1, report["scenarios"] + 1)]
        + ["mine.scenario", "PickPlaceBall-099.scenario", ".PickPlaceBall.btgen-explore"]
    )
    blocked = tmp_path / "file"
    blocked.write_text("")
    assert main(["explore", "-o", str(blocked / "sub"), str(PICK)]) == 1
    assert capsys.readouterr().err.startswith(f"{blocked / 'sub'}:1:1: error: cannot create the output folder")


def test_run_time_errors_are_findings(capsys, tmp_path):
    mission = tmp_path / "err.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">\n'
        '<Sequence><Script code="n := 0"/><Fallback><Act/>\n'
        '<Script name="Oops" code="n := n + missing"/></Fallback></Sequence>\n'
        '</BehaviorTree><TreeNodesModel><Action ID="Act"/></TreeNodesModel></root>\n'
    )
    rc, report, err = _explore(capsys, "-o", str(tmp_path / "out"), str(mission))
    assert rc == 1
    assert report["run_time_errors"] == [
        f'{mission}:3:36: error: script error in `code` of `Script` "Oops": unknown variable `missing` '
        "(no blackboard entry of that name; create it with `missing := ...`)"
    ]
    text = (tmp_path / "out" / "error-1.scenario").read_text()
    assert "leaf Act FAILURE" in text


def test_bad_property_is_a_usage_error(capsys):
    assert main(["explore", "--assert", "sometimes X", str(PICK)]) == 1
    assert "unknown property" in capsys.readouterr().err
    assert main(["explore", "--assert", "never Nobody SUCCESS", str(PICK)]) == 1
    assert "no node is named `Nobody`" in capsys.readouterr().err


LAB = ROOT / "missions" / "LabTour.xml"
RECEPTION = ROOT / "missions" / "Reception.xml"


LOOP = """<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">
  <Sequence>
    <SetBlackboard output_key="q" value="1;2;3"/>
    <Parallel success_count="2" failure_count="2">
      <LoopInt queue="{q}" value="{v}"><Act/></LoopInt>
      <Repeat num_cycles="3"><Check/></Repeat>
    </Parallel>
  </Sequence>
</BehaviorTree>
<TreeNodesModel><Action ID="Act"/><Condition ID="Check"/></TreeNodesModel></root>
"""


@pytest.mark.parametrize("btcpp", ["4.6.2", "4.10.0"])
def test_a_loops_queue_and_a_parallels_set_are_restored(btcpp, tmp_path):
    # state held in mutable objects (a Loop's queue, a Parallel's set of completed children)
    mission = tmp_path / "loop.xml"
    mission.write_text(LOOP)
    test_playing_on_from_a_tick_start_changes_nothing(mission, 10**6, btcpp)


@pytest.mark.parametrize("mission,bound", [(LAB, 1500), (RECEPTION, 400), (CASES / "data.xml", 10**6)])
def test_playing_on_from_a_tick_start_changes_nothing(mission, bound, btcpp="4.6.2"):
    """Each run is played on from the last tick start it shares with the run before (the
    interpreter's state saved there and restored); the same search from tick 1 on a restored
    initial state, and the covering scenarios replayed on fresh interpreters, agree with it."""
    from btgen.tools.explore import Explorer, _possible

    m = load_mission(str(mission), (), None, btcpp=btcpp)

    class Args:
        string_capacity = queue_capacity = None
        sync: list = []

    results = []
    for resume in (True, False):
        ex = Explorer(m, 8, 200, 100, bound, (), _possible(m, Args()))
        ex.resume = resume
        results.append(ex.explore())
    fast, slow = results
    assert (fast.runs, fast.states, fast.covered, fast.truncated) == (
        slow.runs,
        slow.states,
        slow.covered,
        slow.truncated,
    )
    assert [p.picks for p in fast.paths] == [p.picks for p in slow.paths]
    from btgen.diagnostics import UserError
    from btgen.interp.engine import run_trace
    from btgen.tools.explore import scenario_text

    for path in fast.paths:
        if path.end == "error":  # its node erred when ticked: ticked, though no trace line shows it
            with pytest.raises(UserError):
                trace_text(m, parse_scenario_text_of(scenario_text(path, 100)))
            continue
        parts: list = []
        run_trace(m, parse_scenario_text_of(scenario_text(path, 100)), parts.append)
        replayed = _trace_coverage("".join(parts))
        claimed = {
            g if g[0] == "node" else ("outcome", g[1], _NAME[g[2]]) for g in path.goals if g[0] == "node" or g[2] != 4
        }
        assert claimed <= replayed


_NAME = {1: "RUNNING", 2: "SUCCESS", 3: "FAILURE"}


def parse_scenario_text_of(text):
    from btgen.interp.scenario import parse_scenario_text

    return parse_scenario_text(text, "<scenario>")


def test_holds_lines_say_how_far_the_search_went(capsys):
    prop = "never PickBall SUCCESS before FindBall SUCCESS"
    assert main(["explore", "--assert", prop, str(PICK)]) == 0
    out = capsys.readouterr().out
    assert f"  assert `{prop}`: holds (16 states, exhaustive)\n" in out
    assert main(["explore", "--assert", prop, "--ticks", "2", str(PICK)]) == 0
    out = capsys.readouterr().out
    assert f"  assert `{prop}`: holds (" in out and "states, bounded by --ticks 2)\n" in out
    assert main(["explore", "--assert", prop, "--max-states", "3", str(PICK)]) == 0
    assert f"  assert `{prop}`: holds (3 states, bounded by --max-states 3)\n" in capsys.readouterr().out


def test_stop_at_the_first_violation_unless_keep_going(capsys):
    bad, good = "never PlaceBall SUCCESS before FindBall FAILURE", "never PickBall SUCCESS before FindBall SUCCESS"
    argv = ["explore", "--assert", bad, "--assert", good, str(PICK)]
    assert main(argv) == 1
    captured = capsys.readouterr()
    assert captured.err == ""
    out = captured.out
    assert f"  assert `{bad}`: violated (counterexample below)\n" in out
    assert f"  assert `{good}`: not decided: the search stopped at the first violation (--keep-going goes on)\n" in out
    assert f"  counterexample of `{bad}`\n    scenario:\n" in out and "    trace:\n      tick 1\n" in out
    assert "not reached" not in out
    assert main([*argv, "--keep-going"]) == 1
    out = capsys.readouterr().out
    assert f"  assert `{bad}`: violated (counterexample below)\n" in out
    assert f"  assert `{good}`: holds (" in out and "uncovered" not in out


def test_a_violated_goal_is_not_reported_unreached(capsys):
    rc, report, _ = _explore(capsys, "--keep-going", "--assert", "never FindBall FAILURE", str(PICK))
    assert rc == 1 and report["violations"] == ["never FindBall FAILURE"]
    assert '3 FindBall "FindBall" FAILURE' not in report["uncovered"]
    assert report["covered"] == report["goals"]


def test_progress_only_on_a_terminal(tmp_path):
    import os
    import pty

    argv = [sys.executable, "-m", "btgen", "explore", str(LAB), "--max-states", "600"]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "generator"))
    plain = subprocess.run(argv, capture_output=True, text=True, env=env, check=False)
    assert plain.stderr == ""
    master, slave = pty.openpty()
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=slave, env=env)
    os.close(slave)
    seen = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk
    proc.wait(timeout=300)
    os.close(master)
    text = seen.decode()
    assert "explore [" in text and "goals, " in text and "states/s, " in text and "\r" in text
    assert text.endswith("\r\x1b[K")  # the line is cleared before the report
