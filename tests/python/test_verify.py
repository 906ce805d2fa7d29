"""`btgen verify`: SPIN's verdicts on missions with a known answer, counterexamples that replay on
both engines and show the violation, located errors, and agreement with `btgen explore`."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from btgen import pipeline
from btgen.cli import main
from btgen.diagnostics import Loc, UserError
from btgen.tools.verify import load_contract, run_properties
from btgen.tools.verify import props as P
from btgen.tools.verify import replay as R
from btgen.tools.verify.agree import agreement
from btgen.tools.verify.promela import ModelOptions, Refusal, emit_model
from verify_missions import GRASP, write_mission

ROOT = Path(__file__).resolve().parents[2]


# Two branches of a ReactiveFallback: the second is halted whenever the first runs.
GUARD = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveFallback>
      <Sequence><Battery name="Low"/><Dock/></Sequence>
      <Repeat num_cycles="2"><Patrol/></Repeat>
    </ReactiveFallback>
  </BehaviorTree>
  <TreeNodesModel>
    <Condition ID="Battery"/>
    <Action ID="Dock"/>
    <Action ID="Patrol"/>
  </TreeNodesModel>
</root>
"""

# A Control of the mission's own: its tick() is robot code, refused without a contract.
USER_CONTROL = GRASP.replace("<AlwaysFailure/>", "<Gate><AlwaysFailure/></Gate>").replace(
    '<Action ID="Place"/>', '<Action ID="Place"/>\n    <Control ID="Gate"/>'
)

# Counterexamples every test of this module produced: the last test replays them all on the C++.
PRODUCED: list[tuple[str, R.Counterexample, pipeline.CompileOptions]] = []


def _mission(tmp_path: Path, text: str, name: str = "m.xml") -> str:
    return write_mission(tmp_path, text, name)


def _props(program, *texts: str, mission=None) -> list[P.Property]:
    from btgen.tools.verify.blackboard import build_tables, entries_of

    names = P.Names(program, entries_of(build_tables(mission, program)) if mission is not None else None)
    return [P.parse_property(t, Loc("<test>", 1, 1), names, i) for i, t in enumerate(texts)]


def _verdicts(tmp_path, path, texts, compile_options=pipeline.DEFAULTS, **options):
    mission, program = pipeline.build(path, compile_options)
    results = run_properties(
        mission,
        program,
        _props(program, *texts, mission=mission),
        ModelOptions(print_states=True, **options),
        str(tmp_path / "w"),
    )
    for _prop, _res, cx in results:
        if cx is not None:
            PRODUCED.append((path, cx, compile_options))
    return {prop.text: (res.holds, cx) for prop, res, cx in results}


def test_known_verdicts_and_counterexamples_that_show_the_violation(tmp_path):
    path = _mission(tmp_path, GRASP)
    v = _verdicts(
        tmp_path,
        path,
        [
            "absence(returned(Place, FAILURE))",  # Place may fail: violated in one tick
            "[] !running(Grasp)",  # Grasp may run
            "response(returned(Ready, FAILURE), root(FAILURE))",  # the Sequence fails with its first child
            "[] !(running(Grasp) && running(Place))",  # a Sequence runs one child at a time
            "mutex(Grasp, Place)",  # never ticked in the same tick? Grasp can succeed, then Place runs
            "<> root(SUCCESS)",  # Ready may fail for ever
            "[] (returned(Grasp, FAILURE) -> !returned(Place, SUCCESS))",
        ],
    )
    assert v["response(returned(Ready, FAILURE), root(FAILURE))"][0] is True
    assert v["[] !(running(Grasp) && running(Place))"][0] is True
    for text in ("absence(returned(Place, FAILURE))", "[] !running(Grasp)", "mutex(Grasp, Place)", "<> root(SUCCESS)"):
        holds, cx = v[text]
        assert holds is False and cx is not None, text
        assert cx.problems == [] and cx.shown_interp, (text, cx.problems)
    # Grasp fails once (the retry runs it again from IDLE on the next tick), then succeeds and
    # Place succeeds in the same tick: the property is violated
    holds, cx = v["[] (returned(Grasp, FAILURE) -> !returned(Place, SUCCESS))"]
    assert holds is False and cx.shown_interp
    # the counterexample of mutex: Grasp and Place both ticked in one tick, as the trace shows
    cx = v["mutex(Grasp, Place)"][1]
    last = cx.trace.split("tick ")[-1]
    assert '"Grasp"' in last and '"Place"' in last


