"""`btgen upgrade-check`: where moving from 4.6.2 to 4.10.0 changes a mission, as warnings,
and with --scenario the first tick where the two traces part; exit 1 when anything changes."""

import os
import subprocess
import sys

from conftest import ROOT

CASES = os.path.join(ROOT, "tests", "conformance", "btcpp-4.10.0")


def check(stem, *extra):
    args = [sys.executable, "-m", "btgen", "upgrade-check", os.path.join(CASES, stem + ".xml"), *extra]
    return subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=120, check=False)


def case(stem, ext):
    return os.path.join(CASES, stem + ext)


def test_precedence_change_is_named_with_the_release():
    p = check("v410_s1_or_and_precedence")
    assert p.returncode == 1
    assert p.stderr == (
        f"{case('v410_s1_or_and_precedence', '.xml')}:6:45: warning: 4.9.0 parses `a || b && c` in `code` of "
        "`ScriptCondition` as `(a || (b && c))` (before: `((a || b) && c)`)\n"
    )


def test_scenario_prints_the_first_tick_where_the_traces_part():
    p = check("v410_r1_while_sequence", "--scenario", case("v410_r1_while_sequence", ".scenario"))
    assert p.returncode == 1
    assert "the traces part at tick 3:\n" in p.stdout
    assert '  4.6.2: 5 Sequence "Inner" RUNNING -> SUCCESS\n' in p.stdout
    assert '  4.10.0: 5 Sequence "Inner" RUNNING -> IDLE\n' in p.stdout
    assert "decides SKIPPED by counting the children skipped in this run" in p.stderr


def test_refusals_of_484_are_listed():
    p = check("v410_x1_tree_id_with_space")
    assert p.returncode == 1
    assert (
        "warning: refused from BehaviorTree.CPP 4.8.4: BehaviorTree ID `Go There` contains the forbidden character "
        "` `: rename it `Go_There`" in p.stderr
    )


def test_subtree_literal_typed_and_switch_prefix():
    p = check("v410_b1_string_port_type_clash")
    assert p.returncode == 1
    assert 'stores the SubTree literal mode="2" as an int' in p.stderr
    assert "refuses to load this" in p.stderr
    # the Switch variable is written by a Script: only running the mission shows the change
    p = check("v410_r10_switch_prefix_string", "--scenario", case("v410_r10_switch_prefix_string", ".scenario"))
    assert p.returncode == 1
    assert "the traces part at tick 1:" in p.stdout


def test_nothing_changes_exits_0():
    p = check("seq_basic", "--scenario", case("seq_basic", ".scenario"))
    assert p.returncode == 0, p.stderr
    assert p.stderr == ""
    assert "the traces of 4.6.2 and 4.10.0 are the same" in p.stdout
    assert "nothing changes from BehaviorTree.CPP 4.6.2 to 4.10.0" in p.stdout


def test_a_mission_that_does_not_load_is_an_input_error(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><Nope/></BehaviorTree></root>\n')
    p = subprocess.run(
        [sys.executable, "-m", "btgen", "upgrade-check", str(bad)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert p.returncode == 1
    assert p.stderr.startswith(f"{bad}:1:")
    assert "Traceback" not in p.stderr


def test_setblackboard_into_an_entry_port_key_is_named():
    """4.10.0 throws where SetBlackboard writes a string into WasEntryUpdated's BT::Any entry
    (recorded: v410_e1_set_blackboard_first, v410_e1_copy_keeps_bt_any); the finding names the
    watcher, and --scenario shows the run parting at that node."""
    for stem, line in (("v410_e1_set_blackboard_first", 4), ("v410_e1_copy_keeps_bt_any", 8)):
        p = check(stem)
        assert p.returncode == 1
        named = [x for x in p.stderr.splitlines() if 'is also the `entry` of `WasEntryUpdated` "Seen"' in x]
        assert len(named) == 1 and named[0].startswith(f"{case(stem, '.xml')}:{line}:"), p.stderr
        assert "convertFromString<BT::Any> throws" in named[0]
    p = check("v410_e1_set_blackboard_first", "--scenario", case("v410_e1_set_blackboard_first", ".scenario"))
    assert '4.10.0: error: `SetBlackboard` "Text"' in p.stdout + p.stderr
    # without the watcher, no such finding
    assert "is also the `entry`" not in check("v410_b2_copy_into_unsigned").stderr
