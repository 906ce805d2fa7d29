"""`btgen check`'s configuration: `[tool.btgen]` of pyproject.toml or btgen.toml, found upwards from
the checked path; unknown keys and bad values are errors at their place in the file;
`--show-settings FILE` says what applies to a file."""

import os
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.diagnostics import UserError
from btgen.tools.check.config import find_config, load_settings

NODES = """<root BTCPP_format="4">
  <TreeNodesModel>
    <Action ID="Say"><input_port name="text"/></Action>
  </TreeNodesModel>
</root>
"""
MISSION = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Say text="hi"/>
  </BehaviorTree>
  <BehaviorTree ID="Other">
    <Sya/>
  </BehaviorTree>
</root>
"""


def run(cwd, capsys, *args):
    old = os.getcwd()
    os.chdir(cwd)
    try:
        status = main(["check", *args])
    finally:
        os.chdir(old)
    return status, *capsys.readouterr()


@pytest.fixture
def repo(tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "nodes.xml").write_text(NODES)
    (tmp_path / "trees").mkdir()
    (tmp_path / "trees" / "main.xml").write_text(MISSION)
    return tmp_path


def test_found_upwards_and_paths_relative_to_it(repo, capsys):
    # without configuration: `Say` is declared nowhere beside the tree, `Sya` is a typo
    status, _, err = run(repo / "trees", capsys, ".")
    assert status == 1 and "[C101]" in err
    (repo / "pyproject.toml").write_text(
        '[project]\nname = "robot"\n\n[tool.btgen]\nmodels = ["models/nodes.xml"]\n'
        'main-tree = { "trees/main.xml" = "Main" }\n'
    )
    assert find_config(str(repo / "trees")) == str(repo / "pyproject.toml")
    # the main tree is chosen: only `Main` is checked by the IR, but the front end reads `Other` too
    status, _, err = run(repo / "trees", capsys, ".")
    assert status == 1 and "C101" not in err and "unknown node `Sya`" in err
    (repo / "trees" / "main.xml").write_text(MISSION.replace("<Sya/>", '<Say text="x"/>'))
    assert run(repo / "trees", capsys, ".") == (0, "", "")
    assert run(repo, capsys, "trees/main.xml") == (0, "", "")


def test_pyproject_without_table_is_passed_over(repo):
    (repo / "btgen.toml").write_text('btcpp = "4.10.0"\n')
    (repo / "trees" / "pyproject.toml").write_text("[tool.ruff]\nline-length = 100\n")
    assert find_config(str(repo / "trees" / "main.xml")) == str(repo / "btgen.toml")
    assert load_settings(str(repo / "btgen.toml")).btcpp == "4.10.0"


def test_unknown_key_and_bad_value_are_located(repo, capsys):
    (repo / "pyproject.toml").write_text(
        '[project]\nname = "x"\n\n[tool.btgen]\nmodel = ["a.xml"]\n  btcpp = "4.7"\nselect = ["E3", "Q1"]\n'
    )
    status, out, err = run(repo, capsys, ".")
    assert status == 1 and out == ""
    lines = err.splitlines()
    assert (
        lines[0] == "pyproject.toml:5:1: error: unknown key `model` in the btgen configuration (did you mean `models`?)"
    )
    assert lines[1].startswith('pyproject.toml:6:11: error: `btcpp` must be one of "4.6.2", "4.10.0"')
    assert lines[2].startswith("pyproject.toml:7:10: error: `select`: `Q1` is no code")


def test_invalid_toml_is_located(repo, capsys):
    (repo / "btgen.toml").write_text('models = ["a.xml"\nbtcpp = 1\n')
    status, _, err = run(repo, capsys, ".")
    assert status == 1 and err.startswith("btgen.toml:2:") and "invalid TOML" in err


def test_config_option_and_per_file_ignores(repo, capsys, tmp_path):
    cfg = repo / "ci.toml"
    cfg.write_text('models = ["models/nodes.xml"]\n[per-file-ignores]\n"trees/*.xml" = ["E301"]\n')
    assert run(repo, capsys, ".", "--config", "ci.toml") == (0, "", "")
    status, _, err = run(repo, capsys, ".", "--config", "nowhere.toml")
    assert status == 1 and err.startswith("<command-line>:1:")


def test_exclude(repo, capsys):
    (repo / "btgen.toml").write_text('exclude = ["trees"]\n')
    assert run(repo, capsys, ".") == (0, "", "")


def test_show_settings(repo, capsys):
    (repo / "btgen.toml").write_text('models = ["models/nodes.xml"]\nignore = ["A"]\n')
    status, out, err = run(repo, capsys, "--show-settings", "trees/main.xml")
    assert status == 0 and err == ""
    assert "config = 'btgen.toml'" in out and "kind = 'mission'" in out
    assert "models = ['models/nodes.xml']" in out
    # two trees, no main_tree_to_execute: one load per tree
    assert "main-tree = 'Main'" in out and "main-tree = 'Other'" in out
    assert "ignore = ['A']" in out
    (repo / "btgen.toml").write_text('main-tree = { "trees/*.xml" = "Other" }\n')
    out = run(repo, capsys, "--show-settings", "trees/main.xml")[1]
    assert "main-tree = 'Other'" in out and "main-tree = 'Main'" not in out


def test_load_settings_error_is_user_error(repo):
    (repo / "btgen.toml").write_text("string-capacity = 0\n")
    with pytest.raises(UserError) as e:
        load_settings(str(repo / "btgen.toml"))
    assert str(e.value.diagnostics[0]).endswith("`string-capacity` must be a whole number from 1 to 1048576")
    assert Path(e.value.diagnostics[0].loc.path).name == "btgen.toml"
