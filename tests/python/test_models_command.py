"""`btgen models`: a <TreeNodesModel> inferred from how a mission uses its nodes, so that a
team whose nodes are registered only in C++ goes from "unknown node" to a compiled mission in
two commands."""

import os
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.frontend.loader import load_mission

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Pipeline>
      <RateLimit hz="10"><ComputePath goal="{goal}" path="{path}"/></RateLimit>
      <Recovery>
        <Action ID="Follow" path="{path}" speed="0.5"/>
        <Condition ID="IsStuck"/>
      </Recovery>
      <SubTree ID="Lent"/>
      <Follow path="{path}" name="again"/>
    </Pipeline>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Known"/>
  </TreeNodesModel>
</root>
"""
LIBRARY = """<root BTCPP_format="4">
  <BehaviorTree ID="Lent"><Sequence><Known/><Beep volume="3" _collapsed="true"/></Sequence></BehaviorTree>
</root>
"""

EXPECTED_MODELS = """  <TreeNodesModel>
    <Action ID="Beep">
      <input_port name="volume"/>
    </Action>
    <Action ID="ComputePath">
      <inout_port name="goal"/>
      <inout_port name="path"/>
    </Action>
    <Action ID="Follow">
      <inout_port name="path"/>
      <input_port name="speed"/>
    </Action>
    <Condition ID="IsStuck"/>
    <Control ID="Pipeline"/>
    <Decorator ID="RateLimit">
      <input_port name="hz"/>
    </Decorator>
    <Control ID="Recovery"/>
  </TreeNodesModel>
</root>
"""


@pytest.fixture
def files(tmp_path):
    mission = tmp_path / "mission.xml"
    mission.write_text(MISSION, encoding="utf-8")
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "lent.xml").write_text(LIBRARY, encoding="utf-8")
    return str(mission), str(tmp_path / "lib")


def test_models_inferred_from_use(files, capsys):
    mission, lib = files
    assert main(["models", mission, "--trees", lib]) == 0
    out = capsys.readouterr()
    assert out.out.endswith(EXPECTED_MODELS), out.out
    assert out.err == ""
    assert main(["models", mission, "--trees", lib]) == 0
    assert capsys.readouterr().out == out.out  # deterministic


def test_two_commands_from_refused_to_compiled(files, tmp_path, capsys):
    mission, lib = files
    assert main(["validate", "-q", mission, "--trees", lib]) == 1
    assert "unknown node `Pipeline`" in capsys.readouterr().err
    models = str(tmp_path / "models.xml")
    assert main(["models", mission, "--trees", lib, "-o", models]) == 0
    assert main(["compile", mission, "--trees", lib, "--models", models, "-o", str(tmp_path / "out")]) == 0
    assert os.path.exists(tmp_path / "out" / "mission.hpp")
    m = load_mission(mission, models=[models], trees=[lib])
    assert {s.id: s.kind for s in m.user_models()}["IsStuck"] == "Condition"


def test_never_overwrites_an_input(files, capsys):
    mission, lib = files
    before = Path(mission).read_text(encoding="utf-8")
    assert main(["models", mission, "-o", mission]) == 1
    assert "would overwrite this input file" in capsys.readouterr().err
    assert Path(mission).read_text(encoding="utf-8") == before


def test_mixed_use_is_warned(tmp_path, capsys):
    p = tmp_path / "m.xml"
    p.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><Wrap/><Wrap><Go/></Wrap></Sequence>'
        "</BehaviorTree></root>\n",
        encoding="utf-8",
    )
    assert main(["models", str(p)]) == 0
    out = capsys.readouterr()
    assert '<Decorator ID="Wrap"/>' in out.out and '<Action ID="Go"/>' in out.out
    assert "warning: `Wrap` is used with and without children; written as a Decorator" in out.err