def test_bounds_contracts_and_fairness_decide_liveness(tmp_path):
    path = _mission(tmp_path, GUARD)
    mission, program = pipeline.build(path)
    contract = tmp_path / "c.json"
    contract.write_text('{"Low": ["FAILURE"]}', encoding="utf-8")
    never_low = load_contract(str(contract), program)
    ends = "<> (root(SUCCESS) || root(FAILURE))"
    free = _verdicts(tmp_path, path, [ends, "[] (running(Dock) -> !running(Patrol))"])
    assert free[ends][0] is False  # Patrol may answer RUNNING for ever
    assert free["[] (running(Dock) -> !running(Patrol))"][0] is True  # the reactive node halts the other
    assert free[ends][1].shown_interp and free[ends][1].problems == []
    # RUNNING bounded is not enough: Low may flip every tick, restarting Dock and Patrol in turn
    flip = _verdicts(tmp_path, path, [ends], running_bound=2)
    assert flip[ends][0] is False and flip[ends][1].shown_interp
    # ... with Low never holding (a contract), the run ends
    assert _verdicts(tmp_path, path, [ends], running_bound=2, contract=never_low)[ends][0] is True
    assert _verdicts(tmp_path, path, ["absence(ticked(Dock))"], contract=never_low)["absence(ticked(Dock))"][0]


def test_failure_bound_and_fairness_template(tmp_path):
    path = _mission(tmp_path, GRASP)
    mission, program = pipeline.build(path)
    contract = tmp_path / "c.json"
    contract.write_text('{"Ready": ["SUCCESS"], "Place": ["SUCCESS", "RUNNING"]}', encoding="utf-8")
    c = load_contract(str(contract), program)
    goal = "<> root(SUCCESS)"
    # Grasp may fail twice: the retry gives up
    assert _verdicts(tmp_path, path, [goal], running_bound=1, contract=c)[goal][0] is False
    # failing at most once in a row, Grasp succeeds within the two attempts
    assert _verdicts(tmp_path, path, [goal], running_bound=1, failure_bound=1, contract=c)[goal][0] is True
    # the same under fairness of Grasp and Place (LTL): no, a fair Grasp may still fail twice in a row
    fair = "eventually_success(Grasp, Place)"
    assert _verdicts(tmp_path, path, [fair], contract=c)[fair][0] is False


def test_lasso_counterexample_loops_on_both_views(tmp_path):
    """`[]<> ticked(X)` is false when X can be starved for ever: a lasso, unrolled twice."""
    path = _mission(tmp_path, GUARD)
    mission, program = pipeline.build(path)
    contract = tmp_path / "c.json"
    contract.write_text('{"Patrol": ["RUNNING"], "Dock": ["RUNNING"]}', encoding="utf-8")  # the run never ends
    v = _verdicts(tmp_path, path, ["[] <> ticked(Dock)"], contract=load_contract(str(contract), program))
    holds, cx = v["[] <> ticked(Dock)"]
    assert holds is False and cx.shown_interp and cx.problems == []
    assert cx.loop < cx.ticks


