"""--models, --main-tree and --namespace; repeated TreeNodesModel declarations."""

import os
import re
import shutil
from pathlib import Path

import pytest

import cppbuild
from btgen.backend_cpp import naming
from btgen.cli import main
from btgen.compiler import generate, mission_files
from btgen.compiler import main as build_info
from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.pipeline import CompileOptions

ROOT = Path(__file__).resolve().parents[2]

MODELS = (
    '<root BTCPP_format="4">\n'
    "  <TreeNodesModel>\n"
    '    <Action ID="MoveBase">\n'
    '      <input_port name="goal" type="std::string"/>\n'
    "    </Action>\n"
    '    <Condition ID="BatteryOk"/>\n'
    "  </TreeNodesModel>\n"
    "</root>\n"
)
# Two trees, no main_tree_to_execute, no TreeNodesModel: the models live elsewhere.
BARE = (
    '<root BTCPP_format="4">\n'
    '  <BehaviorTree ID="Patrol">\n'
    '    <Sequence><BatteryOk/><MoveBase goal="kitchen"/></Sequence>\n'
    "  </BehaviorTree>\n"
    '  <BehaviorTree ID="Dock"><MoveBase goal="dock"/></BehaviorTree>\n'
    "</root>\n"
)


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def _errors(path, **kw):
    with pytest.raises(UserError) as e:
        load_mission(path, **kw)
    return [str(d) for d in e.value.diagnostics]


def test_models_file_declares_the_missions_nodes(tmp_path):
    mission, models = _write(tmp_path, "m.xml", BARE), _write(tmp_path, "models.xml", MODELS)
    errors = _errors(mission, main_tree="Patrol")
    assert any("`BatteryOk` is not a built-in node" in e or "BatteryOk" in e for e in errors)
    m = load_mission(mission, models=[models], main_tree="Patrol")
    assert m.main_tree == "Patrol"
    assert sorted(s.id for s in m.models) == ["BatteryOk", "MoveBase"]
    assert m.files == (mission, models)
    assert mission_files(mission, CompileOptions(models=(models,))) == [
        os.path.abspath(mission),
        os.path.abspath(models),
    ]


def test_main_tree_picks_and_overrides(tmp_path):
    mission, models = _write(tmp_path, "m.xml", BARE), _write(tmp_path, "models.xml", MODELS)
    errors = _errors(mission, models=[models])
    assert errors == [
        f"{mission}:1:1: error: the mission defines 2 BehaviorTrees; say which one runs with "
        f'main_tree_to_execute="..." or --main-tree (one of `Dock`, `Patrol`)'
    ]
    assert load_mission(mission, models=[models], main_tree="Dock").main_tree == "Dock"
    assert _errors(mission, models=[models], main_tree="Dok") == [
        f"{mission}:1:1: error: --main-tree names `Dok`, but no BehaviorTree has that ID (did you mean `Dock`?)"
    ]
    with_main = _write(
        tmp_path,
        "w.xml",
        BARE.replace('<root BTCPP_format="4">', '<root BTCPP_format="4" main_tree_to_execute="Patrol">'),
    )
    assert load_mission(with_main, models=[models]).main_tree == "Patrol"
    assert load_mission(with_main, models=[models], main_tree="Dock").main_tree == "Dock"
    header = generate(with_main, models=[models], main_tree="Dock")[0].text
    assert 'kMainTree = "Dock";' in header


def test_identical_repeated_declarations_are_one_model(tmp_path):
    """A Groot2 project split over files repeats each model; BehaviorTree.CPP loads it."""
    mission = _write(
        tmp_path, "m.xml", BARE.replace("</root>", MODELS.split("\n", 1)[1].rsplit("</root>", 1)[0] + "</root>")
    )
    models = _write(tmp_path, "models.xml", MODELS)
    m = load_mission(mission, models=[models, models], main_tree="Patrol")
    assert sorted(s.id for s in m.models) == ["BatteryOk", "MoveBase"]
    assert m.models[0].loc.path == mission  # the first declaration is the one kept


