"""Reference interpreter: semantics the recorded conformance cases do not cover.

Every expected trace below was worked out by hand from BehaviorTree.CPP 4.6.2's
sources (the function followed is named in each test), not by running the
interpreter. Time comes from the scenario's `clock_ms`: the clock advances by
that much before every tick after the first, and 4.6.2's timer threads become
deadlines checked when the node is ticked.
"""

import os
import subprocess
import sys
import time

import pytest

from btgen.frontend.loader import load_mission
from btgen.interp.controls import switch_equal
from btgen.interp.engine import Interpreter, trace_text
from btgen.interp.scenario import load_scenario, parse_scenario_text
from btgen.interp.tree import RunError, quote_name
from btgen.lang.status import NodeStatus
from btgen.tools.synth import balanced_mission, count_nodes

MODELS = """
    <Action ID="Work"/>
    <Action ID="Prep"/>
    <Action ID="A"/>
    <Action ID="B"/>
    <Action ID="C"/>
    <Condition ID="IsSafe"/>
    <Condition ID="Check"/>
"""


def mission_file(tmp_path, trees, main="Main", name="m.xml"):
    text = (
        f'<root BTCPP_format="4" main_tree_to_execute="{main}">\n{trees}\n'
        f"  <TreeNodesModel>{MODELS}  </TreeNodesModel>\n</root>\n"
    )
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def tree(body, tree_id="Main"):
    return f'  <BehaviorTree ID="{tree_id}">\n{body}\n  </BehaviorTree>'


def run(tmp_path, trees, scenario):
    path = mission_file(tmp_path, trees)
    sp = tmp_path / "s.scenario"
    sp.write_text(scenario, encoding="utf-8")
    mission = load_mission(path)
    sc, warnings = load_scenario(str(sp), mission)
    assert warnings == []
    return trace_text(mission, sc)


def lines(*rows):
    return "".join(r + "\n" for r in rows)


# ------------------------------------------------------------------ time
def test_sleep_on_the_virtual_clock(tmp_path):
    """SleepNode::onStart (RUNNING, timer of msec) / onRunning (SUCCESS once the timer fired)."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="S">
      <Sleep name="Nap" msec="250"/>
      <Work/>
    </Sequence>"""),
        "ticks 10\nclock_ms 100\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "S" IDLE -> RUNNING',
        '2 Sleep "Nap" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",
        "result RUNNING",  # t = 100
        "tick 3",
        "result RUNNING",  # t = 200
        "tick 4",  # t = 300 >= 250
        '2 Sleep "Nap" RUNNING -> SUCCESS',
        '3 Work "Work" IDLE -> SUCCESS',
        '2 Sleep "Nap" SUCCESS -> IDLE',
        '3 Work "Work" SUCCESS -> IDLE',
        '1 Sequence "S" RUNNING -> SUCCESS',
        '1 Sequence "S" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_sleep_zero_succeeds_at_once_and_without_clock_never_wakes(tmp_path):
    """SleepNode::onStart returns SUCCESS for msec 0; with clock_ms 0 time stands still."""
    got = run(
        tmp_path,
        tree("""
    <Fallback name="F">
      <Sleep name="Long" msec="5"/>
      <Sleep name="Zero" msec="0"/>
    </Fallback>"""),
        "ticks 3\n",
    )
    assert got == lines(
        "tick 1",
        '1 Fallback "F" IDLE -> RUNNING',
        '2 Sleep "Long" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",
        "result RUNNING",
        "tick 3",
        "result RUNNING",
    )


def test_timeout_halts_its_child_when_time_is_up(tmp_path):
    """TimeoutNode::tick: the timer (here a deadline) halts the RUNNING child (haltChild) and the
    node returns FAILURE."""
    got = run(
        tmp_path,
        tree("""
    <Timeout name="Limit" msec="150">
      <Work/>
    </Timeout>"""),
        "ticks 10\nclock_ms 100\nleaf Work RUNNING\n",
    )
    assert got == lines(
        "tick 1",
        '1 Timeout "Limit" IDLE -> RUNNING',
        '2 Work "Work" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",
        "result RUNNING",  # t = 100 < 150
        "tick 3",  # t = 200
        '2 Work "Work" RUNNING -> IDLE',
        '1 Timeout "Limit" RUNNING -> FAILURE',
        '1 Timeout "Limit" FAILURE -> IDLE',
        "result FAILURE",
    )