def test_command_line_output_files_and_exit_status(tmp_path, capsys):
    path = _mission(tmp_path, GRASP)
    out_dir = tmp_path / "cx"
    rc = main(["verify", path, "--property", "[] !running(Grasp)", "--counterexample", str(out_dir)])
    out, err = capsys.readouterr()
    assert rc == 1
    assert "VIOLATED  [] !running(Grasp)" in out and "states " in out and "depth " in out
    assert "replayed on the interpreter: the violation shows" in out
    stem = out_dir / "m-p0"
    scenario = (out_dir / "m-p0.scenario").read_text()
    assert "leaf Grasp" in scenario
    log = (out_dir / "m-p0.btlog").read_bytes()
    assert log.startswith(b"BTCPP4-FileLogger2\x01")
    # the .btlog gives back the scenario's run (btgen scenario-from-log checks every record)
    rc = main(["scenario-from-log", path, str(stem) + ".btlog", "-o", str(tmp_path / "back.scenario")])
    assert rc == 0, capsys.readouterr().err
    capsys.readouterr()
    assert main(["run", path, "--scenario", str(tmp_path / "back.scenario")]) == 0
    assert capsys.readouterr().out == (out_dir / "m-p0.trace").read_text()
    rc = main(["verify", path, "--property", "[] !(running(Grasp) && running(Place))"])
    out, _ = capsys.readouterr()
    assert rc == 0 and "holds     [] !(running(Grasp) && running(Place))" in out


@pytest.mark.parametrize(
    "prop, col, message",
    [
        ("[] running(Nope)", 12, "no node is named `Nope`"),
        ("X ticked(Ready)", 1, "`X` (next) is not supported"),
        ("[] (ticked(Ready)", 18, "expected `)`"),
        ("[] level > 3", 4, "`level` is no blackboard entry the mission's scripts write on the root blackboard"),
        ("returned(Ready, DONE)", 17, "expected a status"),
    ],
)
def test_property_errors_are_located(tmp_path, capsys, prop, col, message):
    path = _mission(tmp_path, GRASP)
    rc = main(["verify", path, "--property", prop])
    err = capsys.readouterr().err
    start = len(path) + len("verify --property ") + 2
    assert rc == 1 and f"<command-line>:1:{start + col - 1}: error: {message}" in err, err


def test_ambiguous_name_lists_the_candidates(tmp_path, capsys):
    path = _mission(tmp_path, GRASP.replace("<Place/>", '<Grasp name="Place"/>'))
    props = tmp_path / "p.ltl"
    props.write_text("# a comment\nsafe: [] !running(Grasp)\n", encoding="utf-8")
    rc = main(["verify", path, "--properties", str(props)])
    err = capsys.readouterr().err
    assert rc == 1
    assert f'{props}:2:19: error: `Grasp` names 2 nodes: #4 (Grasp "Grasp"), #6 (Grasp "Place")' in err
    props.write_text("[] !running(#4)\n", encoding="utf-8")
    assert main(["verify", path, "--properties", str(props)]) == 1  # #4 may run


def test_refused_nodes_are_located_errors(tmp_path, capsys):
    path = _mission(tmp_path, USER_CONTROL)
    rc = main(["verify", path, "--property", "[] !running(Grasp)"])
    err = capsys.readouterr().err
    assert rc == 1 and f'{path}:6:25: error: `Gate` "Gate": btgen verify does not translate a Control of the' in err
    # a script read from the blackboard: no table can be made of it
    path = _mission(tmp_path, GRASP.replace("<AlwaysFailure/>", '<Script code="{x}"/>'), "s.xml")
    assert main(["verify", path, "--property", "[] !running(Grasp)"]) == 1
    err = capsys.readouterr().err
    assert f'{path}:6:39: error: `code` of `Script` "Script" reads its script from blackboard' in err


def test_leaf_names_a_scenario_cannot_carry_are_refused(tmp_path, capsys):
    shared = GRASP.replace('<Check name="Ready"/>', '<Check name="Grasp"/>')
    path = _mission(tmp_path, shared)
    assert main(["verify", path, "--property", "[] !running(#4)"]) == 1
    err = capsys.readouterr().err
    assert f'{path}:4:7: error: Condition "Grasp" shares its name with an Action' in err
    # with a contract that keeps the Action from RUNNING, the scenario is valid: verified
    c = tmp_path / "c.json"
    c.write_text('{"Grasp": ["SUCCESS", "FAILURE"]}', encoding="utf-8")
    assert main(["verify", path, "--property", "[] !running(#4)", "--contract", str(c)]) == 0
    capsys.readouterr()
    path = _mission(tmp_path, GRASP.replace('<Check name="Ready"/>', '<Check name="Ready now"/>'), "b.xml")
    assert main(["verify", path, "--property", "[] !running(Grasp)"]) == 1
    assert "a counterexample is a scenario, which names a leaf by one word" in capsys.readouterr().err