@pytest.mark.parametrize(
    "changed, why",
    [
        (
            '<Condition ID="MoveBase"><input_port name="goal" type="std::string"/></Condition>',
            "<Action> there, <Condition> here",
        ),
        (
            '<Action ID="MoveBase"><input_port name="goal" type="int"/></Action>',
            "port `goal` has type `string` there, `int` here",
        ),
        (
            '<Action ID="MoveBase"><output_port name="goal" type="std::string"/></Action>',
            "port `goal` is an input port there, an output port here",
        ),
        (
            '<Action ID="MoveBase"><input_port name="goal" type="std::string" default="x"/></Action>',
            "port `goal` has no default there, default `x` here",
        ),
        (
            '<Action ID="MoveBase"><input_port name="goal" type="std::string"/><input_port name="speed"/></Action>',
            "port `speed` here, not there",
        ),
        ('<Action ID="MoveBase"/>', "port `goal` there, not here"),
    ],
)
def test_conflicting_declarations_name_both_places(tmp_path, changed, why):
    mission = _write(tmp_path, "m.xml", BARE)
    models = _write(tmp_path, "models.xml", MODELS)
    other = _write(
        tmp_path, "other.xml", f'<root BTCPP_format="4">\n<TreeNodesModel>{changed}</TreeNodesModel></root>\n'
    )
    col = changed.index('"MoveBase"') + 18  # the ID's value, after <TreeNodesModel>
    # BehaviorTree.CPP never reads a registered node's model (recorded on 4.6.2 and 4.10.0): it
    # loads, with a warning that names both places; btgen takes the ports of both
    m = load_mission(mission, models=[models, other], main_tree="Patrol")
    assert [str(d) for d in m.warnings] == [
        f"{other}:2:{col}: warning: `MoveBase` is declared twice in TreeNodesModel and the declarations differ: "
        f"{why} (first at {models}:3:5); BehaviorTree.CPP never reads the models of the nodes it registers: "
        "btgen takes the ports of both (untyped where the types differ)"
    ]
    move = next(s for s in m.models if s.id == "MoveBase")
    assert {p.name for p in move.ports} >= {"goal"}


def test_models_file_holds_only_tree_nodes_model(tmp_path):
    mission = _write(tmp_path, "m.xml", BARE)
    not_models = _write(
        tmp_path, "x.xml", '<root BTCPP_format="4">\n<BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree>\n</root>\n'
    )
    assert _errors(mission, models=[not_models], main_tree="Patrol")[0] == (
        f"{not_models}:2:1: error: a models file (--models) holds only <TreeNodesModel>, not <BehaviorTree>; "
        f"pass a mission as the mission, or include it with <include path=...>"
    )
    missing = str(tmp_path / "nope.xml")
    assert _errors(mission, models=[missing], main_tree="Patrol") == [
        f"{missing}:1:1: error: cannot read file: No such file or directory"
    ]


def test_namespace_default_never_clashes():
    assert naming.namespace_name("main") == "main_"
    assert naming.namespace_name("btgen") == "btgen_"
    assert naming.namespace_name("std") == "std_"
    assert naming.namespace_name("class") == "class_"
    assert naming.namespace_name("LabTour") == "lab_tour"


