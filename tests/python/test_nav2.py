"""Nav2's Controls and Decorators, built in (lang/nav2.py): both engines against the traces
recorded from Nav2's own plugins on the real BehaviorTree.CPP (tests/conformance/nav2/,
scripts/nav2_oracle/record.py), for each distro and each library version; and how a mission
selects them (`--nodes`, or Nav2's models file).

`BTGEN_NAV2_CPP=all` runs the C++ engine on every distro; by default it runs the cases of
lyrical (all families) and those whose jazzy traces differ (RoundRobin before wrap_around),
and the kilted recordings are checked to equal jazzy's (the same families, the same code).
The cases of the Decorators that read ROS 2 (DistanceController, SpeedController,
GoalUpdatedController, PathLongerOnApproach: recorded with scripts/nav2_oracle/ros_shim.hpp)
record the same trace on every distro and version: the C++ engine runs one case of each by
default, all of them with `BTGEN_NAV2_CPP=all`.
"""

import difflib
import os
import subprocess
import sys
from pathlib import Path

import pytest

from btgen import pipeline
from btgen.diagnostics import UserError
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario
from btgen.lang import nav2
from conftest import ROOT as _ROOT

ROOT = Path(_ROOT)
NAV2 = ROOT / "tests" / "conformance" / "nav2"
CASES = NAV2 / "cases"
REAL = ROOT / "tests" / "real_files" / "nav2"
STEMS = sorted(p.stem for p in CASES.glob("*.xml"))
VERSIONS = ("4.6.2", "4.10.0")
RECORDINGS = [(d, v, s) for d in nav2.DISTROS for v in VERSIONS for s in STEMS]


def _opts(distro, version):
    return pipeline.CompileOptions(btcpp=version, nodes=f"nav2:{distro}")


def _expected(distro, version, stem):
    folder = NAV2 / f"{distro}-{version}"
    trace = folder / f"{stem}.trace"
    if trace.exists():
        return trace.read_text(encoding="utf-8"), None
    return None, (folder / f"{stem}.refused").read_text(encoding="utf-8")


def _diff(expected, got, what):
    return "".join(difflib.unified_diff(expected.splitlines(True), got.splitlines(True), "recorded", what, n=2))


def test_recordings_present():
    assert len(STEMS) >= 40
    for distro in nav2.DISTROS:
        for version in VERSIONS:
            folder = NAV2 / f"{distro}-{version}"
            for stem in STEMS:
                assert (folder / f"{stem}.trace").exists() or (folder / f"{stem}.refused").exists(), (folder, stem)


@pytest.mark.parametrize("distro,version,stem", RECORDINGS)
def test_interpreter_matches_recording(distro, version, stem):
    expected, refused = _expected(distro, version, stem)
    xml = str(CASES / f"{stem}.xml")
    scenario = parse_scenario(str(CASES / f"{stem}.scenario"))
    if refused is not None:
        # The distro does not have the node (NonblockingSequence before lyrical) or the port
        # (RoundRobin wrap_around): the library refuses the tree; btgen too, when loading it.
        with pytest.raises(UserError) as e:
            pipeline.load(xml, _opts(distro, version))
        if "wrap_around" in refused:
            assert "`RoundRobin` has no port `wrap_around`" in str(e.value)
        else:
            assert "NonblockingSequence" in refused or "PersistentSequence" in refused
            assert "unknown node" in str(e.value)
        return
    got = trace_text(pipeline.load(xml, _opts(distro, version)), scenario)
    assert got == expected, _diff(expected, got, "interpreter")


def test_kilted_records_as_jazzy():
    # Nav2's kilted and jazzy have the same Controls and Decorators; the C++ test relies on it.
    for version in VERSIONS:
        for stem in STEMS:
            assert _expected("kilted", version, stem) == _expected("jazzy", version, stem), stem


def test_round_robin_wraps_before_lyrical():
    # The one difference the recordings show between distros, as btgen's table has it.
    differ = [s for s in STEMS if _expected("jazzy", "4.6.2", s) != _expected("lyrical", "4.6.2", s)]
    assert {s.split("_")[0] for s in differ} <= {"round", "nonblocking", "persistent"}
    assert nav2.round_robin_wraps_always("jazzy") and not nav2.round_robin_wraps_always("lyrical")


# ----------------------------------------------------------------------- selection
def _mission(tmp_path, body, models=""):
    p = tmp_path / "m.xml"
    p.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Main">' + body + "</BehaviorTree>"
        "<TreeNodesModel>" + models + "</TreeNodesModel></root>"
    )
    return str(p)