def test_contract_errors(tmp_path):
    path = _mission(tmp_path, GRASP)
    _, program = pipeline.build(path)
    c = tmp_path / "c.json"
    for text, message in (
        ('{"Ready": ["RUNNING"]}', "1:2: error: `Ready` (Condition) cannot return `RUNNING`"),
        (
            '{"Redy": ["SUCCESS"]}',
            "1:2: error: the contract names `Redy`, which is no leaf of the mission (did you mean `Ready`?)",
        ),
        ('{"Ready": [}', "1:12: error: not JSON"),
    ):
        c.write_text(text, encoding="utf-8")
        with pytest.raises(UserError) as e:
            load_contract(str(c), program)
        assert str(e.value.diagnostics[0]).startswith(f"{c}:{message}"), str(e.value.diagnostics[0])


def test_lasso_evaluation_by_hand():
    a, b = ("atom", ("ticked", 0)), ("atom", ("ticked", 1))
    frames = [{("ticked", 0): True}, {("ticked", 1): True}, {}]
    assert P.holds_on_lasso(("F", b), frames, 2)
    assert not P.holds_on_lasso(("G", ("F", b)), frames, 2)  # the loop is the last frame: b never again
    assert P.holds_on_lasso(("G", ("F", b)), frames, 1)  # the loop is frames 1, 2: b forever often
    assert P.holds_on_lasso(("U", a, b), frames, 2)
    assert not P.holds_on_lasso(("U", b, a), frames[1:], 0)
    assert P.holds_on_lasso(("W", ("const", True), ("const", False)), frames, 0)
    assert P.start_insensitive(("G", ("not", a))) and not P.start_insensitive(("G", a))


AGREE_SEEDS = (3, 18, 21)
SCRIPT_SEEDS = (5, 8, 9)  # fuzzgen `full` missions whose scripts the model translates


@pytest.mark.parametrize("seed", AGREE_SEEDS)
def test_tick_states_agree_with_explore_on_random_missions(tmp_path, seed):
    from btgen.tools.fuzzgen import random_case

    path = _mission(tmp_path, random_case(seed, "control", 1).mission)
    mission, program = pipeline.build(path)
    a = agreement(mission, program, 3, 20, str(tmp_path / "w"))
    assert not a.explore_truncated and a.explore_states == a.spin_states and len(a.spin_states) > 10


def test_atomic_subtrees_store_fewer_states_and_reach_the_same_tick_ends(tmp_path):
    """A subtree with few paths through a tick is one atomic step: SPIN stores fewer states,
    and the tick-end states are those of the model without atomic steps (and explore's)."""
    from btgen.tools.fuzzgen import random_case
    from btgen.tools.verify.agree import spin_tick_states

    path = _mission(tmp_path, random_case(18, "control", 1).mission)
    mission, program = pipeline.build(path)
    plain, plain_res = spin_tick_states(mission, program, 3, 20, str(tmp_path / "a"), atomic_paths=0)
    packed, packed_res = spin_tick_states(mission, program, 3, 20, str(tmp_path / "b"))
    text = emit_model(mission, program, ModelOptions(ticks=3))
    atomic = "atomic {\n"  # a subtree's tick (a halt's is `atomic { d_step {` either way)
    assert atomic in text and atomic not in emit_model(mission, program, ModelOptions(atomic_paths=0))
    assert plain == packed and len(packed) > 10
    assert packed_res.states < plain_res.states


# Nav2's Controls and Decorators (--nodes nav2): RateController at 5 Hz is 2 ticks of 100 ms.
NAV2 = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <RecoveryNode number_of_retries="1">
      <PipelineSequence>
        <Plan/>
        <RateController hz="5"><Compute/></RateController>
        <Follow/>
      </PipelineSequence>
      <RoundRobin><Clear/><Spin/><Near/></RoundRobin>
    </RecoveryNode>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Plan"/><Action ID="Compute"/><Action ID="Follow"/>
    <Action ID="Clear"/><Action ID="Spin"/><Condition ID="Near"/>
  </TreeNodesModel>
