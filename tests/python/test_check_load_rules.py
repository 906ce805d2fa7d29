"""Load rules of issue 38's item 8, each recorded on the real library first (docs/check.md, "What
BehaviorTree.CPP loads, recorded"): what `validate` (and so `check`) now does with them."""

import shutil
from pathlib import Path

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]

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


# ---------------------------------------------------------------- recorded in tests/conformance/both-releases
# (each mission there runs on both engines against the library's trace: test_both_releases.py)
BOTH = ROOT / "tests" / "conformance" / "both-releases"


def test_element_name_with_a_colon(tmp_path, capsys):
    """tinyxml2 knows no namespaces: 4.6.2 loads `<arm:Grasp/>` and runs it, 4.10.0 refuses the name."""
    m = BOTH / "colon_element_name.xml"
    assert main(["validate", str(m)]) == 0
    err = capsys.readouterr().err
    assert "colon_element_name.xml:7:7: warning: element name `arm:Grasp` has a colon" in err
    assert err.count("has a colon") == 1  # once per name
    assert main(["validate", "--btcpp", "4.10.0", str(m)]) == 1
    assert "7:7: error: node ID `arm:Grasp` contains the forbidden character `:`" in capsys.readouterr().err
    shutil.copy(m, tmp_path / "m.xml")
    assert main(["check", "--select", "W110", str(tmp_path)]) == 0
    assert "[W110]" in capsys.readouterr().err
    # undeclared, `btgen models` declares it under its name as written
    (tmp_path / "m.xml").write_text(m.read_text(encoding="utf-8").split("  <TreeNodesModel>")[0] + "</root>\n")
    assert main(["models", str(tmp_path), "-o", str(tmp_path / "nodes.xml")]) == 0
    assert '<Action ID="arm:Grasp"/>' in (tmp_path / "nodes.xml").read_text(encoding="utf-8")
    capsys.readouterr()


def test_a_declared_prefix_stays_a_namespace(tmp_path, capsys):
    """With xmlns:arm declared the element is in a namespace (btgen's error, as before); a file that
    holds a middle dot already keeps XML's error (the mark btgen gives lxml must stand for one thing)."""
    text = (BOTH / "colon_element_name.xml").read_text(encoding="utf-8")
    m = tmp_path / "m.xml"
    m.write_text(text.replace('<root BTCPP_format="4"', '<root xmlns:arm="urn:arm" BTCPP_format="4"'))
    assert main(["validate", str(m)]) == 1
    assert "BehaviorTree.CPP node elements have no namespace (it is in urn:arm)" in capsys.readouterr().err
    m.write_text(text.replace("Recorded", "Recorded \u00b7"))
    assert main(["validate", str(m)]) == 1
    assert "Namespace prefix arm on Grasp is not defined" in capsys.readouterr().err


def test_node_id_with_a_space(tmp_path, capsys):
    """Both releases load `<Action ID="Grasp Cup"/>`; its trace reads back (graph --trace)."""
    m = BOTH / "space_in_node_id.xml"
    for version in ("4.6.2", "4.10.0"):
        assert main(["validate", "--btcpp", version, str(m)]) == 0
    assert capsys.readouterr().err == ""
    trace = BOTH / "4.6.2" / "space_in_node_id.trace"
    assert main(["graph", str(m), "--trace", str(trace), "-o", str(tmp_path / "g.dot")]) == 0
    assert "Grasp Cup" in (tmp_path / "g.dot").read_text(encoding="utf-8")


def test_entry_braces_alone(tmp_path, capsys):
    """`entry="{}"` loads (one warning); another text that is no key, and SetBlackboard's output_key, do not."""
    for stem in ("empty_entry_skip_unless_updated", "empty_entry_wait_value_update", "empty_entry_was_entry_updated"):
        assert main(["validate", str(BOTH / (stem + ".xml"))]) == 0
        err = capsys.readouterr().err
        assert err.count("warning:") == 1 and "reads it as this literal text" in err, err
    m = tmp_path / "m.xml"
    text = (BOTH / "empty_entry_was_entry_updated.xml").read_text(encoding="utf-8")
    m.write_text(text.replace('entry="{}"', 'entry="{x"'))
    assert main(["validate", str(m)]) == 1
    assert "is not a valid blackboard key" in capsys.readouterr().err
    m.write_text(text.replace('<WasEntryUpdated entry="{}"/>', '<SetBlackboard output_key="{}" value="1"/>'))
    assert main(["validate", str(m)]) == 1
    assert "is not a valid blackboard key" in capsys.readouterr().err


def test_include_hint_never_names_a_file_that_includes_this_one(tmp_path, capsys):
    """A sibling that includes the file asking (its parent, without main_tree_to_execute): including
    it back would be an include cycle."""
    (tmp_path / "work.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Work">\n    <SubTree ID="Dock"/>\n  </BehaviorTree>\n</root>\n'
    )
    (tmp_path / "parent.xml").write_text(
        '<root BTCPP_format="4">\n  <include path="work.xml"/>\n  <BehaviorTree ID="Dock">\n'
        "    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n"
    )
    assert main(["validate", str(tmp_path / "work.xml")]) == 1
    err = capsys.readouterr().err
    assert "defines `Dock` and includes `work.xml` (including it back would be a cycle)" in err
    assert "<include" not in err
    # what the hint says to do loads
    assert main(["validate", "--main-tree", "Work", str(tmp_path / "parent.xml")]) == 0
