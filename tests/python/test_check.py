"""`btgen check`: a whole repository found by content, each file loaded as its project loads it,
findings with stable codes, selection and suppression, exit status and quiet output."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.tools.check import discovery, runner
from btgen.tools.check.codes import BY_CODE, classify, selected
from btgen.tools.check.config import Settings

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT / "tests" / "real_files"

MODELS = """<root BTCPP_format="4">
  <TreeNodesModel>
    <Action ID="Say"><input_port name="text"/></Action>
  </TreeNodesModel>
</root>
"""
MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Say text="hello"/>
      <SubTree ID="Dock"/>
    </Sequence>
  </BehaviorTree>
</root>
"""
LIBRARY = """<root BTCPP_format="4">
  <BehaviorTree ID="Dock">
    <Say text="docking"/>
  </BehaviorTree>
  <BehaviorTree ID="Undock">
    <Say text="undocking"/>
  </BehaviorTree>
</root>
"""


def write(folder: Path, files: dict) -> Path:
    for name, text in files.items():
        p = folder / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return folder


def run_check(args, capsys, cwd=None):
    old = os.getcwd()
    if cwd is not None:
        os.chdir(cwd)
    try:
        status = main(["check", *args])
    finally:
        os.chdir(old)
    out, err = capsys.readouterr()
    return status, out, err


def test_roles_found_by_content(tmp_path):
    write(
        tmp_path,
        {
            "nodes.xml": MODELS,
            "mission.xml": MISSION,
            "library.xml": LIBRARY,
            "patrol.tree": MISSION.replace("Main", "Patrol"),  # no .xml: found by content
            "launch.xml": "<launch><node pkg='x'/></launch>\n",  # XML, not BehaviorTree.CPP
            "notes.txt": "root BTCPP_format",
            "make.py": 'XML = """<root BTCPP_format="4"><BehaviorTree/></root>"""\n',  # XML in a string
            "old.xml": '<?xml version="1.0"?>\n<!-- v3 -->\n<root>\n  <BehaviorTree ID="Old">\n'
            "    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n",
        },
    )
    project = discovery.survey([str(tmp_path)])
    kinds = {os.path.basename(f.path): f.kind for f in project.files.values()}
    assert kinds == {
        "nodes.xml": "models file",
        "mission.xml": "mission",
        "library.xml": "tree library",
        "patrol.tree": "mission",
        "old.xml": "mission",
    }
    units = {(os.path.basename(u.path), u.main_tree): u for u in discovery.plan(project)}
    mission = units[("mission.xml", None)]
    assert [os.path.basename(m) for m in mission.models] == ["nodes.xml"]
    assert [os.path.basename(t) for t in mission.trees] == ["library.xml"]
    # the library names no main tree: checked tree by tree, as the program may pick any
    assert ("library.xml", "Dock") in units and ("library.xml", "Undock") in units
    assert units[("library.xml", "Dock")].library


def test_project_checks_clean_and_quiet(tmp_path, capsys):
    write(tmp_path, {"nodes.xml": MODELS, "mission.xml": MISSION, "library.xml": LIBRARY})
    status, out, err = run_check([str(tmp_path)], capsys)
    assert (status, out, err) == (0, "", "")


def test_error_exit_and_line_shape(tmp_path, capsys):
    write(tmp_path, {"nodes.xml": MODELS, "mission.xml": MISSION.replace("<Say ", "<Sya ")})
    status, out, err = run_check([str(tmp_path)], capsys)
    assert status == 1 and out == ""
    first = err.splitlines()[0]
    assert first.startswith(f"{tmp_path}/mission.xml:4:7: error: unknown node `Sya`")
    assert first.endswith("[E301]")
    assert err.splitlines()[-1].startswith("btgen check: ")


def test_cpp_only_nodes_say_how_to_declare_them(tmp_path, capsys):
    write(tmp_path, {"mission.xml": MISSION.replace('      <SubTree ID="Dock"/>\n', "")})
    status, _, err = run_check([str(tmp_path)], capsys)
    assert status == 1
    assert "[C101]" in err and "`btgen models DIR`" in err and "`models` in [tool.btgen]" in err
    assert "--models FILE.xml" not in err