</root>
"""


@pytest.mark.parametrize("nodes", ["nav2", "nav2:lyrical"])
def test_nav2_nodes_agree_with_explore(tmp_path, nodes):
    """PipelineSequence, RecoveryNode, RoundRobin (wrapping, and lyrical's round that ends at the
    last child) and RateController: the same tick-end states as explore."""
    path = _mission(tmp_path, NAV2)
    mission, program = pipeline.build(path, pipeline.CompileOptions(nodes=nodes))
    a = agreement(mission, program, 6, 100, str(tmp_path / "w"))
    assert not a.explore_truncated and a.explore_states == a.spin_states and len(a.spin_states) >= 8


def test_nav2_verdicts_and_a_counterexample(tmp_path):
    path = _mission(tmp_path, NAV2)
    v = _verdicts(
        tmp_path,
        path,
        ["absence(ticked(Spin))", "[] (ticked(Clear) -> !ticked(Plan))", "absence(returned(Compute, SKIPPED))"],
        pipeline.CompileOptions(nodes="nav2"),
        running_bound=1,
    )
    assert v["absence(ticked(Spin))"][0] is False and v["absence(ticked(Spin))"][1].shown_interp
    assert v["[] (ticked(Clear) -> !ticked(Plan))"][0] is False  # a recovery, then Plan again in one tick
    assert v["absence(returned(Compute, SKIPPED))"][0] is True


# Scripts: a Script, a ScriptCondition, pre-conditions (_successIf, _skipIf) and post-conditions.
SCRIPTS = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="mode := 'idle'; armed := false"/>
      <RetryUntilSuccessful num_attempts="3">
        <Sequence>
          <Script code="armed = !armed"/>
          <Grasp _successIf="armed == false" _onFailure="mode = 'failed'" _onSuccess="mode = 'holding'"/>
        </Sequence>
      </RetryUntilSuccessful>
      <ScriptCondition code="mode == 'holding'"/>
      <Place _skipIf="mode == 'idle'" _while="armed"/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Grasp"/><Action ID="Place"/></TreeNodesModel>
</root>
"""


def test_scripts_agree_with_explore_and_their_counterexamples_replay(tmp_path):
    from btgen.tools.verify.blackboard import build_tables

    path = _mission(tmp_path, SCRIPTS)
    mission, program = pipeline.build(path)
    tables = build_tables(mission, program)
    assert {"mode": "holding", "armed": 1} in tables.values and tables.count == 7
    a = agreement(mission, program, 6, 100, str(tmp_path / "a"))
    assert not a.explore_truncated and a.explore_states == a.spin_states and len(a.spin_states) >= 4
    v = _verdicts(
        tmp_path,
        path,
        ["absence(ticked(Place))", "absence(returned(ScriptCondition, FAILURE))", "absence(returned(Place, SKIPPED))"],
        running_bound=1,
    )
    assert v["absence(ticked(Place))"][0] is False and v["absence(ticked(Place))"][1].shown_interp
    # every SUCCESS of Grasp (its own or _successIf's) runs _onSuccess: mode is `holding` after the loop
    assert v["absence(returned(ScriptCondition, FAILURE))"][0] is True
    # _while="armed" skips Place when Grasp succeeded with `armed` false
    assert v["absence(returned(Place, SKIPPED))"][0] is False and v["absence(returned(Place, SKIPPED))"][1].shown_interp


