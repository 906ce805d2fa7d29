"""`btgen check` over the real projects of tests/real_files, folder by folder, with no flag: what
loads, and why each other file does not (the library refuses it too, on the release recorded in
expected*/, or its nodes are registered in C++ and the finding says how to declare them). Then the
same folders after `btgen models .` (and, for the library's 4.10.0 test trees, `btcpp = "4.10.0"` in
a btgen.toml), as docs/check.md reports them."""

import collections
import os
import shutil
from pathlib import Path
from typing import Optional

import pytest

from btgen.cli import main
from btgen.tools.check import runner
from btgen.tools.check.config import Settings, load_settings

REAL = Path(__file__).resolve().parents[2] / "tests" / "real_files"


def outcome(folder: Path, settings: Optional[Settings] = None):
    """(files of trees, those that load, {file: error codes} of the others), paths relative to `folder`."""
    old = os.getcwd()
    os.chdir(folder)
    try:
        report = runner.check(["."], settings or Settings())
    finally:
        os.chdir(old)
    errors = collections.defaultdict(set)
    messages = collections.defaultdict(list)
    for f in report.findings:
        if f.severity == "error":
            errors[os.path.normpath(f.path)].add(f.code)
            messages[os.path.normpath(f.path)].append(f.message)
    files = sorted(os.path.normpath(p) for p in report.files if report.kinds[p] != "models file")
    loads = [p for p in files if p not in errors]
    return files, loads, dict(errors), messages


def recorded_refusals(version_dir: str, prefix: str) -> set:
    return {
        f[len(prefix) : -len(".refused")] + ".xml"
        for f in os.listdir(REAL / version_dir)
        if f.startswith(prefix) and f.endswith(".refused")
    }


@pytest.mark.parametrize("folder", ["nav2", "btcpp/trees"])
def test_every_file_loads(folder):
    files, loads, errors, _ = outcome(REAL / folder)
    assert files and loads == files, errors


def test_fuzzing_seeds_refused_as_the_library_refuses_them():
    files, loads, errors, _ = outcome(REAL / "btcpp" / "fuzzing")
    assert loads == ["corpus1.xml"]
    assert set(errors) == recorded_refusals("expected", "btcpp__fuzzing__")
    assert set(errors) == recorded_refusals("expected-4.10.0", "btcpp__fuzzing__")


@pytest.mark.parametrize("folder", ["plansys2", "btcpp/examples/subtrees"])
def test_cpp_registered_nodes_say_how_to_declare_them(folder, tmp_path, capsys):
    files, loads, errors, messages = outcome(REAL / folder)
    assert loads == [] and set().union(*errors.values()) == {"C101"}
    assert all("`btgen models DIR`" in m for ms in messages.values() for m in ms)
    # after `btgen models .`, every file loads
    copy = tmp_path / "project"
    shutil.copytree(REAL / folder, copy)
    assert main(["models", str(copy), "-o", str(copy / "nodes.xml")]) == 0
    files, loads, errors, _ = outcome(copy)
    assert loads == files, errors


def test_library_4_10_trees(tmp_path, capsys):
    """The library's own 4.10.0 test trees: under the default 4.6.2, what does not load is TryCatch
    (built in from 4.9.0) or a test node registered in C++; with `btcpp = "4.10.0"` and the models of
    `btgen models`, every file loads but those the real 4.10.0 refuses (its recordings)."""
    folder = REAL / "btcpp" / "tests-4.10.0"
    files, loads, errors, messages = outcome(folder)
    assert len(files) == 27 and len(loads) == 13
    for path, codes in errors.items():
        assert codes <= {"C101", "E301"}, (path, codes)
        assert all("TryCatch" in m or "`btgen models DIR`" in m for m in messages[path]), messages[path]
    copy = tmp_path / "tests-4.10.0"
    shutil.copytree(folder, copy)
    (copy / "btgen.toml").write_text('btcpp = "4.10.0"\n')
    assert main(["models", str(copy), "--btcpp", "4.10.0", "-o", str(copy / "nodes.xml")]) == 0
    capsys.readouterr()
    files, loads, errors, _ = outcome(copy, load_settings(str(copy / "btgen.toml")))
    assert set(errors) == recorded_refusals("expected-4.10.0", "btcpp__tests-4.10.0__")
    assert len(loads) == 15


