"""One pipeline: every command takes the same mission options and reads missions alike.

A mission that needs an option (a scripting enum, a models file, a main tree, a user port
type, a capacity) is accepted by `validate`, `compile` and `build-info --check` with that
option and refused by all three without it; every other command that reads a mission takes
the same options and builds the same CompileOptions from them.
"""

import itertools
import os
import subprocess
import sys

import pytest

from btgen.cli import build_parser
from btgen.cli import main as cli_main
from btgen.compiler import main as build_info
from btgen.pipeline import CompileOptions, options_from_args

ENUM_MISSION = """<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M">
    <Sequence>
      <Script code="c := GREEN"/>
      <ScriptCondition code="c == 1"/>
    </Sequence>
  </BehaviorTree>
</root>
"""

# No TreeNodesModel and no main_tree_to_execute: needs --models and --main-tree.
BARE_MISSION = """<root BTCPP_format="4">
  <BehaviorTree ID="Patrol"><Sequence><BatteryOk/><MoveBase goal="kitchen"/></Sequence></BehaviorTree>
  <BehaviorTree ID="Dock"><MoveBase goal="dock"/></BehaviorTree>
</root>
"""
MODELS = """<root BTCPP_format="4">
  <TreeNodesModel>
    <Action ID="MoveBase"><input_port name="goal" type="std::string"/></Action>
    <Condition ID="BatteryOk"/>
  </TreeNodesModel>
</root>
"""

# A literal of 40 bytes: refused by --string-capacity 16, accepted by default.
LONG_STRING = """<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M"><Script code="s := 'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa'"/></BehaviorTree>
</root>
"""

# A port of a user type: --type Pose=... makes the generated code include its header.
USER_TYPE = """<root BTCPP_format="4" main_tree_to_execute="M">
  <TreeNodesModel><Action ID="Go"><input_port name="p" type="Pose"/></Action></TreeNodesModel>
  <BehaviorTree ID="M"><Go p="1;2"/></BehaviorTree>
</root>
"""

# A SubTree defined in no file of the mission: needs --trees with the library.
USES_LIBRARY = """<root BTCPP_format="4">
  <BehaviorTree ID="M"><SubTree ID="Lent"/></BehaviorTree>
</root>
"""
LIBRARY = """<root BTCPP_format="4">
  <BehaviorTree ID="Lent"><AlwaysSuccess/></BehaviorTree>
</root>
"""

FULL_OPTIONS = [
    "--models",
    "{models}",
    "--trees",
    "lib",
    "--entry",
    "Sub:server_timeout=int",
    "--main-tree",
    "Patrol",
    "--enum",
    "Color=RED,GREEN",
    "--type",
    "Pose=geo::Pose@geo/pose.hpp",
    "--namespace",
    "robot::missions",
    "--string-capacity",
    "64",
    "--queue-capacity",
    "8",
]


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def _exit(argv):
    """The exit status of `btgen ARGV` (in process)."""
    try:
        return cli_main(argv)
    except SystemExit as e:
        return int(e.code or 0)


# Each command is offered the options that change what it does: the C++ namespace where C++ is
# written for the user, the capacities where the mission is lowered (sized).
@pytest.mark.parametrize(
    "command,namespace,capacities",
    [
        (["validate", "M.xml"], False, True),
        (["compile", "M.xml"], True, True),
        (["run", "M.xml", "--scenario", "S"], False, True),
        (["bench", "M.xml"], False, True),
        (["graph", "M.xml", "-o", "g.svg"], False, False),
        (["xsd", "M.xml"], False, False),
        (["analyze", "M.xml"], False, True),
        (["explore", "M.xml"], False, True),
        (["cover", "M.xml", "run.trace"], False, True),
        (["scenario-from-log", "M.xml", "run.btlog"], False, False),
        (["models", "M.xml"], False, False),
        (["upgrade-check", "M.xml"], False, False),
    ],
)
def test_every_command_builds_the_same_options(command, namespace, capacities, tmp_path):
    left_out = set()
    if not namespace:
        left_out.add("--namespace")
    if not capacities:
        left_out |= {"--string-capacity", "--queue-capacity"}
    argv = list(command)
    for name, value in zip(FULL_OPTIONS[::2], FULL_OPTIONS[1::2]):
        if name not in left_out:
            argv += [name, value.replace("{models}", "models.xml")]
    args = build_parser().parse_args(argv)
    assert options_from_args(args) == CompileOptions(
        models=("models.xml",),
        main_tree="Patrol",
        trees=("lib",),
        entries=("Sub:server_timeout=int",),
        enum_decls=("Color=RED,GREEN",),
        types=("Pose=geo::Pose@geo/pose.hpp",),
        namespace="robot::missions" if namespace else None,
        string_capacity=64 if capacities else None,
        queue_capacity=8 if capacities else None,
    )
    for name in sorted(left_out):  # and refused where they would change nothing
        with pytest.raises(SystemExit):
            build_parser().parse_args([*command, name, "8"])