def test_blackboard_atoms(tmp_path, capsys):
    """ENTRY OP VALUE over the root blackboard at tick ends: proved, or a counterexample that the
    interpreter's own blackboard shows (and the C++, in the last test)."""
    path = _mission(tmp_path, SCRIPTS)
    never_failed = "absence(mode == 'failed')"
    holding = "[] (ticked(Place) -> mode == 'holding')"
    both = "absence(mode == 'holding' && armed == false && root(SUCCESS))"
    v = _verdicts(tmp_path, path, [never_failed, holding, both, "[] (armed != 2)"], running_bound=1)
    assert v[never_failed][0] is False and v[never_failed][1].shown_interp
    assert v[holding][0] is True and v["[] (armed != 2)"][0] is True
    assert v[both][0] is False and v[both][1].shown_interp
    rc = main(["verify", path, "--property", "absence(mdoe == 'x')"])
    err = capsys.readouterr().err
    assert rc == 1 and "error: `mdoe` is no blackboard entry" in err and err.count("<command-line>:1:") == 1
    assert "(did you mean `mode`?)" in err
    assert main(["verify", path, "--property", "absence(mode == failed)"]) == 1
    assert "expected a value: a number, true, false or a 'string'" in capsys.readouterr().err


# A Condition the leaf contract makes a function of the blackboard: Low is SUCCESS when level is 'low'.
CONTRACT_BB = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="level := 'ok'"/>
      <ReactiveFallback>
        <Sequence><Battery name="Low"/><Dock/></Sequence>
        <Sequence><Patrol/><Script code="level = 'low'"/></Sequence>
      </ReactiveFallback>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Condition ID="Battery"/><Action ID="Dock"/><Action ID="Patrol"/></TreeNodesModel>
</root>
"""


def test_a_contract_makes_a_condition_a_function_of_the_blackboard(tmp_path, capsys):
    path = _mission(tmp_path, CONTRACT_BB)
    contract = tmp_path / "c.json"
    contract.write_text('{"Low": {"success_if": "level == \'low\'"}}', encoding="utf-8")
    prop = "[] (ticked(Dock) -> level == 'low')"
    # free, Low may answer SUCCESS at once: Dock is ticked while level is 'ok'
    assert main(["verify", path, "--running-bound", "1", "--property", prop]) == 1
    assert "VIOLATED  [] (ticked(Dock)" in capsys.readouterr().out
    args = ["verify", path, "--running-bound", "1", "--contract", str(contract), "--replay-cpp"]
    assert main([*args, "--property", prop, "--property", "absence(ticked(Dock))"]) == 0
    out = capsys.readouterr().out
    assert "holds     [] (ticked(Dock)" in out and "holds     absence(ticked(Dock))" in out
    assert main([*args, "--property", "absence(level == 'low')"]) == 1
    out = capsys.readouterr().out
    assert "VIOLATED  absence(level == 'low')" in out and "generated C++: the violation shows" in out
    contract.write_text('{"Dock": {"success_if": "true"}}', encoding="utf-8")
    assert main([*args, "--property", prop]) == 1
    assert 'c.json:1:2: error: `Dock`: a Condition\'s function of the blackboard is {"success_if": "SCRIPT"}' in (
        capsys.readouterr().err
    )
    contract.write_text('{"Low": {"success_if": "level = = 1"}}', encoding="utf-8")
    assert main([*args, "--property", prop]) == 1
    assert "c.json:1:2: error: `Low`: success_if `level = = 1` is not a script" in capsys.readouterr().err


def test_a_script_of_unbounded_values_is_refused_located(tmp_path):
    counter = SCRIPTS.replace('code="armed = !armed"', 'code="armed = !armed; n := 0; n += 1"').replace(
        "mode := 'idle'; armed := false", "mode := 'idle'; armed := false; n := 0"
    )
    counter = counter.replace('"n := 0; n += 1"', '"n += 1"').replace("armed = !armed; n := 0; n += 1", "n += 1")
    path = _mission(tmp_path, counter)
    mission, program = pipeline.build(path)
    with pytest.raises(Refusal) as e:
        emit_model(mission, program, ModelOptions())
    d = e.value.diagnostics[0]
    assert (d.loc.line, d.loc.col) == (7, 25) and "more than 250 values" in d.message


@pytest.mark.parametrize("seed", SCRIPT_SEEDS)
def test_scripts_of_random_missions_agree_with_explore(tmp_path, seed):
    from btgen.tools.fuzzgen import random_case

    path = _mission(tmp_path, random_case(seed, "full", 1).mission)
    mission, program = pipeline.build(path)
    a = agreement(mission, program, 3, 20, str(tmp_path / "w"), max_states=50000)
    assert "byte bb;" in (tmp_path / "w" / "model.pml").read_text()
    assert not a.explore_truncated and a.explore_states == a.spin_states


def test_rate_controller_without_a_countable_period_is_refused(tmp_path):
    path = _mission(tmp_path, NAV2.replace('hz="5"', 'hz="0"'))
    mission, program = pipeline.build(path, pipeline.CompileOptions(nodes="nav2"))
    with pytest.raises(Refusal) as e:
        emit_model(mission, program, ModelOptions())
    d = e.value.diagnostics[0]
    assert d.loc.line == 6 and "period of 1 to 250 ticks" in d.message


def test_rate_controller_period_in_ticks():
    from btgen.tools.verify.nav2 import rate_ticks

    assert rate_ticks(1.0, 100, 250) == 10 and rate_ticks(5.0, 100, 250) == 2 and rate_ticks(3.0, 100, 250) == 4
    assert rate_ticks(0.001, 100, 250) is None and rate_ticks(-1.0, 100, 250) == 0


def test_tick_states_agree_under_btcpp_4_10(tmp_path):
    """4.10.0's switches (SKIPPED counted, loops never ending SKIPPED) on both sides."""
    from btgen.tools.fuzzgen import random_case

    path = _mission(tmp_path, random_case(21, "control", 1).mission)
    mission, program = pipeline.build(path, pipeline.CompileOptions(btcpp="4.10.0"))
    assert mission.semantics.skipped_by_count
    a = agreement(mission, program, 3, 20, str(tmp_path / "w"))
    assert not a.explore_truncated and a.explore_states == a.spin_states and len(a.spin_states) > 10