def _unit_trees(folder: Path) -> dict:
    from btgen.tools.check import discovery

    old = os.getcwd()
    os.chdir(folder)
    try:
        units = discovery.plan(discovery.survey(["."]))
    finally:
        os.chdir(old)
    return {os.path.normpath(u.path): (u.models, u.trees) for u in units}


def test_nav2_in_its_own_layout(tmp_path):
    """Nav2 keeps its models file in another package than its trees (nav2_behavior_tree/ and
    nav2_bt_navigator/behavior_trees/): a models file found anywhere under the checked paths counts
    for a file whose nodes it declares (before: 0 of 15 loaded, every node C101)."""
    models = tmp_path / "nav2_behavior_tree"
    trees = tmp_path / "nav2_bt_navigator" / "behavior_trees"
    models.mkdir()
    trees.mkdir(parents=True)
    shutil.copy(REAL / "nav2" / "nav2_tree_nodes.xml", models)
    for f in (REAL / "nav2").glob("*.xml"):
        if f.name != "nav2_tree_nodes.xml":
            shutil.copy(f, trees)
    files, loads, errors, _ = outcome(tmp_path)
    assert len(files) == 15 and loads == files, errors


def test_models_at_the_top_count_for_the_folders_below(tmp_path, capsys):
    """`btgen models .` writes one file at the top of a repository; the files of the folders below
    find it (before: only a models file beside a file counted)."""
    deep = tmp_path / "plansys2_bt_actions" / "test" / "behavior_tree"
    shutil.copytree(REAL / "plansys2", deep)
    files, loads, errors, _ = outcome(tmp_path)
    assert loads == [] and set().union(*errors.values()) == {"C101"}
    assert main(["models", str(tmp_path), "-o", str(tmp_path / "nodes.xml")]) == 0
    files, loads, errors, _ = outcome(tmp_path)
    assert len(files) == 2 and loads == files, errors


TREE = '<root BTCPP_format="4"><BehaviorTree ID="{id}">{body}</BehaviorTree></root>\n'


def test_subtree_of_another_folder_is_the_nearest_definition(tmp_path):
    """A SubTree defined in no file of the folder is taken from the nearest file found that defines it
    (MoveIt Pro registers the objectives of several configuration packages): the one fewest folders
    away, then the first by path; the choice depends on the files, not on the order of the walk."""
    (tmp_path / "robot_config" / "objectives").mkdir(parents=True)
    (tmp_path / "base_config" / "objectives").mkdir(parents=True)
    (tmp_path / "other" / "deeper" / "objectives").mkdir(parents=True)
    (tmp_path / "robot_config" / "objectives" / "pick.xml").write_text(
        TREE.format(id="Pick", body='<Sequence><SubTree ID="Open Gripper"/><AlwaysSuccess/></Sequence>')
    )
    near = tmp_path / "base_config" / "objectives" / "open_gripper.xml"
    near.write_text(TREE.format(id="Open Gripper", body="<AlwaysSuccess/>"))
    # farther, and it would not load (an unknown port of a built-in)
    (tmp_path / "other" / "deeper" / "objectives" / "open.xml").write_text(
        TREE.format(id="Open Gripper", body='<AlwaysSuccess speed="3"/>')
    )
    files, loads, errors, _ = outcome(tmp_path)
    assert "robot_config/objectives/pick.xml" in loads, errors
    _, trees = _unit_trees(tmp_path)["robot_config/objectives/pick.xml"]
    assert [os.path.normpath(t) for t in trees] == ["base_config/objectives/open_gripper.xml"]
    # a tie is decided by path: `a_config` comes before `base_config`
    (tmp_path / "a_config" / "objectives").mkdir(parents=True)
    tie = tmp_path / "a_config" / "objectives" / "open.xml"
    tie.write_text(TREE.format(id="Open Gripper", body="<AlwaysFailure/>"))
    _, trees = _unit_trees(tmp_path)["robot_config/objectives/pick.xml"]
    assert [os.path.normpath(t) for t in trees] == ["a_config/objectives/open.xml"]
    # none defines it: the SubTree is refused where it is used
    for f in [near, *tmp_path.glob("*/objectives/open.xml"), *tmp_path.glob("other/deeper/objectives/*.xml")]:
        f.unlink()
    files, loads, errors, _ = outcome(tmp_path)
    assert errors == {"robot_config/objectives/pick.xml": {"E205"}}