def test_build_info_takes_the_same_options(tmp_path, capsys):
    mission, models = _write(tmp_path, "m.xml", BARE_MISSION), _write(tmp_path, "models.xml", MODELS)
    argv = [a.replace("{models}", models) for a in FULL_OPTIONS]
    assert build_info(["--template", mission, *argv]) == 0
    assert capsys.readouterr().out == "robot::missions::M\n"


CASES = [
    # (mission text, options it needs, extra files)
    ("enum", ENUM_MISSION, ["--enum", "Color=RED,GREEN"]),
    ("models_main_tree", BARE_MISSION, ["--models", "{models}", "--main-tree", "Patrol"]),
    ("trees", USES_LIBRARY, ["--trees", "{trees}"]),
]


@pytest.mark.parametrize("name,text,needed", CASES, ids=[c[0] for c in CASES])
def test_validate_compile_and_check_agree(name, text, needed, tmp_path, capsys):
    mission = _write(tmp_path, "m.xml", text)
    models = _write(tmp_path, "models.xml", MODELS)
    (tmp_path / "lib").mkdir()
    _write(tmp_path / "lib", "library.xml", LIBRARY)
    needed = [a.replace("{models}", models).replace("{trees}", str(tmp_path / "lib")) for a in needed]
    out = str(tmp_path / "out")
    with_option = (
        _exit(["validate", "-q", mission, *needed]),
        _exit(["compile", mission, "-o", out, *needed]),
        build_info(["--check", mission, *needed]),
    )
    without = (
        _exit(["validate", "-q", mission]),
        _exit(["compile", mission, "-o", str(tmp_path / "out2")]),
        build_info(["--check", mission]),
    )
    err = capsys.readouterr().err
    assert with_option == (0, 0, 0)
    if name == "enum":
        # Without the enum `GREEN` is an entry nothing creates: the library loads the mission and
        # throws where the script reads it, so btgen loads it with a warning (docs/data-side.md).
        assert without == (0, 0, 0)
        assert "reads `GREEN`, but nothing creates that blackboard entry" in err
    else:
        assert without == (1, 1, 1)


# The 6-line mission of issue 37: an entry of a user type the application provides. compile
# crashed (exit 3, in the template) while validate said ok.
USER_TYPED_ENTRY = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><Go goal="{goal}"/></BehaviorTree>
  <TreeNodesModel>
    <Action ID="Go"><input_port name="goal" type="Pose2D"/></Action>
  </TreeNodesModel>