def test_nav2_models_file_selects_the_families(tmp_path):
    xml = _mission(
        tmp_path, "<PipelineSequence><Plan/><Follow/></PipelineSequence>", '<Action ID="Plan"/><Action ID="Follow"/>'
    )
    models = str(REAL / "nav2_tree_nodes.xml")
    m = pipeline.load(xml, pipeline.CompileOptions(models=(models,)))
    assert m.nav2 == "lyrical"  # the shipped file of main declares RoundRobin's wrap_around
    assert m.spec("PipelineSequence").builtin
    assert not [w for w in m.warnings if "PipelineSequence" in w.message]
    # --nodes btcpp: Nav2's file is only a file of models; PipelineSequence is the user's
    m = pipeline.load(xml, pipeline.CompileOptions(models=(models,), nodes="btcpp"))
    assert m.nav2 is None and not m.spec("PipelineSequence").builtin


def test_without_nav2_they_are_unknown(tmp_path):
    xml = _mission(tmp_path, "<RecoveryNode><A/><B/></RecoveryNode>", '<Action ID="A"/><Action ID="B"/>')
    with pytest.raises(UserError) as e:
        pipeline.load(xml)
    assert "RecoveryNode" in str(e.value)
    assert pipeline.load(xml, pipeline.CompileOptions(nodes="nav2")).nav2 == nav2.NEWEST


def test_recovery_node_takes_two_children(tmp_path):
    xml = _mission(tmp_path, "<RecoveryNode><A/><B/><A/></RecoveryNode>", '<Action ID="A"/><Action ID="B"/>')
    with pytest.raises(UserError) as e:
        pipeline.load(xml, pipeline.CompileOptions(nodes="nav2"))
    assert "exactly 2 children" in str(e.value)


def test_ros_nodes_stay_the_users_and_say_why(tmp_path):
    xml = _mission(
        tmp_path,
        '<PipelineSequence><PauseResumeController pause_service_name="p" resume_service_name="r"><Plan/>'
        "</PauseResumeController><Follow/></PipelineSequence>",
        '<Control ID="PauseResumeController"><input_port name="pause_service_name"/>'
        '<input_port name="resume_service_name"/></Control><Action ID="Plan"/><Action ID="Follow"/>',
    )
    sc = tmp_path / "s.scenario"
    sc.write_text("ticks 2\n")
    r = subprocess.run(
        [sys.executable, "-m", "btgen", "run", xml, "--scenario", str(sc), "--nodes", "nav2"],
        check=False,
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT / "generator")},
    )
    assert r.returncode == 1
    assert "needs ROS 2 (it offers ROS 2 services to pause and resume)" in r.stderr
    assert "declare it in TreeNodesModel" in r.stderr


def test_ros_reading_decorators_are_built_in_with_an_input(tmp_path):
    # DistanceController reads the robot's pose: built in, that fact scripted under its name.
    xml = _mission(
        tmp_path,
        '<PipelineSequence><DistanceController distance="1.0"><Plan/></DistanceController><Follow/></PipelineSequence>',
        '<Action ID="Plan"/><Action ID="Follow"/>',
    )
    sc = tmp_path / "s.scenario"
    sc.write_text("ticks 4\nleaf Follow RUNNING\nleaf DistanceController FAILURE FAILURE SUCCESS FAILURE\n")
    m = pipeline.load(xml, pipeline.CompileOptions(nodes="nav2"))
    trace = trace_text(m, parse_scenario(str(sc)))
    plans = [t for t in trace.split("tick ")[1:] if '"Plan" IDLE -> SUCCESS' in t]
    # one answer per tick: the child is ticked on the first tick of the run (whatever the
    # answer), then only on the tick whose answer is yes (the node's SUCCESS keeps it active)
    assert [t.split("\n")[0] for t in plans] == ["1", "3"], trace


MODELS = ROOT / "tests" / "nav2_models"


@pytest.mark.parametrize("distro", nav2.DISTROS)
@pytest.mark.parametrize("version", VERSIONS)
def test_each_distros_models_file_loads_as_shipped(distro, version, tmp_path):
    # Nav2's file of each distro, as shipped: its distro is read from it, its Controls and
    # Decorators are built in, and the default trees that use only those run on both engines
    # (test_nav2_trees.py).
    models = str(MODELS / distro / "nav2_tree_nodes.xml")
    xml = _mission(
        tmp_path,
        '<PipelineSequence><RateController hz="1.0"><ComputePathToPose goal="{goal}" path="{path}"/>'
        '</RateController><FollowPath path="{path}"/></PipelineSequence>',
    )
    m = pipeline.load(xml, pipeline.CompileOptions(models=(models,), btcpp=version))
    assert m.nav2 == distro
    assert {"PipelineSequence", "RateController"} <= {i for i, s in m.builtins.items() if s.builtin}
    # those reading ROS 2 for one fact are built in too (the fact is an input of the scenario)
    assert m.builtins["DistanceController"].builtin and "DistanceController" not in {s.id for s in m.models}