@pytest.mark.parametrize("mission, ticks", [("PickPlaceBall.xml", 4), ("Reception.xml", 2)])
def test_tick_states_agree_with_explore_on_shipped_missions(tmp_path, mission, ticks):
    m, program = pipeline.build(str(ROOT / "missions" / mission))
    a = agreement(m, program, ticks, 100, str(tmp_path / "w"))
    assert not a.explore_truncated and a.explore_states == a.spin_states and len(a.spin_states) > 5


def test_a_long_random_agreement_run_behind_an_env_var(tmp_path):
    count = int(os.environ.get("BTGEN_VERIFY_AGREE", "0"))
    if not count:
        pytest.skip("set BTGEN_VERIFY_AGREE=N to compare N random missions with explore")
    from btgen.tools.fuzzgen import random_case

    compared = 0
    for seed in range(count):
        path = _mission(tmp_path, random_case(seed, "control", 1).mission, f"r{seed}.xml")
        mission, program = pipeline.build(path)
        try:
            a = agreement(mission, program, 3, 20, str(tmp_path / f"w{seed}"), max_states=50000)
        except Refusal:
            continue
        if a.explore_truncated:
            continue
        assert a.explore_states == a.spin_states, seed
        compared += 1
    assert compared > count // 2


def test_refusal_is_raised_before_any_model(tmp_path):
    path = _mission(tmp_path, USER_CONTROL)
    mission, program = pipeline.build(path)
    with pytest.raises(Refusal):
        emit_model(mission, program, ModelOptions())


def test_every_counterexample_replays_on_the_generated_cpp(tmp_path):
    """Runs last in this module: each counterexample the tests above produced, on the C++."""
    if not PRODUCED:  # run alone: make some
        path = _mission(tmp_path, GRASP)
        _verdicts(tmp_path, path, ["absence(returned(Place, FAILURE))", "[] <> ticked(Place)"])
    assert PRODUCED
    for k, (path, cx, opts) in enumerate(PRODUCED):
        if not os.path.exists(path):  # its tmp_path is gone: write the mission again
            continue
        mission, program = pipeline.build(path, opts)
        scen = tmp_path / f"cx{k}.scenario"
        scen.write_text(cx.scenario, encoding="utf-8")
        R.replay_cpp(cx, path, opts, str(scen), len(program.nodes))
        assert cx.shown_cpp and cx.problems == [], (path, cx.prop.text, cx.problems)
