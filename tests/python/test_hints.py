"""Hints for the mistakes of a mission split over files and of blackboard keys.

A forgotten `--models` (the first unknown node says so, and a node with children is not told
to be an Action), a model or a BehaviorTree that a file beside the mission declares (named,
with how to load it), a misspelt key in a script (did you mean), and a SubTree that reads an
entry its SubTree node does not remap (a warning: its blackboard is its own).
"""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT

MODELS = """<root BTCPP_format="4">
  <TreeNodesModel>
    <Condition ID="BatteryOk"/>
    <Action ID="MoveTo"><input_port name="goal" type="int"/></Action>
    <Decorator ID="AtMostTwice"/>
    <Control ID="Both"/>
  </TreeNodesModel>
</root>
"""

MISSION = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Both>
      <BatteryOk/>
      <AtMostTwice>
        <MoveTo goal="1"/>
      </AtMostTwice>
    </Both>
  </BehaviorTree>
</root>
"""


def btgen(*args, cwd):
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", *args], cwd=cwd, capture_output=True, text=True, timeout=120, check=False
    )
    return proc.returncode, proc.stdout, proc.stderr


def test_a_forgotten_models_file_is_named_once_and_kinds_follow_the_children(tmp_path):
    (tmp_path / "patrol.xml").write_text(MISSION)
    rc, _, err = btgen("validate", "patrol.xml", cwd=tmp_path)
    assert rc == 1
    lines = err.splitlines()
    unknown = "error: unknown node `{}`: it is neither built in nor declared in TreeNodesModel"
    assert lines == [
        f"patrol.xml:3:5: {unknown.format('Both')} "
        '(declare it as <Control ID="Both"/> (it has 2 children)); the mission declares no node models: '
        "if they are in a file of their own, pass it with `--models FILE.xml`",
        f"patrol.xml:4:7: {unknown.format('BatteryOk')} "
        '(declare it as <Action ID="BatteryOk"/> or <Condition ID="BatteryOk"/>)',
        f"patrol.xml:5:7: {unknown.format('AtMostTwice')} "
        '(declare it as <Decorator ID="AtMostTwice"/> (it has a child) or <Control ID="AtMostTwice"/>)',
        f'patrol.xml:6:9: {unknown.format("MoveTo")} (declare it as <Action ID="MoveTo"/> or <Condition ID="MoveTo"/>)',
    ]


def test_a_models_file_beside_the_mission_is_named_with_the_option_to_pass_it(tmp_path):
    (tmp_path / "mission").mkdir()
    (tmp_path / "mission" / "patrol.xml").write_text(MISSION)
    (tmp_path / "mission" / "nodes.xml").write_text(MODELS)
    (tmp_path / "mission" / "broken.xml").write_text("<root><unclosed></root>")  # skipped, not reported
    rc, _, err = btgen("validate", "mission/patrol.xml", cwd=tmp_path)
    assert rc == 1
    assert err.splitlines()[0] == (
        "mission/patrol.xml:3:5: error: unknown node `Both`: it is neither built in nor declared in "
        "TreeNodesModel; `mission/nodes.xml` beside it declares it: pass `--models mission/nodes.xml`"
    )
    assert len(err.splitlines()) == 4 and "broken" not in err
    rc, out, err = btgen("validate", "mission/patrol.xml", "--models", "mission/nodes.xml", cwd=tmp_path)
    assert (rc, err) == (0, "")


def test_the_user_project_example_without_models_is_told_to_pass_them():
    rc, _, err = btgen("validate", "examples/user_project/mission/patrol.xml", cwd=ROOT)
    assert rc == 1
    assert "pass `--models examples/user_project/mission/nodes.xml`" in err.splitlines()[0]


def test_a_tree_defined_beside_the_mission_is_pointed_to_with_its_include(tmp_path):
    (tmp_path / "main.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main">\n    <SubTree ID="Dock"/>\n  </BehaviorTree>\n</root>\n'
    )
    (tmp_path / "dock.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Dock">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n'
    )
    rc, _, err = btgen("validate", "main.xml", cwd=tmp_path)
    assert rc == 1
    assert err == (
        "main.xml:3:18: error: SubTree `Dock` does not exist: no BehaviorTree has that ID; `dock.xml` "
        'beside it defines it: add <include path="dock.xml"/> to <root>\n'
    )
    text = (tmp_path / "main.xml").read_text()
    (tmp_path / "main.xml").write_text(text.replace("  <BehaviorTree", '  <include path="dock.xml"/>\n  <BehaviorTree'))
    assert btgen("validate", "-q", "main.xml", cwd=tmp_path)[0] == 0


def test_a_script_reading_an_entry_the_subtree_node_does_not_remap(tmp_path):
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main">\n    <Sequence>\n      <Script code="target := 3"/>\n'
        '      <SubTree ID="GoTo"/>\n    </Sequence>\n  </BehaviorTree>\n'
        '  <BehaviorTree ID="GoTo">\n    <ScriptCondition code="target == 3"/>\n  </BehaviorTree>\n</root>\n'
    )
    rc, _, err = btgen("validate", "m.xml", cwd=tmp_path)
    assert rc == 0  # (a warning: the library loads it and throws when the script runs)
    assert err.endswith(
        "reads `target`, but nothing creates that blackboard entry: no port, script or SetBlackboard writes "
        "it (the calling tree's `target` is not seen here: the SubTree node does not remap it; add "
        'target="{target}" or _autoremap="true")\n'
    )


UNMAPPED = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="target := 3"/>
      <SubTree ID="GoTo"{attrs}/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="GoTo">
    <MoveTo goal="{{target}}"/>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="MoveTo"><input_port name="goal" type="int"/></Action>{model}
  </TreeNodesModel>
</root>
"""


def test_an_unmapped_subtree_port_is_a_warning_when_the_subtree_has_no_model(tmp_path):
    path = tmp_path / "m.xml"
    path.write_text(UNMAPPED.format(attrs="", model=""))
    rc, out, err = btgen("validate", "m.xml", cwd=tmp_path)
    assert rc == 0
    assert err == (
        "m.xml:5:7: warning: SubTree `GoTo` reads `{target}` (the `goal` port of `MoveTo` at m.xml:9:19), "
        "which this SubTree node does not remap: without `_autoremap` the SubTree has a blackboard of its "
        'own, so that is not `target` of `Main` (add target="{target}", or _autoremap="true")\n'
    )
    for attrs, model in (
        (' target="{target}"', ""),
        (' _autoremap="true"', ""),
        ("", '\n    <SubTree ID="GoTo"><input_port name="target" default="{target}"/></SubTree>'),
    ):
        path.write_text(UNMAPPED.format(attrs=attrs, model=model))
        assert btgen("validate", "m.xml", cwd=tmp_path)[2] == "", (attrs, model)