def test_includes_are_checked_through_their_includer(tmp_path, capsys):
    write(
        tmp_path,
        {
            "nodes.xml": MODELS,
            "main.xml": MISSION.replace("</root>", '  <include path="sub/dock.xml"/>\n</root>'),
            "sub/dock.xml": LIBRARY.replace("undocking", "undocking").replace('<Say text="docking"/>', "<Sya/>"),
        },
    )
    project = discovery.survey([str(tmp_path)])
    dock = next(f for f in project.files.values() if f.path.endswith("dock.xml"))
    assert dock.kind == "included file"
    assert [u.path for u in discovery.plan(project)] == [str(tmp_path / "main.xml")]
    # sub/dock.xml has no models file beside it, but its includer has: one finding, from the includer
    status, _, err = run_check([str(tmp_path)], capsys)
    assert status == 1 and err.count("unknown node `Sya`") == 1 and "sub/dock.xml:3:5:" in err


def test_groot2_project_models_count(tmp_path, capsys):
    proj = """<?xml version="1.0" encoding="UTF-8"?>
<root BTCPP_format="4" project_name="Demo">
    <include path="trees/mission.xml"/>
    <include path="trees/library.xml"/>
    <TreeNodesModel>
        <Action ID="Say"><input_port name="text"/></Action>
    </TreeNodesModel>
</root>
"""
    write(tmp_path, {"demo.btproj": proj, "trees/mission.xml": MISSION, "trees/library.xml": LIBRARY})
    project = discovery.survey([str(tmp_path)])
    assert {os.path.basename(f.path): f.kind for f in project.files.values()}["demo.btproj"] == "Groot2 project"
    status, out, err = run_check([str(tmp_path)], capsys)
    assert (status, err) == (0, "")
    # an error in the project's models is reported at the .btproj's own line
    write(tmp_path, {"demo.btproj": proj.replace('name="text"/>', 'name="text"/><input_port name="text"/>')})
    status, _, err = run_check([str(tmp_path)], capsys)
    assert status == 1 and f"{tmp_path}/demo.btproj:6:" in err and "[E304]" in err


def test_findings_do_not_depend_on_walk_order(tmp_path, capsys):
    write(
        tmp_path,
        {
            "a/nodes.xml": MODELS,
            "a/m1.xml": MISSION.replace("<Say ", "<Sya "),
            "a/library.xml": LIBRARY,
            "b/m2.xml": MISSION,
        },
    )
    s = Settings()
    one = runner.check([str(tmp_path / "a"), str(tmp_path / "b")], s).findings
    two = runner.check([str(tmp_path / "b"), str(tmp_path / "a")], s).findings
    assert one == two and one


def test_select_ignore_and_inline_suppression(tmp_path, capsys):
    bad = MISSION.replace('<Say text="hello"/>', '<Sya text="hello"/>')
    write(tmp_path, {"nodes.xml": MODELS, "library.xml": LIBRARY, "mission.xml": bad})
    assert run_check([str(tmp_path), "--ignore", "E3"], capsys)[0] == 0
    assert run_check([str(tmp_path), "--select", "A"], capsys)[0] == 0
    assert run_check([str(tmp_path), "--select", "E", "--ignore", "E30"], capsys)[0] == 0
    assert run_check([str(tmp_path), "--select", "E301"], capsys)[0] == 1
    write(tmp_path, {"mission.xml": bad.replace('"hello"/>', '"hello"/> <!-- btgen: ignore[E301] -->')})
    assert run_check([str(tmp_path)], capsys)[:3] == (0, "", "")
    write(tmp_path, {"mission.xml": bad.replace('"hello"/>', '"hello"/> <!-- btgen: ignore[A101] -->')})
    assert run_check([str(tmp_path)], capsys)[0] == 1


