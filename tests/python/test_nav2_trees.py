"""All of btgen on Nav2's default trees (tests/real_files/nav2), Nav2's leaves scripted, no user C++.

With Nav2's models file the trees' Controls and Decorators are built in (lang/nav2.py), so
`run`, `explore`, `cover`, `analyze`, `scenario-from-log` and `bench` work on them. The five
trees that use a Nav2 Decorator needing ROS 2 (DistanceController, SpeedController,
GoalUpdater, GoalUpdatedController, PathLongerOnApproach) are refused by `run` with the
reason and what to do.

Kept fast: every runnable tree runs and is analysed on the interpreter; the C++ engine, explore,
cover and bench run on a sample (SAMPLE); `BTGEN_NAV2_TREES=all` runs them on every tree and
on both BehaviorTree.CPP versions.
"""

from __future__ import annotations

import os
import re
import struct
from pathlib import Path

import pytest

from btgen import pipeline
from btgen.cli import main
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario
from btgen.ir.treexml import groot2_tree
from btgen.lang.leaves import mission_leaves
from btgen.lang.nav2 import ROS_NODES
from btgen.tools.cover import trace_transitions

ROOT = Path(__file__).resolve().parents[2]
NAV2 = ROOT / "tests" / "real_files" / "nav2"
MODELS = str(NAV2 / "nav2_tree_nodes.xml")
JAZZY = ROOT / "tests" / "nav2_models" / "jazzy"
JAZZY_MODELS = str(JAZZY / "nav2_tree_nodes.xml")
# (models file, tree): main's trees with main's file, jazzy's with jazzy's (RoundRobin wraps there)
TREES = [(MODELS, p) for p in sorted(NAV2.glob("*.xml")) if p.name != "nav2_tree_nodes.xml"] + [
    (JAZZY_MODELS, p) for p in sorted((JAZZY / "behavior_trees").glob("*.xml"))
]
ROS_TREES = [t for t in TREES if any(f"<{r}" in t[1].read_text() for r in ROS_NODES)]
RUNNABLE = [t for t in TREES if t not in ROS_TREES]
ALL = os.environ.get("BTGEN_NAV2_TREES", "") == "all"
SAMPLE = (
    RUNNABLE
    if ALL
    else [
        (m, p)
        for m, p in RUNNABLE
        if (m == MODELS and p.stem in ("navigate_to_pose_w_replanning_and_recovery", "navigate_w_replanning_time"))
        or (m == JAZZY_MODELS and p.stem == "navigate_through_poses_w_replanning_and_recovery")
    ]
)
VERSIONS = ("4.6.2", "4.10.0") if ALL else ("4.6.2",)


def _id(t):
    return ("jazzy-" if t[0] == JAZZY_MODELS else "") + t[1].stem


# What Nav2's leaves do in these runs: the robot plans, follows, the controller fails once and
# recovers, a plan fails once; the goal is never updated.
SCRIPT = {
    "FollowPath": "RUNNING RUNNING FAILURE RUNNING RUNNING RUNNING SUCCESS",
    "ComputePathToPose": "SUCCESS FAILURE SUCCESS",
    "ComputePathThroughPoses": "SUCCESS FAILURE SUCCESS",
    "ComputeRoute": "SUCCESS",
    "GoalUpdated": "FAILURE",
    "GlobalUpdatedGoal": "FAILURE",
    "Spin": "RUNNING SUCCESS",
}


CODES = {"IDLE": 0, "RUNNING": 1, "SUCCESS": 2, "FAILURE": 3, "SKIPPED": 4}


def _btlog(mission, trace: str, out: Path, clock_ms: int = 250) -> Path:
    """A .btlog as btgen::btlog::FileLogger writes it of a run whose tick k happens at
    (k - 1) * clock_ms on the mission's clock (each record stamped with its tick's time)."""
    xml = groot2_tree(mission).xml.encode()
    records, tick, seq = [], 0, 0
    for line in trace.splitlines():
        if line.startswith("tick "):
            tick, seq = int(line.split()[1]), 0
            continue
        for uid, _, to in trace_transitions(line):
            records.append(
                struct.pack("<Q", (tick - 1) * clock_ms * 1000 + seq)[:6] + struct.pack("<HB", uid, CODES[to])
            )
            seq += 1
    body = b"".join(records)
    out.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + body)
    return out


class _Result:
    def __init__(self, returncode: int, stdout: str, stderr: str) -> None:
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


_CAP: list = []


@pytest.fixture(autouse=True)
def _capture(capfd):
    _CAP.append(capfd)
    yield
    _CAP.pop()


def _btgen(*args):
    """`btgen ARGS` in this process (the C++ engine's output goes through the file descriptors)."""
    cap = _CAP[-1]
    cap.readouterr()
    rc = main(list(args))
    out, err = cap.readouterr()
    return _Result(rc, out, err)