def test_xml_version_2_is_a_file_of_trees_with_its_models(tmp_path):
    """`<?xml version="2.0"?>` (a real project's file): tinyxml2 reads it, libxml2 refuses the
    version; check finds it as a file of trees, loads it with the models beside it, and warns (W110)."""
    (tmp_path / "models.xml").write_text(
        '<root BTCPP_format="4"><TreeNodesModel><Action ID="Drive"/></TreeNodesModel></root>\n'
    )
    (tmp_path / "v2.xml").write_text(
        '<?xml version="2.0"?>\n<root BTCPP_format="4"><BehaviorTree ID="Main"><Drive/></BehaviorTree></root>\n'
    )
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        report = runner.check(["."], Settings())
    finally:
        os.chdir(old)
    assert [(f.path, f.line, f.code) for f in report.findings] == [("v2.xml", 1, "W110")]


def test_models_types_a_port_whose_entry_a_loop_reads_as_its_queue(tmp_path, capsys):
    """A real project (mounteverset/generalist_bt_gen) fills a queue in C++ and loops over it with
    LoopString: `btgen models .` declared the port untyped, so btgen took the entry for text and
    refused the Loop (E504: "holds a string"), which the library loads. The port now gets the queue's
    type, and the C++ back end gives the node a view of the queue (E601 before: "queue ports of user
    nodes are not supported by the C++ back end yet"): the file loads."""
    (tmp_path / "route.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Main"><Sequence>'
        '<ParseWaypoints raw="{payload}" waypoint_queue="{queue}"/>'
        '<LoopString queue="{queue}" value="{wp}"><MoveTo pose="{wp}"/></LoopString>'
        "</Sequence></BehaviorTree></root>\n"
    )
    assert main(["models", str(tmp_path), "-o", str(tmp_path / "nodes.xml")]) == 0
    text = (tmp_path / "nodes.xml").read_text()
    assert '<inout_port name="waypoint_queue" type="BT::SharedQueue&lt;std::string&gt;"/>' in text
    assert '<inout_port name="raw"/>' in text and '<inout_port name="pose"/>' in text
    files, loads, errors, messages = outcome(tmp_path)
    assert (files, loads, errors) == (["route.xml"], ["route.xml"], {}), messages


def test_a_models_file_found_is_a_palette_of_the_project(tmp_path, capsys):
    """aerostack2 keeps a models file (Groot2's palette) beside its missions: its SubTree models name
    trees of other missions, and one declares a SubTree's ports otherwise than the mission that has
    it. The library never reads that file: check loaded each mission with an error (E205, E304); it
    now takes the palette's SubTree models of other trees as documentation, and the mission's own
    declaration over the palette's (a warning, W105). Given with --models, the rule stays strict."""
    (tmp_path / "actions.xml").write_text(
        "<root>\n  <TreeNodesModel>\n"
        '    <SubTree ID="ArmTakeoff"><input_port name="height"/></SubTree>\n'
        '    <SubTree ID="RTL"/>\n'
        "  </TreeNodesModel>\n</root>\n"
    )
    (tmp_path / "mission.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main"><SubTree ID="RTL" pose="{home}"/></BehaviorTree>\n'
        '  <BehaviorTree ID="RTL"><AlwaysSuccess/></BehaviorTree>\n'
        '  <TreeNodesModel><SubTree ID="RTL"><input_port name="pose"/></SubTree></TreeNodesModel>\n'
        "</root>\n"
    )
    files, loads, errors, _ = outcome(tmp_path)
    assert files == ["mission.xml"] and loads == files, errors
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        report = runner.check(["."], Settings())
    finally:
        os.chdir(old)
    assert [(f.path, f.line, f.code) for f in report.findings] == [("actions.xml", 4, "W105")]
    assert main(["validate", str(tmp_path / "mission.xml"), "--models", str(tmp_path / "actions.xml")]) == 1
    assert "error: `RTL` is declared twice in TreeNodesModel" in capsys.readouterr().err


