"""Straight-line code shared by equal subtrees (btgen.backend_cpp.shapes, Engine::tick_node).

Nodes of one shape run one C++ function with their own index: each must still read and
write its own statuses, counters and timers. The missions here repeat shapes whose
instances the scenario drives differently (RUNNING in one, FAILURE in another, halts,
retries), and nest deeper than the straight-line code goes; the compiled executor must
give the reference interpreter's trace byte for byte, with the default budget and with a
budget of 3 (the interpreter boundary) and with one that shares the shapes' code.
"""

import subprocess

import pytest

from btgen.backend_cpp.shapes import COMPILED_DEPTH, NO_NODE, shapes
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import load_scenario
from btgen.ir.lower import lower
from btgen.tools.cppengine import build_cpp

MODELS = '<TreeNodesModel><Action ID="Act"/><Condition ID="Ok"/></TreeNodesModel>'


def _part(i: int) -> str:
    return (
        f'<ReactiveSequence name="R{i}"><Ok name="ok{i}"/>'
        f'<Fallback name="F{i}"><Act name="a{i}"/><Inverter><Act name="b{i}"/></Inverter></Fallback>'
        f'<RetryUntilSuccessful num_attempts="3"><Act name="c{i}"/></RetryUntilSuccessful>'
        f'<SubTree ID="Leg"/></ReactiveSequence>'
    )


REPEATED = (
    '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">'
    '<Repeat num_cycles="5"><Sequence name="Top">'
    + "".join(_part(i) for i in range(4))
    + "</Sequence></Repeat></BehaviorTree>"
    '<BehaviorTree ID="Leg"><Sequence><Act name="leg"/><ForceSuccess><Act name="legf"/></ForceSuccess>'
    "</Sequence></BehaviorTree>" + MODELS + "</root>\n"
)
REPEATED_SCENARIO = """ticks 14
default SUCCESS
leaf ok1 SUCCESS FAILURE SUCCESS
leaf a0 RUNNING SUCCESS FAILURE
leaf b0 FAILURE
leaf a2 FAILURE RUNNING FAILURE
leaf b2 RUNNING FAILURE SUCCESS
leaf c1 FAILURE FAILURE RUNNING SUCCESS
leaf c3 FAILURE FAILURE FAILURE SUCCESS
leaf leg RUNNING SUCCESS SUCCESS RUNNING FAILURE SUCCESS
leaf legf FAILURE RUNNING SUCCESS
"""

DEPTH = COMPILED_DEPTH + 12


def _deep() -> str:
    opening = "".join(f'<Sequence name="D{d}"><Act name="x{d}"/>' for d in range(DEPTH))
    closing = "</Sequence>" * DEPTH
    inner = '<Fallback><Act name="deepest"/><Act name="other"/></Fallback>'
    return (
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">'
        + opening
        + inner
        + closing
        + "</BehaviorTree>"
        + MODELS
        + "</root>\n"
    )


DEEP_SCENARIO = """ticks 8
default SUCCESS
leaf x3 SUCCESS RUNNING SUCCESS
leaf x50 RUNNING SUCCESS FAILURE SUCCESS
leaf deepest FAILURE RUNNING SUCCESS
leaf other RUNNING FAILURE
"""


def _write(tmp_path, stem, xml, scenario):
    mission = tmp_path / f"{stem}.xml"
    mission.write_text(xml)
    sc = tmp_path / f"{stem}.scenario"
    sc.write_text(scenario)
    return str(mission), str(sc)


def test_equal_subtrees_share_a_shape_and_different_ones_do_not(tmp_path):
    mission, _ = _write(tmp_path, "repeated", REPEATED, REPEATED_SCENARIO)
    program = lower(load_mission(mission))
    s = shapes(program)
    by_name = {n.name: n.index for n in program.nodes}
    # The four parts are equal subtrees, the leaves within a part are of one model.
    assert len({s.of_node[by_name[f"R{i}"]] for i in range(4)}) == 1
    assert s.of_node[by_name["a0"]] == s.of_node[by_name["c3"]]
    assert s.of_node[by_name["F0"]] != s.of_node[by_name["R0"]]
    assert s.of_node[by_name["ok0"]] != s.of_node[by_name["a0"]]  # a Condition, not an Action
    # Each shape is numbered by its first node, which is its representative.
    for shape, rep in enumerate(s.rep):
        assert s.of_node[rep] == shape and s.of_node.index(shape) == rep
    assert sum(s.uses) == len(program.nodes)
    assert s.uses[s.of_node[by_name["R0"]]] == 4


def test_nodes_below_the_compiled_depth_share_the_interpreted_shape(tmp_path):
    mission, _ = _write(tmp_path, "deep", _deep(), DEEP_SCENARIO)
    program = lower(load_mission(mission))
    s = shapes(program)
    deep = {s.of_node[n.index] for n in program.nodes if n.depth - 1 >= COMPILED_DEPTH}
    assert len(deep) == 1
    assert s.rep[deep.pop()] == NO_NODE
    assert all(s.rep[s.of_node[n.index]] != NO_NODE for n in program.nodes if n.depth - 1 < COMPILED_DEPTH)


def _weight(n) -> int:
    """A node's weight in BTGEN_STRAIGHT_LINE_BUDGET (Engine::node_weight)."""
    scripted = n.scripts != 0 or n.kind in ("Script", "ScriptCondition", "Precondition")
    return (6 if scripted else 1) + len(n.children)


def _shared_budget(program) -> int:
    """A budget that compiles every shape once but is too small for a function per node, so
    the engine shares the shapes' code (Engine::kPerNode false)."""
    s = shapes(program)
    by_shapes = sum(_weight(program.nodes[r]) for r in s.rep if r != NO_NODE)
    by_nodes = sum(_weight(n) for n in program.nodes)
    assert by_shapes < by_nodes
    return by_shapes


# "": a function per node (the mission fits the default budget); "3": the root only, the rest
# on the interpreter; "shared": every shape compiled once, shared by its nodes.
@pytest.mark.parametrize("budget", ["", "3", "shared"])
@pytest.mark.parametrize("stem", ["repeated", "deep"])
def test_shared_code_keeps_every_node_s_own_state(stem, budget, tmp_path, monkeypatch):
    xml, scenario_text = (REPEATED, REPEATED_SCENARIO) if stem == "repeated" else (_deep(), DEEP_SCENARIO)
    mission, scenario = _write(tmp_path, stem, xml, scenario_text)
    if budget == "shared":
        budget = str(_shared_budget(lower(load_mission(mission))))
    if budget:
        monkeypatch.setenv("BTGEN_STRAIGHT_LINE_BUDGET", budget)
    m = load_mission(mission)
    sc, _ = load_scenario(scenario, m)
    expected = trace_text(m, sc)
    proc = subprocess.run([str(build_cpp(mission)), scenario], capture_output=True, check=False)
    assert (proc.returncode, proc.stderr.decode()) == (0, "")
    assert proc.stdout.decode() == expected
