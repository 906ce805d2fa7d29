"""`btgen tests`' scenarios on the real library in CI: behaviortreepy 0.1.4 (BehaviorTree.CPP 4.8.2).

No package registry ships BehaviorTree.CPP's headers, so CI cannot build the GoogleTest suites;
it runs the same scenarios through the library's Python bindings instead
(btgen/tools/gtests/btpy.py says how, and what the bindings do not allow). The expected status
changes are the interpreter's under 4.8.2's switches (versions.at_release).

Each test explores as `btgen tests` does and runs every scenario of the covering set: Reception
and Nav2's navigate_to_pose_w_bounds_check whole (default bounds), the Lab Tour on a partial
exploration (--max-states 1500; its full 68-scenario set, five minutes of exploration, with
BTGEN_BTPY_FULL=1; docs/tests.md gives the counts of the full runs).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from btgen import pipeline
from btgen.interp.scenario import format_scenario, parse_scenario_text
from btgen.lang.versions import at_release
from btgen.tools.explore import Explorer, _possible, scenario_text
from btgen.tools.gtests import btpy, mission_leaves

ROOT = Path(__file__).resolve().parents[2]
NAV2 = ROOT / "tests" / "real_files" / "nav2"
BOUNDS = NAV2 / "navigate_to_pose_w_bounds_check.xml"
NAV2_MODELS = str(NAV2 / "nav2_tree_nodes.xml")
CRIT = ROOT / "tests" / "coverage" / "Criteria.xml"
FULL = os.environ.get("BTGEN_BTPY_FULL") == "1"


class _Args:
    def __init__(self, models=()):
        self.models = list(models)
        self.sync = []
        self.btcpp = "4.6.2"
        self.main_tree = None


def _explored(path: Path, models=(), criteria=("node", "outcome", "halt"), max_states=200000):
    options = pipeline.CompileOptions(models=tuple(models))
    mission = pipeline.load(str(path), options)
    args = _Args(models)
    ex = Explorer(mission, 8, 200, 0, max_states, (), _possible(mission, args), True, criteria=criteria)
    result = ex.explore()
    texts = [scenario_text(p, 0) for p in result.paths]
    return options, [(f"{path.stem}-{i:03d}", parse_scenario_text(t)) for i, t in enumerate(texts, start=1)]


def _check_all(path: Path, options, scenarios) -> list[btpy.Outcome]:
    outcomes = btpy.compare(str(path), scenarios, options)
    assert len(outcomes) == len(scenarios)
    bad = [f"{o.name}: {o.message}" for o in outcomes if not o.ok]
    assert bad == []
    return outcomes


def test_reception_on_the_library():
    options, scenarios = _explored(ROOT / "missions" / "Reception.xml")
    assert len(scenarios) == 36
    outcomes = _check_all(ROOT / "missions" / "Reception.xml", options, scenarios)
    # its leaves' ports are removed for the bindings, and that changes none of the runs
    assert outcomes[0].stripped and "IsVisitorDetected" not in outcomes[0].stripped
    assert not any(o.differs_from_462 for o in outcomes)


def test_nav2_tree_on_the_library():
    options, scenarios = _explored(BOUNDS, [NAV2_MODELS])
    assert len(scenarios) == 4
    _check_all(BOUNDS, options, scenarios)


def test_lab_tour_on_the_library():
    lab = ROOT / "missions" / "LabTour.xml"
    options, scenarios = _explored(lab, max_states=200000 if FULL else 1500)
    for name in ("LabTour.yes", "LabTour.no"):
        text = (ROOT / "missions" / "scenarios" / f"{name}.scenario").read_text()
        scenarios.append((name, parse_scenario_text(text)))
    assert len(scenarios) >= (70 if FULL else 10)
    _check_all(lab, options, scenarios)


def test_conditions_and_scripts_on_the_library():
    """Pre- and post-conditions and `&&`/`||` scripts: the criteria's own scenarios."""
    options, scenarios = _explored(CRIT, criteria=("node", "outcome", "halt", "condition", "mcdc"))
    assert len(scenarios) == 5
    outcomes = _check_all(CRIT, options, scenarios)
    assert not any(o.stripped for o in outcomes)