def test_rename_table():
    assert [r.to for r in nav2.renames("jazzy", "lyrical") if r.port == ""] == [
        "ValidatePath",
        "CheckStopStatus",
        "CheckPoseOccupancy",
    ]
    assert nav2.renames("jazzy", "kilted") == ()
    assert any(r.port == "wrap_around" for r in nav2.renames("kilted", "lyrical"))


# ----------------------------------------------------------------------- the C++ engine
# Cases the C++ back end refuses, with a located error (the interpreter runs them).
CPP_REFUSED: dict[str, str] = {}  # (none: both engines run every case)


def _cpp_cases():
    every = os.environ.get("BTGEN_NAV2_CPP", "") == "all"
    out = []
    for distro, version, stem in RECORDINGS:
        expected, refused = _expected(distro, version, stem)
        if refused is not None:
            continue  # a tree the distro cannot load: the front end refuses it (interpreter test)
        if stem in ENV_CASES and not every:
            # the same trace everywhere (test_env_cases_...): one case per node, on one distro
            if (distro, version) == ("lyrical", "4.6.2") and stem in ENV_CPP_SAMPLE:
                out.append((distro, version, stem))
            continue
        if every or distro == "lyrical" or (distro == "jazzy" and expected != _expected("lyrical", version, stem)[0]):
            out.append((distro, version, stem))
    return out


# The cases of the Decorators that read ROS 2 (recorded with scripts/nav2_oracle/ros_shim.hpp).
ENV_CASES = [s for s in STEMS if s.startswith(("distance_", "speed_", "goal_updated_", "longer_"))]
ENV_CPP_SAMPLE = ("distance_child_fails", "speed_halted", "goal_updated_replans", "longer_on_approach")


def test_env_cases_record_the_same_everywhere():
    assert len(ENV_CASES) == 10
    for stem in ENV_CASES:
        first = _expected("lyrical", "4.6.2", stem)[0]
        assert first is not None
        for distro in nav2.DISTROS:
            for version in VERSIONS:
                assert _expected(distro, version, stem)[0] == first, (distro, version, stem)
    for distro in nav2.DISTROS:
        recorded = (NAV2 / f"{distro}-4.6.2" / "RECORDED.md").read_text()
        for src in ("distance_controller", "speed_controller", "goal_updated_controller", "path_longer_on_approach"):
            assert f"`plugins/decorator/{src}.cpp` | yes, with ros_shim.hpp" in recorded, (distro, src)


@pytest.mark.parametrize("distro,version,stem", _cpp_cases())
def test_cpp_engine_matches_recording(distro, version, stem):
    from btgen.tools.cppengine import build_cpp

    expected, _ = _expected(distro, version, stem)
    xml = str(CASES / f"{stem}.xml")
    if stem in CPP_REFUSED:
        with pytest.raises(UserError) as e:
            build_cpp(xml, opts=_opts(distro, version))
        assert CPP_REFUSED[stem] in str(e.value)
        assert f"{stem}.xml:" in str(e.value)
        return
    binary = build_cpp(xml, opts=_opts(distro, version))
    r = subprocess.run([str(binary), str(CASES / f"{stem}.scenario")], capture_output=True, check=False)
    assert r.returncode == 0, r.stderr.decode()
    assert r.stdout.decode("utf-8") == expected, _diff(expected, r.stdout.decode("utf-8"), "C++ engine")


def test_a_mission_implementing_them_itself_keeps_them():
    # tests/cpp/missions/user_nodes.xml declares PipelineSequence, RecoveryNode and RateController
    # as its own (test_user_nodes.cpp implements them): not Nav2's models file, nothing built in.
    m = pipeline.load(str(ROOT / "tests" / "cpp" / "missions" / "user_nodes.xml"))
    assert m.nav2 is None
    assert not m.spec("RecoveryNode").builtin and not m.spec("PipelineSequence").builtin


# ----------------------------------------------------------------------- random missions
# Random trees of Nav2's nodes and BehaviorTree.CPP's, with random leaf scripts and time: the
# C++ engine prints the interpreter's trace (the recordings tie the interpreter to Nav2's code).
# BTGEN_NAV2_RANDOM=N runs N missions (default 3, four scenarios each).
_CONTROLS = ("PipelineSequence", "RecoveryNode", "RoundRobin", "NonblockingSequence", "Sequence", "ReactiveSequence")
_DECORATORS = ("RateController", "SingleTrigger", "Inverter", "ForceSuccess", *sorted(nav2.ENV_NODES))