def test_timeout_child_finishing_in_time(tmp_path):
    """TimeoutNode::tick: a completed child cancels the timer and is reset before the node's
    own status is set."""
    got = run(
        tmp_path,
        tree("""
    <Timeout name="Limit" msec="500">
      <Work/>
    </Timeout>"""),
        "ticks 10\nclock_ms 100\nleaf Work RUNNING SUCCESS\n",
    )
    assert got == lines(
        "tick 1",
        '1 Timeout "Limit" IDLE -> RUNNING',
        '2 Work "Work" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",
        '2 Work "Work" RUNNING -> SUCCESS',
        '2 Work "Work" SUCCESS -> IDLE',
        '1 Timeout "Limit" RUNNING -> SUCCESS',
        '1 Timeout "Limit" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_timeout_restarts_after_completion(tmp_path):
    """TimeoutNode: timeout_started_ is cleared on completion, so a new run gets a new deadline."""
    got = run(
        tmp_path,
        tree("""
    <Repeat name="Twice" num_cycles="2">
      <Timeout name="Limit" msec="150">
        <Work/>
      </Timeout>
    </Repeat>"""),
        "ticks 10\nclock_ms 100\nleaf Work RUNNING SUCCESS RUNNING SUCCESS\n",
    )
    # Repeat: the child succeeded from RUNNING (not IDLE), so the next cycle starts in the same tick.
    assert got == lines(
        "tick 1",
        '1 Repeat "Twice" IDLE -> RUNNING',
        '2 Timeout "Limit" IDLE -> RUNNING',
        '3 Work "Work" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",  # t = 100: first run ends in time
        '3 Work "Work" RUNNING -> SUCCESS',
        '3 Work "Work" SUCCESS -> IDLE',
        '2 Timeout "Limit" RUNNING -> SUCCESS',
        '2 Timeout "Limit" SUCCESS -> IDLE',
        '2 Timeout "Limit" IDLE -> RUNNING',
        '3 Work "Work" IDLE -> RUNNING',
        "result RUNNING",
        "tick 3",  # t = 200: only 100 ms into the second run
        '3 Work "Work" RUNNING -> SUCCESS',
        '3 Work "Work" SUCCESS -> IDLE',
        '2 Timeout "Limit" RUNNING -> SUCCESS',
        '2 Timeout "Limit" SUCCESS -> IDLE',
        '1 Repeat "Twice" RUNNING -> SUCCESS',
        '1 Repeat "Twice" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_delay_waits_then_ticks_its_child(tmp_path):
    """DelayNode::tick: RUNNING until the delay timer fired, then the child."""
    got = run(
        tmp_path,
        tree("""
    <Delay name="Wait" delay_msec="200">
      <Work/>
    </Delay>"""),
        "ticks 10\nclock_ms 100\n",
    )
    assert got == lines(
        "tick 1",
        '1 Delay "Wait" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",
        "result RUNNING",  # t = 100
        "tick 3",  # t = 200
        '2 Work "Work" IDLE -> SUCCESS',
        '2 Work "Work" SUCCESS -> IDLE',
        '1 Delay "Wait" RUNNING -> SUCCESS',
        '1 Delay "Wait" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_delay_halted_starts_over(tmp_path):
    """DelayNode::halt clears delay_started_, so a halted Delay waits its whole delay again;
    RetryNode::tick retries in the same tick when the child failed from RUNNING."""
    got = run(
        tmp_path,
        tree("""
    <RetryUntilSuccessful name="Retry" num_attempts="3">
      <ReactiveSequence name="R">
        <IsSafe/>
        <Delay name="Wait" delay_msec="150">
          <Work/>
        </Delay>
      </ReactiveSequence>
    </RetryUntilSuccessful>"""),
        "ticks 10\nclock_ms 100\nleaf IsSafe SUCCESS FAILURE SUCCESS\n",
    )
    assert got == lines(
        "tick 1",  # t = 0: the delay ends at 150
        '1 RetryUntilSuccessful "Retry" IDLE -> RUNNING',
        '2 ReactiveSequence "R" IDLE -> RUNNING',
        '3 IsSafe "IsSafe" IDLE -> SUCCESS',
        '4 Delay "Wait" IDLE -> RUNNING',
        '3 IsSafe "IsSafe" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 2",  # t = 100: the guard fails, the Delay is halted, the retry starts it again (ends at 250)
        '3 IsSafe "IsSafe" IDLE -> FAILURE',
        '3 IsSafe "IsSafe" FAILURE -> IDLE',
        '4 Delay "Wait" RUNNING -> IDLE',
        '2 ReactiveSequence "R" RUNNING -> FAILURE',
        '2 ReactiveSequence "R" FAILURE -> IDLE',
        '2 ReactiveSequence "R" IDLE -> RUNNING',
        '3 IsSafe "IsSafe" IDLE -> SUCCESS',
        '4 Delay "Wait" IDLE -> RUNNING',
        '3 IsSafe "IsSafe" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 3",  # t = 200 < 250
        '3 IsSafe "IsSafe" IDLE -> SUCCESS',
        '3 IsSafe "IsSafe" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 4",  # t = 300
        '3 IsSafe "IsSafe" IDLE -> SUCCESS',
        '5 Work "Work" IDLE -> SUCCESS',
        '5 Work "Work" SUCCESS -> IDLE',
        '4 Delay "Wait" RUNNING -> SUCCESS',
        '3 IsSafe "IsSafe" SUCCESS -> IDLE',
        '4 Delay "Wait" SUCCESS -> IDLE',
        '2 ReactiveSequence "R" RUNNING -> SUCCESS',
        '2 ReactiveSequence "R" SUCCESS -> IDLE',
        '1 RetryUntilSuccessful "Retry" RUNNING -> SUCCESS',
        '1 RetryUntilSuccessful "Retry" SUCCESS -> IDLE',
        "result SUCCESS",
    )


# -------------------------------------------------------------- Parallel
def test_parallel_skipped_children_count_as_successes_with_negative_threshold(tmp_path):
    """ParallelNode::tick: with success_count < 0, success_count + skipped reaching the threshold
    succeeds."""
    got = run(
        tmp_path,
        tree("""
    <Parallel name="P" success_count="-1" failure_count="1">
      <A/>
      <B _skipIf="true"/>
    </Parallel>"""),
        "ticks 3\n",
    )
    assert got == lines(
        "tick 1",
        '1 Parallel "P" IDLE -> RUNNING',
        '2 A "A" IDLE -> SUCCESS',
        '2 A "A" SUCCESS -> IDLE',
        '1 Parallel "P" RUNNING -> SUCCESS',
        '1 Parallel "P" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_parallel_all_children_skipped_is_skipped_and_the_run_goes_on(tmp_path):
    """ParallelNode::tick returns SKIPPED when every child skipped (positive threshold); a SKIPPED
    root does not end the run and its RUNNING status (set before ticking) stays."""
    got = run(
        tmp_path,
        tree("""
    <Parallel name="P" success_count="1" failure_count="1">
      <A _skipIf="true"/>
      <B _skipIf="true"/>
    </Parallel>"""),
        "ticks 3\n",
    )
    assert got == lines(
        "tick 1",
        '1 Parallel "P" IDLE -> RUNNING',
        "result SKIPPED",
        "tick 2",
        "result SKIPPED",
        "tick 3",
        "result SKIPPED",
    )


def test_parallel_negative_failure_count_waits_for_all_failures(tmp_path):
    """ParallelNode::failureThreshold: -1 of 3 children is 3."""
    got = run(
        tmp_path,
        tree("""
    <Parallel name="P" success_count="1" failure_count="-1">
      <A/>
      <B/>
      <C/>
    </Parallel>"""),
        "ticks 5\nleaf A FAILURE\nleaf B FAILURE\nleaf C RUNNING RUNNING FAILURE\n",
    )
    assert got == lines(
        "tick 1",
        '1 Parallel "P" IDLE -> RUNNING',
        '2 A "A" IDLE -> FAILURE',
        '3 B "B" IDLE -> FAILURE',
        '4 C "C" IDLE -> RUNNING',
        "result RUNNING",
        "tick 2",
        "result RUNNING",
        "tick 3",
        '4 C "C" RUNNING -> FAILURE',
        '2 A "A" FAILURE -> IDLE',
        '3 B "B" FAILURE -> IDLE',
        '4 C "C" FAILURE -> IDLE',
        '1 Parallel "P" RUNNING -> FAILURE',
        '1 Parallel "P" FAILURE -> IDLE',
        "result FAILURE",
    )


def test_parallel_threshold_above_children_is_a_run_time_error(tmp_path):
    """ParallelNode::tick throws "Number of children is less than threshold"."""
    path = mission_file(
        tmp_path,
        tree("""
    <Parallel name="P" success_count="3">
      <A/>
      <B/>
    </Parallel>"""),
    )
    mission = load_mission(path)
    parts = []
    with pytest.raises(RunError) as e:
        from btgen.interp.engine import run_trace

        run_trace(mission, parse_scenario_text("ticks 2\n"), parts.append)
    assert "".join(parts) == "tick 1\n"
    assert [str(d) for d in e.value.diagnostics] == [
        f'{path}:4:39: error: `Parallel` "P" needs 3 successes but has only 2 children: it can never succeed'
    ]


# --------------------------------------------------------- SubTree halting
def test_halt_travels_through_nested_subtrees_running_on_halted(tmp_path):
    """ControlNode::resetChildren -> TreeNode::haltNode (halt(), then _onHalted) -> DecoratorNode::halt
    (resetChild, resetStatus) down to StatefulActionNode::halt; children are reset before their
    parent, and a SubTree's _onHalted runs after its own reset."""
    trees = (
        tree("""
    <Sequence name="Main">
      <ForceSuccess>
        <ReactiveSequence name="Guard">
          <IsSafe/>
          <SubTree ID="Job" name="JobA" _autoremap="true" _onHalted="halted := inner + 1"/>
        </ReactiveSequence>
      </ForceSuccess>
      <ScriptCondition name="Verify" code="halted == 3 &amp;&amp; inner == 2"/>
    </Sequence>""")
        + "\n"
        + tree(
            """
    <Sequence name="Steps">
      <Prep/>
      <SubTree ID="Inner" name="InnerA" _autoremap="true"/>
    </Sequence>""",
            "Job",
        )
        + "\n"
        + tree(
            """
    <Work _onHalted="inner := 2"/>""",
            "Inner",
        )
    )
    got = run(tmp_path, trees, "ticks 5\nleaf IsSafe SUCCESS SUCCESS FAILURE\nleaf Work RUNNING\n")
    assert got == lines(
        "tick 1",
        '1 Sequence "Main" IDLE -> RUNNING',
        '2 ForceSuccess "ForceSuccess" IDLE -> RUNNING',
        '3 ReactiveSequence "Guard" IDLE -> RUNNING',
        '4 IsSafe "IsSafe" IDLE -> SUCCESS',
        '5 SubTree "JobA" IDLE -> RUNNING',
        '6 Sequence "Steps" IDLE -> RUNNING',
        '7 Prep "Prep" IDLE -> SUCCESS',
        '8 SubTree "InnerA" IDLE -> RUNNING',
        '9 Work "Work" IDLE -> RUNNING',
        '4 IsSafe "IsSafe" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 2",
        '4 IsSafe "IsSafe" IDLE -> SUCCESS',
        '4 IsSafe "IsSafe" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 3",
        '4 IsSafe "IsSafe" IDLE -> FAILURE',
        '4 IsSafe "IsSafe" FAILURE -> IDLE',
        '7 Prep "Prep" SUCCESS -> IDLE',
        '9 Work "Work" RUNNING -> IDLE',
        '8 SubTree "InnerA" RUNNING -> IDLE',
        '6 Sequence "Steps" RUNNING -> IDLE',
        '5 SubTree "JobA" RUNNING -> IDLE',
        '3 ReactiveSequence "Guard" RUNNING -> FAILURE',
        '3 ReactiveSequence "Guard" FAILURE -> IDLE',
        '2 ForceSuccess "ForceSuccess" RUNNING -> SUCCESS',
        '10 ScriptCondition "Verify" IDLE -> SUCCESS',
        '2 ForceSuccess "ForceSuccess" SUCCESS -> IDLE',
        '10 ScriptCondition "Verify" SUCCESS -> IDLE',
        '1 Sequence "Main" RUNNING -> SUCCESS',
        '1 Sequence "Main" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_subtree_blackboards_are_isolated_without_remapping(tmp_path):
    """recursivelyCreateSubtree: a SubTree gets a new blackboard; without remapping or _autoremap
    its keys are its own, with `x="{y}"` its `x` is the parent's `y`. SubTreeNode::tick resets a
    completed child before the SubTree's own status is set."""
    trees = (
        tree("""
    <Sequence name="Main">
      <Script name="Init" code="x := 1; y := 1"/>
      <SubTree ID="Sub" name="Plain"/>
      <SubTree ID="Sub" name="Mapped" x="{y}"/>
      <ScriptCondition name="Verify" code="x == 1 &amp;&amp; y == 11"/>
    </Sequence>""")
        + "\n"
        + tree(
            """
    <Script name="Bump" code="x := 10; x += 1"/>""",
            "Sub",
        )
    )
    got = run(tmp_path, trees, "ticks 1\n")
    assert got == lines(
        "tick 1",
        '1 Sequence "Main" IDLE -> RUNNING',
        '2 Script "Init" IDLE -> SUCCESS',
        '3 SubTree "Plain" IDLE -> RUNNING',
        '4 Script "Bump" IDLE -> SUCCESS',
        '4 Script "Bump" SUCCESS -> IDLE',
        '3 SubTree "Plain" RUNNING -> SUCCESS',
        '5 SubTree "Mapped" IDLE -> RUNNING',
        '6 Script "Bump" IDLE -> SUCCESS',
        '6 Script "Bump" SUCCESS -> IDLE',
        '5 SubTree "Mapped" RUNNING -> SUCCESS',
        '7 ScriptCondition "Verify" IDLE -> SUCCESS',
        '2 Script "Init" SUCCESS -> IDLE',
        '3 SubTree "Plain" SUCCESS -> IDLE',
        '5 SubTree "Mapped" SUCCESS -> IDLE',
        '7 ScriptCondition "Verify" SUCCESS -> IDLE',
        '1 Sequence "Main" RUNNING -> SUCCESS',
        '1 Sequence "Main" SUCCESS -> IDLE',
        "result SUCCESS",
    )


# ------------------------------------------------------ pre-conditions
def test_while_skips_an_idle_node_and_halts_a_running_one(tmp_path):
    """TreeNode::checkPreConditions: IDLE and _while false -> SKIPPED without ticking; RUNNING and
    _while false -> haltNode() (halt, then _onHalted) and SKIPPED; SKIPPED is never stored."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="Main">
      <Script name="Init" code="n := 0"/>
      <A name="Never" _while="n &gt; 0"/>
      <ReactiveSequence name="Loop">
        <Script name="Count" code="n += 1"/>
        <B name="Busy" _while="n &lt; 3" _onHalted="stopped := n"/>
      </ReactiveSequence>
      <ScriptCondition name="Verify" code="stopped == 3"/>
    </Sequence>"""),
        "ticks 10\nleaf Never FAILURE\nleaf Busy RUNNING\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "Main" IDLE -> RUNNING',
        '2 Script "Init" IDLE -> SUCCESS',
        '4 ReactiveSequence "Loop" IDLE -> RUNNING',
        '5 Script "Count" IDLE -> SUCCESS',
        '6 B "Busy" IDLE -> RUNNING',
        '5 Script "Count" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 2",
        '5 Script "Count" IDLE -> SUCCESS',
        '5 Script "Count" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 3",
        '5 Script "Count" IDLE -> SUCCESS',
        '6 B "Busy" RUNNING -> IDLE',
        '5 Script "Count" SUCCESS -> IDLE',
        '4 ReactiveSequence "Loop" RUNNING -> SUCCESS',
        '7 ScriptCondition "Verify" IDLE -> SUCCESS',
        '2 Script "Init" SUCCESS -> IDLE',
        '4 ReactiveSequence "Loop" SUCCESS -> IDLE',
        '7 ScriptCondition "Verify" SUCCESS -> IDLE',
        '1 Sequence "Main" RUNNING -> SUCCESS',
        '1 Sequence "Main" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_pre_condition_order_and_post_conditions_on_decided_ticks(tmp_path):
    """checkPreConditions goes _failureIf, _successIf, _skipIf, _while; a decided status still runs
    checkPostConditions (_onSuccess/_onFailure, then _post)."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="Main">
      <Script name="Init" code="log := ''"/>
      <ForceSuccess>
        <A name="Both" _successIf="true" _failureIf="true" _onFailure="log := log .. 'f'" _post="log := log .. 'p'"/>
      </ForceSuccess>
      <B name="Ok" _skipIf="true" _successIf="true" _onSuccess="log := log .. 's'"/>
      <ScriptCondition name="Verify" code="log == 'fps'"/>
    </Sequence>"""),
        "ticks 1\nleaf Both SUCCESS\nleaf Ok FAILURE\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "Main" IDLE -> RUNNING',
        '2 Script "Init" IDLE -> SUCCESS',
        '3 ForceSuccess "ForceSuccess" IDLE -> RUNNING',
        '4 A "Both" IDLE -> FAILURE',
        '4 A "Both" FAILURE -> IDLE',
        '3 ForceSuccess "ForceSuccess" RUNNING -> SUCCESS',
        '5 B "Ok" IDLE -> SUCCESS',
        '6 ScriptCondition "Verify" IDLE -> SUCCESS',
        '2 Script "Init" SUCCESS -> IDLE',
        '3 ForceSuccess "ForceSuccess" SUCCESS -> IDLE',
        '5 B "Ok" SUCCESS -> IDLE',
        '6 ScriptCondition "Verify" SUCCESS -> IDLE',
        '1 Sequence "Main" RUNNING -> SUCCESS',
        '1 Sequence "Main" SUCCESS -> IDLE',
        "result SUCCESS",
    )


# ------------------------------------------- conditions that may not skip
@pytest.mark.parametrize("control", ["IfThenElse", "WhileDoElse"])
def test_skipped_condition_is_an_error(tmp_path, control):
    """IfThenElseNode::tick throws "Something unexpected happened" and WhileDoElseNode::tick ends
    in setStatus(IDLE) when the condition is SKIPPED; btgen reports an error at the condition
    (FORMAT.md), after the lines already printed."""
    path = mission_file(
        tmp_path,
        tree(f"""
    <{control} name="Choose">
      <Check _skipIf="true"/>
      <A/>
      <B/>
    </{control}>"""),
    )
    (tmp_path / "s.scenario").write_text("ticks 3\n")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "m.xml", "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 1
    assert proc.stdout == lines("tick 1", f'1 {control} "Choose" IDLE -> RUNNING')
    assert proc.stderr.splitlines() == [
        f"m.xml:5:7: error: the condition of this `{control}` returned SKIPPED, which makes "
        f"BehaviorTree.CPP throw (a condition child must not be skippable)"
    ]
    assert os.path.exists(path)


# ------------------------------------------------------------ Precondition
def test_precondition_false_while_running_returns_else_without_halting(tmp_path):
    """PreconditionNode::tick (4.6.2) evaluates `if` on every tick; when it turns false it returns
    `else` and neither ticks nor halts its RUNNING child (later releases changed this)."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="Main">
      <Script name="Init" code="k := 0"/>
      <ReactiveSequence name="R">
        <Script name="Flip" code="k += 1; ok := k &lt; 2"/>
        <Precondition name="Gate" if="ok" else="FAILURE">
          <Work/>
        </Precondition>
      </ReactiveSequence>
    </Sequence>"""),
        "ticks 5\nleaf Work RUNNING\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "Main" IDLE -> RUNNING',
        '2 Script "Init" IDLE -> SUCCESS',
        '3 ReactiveSequence "R" IDLE -> RUNNING',
        '4 Script "Flip" IDLE -> SUCCESS',
        '6 Work "Work" IDLE -> RUNNING',
        '5 Precondition "Gate" IDLE -> RUNNING',
        '4 Script "Flip" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 2",
        '4 Script "Flip" IDLE -> SUCCESS',
        '5 Precondition "Gate" RUNNING -> FAILURE',
        '4 Script "Flip" SUCCESS -> IDLE',
        '5 Precondition "Gate" FAILURE -> IDLE',
        '3 ReactiveSequence "R" RUNNING -> FAILURE',
        '2 Script "Init" SUCCESS -> IDLE',
        '3 ReactiveSequence "R" FAILURE -> IDLE',
        '1 Sequence "Main" RUNNING -> FAILURE',
        '1 Sequence "Main" FAILURE -> IDLE',
        "result FAILURE",
    )