def test_a_4_7_switch_is_followed(tmp_path):
    """`Repeat num_cycles="0"`: 4.6.2 returns SKIPPED, 4.7.0 and later SUCCESS
    (loop_end_never_skipped). The library (4.8.2) agrees with the 4.8.2 expectation, which
    differs from 4.6.2's."""
    mission = tmp_path / "repeat0.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>'
        '<Repeat num_cycles="0"><Work/></Repeat><Work name="After"/></Sequence></BehaviorTree>'
        '<TreeNodesModel><Action ID="Work"/></TreeNodesModel></root>'
    )
    options = pipeline.CompileOptions()
    (outcome,) = _check_all(mission, options, [("one", parse_scenario_text("ticks 3\n"))])
    assert outcome.differs_from_462
    assert "Repeat RUNNING -> SUCCESS" in outcome.library  # 4.6.2: Repeat never leaves IDLE
    assert at_release("4.8.2").loop_end_never_skipped and not at_release("4.8.2").script_grammar_49


def test_an_edited_mission_fails(tmp_path):
    """The comparison can fail: the library runs the tree with its ReactiveSequence turned into
    a Sequence, the expectation is the mission's."""
    options, scenarios = _explored(BOUNDS, [NAV2_MODELS])
    edited = tmp_path / BOUNDS.name
    edited.write_text(BOUNDS.read_text().replace("ReactiveSequence", "Sequence"))
    mission = pipeline.load(str(BOUNDS), options)
    leaves = mission_leaves(mission)
    at = btpy.mission_at(mission, btpy.VERSION)
    from btgen.interp.engine import trace_text

    different = 0
    for _, sc in scenarios:
        text, _ = btpy.strip_leaf_ports(edited.read_text(), {leaf.id for leaf in leaves})
        stripped = tmp_path / "stripped.xml"
        stripped.write_text(text)
        changes, results = btpy.run_on_library(str(stripped), leaves, sc, None)
        expected = btpy.lines_of_trace(trace_text(at, sc))
        different += changes + [f"result {r}" for r in results] != [
            line for line in expected if not line.startswith("result ")
        ] + [line for line in expected if line.startswith("result ")]
    assert different >= 1


def test_strip_leaf_ports():
    text = (
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence name="s">'
        '<Go name="g" target="{t}" _skipIf="x"/><Action ID="Go" speed="3"/></Sequence></BehaviorTree></root>'
    )
    out, removed = btpy.strip_leaf_ports(text, {"Go"})
    assert removed == ["g.target", "Go.speed"]
    assert 'target="' not in out and 'speed="' not in out and '_skipIf="x"' in out and 'name="s"' in out
    assert btpy.strip_leaf_ports(text, {"Other"}) == (text, [])


@pytest.mark.parametrize("bad", ["4.6.1", "4.11.0"])
def test_at_release_bounds(bad):
    with pytest.raises(ValueError):
        at_release(bad)


def test_a_nav2_control_is_a_located_refusal(capsys, tmp_path):
    """Nav2's PipelineSequence is no node of the library's, and the bindings register no Control:
    the command says so at the mission, exit 1, no traceback."""
    tree = NAV2 / "navigate_w_replanning_time.xml"
    options, scenarios = _explored(tree, [NAV2_MODELS], max_states=200)
    sc = scenarios[0][1]
    path = tmp_path / "one.scenario"
    path.write_text(format_scenario(sc.ticks, [(s.name, list(s.statuses)) for s in sc.leaves], 0, ""))
    assert btpy.main([str(tree), "--models", NAV2_MODELS, str(path)]) == 1
    err = capsys.readouterr().err
    assert f"{tree}:1:1: error: BehaviorTree.CPP 4.8.2 (behaviortreepy) refuses it: " in err
    assert "PipelineSequence" in err and "Traceback" not in err
