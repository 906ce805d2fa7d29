"""All of btgen on Nav2's default trees (tests/real_files/nav2), Nav2's leaves scripted, no user C++.

With Nav2's models file the trees' Controls and Decorators are built in (lang/nav2.py), so
`run`, `explore`, `cover`, `analyze`, `scenario-from-log` and `bench` work on all 27 trees (main
and jazzy). The ten that use a Nav2 Decorator reading ROS 2 (DistanceController, SpeedController,
GoalUpdater, GoalUpdatedController, PathLongerOnApproach) get that fact from the scenario: a
`leaf NAME SUCCESS FAILURE ...` line under the Decorator's name (lang/nav2.py ENV_INPUTS), which
explore branches on and cover counts, on both engines.

Kept fast: every tree runs and is analysed on the interpreter; the C++ engine, explore, cover
and bench run on a sample (SAMPLE, with a tree of our own using the five Decorators that no
test tree has: OWN); `BTGEN_NAV2_TREES=all` runs them on every tree and on both
BehaviorTree.CPP versions.
"""

from __future__ import annotations

import os
import re
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from btgen import pipeline
from btgen.cli import main
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario
from btgen.ir.treexml import groot2_tree
from btgen.lang.leaves import mission_leaves
from btgen.lang.nav2 import ENV_NODES
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
ENV_TREES = [t for t in TREES if any(f"<{r}" in t[1].read_text() for r in ENV_NODES)]
RUNNABLE = TREES
ALL = os.environ.get("BTGEN_NAV2_TREES", "") == "all"

# A Nav2 tree of our own, in no test folder (as a tree held back from the developers would
# be): the five Decorators that read ROS 2 under Nav2's Controls, with main's models file.
OWN_XML = """<root BTCPP_format="4" main_tree_to_execute="Patrol">
  <BehaviorTree ID="Patrol">
    <RecoveryNode number_of_retries="2" name="PatrolRecovery">
      <PipelineSequence name="Patrol">
        <GoalUpdatedController name="NewGoal">
          <GoalUpdater input_goal="{goal}" output_goal="{goal}">
            <ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased"/>
          </GoalUpdater>
        </GoalUpdatedController>
        <DistanceController distance="0.5" name="EveryHalfMetre">
          <SpeedController max_rate="2.0" name="BySpeed">
            <ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased" name="Replan"/>
          </SpeedController>
        </DistanceController>
        <ReactiveSequence name="Follow">
          <PathLongerOnApproach path="{path}" prox_len="2.0" length_factor="1.5" name="Longer">
            <CancelControl name="Stop"/>
          </PathLongerOnApproach>
          <FollowPath path="{path}" controller_id="FollowPath"/>
        </ReactiveSequence>
      </PipelineSequence>
      <RoundRobin name="Recoveries">
        <Spin spin_dist="1.57"/>
        <BackUp backup_dist="0.3" backup_speed="0.1"/>
      </RoundRobin>
    </RecoveryNode>
  </BehaviorTree>
</root>
"""
OWN = "own_patrol"
SAMPLE = (
    RUNNABLE
    if ALL
    else [
        (m, p)
        for m, p in RUNNABLE
        if (m == MODELS and p.stem in ("navigate_to_pose_w_replanning_and_recovery", "navigate_w_replanning_time"))
        or (m == JAZZY_MODELS and p.stem == "navigate_through_poses_w_replanning_and_recovery")
    ]
) + [(MODELS, Path(OWN))]
VERSIONS = ("4.6.2", "4.10.0") if ALL else ("4.6.2",)


def _id(t):
    return ("jazzy-" if t[0] == JAZZY_MODELS else "") + t[1].stem