@pytest.mark.parametrize(
    "ns, problem",
    [
        ("class", "`class` is a C++ keyword"),
        ("main", "`main` clashes with the program's main(); choose another name"),
        ("btgen::x", "`btgen` clashes with btgen's runtime; choose another name"),
        ("errno", "`errno` is a macro of the C++ standard library"),
        ("exit::robot", "`exit` names something of the C++ standard library at global scope; choose another name"),
        ("std", "`std` clashes with the standard library; choose another name"),
        ("9lives", "`9lives` is not a C++ identifier (letters, digits and `_`, not starting with a digit)"),
        ("a__b", "`a__b` is reserved in C++ (a leading `_` or a double underscore)"),
        ("_robot", "`_robot` is reserved in C++ (a leading `_` or a double underscore)"),
        ("robot::", "`robot::` has an empty part"),
        ("", "the namespace is empty"),
        # Each of these generated C++ that does not build
        (
            "robot::std",
            "`std` inside the mission's namespace would hide `::std`, which the generated code names there; "
            "choose another name",
        ),
        (
            "robot::btgen",
            "`btgen` inside the mission's namespace would hide `::btgen`, which the generated code names there; "
            "choose another name",
        ),
        ("a\n::b", "`a\\n` is not a C++ identifier (letters, digits and `_`, not starting with a digit)"),
        ("a::b\n", "`b\\n` is not a C++ identifier (letters, digits and `_`, not starting with a digit)"),
        (
            "r\u00e9sum\u00e9",
            "`r\u00e9sum\u00e9` is not a C++ identifier (letters, digits and `_`, not starting with a digit)",
        ),
        ("nullptr_t", "`nullptr_t` names something of the C++ standard library at global scope; choose another name"),
        ("NDEBUG", "`NDEBUG` is a macro of btgen's runtime or of a build (`NDEBUG`, `BTGEN_...`, `ZMQ_...`)"),
        ("robot::NDEBUG", "`NDEBUG` is a macro of btgen's runtime or of a build (`NDEBUG`, `BTGEN_...`, `ZMQ_...`)"),
        (
            "BTGEN_STRAIGHT_LINE_BUDGET",
            "`BTGEN_STRAIGHT_LINE_BUDGET` is a macro of btgen's runtime or of a build "
            "(`NDEBUG`, `BTGEN_...`, `ZMQ_...`)",
        ),
    ],
)
def test_bad_namespace_is_rejected_clearly(tmp_path, capsys, ns, problem):
    assert naming.namespace_problem(ns) == problem
    mission = _write(tmp_path, "m.xml", BARE)
    with pytest.raises(SystemExit) as e:
        main(["compile", mission, "--namespace", ns, "-o", str(tmp_path / "o")])
    assert e.value.code == 1
    assert f": error: argument --namespace: {problem}" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.skipif(shutil.which("g++") is None, reason="no g++")
def test_accepted_namespaces_with_odd_parts_build(tmp_path):
    # Inner parts that are names the generated code declares itself, or globals: they build.
    mission, models = _write(tmp_path, "m.xml", BARE), _write(tmp_path, "models.xml", MODELS)
    for ns in ("robot::detail", "robot::leaf", "robot::exit", "robot::main", "robot::errno_"):
        out = tmp_path / ns.replace("::", "_")
        assert (
            main(["compile", mission, "--models", models, "--main-tree", "Patrol", "--namespace", ns, "-o", str(out)])
            == 0
        )
        proc = cppbuild.run(
            cppbuild.command(
                [out / "m.cpp"], cxx="g++", mode="syntax", warnings=False, flags=["-Wall", "-Wextra", "-Werror"]
            )
            + ["-DNDEBUG"]
        )
        assert proc.returncode == 0, (ns, proc.stderr[:3000])


def test_compile_with_all_options(tmp_path, capsys):
    mission, models = _write(tmp_path, "main.xml", BARE), _write(tmp_path, "models.xml", MODELS)
    out = tmp_path / "o"
    assert (
        main(
            [
                "compile",
                mission,
                "--models",
                models,
                "--main-tree",
                "Patrol",
                "--namespace",
                "robot::missions",
                "-o",
                str(out),
            ]
        )
        == 0
    )
    header = (out / "main.hpp").read_text()
    assert "namespace robot::missions {" in header and "}  // namespace robot::missions" in header
    assert main(["compile", mission, "--models", models, "--main-tree", "Patrol", "-o", str(out)]) == 0
    assert "namespace main_ {" in (out / "main.hpp").read_text()
    assert build_info(["--template", mission, "--namespace", "robot::missions"]) == 0
    assert capsys.readouterr().out == "robot::missions::Main\n"
    assert build_info(["--check", mission, "--models", models, "--main-tree", "Dock"]) == 0
    assert build_info(["--check", mission, "--models", models]) == 1