# ---------------------------------------------------------------- Loop
def test_literal_loop_queue_is_fresh_on_every_start(tmp_path):
    """LoopNode::tick copies the literal queue when it starts from IDLE (4.7.0 behaviour that
    FORMAT.md asks for; 4.6.2 emptied it for good)."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="Main">
      <Script name="Init" code="sum := 0"/>
      <Repeat name="Twice" num_cycles="2">
        <LoopInt name="Each" queue="1;2" value="{v}">
          <Script name="Add" code="sum += v"/>
        </LoopInt>
      </Repeat>
      <ScriptCondition name="Verify" code="sum == 6"/>
    </Sequence>"""),
        "ticks 20\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "Main" IDLE -> RUNNING',
        '2 Script "Init" IDLE -> SUCCESS',
        '3 Repeat "Twice" IDLE -> RUNNING',
        '4 LoopInt "Each" IDLE -> RUNNING',
        '5 Script "Add" IDLE -> SUCCESS',
        '5 Script "Add" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 2",
        '5 Script "Add" IDLE -> SUCCESS',
        '5 Script "Add" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 3",  # queue empty: if_empty SUCCESS; Repeat starts the loop again from IDLE at once
        '4 LoopInt "Each" RUNNING -> SUCCESS',
        '4 LoopInt "Each" SUCCESS -> IDLE',
        '4 LoopInt "Each" IDLE -> RUNNING',
        '5 Script "Add" IDLE -> SUCCESS',
        '5 Script "Add" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 4",
        '5 Script "Add" IDLE -> SUCCESS',
        '5 Script "Add" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 5",
        '4 LoopInt "Each" RUNNING -> SUCCESS',
        '4 LoopInt "Each" SUCCESS -> IDLE',
        '3 Repeat "Twice" RUNNING -> SUCCESS',
        '6 ScriptCondition "Verify" IDLE -> SUCCESS',  # sum == 1 + 2 + 1 + 2
        '2 Script "Init" SUCCESS -> IDLE',
        '3 Repeat "Twice" SUCCESS -> IDLE',
        '6 ScriptCondition "Verify" SUCCESS -> IDLE',
        '1 Sequence "Main" RUNNING -> SUCCESS',
        '1 Sequence "Main" SUCCESS -> IDLE',
        "result SUCCESS",
    )