def _tree(tree: Path, tmp_path: Path) -> Path:
    """The tree's file (ours is written where the test runs)."""
    if tree.name != OWN:
        return tree
    path = tmp_path / "patrol.xml"
    path.write_text(OWN_XML)
    return path


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
    "CancelControl": "RUNNING SUCCESS",
    # the inputs of the Decorators that read ROS 2 (SUCCESS: yes; lang/nav2.py ENV_INPUTS)
    "DistanceController": "FAILURE SUCCESS FAILURE FAILURE SUCCESS FAILURE",
    "EveryHalfMetre": "FAILURE SUCCESS FAILURE FAILURE SUCCESS FAILURE",
    "SpeedController": "FAILURE FAILURE SUCCESS FAILURE",
    "BySpeed": "FAILURE FAILURE SUCCESS FAILURE",
    "GoalUpdatedController": "FAILURE SUCCESS FAILURE",
    "NewGoal": "FAILURE FAILURE FAILURE SUCCESS FAILURE",
    "PathLongerOnApproach": "FAILURE FAILURE SUCCESS FAILURE FAILURE SUCCESS FAILURE",
    "Longer": "FAILURE FAILURE SUCCESS FAILURE FAILURE SUCCESS FAILURE",
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
    assert len(TREES) == 15 + 12 and len(ENV_TREES) == 5 + 5 and len(RUNNABLE) == 27
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


def _explore(tree: Path, opts: list, out: Path, ticks: str = "3", states: str = "300") -> list:
    e = _btgen("explore", str(tree), *opts, "--ticks", ticks, "--max-states", states, "-o", str(out))
    assert e.returncode == 0, e.stderr
    written = sorted(out.glob("*.scenario"))
    assert written
    return written


@pytest.mark.parametrize("models,tree", ENV_TREES, ids=[_id(t) for t in ENV_TREES])
def test_ros_decorators_inputs_are_explored_and_covered(models, tree, tmp_path):
    # The Decorator's input is a branch of explore, as a Condition's result: its yes and no are
    # goals, and the written scenarios reach both; cover counts them from those scenarios.
    opts = ["--models", models]
    out = tmp_path / "explored"
    e = _btgen("explore", str(tree), *opts, "--ticks", "4", "--max-states", "3000", "-o", str(out))
    assert e.returncode == 0, e.stderr
    inputs = [d for d in ENV_NODES if f"<{d}" in tree.read_text() and d != "GoalUpdater"]
    text = "\n".join(p.read_text() for p in sorted(out.glob("*.scenario")))
    if inputs:
        assert re.search(rf"inputs: +{2 * len(inputs)}/{2 * len(inputs)} = 100.0%", e.stdout), e.stdout
        for d in inputs:
            lines = re.findall(rf"^leaf {d} (.*)$", text, re.M)
            assert any("SUCCESS" in ln for ln in lines) and any("FAILURE" in ln for ln in lines), (d, lines)
    else:  # GoalUpdater has no input: no goal arrives on its topic in a scenario
        assert "inputs:" not in e.stdout and "leaf GoalUpdater " not in text
    c = _btgen("cover", str(tree), *opts, *map(str, sorted(out.glob("*.scenario"))))
    assert c.returncode == 0, c.stderr
    if inputs:
        assert re.search(rf"inputs: +{2 * len(inputs)}/{2 * len(inputs)} = 100.0%", c.stdout), c.stdout
        # one scenario alone, whose inputs say no only: half of them
        sc = tmp_path / "no.scenario"
        sc.write_text("ticks 4\n" + "".join(f"leaf {d} FAILURE\n" for d in inputs))
        one = _btgen("cover", str(tree), *opts, str(sc))
        assert re.search(rf"inputs: +{len(inputs)}/{2 * len(inputs)} = 50.0%", one.stdout), one.stdout


@pytest.mark.parametrize("engine", ("interp", "cpp"))
def test_a_running_input_is_a_located_error(engine, tmp_path):
    tree = NAV2 / "navigate_w_replanning_distance.xml"
    sc = tmp_path / "bad.scenario"
    sc.write_text("ticks 3\nleaf DistanceController FAILURE RUNNING\n")
    r = _btgen("run", str(tree), "--models", MODELS, "--scenario", str(sc), "--engine", engine)
    assert r.returncode == 1
    assert re.search(
        rf"^{re.escape(str(sc))}:2:33: error: .*input of Nav2's `DistanceController`.*not RUNNING", r.stderr, re.M
    ), r.stderr
    assert "Traceback" not in r.stderr


