"""`btgen models DIR`: one models file for the nodes a whole project registers only in C++, merged
across its files, which `btgen check` then finds beside the trees."""

import os
import shutil
from pathlib import Path

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
A = """<root BTCPP_format="4">
  <BehaviorTree ID="A">
    <Sequence>
      <Action ID="Grasp" object="cup"/>
      <Wrap><AlwaysSuccess/></Wrap>
    </Sequence>
  </BehaviorTree>
</root>
"""
B = """<root BTCPP_format="4">
  <BehaviorTree ID="B">
    <Sequence>
      <Condition ID="Grasp" object="{obj}" force="2"/>
      <Wrap/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def test_models_over_a_folder_then_check(tmp_path, capsys):
    (tmp_path / "a.xml").write_text(A)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.xml").write_text(B)
    assert main(["check", str(tmp_path)]) == 1
    assert "[C101]" in capsys.readouterr().err
    out = tmp_path / "nodes.xml"
    assert main(["models", str(tmp_path), "-o", str(out)]) == 0
    err = capsys.readouterr().err.splitlines()
    # each conflict at its second place, naming the first
    grasp = f"{tmp_path}/sub/b.xml:4:7: warning: `Grasp` is written <Condition> here and <Action> at "
    assert grasp + f"{tmp_path}/a.xml:4:7; <Action> is written" in err
    wrap = f"{tmp_path}/a.xml:5:7: warning: `Wrap` has 1 child here and none at {tmp_path}/sub/b.xml:5:7; "
    assert wrap + "written as a Decorator" in err
    text = out.read_text()
    assert '<Action ID="Grasp">' in text and '<input_port name="object"/>' in text
    assert '<input_port name="force"/>' in text and '<Decorator ID="Wrap"/>' in text
    # written again from the same files: the models file itself is not read as declarations
    assert main(["models", str(tmp_path), "-o", str(out)]) == 0
    assert out.read_text() == text
    capsys.readouterr()
    # a.xml sees nodes.xml beside it; sub/b.xml is checked with it when named in the configuration
    (tmp_path / "btgen.toml").write_text('models = ["nodes.xml"]\n')
    status = main(["check", str(tmp_path)])
    err = capsys.readouterr().err
    assert "C101" not in err
    # `<Wrap/>` without its child is what BehaviorTree.CPP refuses too
    assert status == 1 and "`Wrap` is a decorator and takes exactly 1 child, but has no children [E302]" in err


def test_plansys2_folder_loads_after_models(tmp_path, capsys):
    """PlanSys2's trees use actions registered in C++: `btgen models .` then `btgen check .` loads both."""
    shutil.copytree(ROOT / "tests" / "real_files" / "plansys2", tmp_path / "plansys2")
    old = os.getcwd()
    os.chdir(tmp_path / "plansys2")
    try:
        assert main(["check", "."]) == 1
        assert main(["models", ".", "-o", "plansys2_nodes.xml"]) == 0
        capsys.readouterr()
        assert main(["check", "."]) == 0
    finally:
        os.chdir(old)
    err = capsys.readouterr().err
    assert " error: " not in err