# ------------------------------------------------------------ Switch
@pytest.mark.parametrize(
    "a,b,equal",
    [
        ("kitchen", "kitchen", True),
        ("kitchen", "lab", False),
        ("2", "2.000000", True),  # a double read as a string compares as a number
        ("12abc", "12", True),  # std::from_chars stops at the first non-digit
        ("1e2", "100", True),
        ("2.5", "3.5", False),
        ("2.5", "2.50000001", True),
        ("0.1", "0.9", True),  # both read as the integer 0 first: 4.6.2 calls them equal
        ("-3", "-3.0", True),
        ("+3", "3", False),
        (" 3", "3", False),
        ("", "0", False),
    ],
)
def test_switch_string_equality(a, b, equal):
    """switch_node.cpp CheckStringEquality: text, then from_chars int, then from_chars double within
    float epsilon."""
    assert switch_equal(a, b) is equal
    assert switch_equal(b, a) is equal


# ------------------------------------------------------------- trace names
def test_quote_name_escapes():
    assert quote_name('a"b\\c') == '"a\\"b\\\\c"'
    assert quote_name("l1\nl2\rx\ty") == '"l1\\nl2\\rx\\ty"'
    assert quote_name("\x01\x1f\x7f") == '"\\x01\\x1F\\x7F"'
    assert quote_name("Küche 台所") == '"Küche 台所"'
    assert quote_name("") == '""'


