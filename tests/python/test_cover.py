"""`btgen cover` and `btgen scenario-from-log`."""

from __future__ import annotations

import os
import struct
import subprocess
import sys
from pathlib import Path

import cppbuild
from btgen.cli import main
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario
from btgen.ir.treexml import groot2_tree
from btgen.tools.cover import trace_transitions

ROOT = Path(__file__).resolve().parents[2]
PICK = ROOT / "missions" / "PickPlaceBall.xml"
LAB = ROOT / "missions" / "LabTour.xml"
CODES = {"IDLE": 0, "RUNNING": 1, "SUCCESS": 2, "FAILURE": 3, "SKIPPED": 4}


def _btlog(mission_path: Path, trace: str, out: Path) -> Path:
    """A .btlog as btgen::btlog::FileLogger writes it (FileLogger2: header, tree XML, records)."""
    xml = groot2_tree(load_mission(str(mission_path))).xml.encode()
    body = b"".join(
        struct.pack("<Q", 10 * i)[:6] + struct.pack("<HB", uid, CODES[to])
        for i, (uid, _, to) in enumerate(trace_transitions(trace))
    )
    out.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + body)
    return out


def test_cover_counts_nodes_and_outcomes(tmp_path, capsys):
    one = tmp_path / "one.scenario"
    one.write_text("ticks 5\nleaf FindBall FAILURE SUCCESS\n")
    assert main(["cover", str(PICK), str(one), "--uncovered"]) == 0
    out = capsys.readouterr().out
    # FindBall fails once (Retry RUNNING), then all succeed: 7 of 7 nodes ticked. Every node can
    # return SUCCESS, FAILURE and RUNNING (21 goals); seen: the root Sequence RUNNING SUCCESS,
    # Retry RUNNING SUCCESS, FindBall FAILURE SUCCESS, PickMovePlace RUNNING SUCCESS, the three
    # leaves SUCCESS: 11.
    assert "nodes:    7/7 = 100.0%" in out
    assert "outcomes: 11/21 = 52.4%" in out
    assert "FindBall" in out and "RUNNING" in out
    # a trace file and a scenario file of the same run count the same
    trace = tmp_path / "one.trace"
    trace.write_text(trace_text(load_mission(str(PICK)), parse_scenario(str(one))))
    assert main(["cover", str(PICK), str(trace)]) == 0
    assert "outcomes: 11/21" in capsys.readouterr().out
    assert main(["cover", str(PICK), str(one), "--min", "100", "--graph", str(tmp_path / "c.dot")]) == 0
    dot = (tmp_path / "c.dot").read_text()
    assert "never ticked</td>" in dot and "52.4% of outcomes" in dot


def test_explore_scenarios_give_full_coverage(tmp_path, capsys):
    out = tmp_path / "sc"
    assert main(["explore", str(PICK), "-o", str(out)]) == 0
    capsys.readouterr()
    files = sorted(str(p) for p in out.glob("*.scenario"))
    assert main(["cover", str(PICK), *files]) == 0
    text = capsys.readouterr().out
    assert "nodes:    7/7 = 100.0%" in text and "outcomes: 21/21 = 100.0%" in text


def test_scenario_from_log_replays_the_same_transitions(tmp_path, capsys):
    for mission, scenario in (
        (PICK, "ticks 9\nleaf FindBall RUNNING FAILURE RUNNING RUNNING SUCCESS\nleaf MoveBall RUNNING SUCCESS\n"),
        (LAB, (ROOT / "missions" / "scenarios" / "LabTour.yes.scenario").read_text()),
    ):
        src = tmp_path / f"{mission.stem}.scenario"
        src.write_text(scenario)
        m = load_mission(str(mission))
        trace = trace_text(m, parse_scenario(str(src)))
        log = _btlog(mission, trace, tmp_path / f"{mission.stem}.btlog")
        back = tmp_path / f"{mission.stem}.back.scenario"
        assert main(["scenario-from-log", str(mission), str(log), "-o", str(back)]) == 0
        replay = trace_text(m, parse_scenario(str(back)))
        assert trace_transitions(replay) == trace_transitions(trace)
        if mission == PICK:  # and on the compiled engine (built once for test_explore too)
            got = subprocess.run(
                [sys.executable, "-m", "btgen", "run", str(mission), "--scenario", str(back), "--engine", "cpp"],
                capture_output=True,
                text=True,
                check=False,
            )
            assert got.returncode == 0, got.stderr
            assert got.stdout == replay