def test_pause_resume_controller_stays_the_users(tmp_path):
    xml = tmp_path / "pause.xml"
    xml.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="T"><PauseResumeController pause_service_name="p" '
        'resume_service_name="r"><Spin/></PauseResumeController></BehaviorTree></root>'
    )
    sc = tmp_path / "s.scenario"
    sc.write_text("ticks 2\n")
    r = _btgen("run", str(xml), "--models", MODELS, "--scenario", str(sc))
    assert r.returncode == 1
    assert "needs ROS 2 (it offers ROS 2 services" in r.stderr and "declare it in TreeNodesModel" in r.stderr


@pytest.mark.skipif(not ALL, reason="BTGEN_NAV2_TREES=all: one C++ build per tree")
@pytest.mark.parametrize("models,tree", ENV_TREES, ids=[_id(t) for t in ENV_TREES])
def test_ros_decorator_trees_on_both_engines(models, tree, tmp_path):
    opts = ["--models", models]
    sc = _scenario(models, tree, tmp_path)
    interp = _btgen("run", str(tree), *opts, "--scenario", str(sc))
    cpp = _btgen("run", str(tree), *opts, "--scenario", str(sc), "--engine", "cpp")
    assert interp.returncode == 0 and cpp.returncode == 0, cpp.stderr
    assert cpp.stdout == interp.stdout
    for s in _explore(tree, opts, tmp_path / "explored", "4", "2000"):
        a = _btgen("run", str(tree), *opts, "--scenario", str(s))
        b = _btgen("run", str(tree), *opts, "--scenario", str(s), "--engine", "cpp")
        assert a.returncode == b.returncode and a.stdout == b.stdout, s.name


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("models,tree", SAMPLE, ids=[_id(t) for t in SAMPLE])
def test_both_engines_explore_cover_replay_and_bench(models, tree, version, tmp_path):
    tree = _tree(tree, tmp_path)
    opts = ["--models", models, "--btcpp", version]
    sc = _scenario(models, tree, tmp_path)
    # run: the two engines print the same trace
    interp = _btgen("run", str(tree), *opts, "--scenario", str(sc))
    cpp = _btgen("run", str(tree), *opts, "--scenario", str(sc), "--engine", "cpp")
    assert interp.returncode == 0 and cpp.returncode == 0, cpp.stderr
    assert cpp.stdout == interp.stdout
    # explore (bounded here) writes scenarios; both engines replay each the same way
    written = _explore(tree, opts, tmp_path / "explored")
    for s in written[:3] if tree.name != "patrol.xml" else written:
        a = _btgen("run", str(tree), *opts, "--scenario", str(s))
        b = _btgen("run", str(tree), *opts, "--scenario", str(s), "--engine", "cpp")
        assert a.returncode == b.returncode and a.stdout == b.stdout, s.name
    # cover: what the explored scenarios reach
    c = _btgen("cover", str(tree), *opts, *map(str, written))
    assert c.returncode == 0, c.stderr
    assert re.search(r"nodes: +\d+/\d+", c.stdout)
    # scenario-from-log: a Groot2 log of the run gives a scenario that replays it (a log has no
    # record of the Decorators' inputs: refused for our tree)
    m = pipeline.load(str(tree), pipeline.CompileOptions(models=(models,), btcpp=version))
    trace = trace_text(m, parse_scenario(str(sc)))
    log = _btlog(m, trace, tmp_path / "run.btlog")
    back = tmp_path / "back.scenario"
    r = _btgen("scenario-from-log", str(tree), str(log), "-o", str(back), "--clock-ms", "250", *opts)
    if tree.name != "patrol.xml":
        assert r.returncode == 0, r.stderr
        assert trace_transitions(trace_text(m, parse_scenario(str(back)))) == trace_transitions(trace)
    else:  # located at the first Decorator with an input, and no file written
        assert r.returncode == 1 and not back.exists()
        why = r"error: .*cannot recover the input of Nav2's `GoalUpdatedController`"
        assert re.search(r"patrol.xml:5:\d+: " + why, r.stderr), r.stderr
    # bench: the compiled tree ticks with instant leaves and prints its numbers
    b = _btgen("bench", str(tree), *opts, "--ticks", "2000")
    assert b.returncode == 0, b.stderr
    assert re.search(r"\d", b.stdout)