def test_names_in_the_trace(tmp_path):
    got = run(
        tmp_path,
        tree("""
    <Sequence name="a&quot;b\\c&#10;d&#9;e&#127;é">
      <A name=""/>
      <SubTree ID="Other"/>
    </Sequence>""")
        + "\n"
        + tree("    <B/>", "Other"),
        "ticks 1\n",
    )
    assert got.splitlines()[1:5] == [
        '1 Sequence "a\\"b\\\\c\\nd\\te\\x7Fé" IDLE -> RUNNING',
        '2 A "" IDLE -> SUCCESS',
        '3 SubTree "Other" IDLE -> RUNNING',
        '4 B "B" IDLE -> SUCCESS',
    ]


# ------------------------------------------------------------ run-time errors
def test_script_error_points_into_the_attribute(tmp_path):
    """A script that fails at run time is reported at the failing operand, entities counted as
    written, after the trace lines already printed."""
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4">\n'
        '  <BehaviorTree ID="Main">\n'
        '    <Sequence name="Main">\n'
        '      <Script name="Init" code="a := \'x\'"/>\n'
        '      <ScriptCondition name="Bad" code="a &lt; 3 &amp;&amp; a"/>\n'
        "    </Sequence>\n"
        "  </BehaviorTree>\n"
        "</root>\n"
    )
    (tmp_path / "s.scenario").write_text("ticks 2\n")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "m.xml", "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 1
    assert proc.stdout == lines("tick 1", '1 Sequence "Main" IDLE -> RUNNING', '2 Script "Init" IDLE -> SUCCESS')
    assert len(proc.stderr.splitlines()) == 1
    assert proc.stderr.startswith('m.xml:5:43: error: script error in `code` of `ScriptCondition` "Bad": ')