def _scenario(models: str, tree: Path, tmp_path: Path) -> Path:
    m = pipeline.load(str(tree), pipeline.CompileOptions(models=(models,)))
    names = {u.name for u in mission_leaves(m)}
    lines = ["ticks 60", "clock_ms 250", "default SUCCESS"]
    lines += [f"leaf {n} {s}" for n, s in SCRIPT.items() if n in names]
    path = tmp_path / f"{tree.stem}.scenario"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_the_trees():
    assert len(TREES) == 15 + 12 and len(ROS_TREES) == 5 + 5 and len(RUNNABLE) == 10 + 7
    for models, tree in TREES:
        assert pipeline.load(str(tree), pipeline.CompileOptions(models=(models,))).nav2 == (
            "jazzy" if models == JAZZY_MODELS else "lyrical"
        )


@pytest.mark.parametrize("models,tree", RUNNABLE, ids=[_id(t) for t in RUNNABLE])
def test_runs_and_analyses_on_the_interpreter(models, tree, tmp_path):
    sc = _scenario(models, tree, tmp_path)
    r = _btgen("run", str(tree), "--models", models, "--scenario", str(sc))
    assert r.returncode == 0, r.stderr
    assert r.stdout.rstrip().splitlines()[-1] in ("result SUCCESS", "result FAILURE"), tree.stem
    a = _btgen("analyze", str(tree), "--models", models)
    assert a.returncode == 0, a.stderr
    assert "unbounded" not in a.stdout
    if "<RateController" in tree.read_text():
        assert re.search(r'rate limit +RateController "[^"]+": its child starts again at most [0-9.]+ times', a.stdout)


@pytest.mark.parametrize("models,tree", ROS_TREES, ids=[_id(t) for t in ROS_TREES])
def test_ros_decorators_are_refused_with_the_reason(models, tree, tmp_path):
    sc = _scenario(models, tree, tmp_path)
    for engine in ("interp", "cpp"):
        r = _btgen("run", str(tree), "--models", models, "--scenario", str(sc), "--engine", engine)
        assert r.returncode == 1
        assert "needs ROS 2 (" in r.stderr and "declare it in TreeNodesModel" in r.stderr, r.stderr
        assert "Traceback" not in r.stderr


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("models,tree", SAMPLE, ids=[_id(t) for t in SAMPLE])
def test_both_engines_explore_cover_replay_and_bench(models, tree, version, tmp_path):
    opts = ["--models", models, "--btcpp", version]
    sc = _scenario(models, tree, tmp_path)
    # run: the two engines print the same trace
    interp = _btgen("run", str(tree), *opts, "--scenario", str(sc))
    cpp = _btgen("run", str(tree), *opts, "--scenario", str(sc), "--engine", "cpp")
    assert interp.returncode == 0 and cpp.returncode == 0, cpp.stderr
    assert cpp.stdout == interp.stdout
    # explore (bounded here) writes scenarios; both engines replay each the same way
    out = tmp_path / "explored"
    e = _btgen("explore", str(tree), *opts, "--ticks", "3", "--max-states", "300", "-o", str(out))
    assert e.returncode == 0, e.stderr
    written = sorted(out.glob("*.scenario"))
    assert written
    for s in written[:3]:
        a = _btgen("run", str(tree), *opts, "--scenario", str(s))
        b = _btgen("run", str(tree), *opts, "--scenario", str(s), "--engine", "cpp")
        assert a.returncode == b.returncode and a.stdout == b.stdout, s.name
    # cover: what the explored scenarios reach
    c = _btgen("cover", str(tree), *opts, *map(str, written))
    assert c.returncode == 0, c.stderr
    assert re.search(r"nodes: +\d+/\d+", c.stdout)
    # scenario-from-log: a Groot2 log of the run gives a scenario that replays it
    m = pipeline.load(str(tree), pipeline.CompileOptions(models=(models,), btcpp=version))
    trace = trace_text(m, parse_scenario(str(sc)))
    log = _btlog(m, trace, tmp_path / "run.btlog")
    if log is not None:
        back = tmp_path / "back.scenario"
        r = _btgen("scenario-from-log", str(tree), str(log), "-o", str(back), "--clock-ms", "250", *opts)
        assert r.returncode == 0, r.stderr
        assert trace_transitions(trace_text(m, parse_scenario(str(back)))) == trace_transitions(trace)
    # bench: the compiled tree ticks with instant leaves and prints its numbers
    b = _btgen("bench", str(tree), *opts, "--ticks", "2000")
    assert b.returncode == 0, b.stderr
    assert re.search(r"\d", b.stdout)