def _random_mission(rng, distro):
    leaves = []

    def node(depth):
        if depth >= 3 or rng.random() < 0.3:
            kind = "Condition" if rng.random() < 0.25 else "Action"
            name = f"{kind[0]}{len(leaves)}"
            leaves.append((kind, name))
            return f"<{name}/>"
        if rng.random() < 0.35:
            d = rng.choice(_DECORATORS)
            attrs = f' hz="{rng.choice(["2", "5", "10", "3.3"])}"' if d == "RateController" else ""
            if d in nav2.ENV_INPUTS:  # its input, scripted under its name (one per instance)
                name = f"{d}{len(leaves)}"
                leaves.append(("Input", name))
                attrs = f' name="{name}"'
            return f"<{d}{attrs}>{node(depth + 1)}</{d}>"
        c = rng.choice(_CONTROLS if distro == "lyrical" else _CONTROLS[:3] + _CONTROLS[4:])
        n = 2 if c == "RecoveryNode" else rng.randint(1, 3)
        attrs = ""
        if c == "RecoveryNode":
            attrs = f' number_of_retries="{rng.randint(0, 2)}"'
        elif c == "RoundRobin" and distro == "lyrical" and rng.random() < 0.5:
            attrs = f' wrap_around="{rng.choice(["true", "false"])}"'
        return f"<{c}{attrs}>{''.join(node(depth + 1) for _ in range(n))}</{c}>"

    body = node(0)
    models = "".join(f'<{k} ID="{n}"/>' for k, n in leaves if k != "Input")
    xml = (
        f'<root BTCPP_format="4"><BehaviorTree ID="Main">{body}</BehaviorTree>'
        f"<TreeNodesModel>{models}</TreeNodesModel></root>"
    )
    return xml, leaves


def _random_scenario(rng, leaves):
    lines = [f"ticks {rng.randint(4, 14)}", f"clock_ms {rng.choice([0, 40, 100, 150])}"]
    for kind, name in leaves:
        either = ("SUCCESS", "FAILURE")
        pool = either if kind in ("Condition", "Input") else (*either, "RUNNING", "RUNNING")
        lines.append(f"leaf {name} " + " ".join(rng.choice(pool) for _ in range(rng.randint(1, 6))))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("seed", range(int(os.environ.get("BTGEN_NAV2_RANDOM", "3"))))
def test_random_missions_both_engines(seed, tmp_path):
    import random

    from btgen.tools.cppengine import build_cpp

    rng = random.Random(seed)
    distro = ("lyrical", "jazzy")[seed % 2]
    version = VERSIONS[(seed // 2) % 2]
    xml, leaves = _random_mission(rng, distro)
    path = tmp_path / f"r{seed}.xml"
    path.write_text(xml)
    opts = _opts(distro, version)
    mission = pipeline.load(str(path), opts)
    binary = build_cpp(str(path), opts=opts)
    for k in range(4):
        sc = tmp_path / f"r{seed}_{k}.scenario"
        sc.write_text(_random_scenario(rng, leaves))
        expected = trace_text(mission, parse_scenario(str(sc)))
        r = subprocess.run([str(binary), str(sc)], capture_output=True, check=False)
        assert r.returncode == 0, r.stderr.decode()
        got = r.stdout.decode("utf-8")
        assert got == expected, f"{xml}\n{sc.read_text()}\n" + _diff(expected, got, "C++ engine")


@pytest.mark.parametrize(
    "setup",
    [
        "<Script code=\"rate := '2.5'\"/>",  # text, converted as getInput<double> converts it
        '<Script code="rate := 4"/>',  # an int entry
        "<AlwaysSuccess/>",  # the entry has no value: getInput fails, Nav2 keeps its local 1.0
    ],
)
def test_rate_controller_hz_from_the_blackboard_on_both_engines(setup, tmp_path):
    # Beyond the recorded `{rate}` case: what getInput<double> does with other entries, the
    # interpreter and the C++ engine alike; analyze says the limit comes from the entry.
    from btgen.tools.cppengine import build_cpp

    xml = tmp_path / "hz.xml"
    xml.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Main"><Sequence>' + setup + "<PipelineSequence>"
        '<RateController hz="{rate}"><Work/></RateController><Keep/></PipelineSequence></Sequence></BehaviorTree>'
        '<TreeNodesModel><Action ID="Work"/><Action ID="Keep"/></TreeNodesModel></root>'
    )
    sc = tmp_path / "hz.scenario"
    sc.write_text("ticks 30\nclock_ms 150\nleaf Keep RUNNING\n")
    opts = _opts("lyrical", "4.6.2")
    expected = trace_text(pipeline.load(str(xml), opts), parse_scenario(str(sc)))
    assert expected.count('Work "Work" IDLE -> SUCCESS') > 2
    r = subprocess.run([str(build_cpp(str(xml), opts=opts)), str(sc)], capture_output=True, check=False)
    assert r.returncode == 0, r.stderr.decode()
    assert r.stdout.decode() == expected, _diff(expected, r.stdout.decode(), "C++ engine")
    from btgen.cli import main

    assert main(["analyze", str(xml), "--nodes", "nav2"]) == 0