# ------------------------------------------------------- balanced missions
@pytest.mark.parametrize("n", [1, 2, 3, 7, 50, 333])
def test_balanced_mission_visits_every_node_each_tick(tmp_path, n):
    text = balanced_mission(n)
    assert count_nodes(text) == n
    p = tmp_path / "big.xml"
    p.write_text(text)
    mission = load_mission(str(p))
    interp = Interpreter(mission, parse_scenario_text("ticks 3\n"))
    assert len(interp.nodes) == n
    for _ in range(3):
        assert interp.tick_once() is NodeStatus.SUCCESS
        uids = {int(line.split(" ", 1)[0]) for line in interp.take_lines()}
        assert uids == set(range(1, n + 1))
        assert all(node.status == 0 for node in interp.nodes)  # everything back to IDLE


def test_ten_thousand_nodes_tick_fast(tmp_path):
    """1,000 ticks of a 10,000-node mission must take under 10 s; this runs 100 ticks with the
    trace collected and allows 3 s of CPU (about 0.8 s expected)."""
    p = tmp_path / "big.xml"
    p.write_text(balanced_mission(10000))
    interp = Interpreter(load_mission(str(p)), parse_scenario_text("ticks 1000\n"))
    start = time.process_time()
    total = 0
    for _ in range(100):
        interp.tick_once()
        total += interp.take_text().count("\n")
    elapsed = time.process_time() - start
    assert total > 100 * 2 * 10000
    assert elapsed < 3.0, f"100 ticks of 10,000 nodes took {elapsed:.2f} s of CPU"