</root>
"""

MISSIONS = {
    "enum": ENUM_MISSION,
    "bare": BARE_MISSION,
    "long_string": LONG_STRING,
    "user_type": USER_TYPE,
    "library": USES_LIBRARY,
    "user_typed_entry": USER_TYPED_ENTRY,
}
# The options these missions need or are refused with, in groups; every subset of the groups is
# one combination. BTGEN_FULL_OPTION_MATRIX=1 adds --namespace and --btcpp 4.10.0 (four times
# the combinations: 256 per mission).
OPTION_GROUPS = {
    "enum": ["--enum", "Color=RED,GREEN"],
    "models": ["--models", "{models}", "--main-tree", "Patrol"],
    "trees": ["--trees", "{trees}"],
    "entry": ["--entry", "goal=Pose2D"],
    "types": ["--type", "Pose=geo::Pose@geo/pose.hpp", "--type", "Pose2D=nav::Pose2D@nav/types.hpp"],
    "capacities": ["--string-capacity", "16", "--queue-capacity", "8"],
}
if os.environ.get("BTGEN_FULL_OPTION_MATRIX"):
    OPTION_GROUPS.update(namespace=["--namespace", "robot::missions"], btcpp=["--btcpp", "4.10.0"])


@pytest.mark.parametrize("name", list(MISSIONS))
def test_validate_runs_every_check_compile_runs(name, tmp_path, capsys):
    """Over every combination of the option groups: validate and compile give the same exit
    status and the same diagnostics (validate may add warnings; neither ever exits 3)."""
    mission = _write(tmp_path, "m.xml", MISSIONS[name])
    models = _write(tmp_path, "models.xml", MODELS)
    (tmp_path / "lib").mkdir()
    _write(tmp_path / "lib", "library.xml", LIBRARY)
    groups = list(OPTION_GROUPS)
    verdicts = set()
    for n in range(len(groups) + 1):
        for chosen in itertools.combinations(groups, n):
            options = [
                a.replace("{models}", models).replace("{trees}", str(tmp_path / "lib"))
                for g in chosen
                for a in OPTION_GROUPS[g]
            ]
            validate = _exit(["validate", mission, *options])
            validate_err = capsys.readouterr().err
            compiled = _exit(["compile", mission, "-o", str(tmp_path / "out"), *options])
            compile_err = capsys.readouterr().err
            assert validate == compiled, (chosen, validate_err, compile_err)
            # every diagnostic of compile, in its order; validate may add warnings of its own
            # (a script reading an entry nothing writes), never an error
            v_lines = validate_err.splitlines()
            extra = [line for line in v_lines if line not in compile_err.splitlines()]
            assert [line for line in v_lines if line not in extra] == compile_err.splitlines(), chosen
            assert not [line for line in extra if ": error: " in line], (chosen, extra)
            assert validate in (0, 1), (chosen, validate_err)
            verdicts.add(validate)
    assert verdicts == {0, 1}  # each mission is accepted with some options and refused with others


def test_capacities_agree(tmp_path, capsys):
    mission = _write(tmp_path, "m.xml", LONG_STRING)
    small = ["--string-capacity", "16"]
    got = (
        _exit(["validate", "-q", mission, *small]),
        _exit(["compile", mission, "-o", str(tmp_path / "o"), *small]),
        build_info(["--check", mission, *small]),
        _exit(["validate", "-q", mission]),
        build_info(["--check", mission]),
    )
    capsys.readouterr()
    # a literal longer than the capacity widens its entry (issue 44): all agree, none refuses
    assert got == (0, 0, 0, 0, 0)


def test_types_reach_the_generated_header(tmp_path, capsys):
    mission = _write(tmp_path, "m.xml", USER_TYPE)
    out = tmp_path / "out"
    assert _exit(["compile", mission, "-o", str(out), "--type", "Pose=geo::Pose@geo/pose.hpp"]) == 0
    assert '#include "geo/pose.hpp"' in (out / "m.hpp").read_text(encoding="utf-8")
    assert build_info(["--check", mission, "--type", "Pose=geo::Pose@geo/pose.hpp"]) == 0
    assert _exit(["validate", "-q", mission, "--type", "Pose=not a type@x.hpp"]) == 1
    assert build_info(["--check", mission, "--type", "Pose=not a type@x.hpp"]) == 1
    capsys.readouterr()


def test_run_takes_enums(tmp_path):
    # The interpreter reads the same options: the enum makes the condition true.
    mission = _write(tmp_path, "m.xml", ENUM_MISSION)
    scenario = _write(tmp_path, "s.scenario", "")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", mission, "--scenario", scenario, "--enum", "Color=RED,GREEN"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.rstrip().endswith("SUCCESS")


def test_cmake_mission_compiles_takes_the_options(tmp_path, repo_root):
    # btgen_mission_compiles() gives build-info --check the options btgen_add_mission() gives
    # compile: a mission that needs a scripting enum compiles with ENUMS, not without.
    import shutil

    if shutil.which("cmake") is None:
        pytest.skip("cmake is not installed")
    _write(tmp_path, "m.xml", ENUM_MISSION)
    _write(tmp_path, "uses.xml", USES_LIBRARY)
    (tmp_path / "lib").mkdir()
    _write(tmp_path / "lib", "library.xml", LIBRARY)
    _write(
        tmp_path,
        "trycatch.xml",
        '<root BTCPP_format="4"><BehaviorTree ID="M"><TryCatch><AlwaysSuccess/><AlwaysFailure/>'
        "</TryCatch></BehaviorTree></root>\n",
    )
    _write(
        tmp_path,
        "CMakeLists.txt",
        "cmake_minimum_required(VERSION 3.16)\nproject(p CXX)\n"
        f'include("{repo_root}/cmake/btgen.cmake")\n'
        'btgen_mission_compiles(with_enum m.xml ENUMS "Color=RED,GREEN")\n'
        "btgen_mission_compiles(without m.xml)\n"
        "btgen_mission_compiles(with_trees uses.xml TREES lib)\n"
        "btgen_mission_compiles(without_trees uses.xml)\n"
        "btgen_mission_compiles(trycatch_410 trycatch.xml BTCPP_VERSION 4.10.0)\n"
        "btgen_mission_compiles(trycatch_462 trycatch.xml)\n"
        'message(STATUS "RESULT ${with_enum} ${without} ${with_trees} ${without_trees}")\n'
        'message(STATUS "BTCPP ${trycatch_410} ${trycatch_462}")\n',
    )
    proc = subprocess.run(
        ["cmake", "-S", str(tmp_path), "-B", str(tmp_path / "build"), f"-DPython3_EXECUTABLE={sys.executable}"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    # (without ENUMS the mission loads, with a warning btgen_mission_compiles keeps quiet: the
    # library throws where `GREEN` is read; test_validate_compile_and_check_agree reads it)
    assert "RESULT TRUE TRUE TRUE FALSE" in proc.stdout
    assert "BTCPP TRUE FALSE" in proc.stdout  # TryCatch is built in from 4.9.0
