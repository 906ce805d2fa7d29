"""Load rules of issue 38's item 8, each recorded on the real library first (docs/check.md, "What
BehaviorTree.CPP loads, recorded"): what `validate` (and so `check`) now does with them."""

from btgen.cli import main

MAIN = """<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <SubTree ID="Dock"/>
  </BehaviorTree>
</root>
"""
OTHER_MISSION = """<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <SubTree ID="Dock"/>
  </BehaviorTree>
  <BehaviorTree ID="Dock">
    <AlwaysSuccess/>
  </BehaviorTree>
</root>
"""
DOTTED = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <SubTree ID="Sub" target.room="{room}"/>
  </BehaviorTree>
  <BehaviorTree ID="Sub">
    <AlwaysSuccess/>
  </BehaviorTree>
</root>
"""


def test_include_hint_never_names_a_mission(tmp_path, capsys):
    """Including a sibling that is a mission itself gives "BehaviorTree `MainTree` is defined twice"."""
    (tmp_path / "main.xml").write_text(MAIN)
    (tmp_path / "other.xml").write_text(OTHER_MISSION)
    assert main(["validate", str(tmp_path / "main.xml")]) == 1
    err = capsys.readouterr().err
    assert "`Dock`, but it defines `MainTree` too: move `Dock` to a file of its own and include that" in err
    assert "<include" not in err
    # a library beside it is preferred, and is the one suggested
    (tmp_path / "dock.xml").write_text(
        OTHER_MISSION.replace(' main_tree_to_execute="MainTree"', "").replace(
            '  <BehaviorTree ID="MainTree">\n    <SubTree ID="Dock"/>\n  </BehaviorTree>\n', ""
        )
    )
    assert main(["validate", str(tmp_path / "main.xml")]) == 1
    assert 'beside it defines it: add <include path="dock.xml"/> to <root>' in capsys.readouterr().err


def test_subtree_dotted_remap_loads_on_both_releases(tmp_path, capsys):
    (tmp_path / "m.xml").write_text(DOTTED)
    assert main(["validate", str(tmp_path / "m.xml")]) == 0
    assert capsys.readouterr().err == ""
    assert main(["validate", "--btcpp", "4.10.0", str(tmp_path / "m.xml")]) == 0
    err = capsys.readouterr().err
    assert "m.xml:3:23: warning: attribute `target.room` on `Sub` is ignored: BehaviorTree.CPP 4.10.0" in err


def test_include_ros_pkg_in_validate(tmp_path, capsys, monkeypatch):
    share = tmp_path / "install" / "share" / "trees_pkg"
    share.mkdir(parents=True)
    (share / "dock.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Dock">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n'
    )
    (tmp_path / "m.xml").write_text(
        MAIN.replace("</root>", '  <include ros_pkg="trees_pkg" path="dock.xml"/>\n</root>')
    )
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "nothing"))
    assert main(["validate", str(tmp_path / "m.xml")]) == 1
    assert "package `trees_pkg` not found (looked in AMENT_PREFIX_PATH" in capsys.readouterr().err
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "install" / "share"))
    assert main(["validate", str(tmp_path / "m.xml")]) == 0


def test_a_node_declared_differently_in_two_files_loads(tmp_path, capsys):
    """Recorded on 4.6.2 and 4.10.0: a mission and its include declaring `Say` with different ports
    load (the library never reads a registered node's model); btgen warns and takes both."""
    (tmp_path / "inc.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Other">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n'
        '  <TreeNodesModel>\n    <Action ID="Say"><input_port name="text" type="int"/><output_port name="done"/>'
        "</Action>\n  </TreeNodesModel>\n</root>\n"
    )
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n  <include path="inc.xml"/>\n'
        '  <BehaviorTree ID="Main">\n    <Say text="hi" done="{d}"/>\n  </BehaviorTree>\n'
        '  <TreeNodesModel>\n    <Action ID="Say"><input_port name="text"/></Action>\n  </TreeNodesModel>\n</root>\n'
    )
    assert main(["validate", str(tmp_path / "m.xml")]) == 0
    err = capsys.readouterr().err
    assert "m.xml:7:17: warning: `Say` is declared twice in TreeNodesModel and the declarations differ" in err
    assert main(["check", str(tmp_path)]) == 0
    assert "[W105]" in capsys.readouterr().err


SUB_MODEL = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <SubTree ID="Sub"AUTO/>
  </BehaviorTree>
  <BehaviorTree ID="Sub">
    <AlwaysSuccess/>
  </BehaviorTree>
  <TreeNodesModel>
    <SubTree ID="Sub">
      <input_port name="1st"DEFAULT/>
    </SubTree>
  </TreeNodesModel>
</root>
"""


def test_subtree_model_port_starting_with_a_digit(tmp_path, capsys):
    """Recorded on 4.6.2: such a port is kept; without a default it is a mandatory port no attribute
    can give (refused, unless `_autoremap`), with one the mission loads. 4.10.0 refuses the name."""
    m = tmp_path / "m.xml"
    m.write_text(SUB_MODEL.replace("AUTO", "").replace("DEFAULT", ""))
    assert main(["validate", str(m)]) == 1
    assert "m.xml:3:5: error: SubTree `Sub` declares port `1st` without a default" in capsys.readouterr().err
    m.write_text(SUB_MODEL.replace("AUTO", ' _autoremap="true"').replace("DEFAULT", ""))
    assert main(["validate", str(m)]) == 0
    m.write_text(SUB_MODEL.replace("AUTO", "").replace("DEFAULT", ' default="a"'))
    assert main(["validate", str(m)]) == 0
    assert "keeps it all the same (refused from 4.8.4)" in capsys.readouterr().err
    assert main(["validate", "--btcpp", "4.10.0", str(m)]) == 1
    assert "invalid port name `1st` in `Sub`" in capsys.readouterr().err