# ------------------------------------------------------ more built-ins
def test_keep_running_until_failure_with_a_skipped_child_stays_running(tmp_path):
    """KeepRunningUntilFailureNode::tick: a SKIPPED child falls to `return status()`, which is the
    RUNNING the node set before ticking."""
    got = run(
        tmp_path,
        tree("""
    <KeepRunningUntilFailure name="K">
      <A _skipIf="true"/>
    </KeepRunningUntilFailure>"""),
        "ticks 2\nleaf A FAILURE\n",
    )
    assert got == lines(
        "tick 1", '1 KeepRunningUntilFailure "K" IDLE -> RUNNING', "result RUNNING", "tick 2", "result RUNNING"
    )


def test_switch_on_a_double_entry(tmp_path):
    """SwitchNode::tick reads `variable` as a string (a double prints as 2.000000) and matches
    case_2 by CheckStringEquality; no RUNNING before the selected child is ticked."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="S">
      <Script name="Set" code="v := 2.0"/>
      <Switch3 name="Sw" variable="{v}" case_1="1" case_2="2" case_3="3">
        <A/>
        <B/>
        <C/>
        <AlwaysFailure name="Default"/>
      </Switch3>
    </Sequence>"""),
        "ticks 1\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "S" IDLE -> RUNNING',
        '2 Script "Set" IDLE -> SUCCESS',
        '5 B "B" IDLE -> SUCCESS',
        '5 B "B" SUCCESS -> IDLE',
        '3 Switch3 "Sw" IDLE -> SUCCESS',
        '2 Script "Set" SUCCESS -> IDLE',
        '3 Switch3 "Sw" SUCCESS -> IDLE',
        '1 Sequence "S" RUNNING -> SUCCESS',
        '1 Sequence "S" SUCCESS -> IDLE',
        "result SUCCESS",
    )