def test_models_declares_what_another_folder_declares(tmp_path, capsys):
    """AutoAPMS declares `Logger` in the TreeNodesModel of a mission and of a Groot2 project of one
    folder and uses it in another folder's trees too: `btgen models .` took it as declared (somewhere
    in the project) and wrote no model, so check still found it unknown there (C101). It now writes a
    model for every node some file uses and nothing declares where check loads that file."""
    (tmp_path / "mission").mkdir()
    (tmp_path / "examples").mkdir()
    (tmp_path / "mission" / "orchestrator.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Main"><Logger message="up"/></BehaviorTree>'
        '<TreeNodesModel><Action ID="Logger"><input_port name="message"/></Action></TreeNodesModel></root>\n'
    )
    (tmp_path / "examples" / "demo.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Demo"><Logger message="hi"/></BehaviorTree></root>\n'
    )
    assert main(["models", str(tmp_path), "-o", str(tmp_path / "nodes.xml")]) == 0
    assert '<Action ID="Logger">' in (tmp_path / "nodes.xml").read_text()
    files, loads, errors, _ = outcome(tmp_path)
    assert loads == files == ["examples/demo.xml", "mission/orchestrator.xml"], errors


def test_an_entry_its_own_subtree_model_declares_is_the_callers(tmp_path):
    """A MoveIt Pro objective names itself as main tree and declares its own SubTree model, whose
    ports its callers give (`expected_vector_size` of ErrorCheckVectorSize). A script reading such a
    port's entry was an error (E503) the library does not have on load; it is now a warning (C102),
    as in a tree library. An entry that no port declares stays an error."""
    mission = (
        '<root BTCPP_format="4" main_tree_to_execute="Check">\n'
        '  <BehaviorTree ID="Check">\n'
        '    <Precondition if="size != expected" else="SUCCESS"><AlwaysFailure/></Precondition>\n'
        "  </BehaviorTree>\n"
        '  <TreeNodesModel><SubTree ID="Check"><input_port name="{port}"/></SubTree></TreeNodesModel>\n'
        "</root>\n"
    )
    (tmp_path / "check.xml").write_text(mission.format(port="expected"))
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        codes = [(f.code, f.severity, f.message.split("`")[5]) for f in runner.check(["."], Settings()).findings]
        assert ("C102", "warning", "expected") in codes and ("E503", "error", "size") in codes, codes
        (tmp_path / "check.xml").write_text(mission.format(port="other"))
        codes = [(f.code, f.message.split("`")[5]) for f in runner.check(["."], Settings()).findings]
        assert ("E503", "expected") in codes and ("E503", "size") in codes, codes
    finally:
        os.chdir(old)


def test_a_file_given_by_name_finds_the_models_file_above(tmp_path, capsys):
    """pre-commit passes the changed files by name: the models file `btgen models .` wrote at the top
    of the repository counts for them as when the whole repository is checked (before: only the
    files of the file's own folder were read)."""
    deep = tmp_path / "src" / "robot" / "objectives"
    deep.mkdir(parents=True)
    (deep / "pick.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Pick"><CloseGripper/></BehaviorTree></root>\n'
    )
    (tmp_path / "btgen_models.xml").write_text(
        '<root BTCPP_format="4"><TreeNodesModel><Action ID="CloseGripper"/></TreeNodesModel></root>\n'
    )
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        report = runner.check(["src/robot/objectives/pick.xml"], Settings())
        folder = runner.check(["src/robot"], Settings())  # a folder given by name: the same
    finally:
        os.chdir(old)
    assert report.findings == [] and report.files == ["src/robot/objectives/pick.xml"]
    assert folder.findings == [] and folder.files == ["src/robot/objectives/pick.xml"]