def test_validate_run_and_xsd_take_the_options(tmp_path, capsys):
    mission, models = _write(tmp_path, "m.xml", BARE), _write(tmp_path, "models.xml", MODELS)
    scenario = _write(tmp_path, "s.scenario", "")
    assert main(["validate", mission, "--models", models, "--main-tree", "Dock"]) == 0
    assert capsys.readouterr().out == f"{mission}: ok (2 trees, main `Dock`)\n"
    assert main(["validate", mission, "--models", models]) == 1
    capsys.readouterr()
    assert main(["xsd", mission, "--models", models, "--main-tree", "Dock"]) == 0
    assert 'name="MoveBase"' in capsys.readouterr().out
    assert main(["run", mission, "--models", models, "--main-tree", "Dock", "--scenario", scenario]) == 0
    assert capsys.readouterr().out == (
        'tick 1\n1 MoveBase "MoveBase" IDLE -> SUCCESS\n1 MoveBase "MoveBase" SUCCESS -> IDLE\nresult SUCCESS\n'
    )


def test_models_no_node_uses_cost_nothing(tmp_path):
    """A 2-node mission with a palette of 600 unused Actions took g++ 45 s (2,000: 7 minutes,
    1.4 GB): every model got a leaf class, dispatch branches and virtual hooks, a pure virtual
    check() per Condition. Only used models get them; Groot2 still sees the whole palette."""
    palette = (
        "\n".join(f'    <Action ID="Unused{i}"><input_port name="a" type="int"/></Action>' for i in range(600))
        + '\n    <Condition ID="UnusedCheck"/>\n    <Condition ID="Used"/>'
    )
    models = _write(
        tmp_path, "models.xml", f'<root BTCPP_format="4"><TreeNodesModel>\n{palette}\n</TreeNodesModel></root>'
    )
    mission = _write(
        tmp_path,
        "m.xml",
        '<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M">'
        "<Sequence><Used/><AlwaysSuccess/></Sequence></BehaviorTree></root>",
    )
    assert main(["compile", mission, "--models", models, "-o", str(tmp_path / "o")]) == 0
    header = (tmp_path / "o" / "m.hpp").read_text()
    assert re.search(r"\bUsed\b", header) and "check(" in header
    assert not re.search(r"\b(class|struct) Unused", header)
    assert "Unused" not in header  # (the tree XML of Groot2 is in the mission's .cpp)
    source = (tmp_path / "o" / "m.cpp").read_text()
    assert source.count('<Action ID=\\"Unused') == 600


@pytest.mark.parametrize(
    "root, models, expected",
    [
        # (each was taken silently)
        (
            '<root BTCPP_format="3">',
            '<Action ID="MoveBase"><input_port name="goal"/></Action><Condition ID="BatteryOk"/>',
            [
                '1:21: error: BTCPP_format="3" is not supported; btgen reads BehaviorTree.CPP v4 files '
                '(BTCPP_format="4")'
            ],
        ),
        (
            '<root BTCPP_format="4" main_tree_to_execute="Dock">',
            '<Action ID="MoveBase"><input_port name="goal"/></Action><Condition ID="BatteryOk"/>',
            [
                "1:24: error: a models file does not choose the tree to run; main_tree_to_execute belongs to the "
                "mission (or --main-tree)"
            ],
        ),
        (
            '<root BTCPP_format="4">',
            '<Action ID="MoveBase"><input_port name="goal"/></Action><Condition ID="BatteryOk"/><SubTree ID="Dok"/>',
            ["2:100: error: SubTree model `Dok` names no BehaviorTree of the mission (did you mean `Dock`?)"],
        ),
    ],
)
def test_models_file_mistakes_are_reported(tmp_path, capsys, root, models, expected):
    mission = _write(tmp_path, "m.xml", BARE)
    path = _write(tmp_path, "models.xml", f"{root}\n<TreeNodesModel>{models}</TreeNodesModel></root>\n")
    assert main(["validate", mission, "--models", path, "--main-tree", "Patrol"]) == 1
    assert capsys.readouterr().err.splitlines() == [f"{path}:{e}" for e in expected]


def test_an_empty_models_file_name(tmp_path, capsys):
    # (it was reported at `:1:1:`)
    mission = _write(tmp_path, "m.xml", BARE)
    assert main(["validate", mission, "--models", "", "--main-tree", "Dock"]) == 1
    assert capsys.readouterr().err == "--models:1:1: error: the file name is empty\n"