def test_loop_bool_fails_when_its_child_fails(tmp_path):
    """LoopNode<bool>::tick: one element per child run into `value`; RUNNING after a child
    SUCCESS, FAILURE (and the rest left) when the child fails."""
    got = run(
        tmp_path,
        tree("""
    <LoopBool name="L" queue="true;0;1" value="{b}">
      <ScriptCondition name="C" code="b"/>
    </LoopBool>"""),
        "ticks 5\n",
    )
    assert got == lines(
        "tick 1",
        '1 LoopBool "L" IDLE -> RUNNING',
        '2 ScriptCondition "C" IDLE -> SUCCESS',
        '2 ScriptCondition "C" SUCCESS -> IDLE',
        "result RUNNING",
        "tick 2",
        '2 ScriptCondition "C" IDLE -> FAILURE',
        '2 ScriptCondition "C" FAILURE -> IDLE',
        '1 LoopBool "L" RUNNING -> FAILURE',
        '1 LoopBool "L" FAILURE -> IDLE',
        "result FAILURE",
    )


def test_set_blackboard_output_key_read_through_an_entry(tmp_path):
    """SetBlackboardNode::tick reads `output_key` with getInput<std::string>: `{dest}` names the
    entry whose value is the key written."""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="S">
      <Script name="Init" code="dest := 'target'"/>
      <SetBlackboard name="Indirect" value="42" output_key="{dest}"/>
      <ScriptCondition name="Verify" code="target == 42"/>
    </Sequence>"""),
        "ticks 1\n",
    )
    assert got.splitlines()[-1] == "result SUCCESS"
    assert '4 ScriptCondition "Verify" IDLE -> SUCCESS' in got.splitlines()


def test_parallel_all_threshold_above_children_is_an_error(tmp_path):
    """ParallelAllNode::tick throws "Number of children is less than threshold. Can never fail."."""
    path = mission_file(
        tmp_path,
        tree("""
    <ParallelAll name="PA" max_failures="3">
      <A/>
      <B/>
    </ParallelAll>"""),
    )
    with pytest.raises(RunError) as e:
        trace_text(load_mission(path), parse_scenario_text("ticks 1\n"))
    assert [str(d) for d in e.value.diagnostics] == [
        f'{path}:4:42: error: `ParallelAll` "PA" fails after 3 failures but has only 2 children: it can never fail'
    ]


def test_deeply_nested_subtrees_run(tmp_path):
    """Three SubTrees, each 200 Inverters deep (600+ levels in all): no recursion limit is hit."""
    depth = 200
    trees = []
    for i in range(3):
        inner = f'<SubTree ID="T{i + 1}"/>' if i < 2 else "<AlwaysSuccess/>"
        trees.append(
            f'<BehaviorTree ID="T{i}">' + "<Inverter>" * depth + inner + "</Inverter>" * depth + "</BehaviorTree>"
        )
    (tmp_path / "deep.xml").write_text('<root BTCPP_format="4" main_tree_to_execute="T0">' + "".join(trees) + "</root>")
    (tmp_path / "s.scenario").write_text("ticks 1\n")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "deep.xml", "--scenario", "s.scenario"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = proc.stdout.splitlines()
    assert out[0] == "tick 1" and out[-1] == "result SUCCESS"
    assert '603 AlwaysSuccess "AlwaysSuccess" IDLE -> SUCCESS' in out  # 3 x 200 Inverters + 2 SubTrees first


def test_retry_reads_num_attempts_once_per_tick(tmp_path):
    """RetryNode::tick (4.6.2): getInput("num_attempts") once at the start of tick(); a child that
    lowers the entry and fails synchronously gets the wake-up RUNNING (1 < 3 with the value read),
    and the next tick reads 1 and fails without ticking the child. Re-reading the port after each
    failure (#905) is 4.7.0 and failed on tick 1. (The C++ back end needs a literal num_attempts,
    so this case is the interpreter's only.)"""
    got = run(
        tmp_path,
        tree("""
    <Sequence name="root">
      <Script name="init" code="n := 3"/>
      <RetryUntilSuccessful name="retry" num_attempts="{n}">
        <Sequence name="attempt">
          <Script name="lower" code="n = 1"/>
          <A name="try"/>
        </Sequence>
      </RetryUntilSuccessful>
    </Sequence>"""),
        "ticks 5\nleaf try FAILURE\n",
    )
    assert got == lines(
        "tick 1",
        '1 Sequence "root" IDLE -> RUNNING',
        '2 Script "init" IDLE -> SUCCESS',
        '3 RetryUntilSuccessful "retry" IDLE -> RUNNING',
        '4 Sequence "attempt" IDLE -> RUNNING',
        '5 Script "lower" IDLE -> SUCCESS',
        '6 A "try" IDLE -> FAILURE',
        '5 Script "lower" SUCCESS -> IDLE',
        '6 A "try" FAILURE -> IDLE',
        '4 Sequence "attempt" RUNNING -> FAILURE',
        '4 Sequence "attempt" FAILURE -> IDLE',
        "result RUNNING",
        "tick 2",
        '3 RetryUntilSuccessful "retry" RUNNING -> FAILURE',
        '2 Script "init" SUCCESS -> IDLE',
        '3 RetryUntilSuccessful "retry" FAILURE -> IDLE',
        '1 Sequence "root" RUNNING -> FAILURE',
        '1 Sequence "root" FAILURE -> IDLE',
        "result FAILURE",
    )