def test_diff_branches_on_the_inputs(tmp_path):
    # Always yes, DistanceController would tick its child on every tick, as a one-attempt
    # RetryUntilSuccessful does: `btgen diff` must try its no (it once found them equivalent).
    def tree(name: str, decorator: str) -> str:
        path = tmp_path / f"{name}.xml"
        path.write_text(
            '<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T"><PipelineSequence>'
            f"<{decorator}><Plan/></{decorator.split()[0]}><Follow/></PipelineSequence></BehaviorTree>"
            '<TreeNodesModel><Action ID="Plan"/><Action ID="Follow"/></TreeNodesModel></root>'
        )
        return str(path)

    a = tree("a", 'DistanceController distance="1.0"')
    b = tree("b", 'RetryUntilSuccessful num_attempts="1"')
    r = _btgen("diff", a, b, "--nodes", "nav2", "--max-ticks", "4")
    assert r.returncode == 1 and ": different" in r.stdout, r.stdout + r.stderr
    assert re.search(r"^ +leaf DistanceController (SUCCESS|FAILURE)", r.stdout, re.M), r.stdout
    same = _btgen("diff", a, a, "--nodes", "nav2", "--max-ticks", "4")
    assert same.returncode == 0 and "equivalent" in same.stdout


BTVIEW = Path(sys.executable).parent / "btview"


@pytest.mark.skipif(not BTVIEW.exists() and not os.environ.get("CI"), reason="btview is not installed")
def test_groot2_monitor_on_a_nav2_tree(tmp_path):
    # The compiled tree under btgen::groot2::Publisher (runtime/src/monitor_driver.cpp), its
    # leaves and DistanceController's input scripted: after three ticks btview (a Groot2 client
    # no one here wrote) shows every node with the status the interpreter has then.
    import cppbuild
    from conftest import free_port_pair

    tree = NAV2 / "navigate_w_replanning_distance.xml"
    out = tmp_path / "out"
    assert _btgen("compile", str(tree), "--models", MODELS, "-o", str(out)).returncode == 0
    stem = tree.stem
    exe = cppbuild.build(
        [ROOT / "runtime" / "src" / "monitor_driver.cpp", out / f"{stem}.cpp"],
        tmp_path / "monitor",
        opt="-O1",
        includes=[out],
        defines=[f'BTGEN_MISSION_HEADER="{stem}.hpp"', f"BTGEN_MISSION_TEMPLATE={stem}::NavigateWReplanningDistance"],
        libs=["-lzmq", "-pthread"],
    )
    sc = tmp_path / "run.scenario"
    sc.write_text("ticks 3\nleaf FollowPath RUNNING\nleaf DistanceController FAILURE FAILURE SUCCESS\n")
    port = free_port_pair()
    proc = subprocess.Popen(
        [str(exe), str(sc), "--groot2", str(port), "--address", "127.0.0.1"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout.readline().strip() == "ready"
        for _ in range(3):
            proc.stdin.write("tick\n")
            proc.stdin.flush()
            assert proc.stdout.readline().split()[1] == "RUNNING"
        shown = subprocess.run(
            [str(BTVIEW), "snapshot", "-p", str(port), "--uid", "--no-color"],
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
    finally:
        proc.stdin.write("quit\n")
        proc.stdin.flush()
        proc.wait(timeout=10)
    assert shown.returncode == 0, shown.stderr
    seen = {}
    for line in shown.stdout.splitlines():
        m = re.search(r"#(\d+)\s+\S+\s+(?:was )?(\w+)\s*$", line)
        if m:
            seen[int(m.group(1))] = "IDLE" if " was " in line or "· idle" in line else m.group(2)
    mission = pipeline.load(str(tree), pipeline.CompileOptions(models=(MODELS,)))
    status = {}
    for uid, _, to in trace_transitions(trace_text(mission, parse_scenario(str(sc)))):
        status[uid] = to
    expected = {uid: status.get(uid, "IDLE") for uid in range(1, 7)}
    assert seen == expected, shown.stdout
    assert expected[4] == "SUCCESS"  # DistanceController: its child ran again on the third tick (a yes)