# The projects kept in their own layout (ORIGIN.md, "Projects in their own layout"): files of trees;
# those that load with no flag; those that load after one `btgen models .` (at the top of a copy);
# and, for each other file, the codes check gives. Every code left is one BehaviorTree.CPP refuses
# too, recorded with the real 4.6.2 and 4.10.0 (docs/check.md, "More real projects"): WHY says which.
WHY = {
    "E401": "v3's Parallel `failure_threshold`/`success_threshold`: 4.x has no such port ('a port with name "
    "[failure_threshold] is found in the XML, but not in the providedPorts()')",
    "E403": '`Timeout msec=""`: \'The port with name "msec" and value "" can not be converted to unsigned int\'',
    "E205": "a SubTree of MoveIt Pro's own objectives, which are not in the repository: 'Can't find a tree "
    "with name: Move to Waypoint'",
}
_PAR = {"E401"}
PROJECTS = {
    "aerostack2": (
        8,
        2,
        {"as2_behavior_tree/resource/" + f: _PAR for f in ("RTL_test_2.xml", "event_test.xml", "event_test_2.xml")},
    ),
    "auto-apms": (7, 6, {}),
    "behavior_tree_moveit2_nodes": (3, 3, {}),
    "btcpp-ros2-example": (1, 0, {"ros2_ws/src/coordinator/trees/example_main.xml": _PAR}),
    "giu_f1t_behavior_tree": (8, 8, {}),
    "moveit_pro_mobile_manipulation": (36, 1, 13),
    "moveit_pro_training_ws": (26, 2, {}),
    "moveit_pro_ur_config": (2, 0, {}),
    "opennav_coverage": (3, 0, {}),
    "project_mbzirc": (
        28,
        2,
        {
            **{
                f: _PAR
                for f in (
                    "drone_roles/anchor.xml",
                    "drone_roles/inspection.xml",
                    "drone_roles/inspection_drone_4.xml",
                    "drone_roles/inspection_drone_5.xml",
                    "drone_roles/inspection_drone_6.xml",
                    "drone_roles/inspection_test.xml",
                    "test/pick/full_pick.xml",
                    "usv/tree.xml",
                    "usv/usv.xml",
                )
            },
            "drone_roles/usv_v1.xml": {"E403"},
        },
    ),
    # ours (ORIGIN.md): generalist_bt_gen's layout and C++ queue port, E601 on all 6 queue files before
    "queue_project": (7, 0, {}),
    "ros2_behavior_tree_example": (6, 6, {}),
    "ros2_planning_system_examples": (3, 0, {}),
    "turtlebot3_behavior_demos": (4, 4, {}),
    # 296 files, checked twice: 114 s wall on the busy shared machine; run with BTGEN_REAL_PROJECTS=all
    "moveit_pro_example_ws": (296, 23, 109),
}
SLOW = {"moveit_pro_example_ws"}


@pytest.mark.parametrize("project", sorted(PROJECTS))
def test_real_project_in_its_layout(project, tmp_path, capsys):
    if project in SLOW and os.environ.get("BTGEN_REAL_PROJECTS") != "all":
        pytest.skip("set BTGEN_REAL_PROJECTS=all")
    count, zero, after = PROJECTS[project]
    files, loads, errors, messages = outcome(REAL / project)
    assert (len(files), len(loads)) == (count, zero)
    # what does not load with no flag: nodes the program registers in C++ (C101 says how to declare
    # them: `btgen models DIR`), or what is left after that
    left = after if isinstance(after, dict) else {}
    for path, codes in errors.items():
        assert codes <= {"C101", "E301"} | set().union(*left.values(), WHY if not left else set()), (path, codes)
    copy = tmp_path / project
    shutil.copytree(REAL / project, copy)
    assert main(["models", str(copy), "-o", str(copy / "btgen_models.xml")]) == 0
    capsys.readouterr()
    files, loads, errors, messages = outcome(copy)
    if isinstance(after, dict):
        assert errors == after, messages
    else:
        assert len(files) - len(loads) == after and set().union(*errors.values()) <= set(WHY), errors
    for path, codes in errors.items():
        if "E205" in codes:
            assert all("does not exist" in m for m in messages[path] if "SubTree" in m), messages[path]