def test_log_of_another_run_is_an_error(tmp_path, capsys):
    m = load_mission(str(PICK))
    src = tmp_path / "a.scenario"
    src.write_text("ticks 3\n")
    trace = trace_text(m, parse_scenario(str(src)))
    # the same records with one status changed: PlaceBall fails in the log, the Sequence succeeds
    bad = trace.replace('7 PlaceBall "PlaceBall" IDLE -> SUCCESS', '7 PlaceBall "PlaceBall" IDLE -> FAILURE')
    log = _btlog(PICK, bad, tmp_path / "bad.btlog")
    assert main(["scenario-from-log", str(PICK), str(log)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{log}:1:1: error: the log is not a run of this mission: record ")


def test_a_log_written_by_the_compiled_file_logger_replays(tmp_path, capsys):
    """Record with btgen::btlog::FileLogger (runtime/src/monitor_driver.cpp, as on the robot), then
    scenario-from-log: the interpreter replays the same status changes."""
    out = tmp_path / "build"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "generator")}
    subprocess.run([sys.executable, "-m", "btgen", "compile", str(PICK), "-o", str(out)], check=True, env=env)
    template = subprocess.run(
        [sys.executable, "-m", "btgen.compiler", "--template", str(PICK)],
        check=True,
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    ).stdout.strip()
    exe = out / "pick"
    (header,) = out.glob("*.hpp")
    cppbuild.build(
        [ROOT / "runtime" / "src" / "monitor_driver.cpp", header.with_suffix(".cpp")],
        exe,
        opt="-O0",
        warnings=False,
        includes=[out],
        defines=[f'BTGEN_MISSION_HEADER="{header.name}"', f"BTGEN_MISSION_TEMPLATE={template}"],
        libs=["-lzmq", "-pthread"],
    )
    recorded = tmp_path / "robot.scenario"
    recorded.write_text(
        "ticks 8\nleaf FindBall RUNNING FAILURE RUNNING SUCCESS\nleaf MoveBall RUNNING RUNNING SUCCESS\n"
    )
    log = tmp_path / "robot.btlog"
    subprocess.run(
        [str(exe), str(recorded), "--btlog", str(log)],
        input="tick\n" * 8 + "quit\n",
        text=True,
        check=True,
        capture_output=True,
    )
    back = tmp_path / "replay.scenario"
    assert main(["scenario-from-log", str(PICK), str(log), "-o", str(back)]) == 0
    # the driver ticked 8 times; the mission completed before, and the tree ran again after it
    assert "are a new run of the tree, which this scenario does not replay" in capsys.readouterr().err
    m = load_mission(str(PICK))
    original = trace_text(
        m, parse_scenario(str(recorded)).__class__(str(recorded), 8, "SUCCESS", parse_scenario(str(recorded)).leaves)
    )
    assert trace_transitions(trace_text(m, parse_scenario(str(back)))) == trace_transitions(original)


def test_min_failing_says_why(tmp_path, capsys):
    one = tmp_path / "one.scenario"
    one.write_text("leaf FindBall FAILURE FAILURE\n")
    argv = ["cover", str(PICK), str(one), "--min", "90"]
    assert main(argv) == 1
    captured = capsys.readouterr()
    assert captured.out.startswith(f"{PICK}: 1 run\n")  # not "1 runs"
    col = 1 + sum(len(a) + 1 for a in argv[:3])
    assert captured.err == (
        f"<command-line>:1:{col}: error: node coverage 42.9% is below --min 90%: 4 of 7 nodes never ticked "
        "by the 1 run (`--uncovered` lists them)\n"
    )


def test_explore_and_cover_say_the_same_lines(tmp_path, capsys):
    out = tmp_path / "sc"
    assert main(["explore", str(PICK), "-o", str(out)]) == 0
    explored = [line for line in capsys.readouterr().out.splitlines() if line.startswith(("  nodes:", "  outcomes:"))]
    assert main(["cover", str(PICK), *sorted(str(p) for p in out.glob("*.scenario"))]) == 0
    covered = [line for line in capsys.readouterr().out.splitlines() if line.startswith(("  nodes:", "  outcomes:"))]
    assert (
        explored
        == covered
        == [
            "  nodes:    7/7 = 100.0% ticked",
            "  outcomes: 21/21 = 100.0% (each SUCCESS, FAILURE, RUNNING a node can return, seen)",
        ]
    )


def test_a_synchronous_action_is_not_missing_running(tmp_path, capsys):
    one = tmp_path / "one.scenario"
    one.write_text("ticks 5\nleaf FindBall FAILURE SUCCESS\n")
    assert main(["cover", str(PICK), str(one), "--table"]) == 0
    table = capsys.readouterr().out
    assert "outcomes: 11/21" in table
    pick_row = next(line for line in table.splitlines() if " PickBall " in line or line.rstrip().endswith("PickBall"))
    assert pick_row.rstrip().endswith("FAILURE,RUNNING")
    sync = ["--sync", "PickBall", "--sync", "PlaceBall", "--sync", "FindBall"]
    assert main(["cover", str(PICK), str(one), "--table", *sync]) == 0
    table = capsys.readouterr().out
    assert "outcomes: 11/18" in table  # RUNNING of the three is no goal
    pick_row = next(line for line in table.splitlines() if " PickBall " in line or line.rstrip().endswith("PickBall"))
    assert pick_row.rstrip().endswith("FAILURE")
    # explore never makes them RUNNING either, and covers the rest
    assert main(["explore", str(PICK), "--json", *sync]) == 0
    import json

    report = json.loads(capsys.readouterr().out)
    assert report["outcome_goals"] == 18 and report["outcomes_covered"] == 18


def test_sync_names_an_action_of_the_mission(capsys):
    assert main(["cover", str(PICK), "x.scenario", "--sync", "PickBal"]) == 1
    assert (
        "--sync PickBal: the mission declares no Action `PickBal` (did you mean `PickBall`?)" in capsys.readouterr().err
    )


def test_cover_takes_the_mission_options_of_tests(tmp_path, capsys):
    """--entry as `btgen tests` takes it: Entry.xml's script adds 1 to an entry it wrote as text,
    which runs only with the entry declared int; without it the run stops with a located error."""
    mission = ROOT / "tests" / "gtests" / "Entry.xml"
    sc = tmp_path / "one.scenario"
    sc.write_text("ticks 1\nleaf Go RUNNING\n")
    assert main(["cover", str(mission), str(sc), "--entry", "level=int"]) == 0
    assert "nodes:    5/6" in capsys.readouterr().out  # all but the Fallback's second child
    assert main(["cover", str(mission), str(sc)]) == 1
    assert f"{mission}:6:" in capsys.readouterr().err