def test_bad_selector_is_a_command_line_error(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(["check", str(tmp_path), "--select", "Q9"])
    assert e.value.code == 1
    assert "<command-line>:1:" in capsys.readouterr().err


def test_selection_rules():
    assert selected("E301", (), ())
    assert not selected("A105", (), ())  # not a default rule
    assert selected("A105", ("ALL", "A105"), ())
    assert not selected("A105", ("A",), ())
    assert selected("E301", ("E",), ("E30", "E301")) is False
    assert selected("E301", ("E301",), ("E",))


def test_every_known_message_has_its_own_code():
    """Every diagnostic the bad-input corpora record gets a code of the table, not the fallback."""
    fallback = []
    for folder in ("bad_missions", "bad_data", "warned_data", "tree_libraries", "provided_entries"):
        for f in sorted((ROOT / "tests" / folder).rglob("*.stderr")):
            for line in f.read_text().splitlines():
                parts = line.split(": ", 2)
                if len(parts) == 3 and parts[1] in ("error", "warning"):
                    if classify(parts[2], parts[1]) in ("E999", "W999"):
                        fallback.append(f"{f.name}: {parts[2]}")
    assert fallback == []


@pytest.mark.parametrize("folder", ["nav2", "btcpp/trees"])
def test_real_project_folders_load_with_no_flags(folder, capsys):
    """Nav2's trees with its models file beside them, the library's own test trees with their
    includes: all load with no flag (the findings left are warnings)."""
    status, out, err = run_check([str(REAL / folder)], capsys)
    assert status == 0, err
    assert " error: " not in err


def test_subprocess_is_quiet_without_a_terminal(tmp_path):
    write(tmp_path, {"nodes.xml": MODELS, "mission.xml": MISSION, "library.xml": LIBRARY})
    env = dict(os.environ, PYTHONPATH=str(ROOT / "generator"))
    r = subprocess.run(
        [sys.executable, "-m", "btgen", "check", str(tmp_path)], check=False, capture_output=True, text=True, env=env
    )
    assert (r.returncode, r.stdout, r.stderr) == (0, "", "")


def test_codes_are_unique_and_documented():
    assert len(BY_CODE) == len({r.name for r in BY_CODE.values()})
    for r in BY_CODE.values():
        assert r.severity in ("error", "warning") and r.summary


def test_a_file_given_by_name_is_loaded_as_in_its_folder(tmp_path, capsys):
    """What pre-commit does: it passes the changed files. Their models files, libraries and
    includers beside them count; only the given files' findings are reported."""
    write(
        tmp_path,
        {
            "nodes.xml": MODELS,
            "library.xml": LIBRARY,
            "mission.xml": MISSION,
            "other.xml": MISSION.replace("Main", "Other").replace("<Say ", "<Sya "),
            "main.xml": '<root BTCPP_format="4" main_tree_to_execute="M">\n  <include path="part.xml"/>\n'
            '  <BehaviorTree ID="M">\n    <SubTree ID="Part"/>\n  </BehaviorTree>\n</root>\n',
            "part.xml": '<root BTCPP_format="4">\n  <BehaviorTree ID="Part">\n    <Sya/>\n  </BehaviorTree>\n</root>\n',
        },
    )
    assert run_check([str(tmp_path / "mission.xml")], capsys)[:3] == (0, "", "")
    status, _, err = run_check([str(tmp_path / "part.xml")], capsys)
    assert status == 1 and err.startswith(f"{tmp_path}/part.xml:3:5: error: unknown node `Sya`")
    assert "other.xml" not in err


def test_jobs_give_the_same_findings(tmp_path):
    write(
        tmp_path,
        {
            "nodes.xml": MODELS,
            "library.xml": LIBRARY,
            "m1.xml": MISSION.replace("<Say ", "<Sya "),
            "m2.xml": MISSION.replace("Main", "Two"),
            "m3.xml": MISSION.replace("Main", "Three").replace("Dock", "Undock"),
        },
    )
    one = runner.check([str(tmp_path)], Settings())
    two = runner.check([str(tmp_path)], Settings(), jobs=2)
    assert one.findings == two.findings and one.findings


def test_nothing_found_is_said(tmp_path, capsys):
    (tmp_path / "launch.xml").write_text("<launch/>\n")
    status, out, err = run_check([str(tmp_path)], capsys)
    assert status == 0 and out == ""
    assert err == f"btgen check: warning: no BehaviorTree.CPP file (<root BTCPP_format=...>) found under {tmp_path}\n"


def test_include_ros_pkg_through_config_or_environment(tmp_path, capsys, monkeypatch):
    """<include ros_pkg=...>: the library built without ROS refuses it (recorded on 4.6.2 and 4.10.0);
    with ROS it opens the package's share folder, which the configuration or AMENT_PREFIX_PATH give."""
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    write(
        tmp_path,
        {
            "ws/install/share/robot_trees/trees/dock.xml": LIBRARY.replace("Say", "AlwaysSuccess")
            .replace(' text="docking"', "")
            .replace(' text="undocking"', ""),
            "app/mission.xml": MISSION.replace('<Say text="hello"/>', "<AlwaysSuccess/>").replace(
                "</root>", '  <include ros_pkg="robot_trees" path="trees/dock.xml"/>\n</root>'
            ),
        },
    )
    status, _, err = run_check([str(tmp_path / "app")], capsys)
    assert status == 1
    assert "mission.xml:8:12: error: <include ros_pkg=...>: package `robot_trees` not found" in err and "[E202]" in err
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "ws" / "install"))
    assert run_check([str(tmp_path / "app")], capsys)[:3] == (0, "", "")
    monkeypatch.delenv("AMENT_PREFIX_PATH")
    (tmp_path / "app" / "btgen.toml").write_text('[ros-packages]\nrobot_trees = "../ws/install/share/robot_trees"\n')
    assert run_check([str(tmp_path / "app")], capsys)[:3] == (0, "", "")
