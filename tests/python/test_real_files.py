"""Real BehaviorTree.CPP v4 files from public projects (tests/real_files/, ORIGIN.md): each is
validated, compiled and built (g++ -Werror) for 4.6.2 and for 4.10.0, those using only built-in
nodes and plain leaves (runnable.txt) run on both engines and print the trace the real 4.6.2
(expected/) and the real 4.10.0 (expected-4.10.0/) printed, and those the real library refuses
(refused.txt) are refused with a path:line:col error on the line the library names."""

import glob
import os
import re
import shutil
import subprocess
import sys

import pytest

import cppbuild
from btgen.cli import main
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "real_files")
NAV2_MODELS = os.path.join(HERE, "nav2", "nav2_tree_nodes.xml")


def _runnable() -> dict[str, str]:
    out = {}
    with open(os.path.join(HERE, "runnable.txt"), encoding="utf-8") as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                path, scenario = line.split()
                out[path] = scenario
    return out


def _flat(rel: str) -> str:
    """expected/ names a file by its path with `/` as `__`, without `.xml`."""
    return rel.replace("/", "__")[: -len(".xml")]


def _refused() -> list[str]:
    with open(os.path.join(HERE, "refused.txt"), encoding="utf-8") as f:
        return sorted(line.strip() for line in f if line.strip() and not line.startswith("#"))


RUNNABLE = _runnable()
REFUSED = _refused()
NAV2 = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "nav2", "*.xml")) if p != NAV2_MODELS)
ALL = NAV2 + sorted(RUNNABLE)
VERSIONS = ["4.6.2", "4.10.0"]
EXPECTED = {"4.6.2": "expected", "4.10.0": "expected-4.10.0"}
# The generated C++ of 4.6.2 and 4.10.0 differs in the version flags the runtime reads: both are
# built for every file (cheap); the cpp engine, which compiles and links a whole program per
# run, runs on these representatives (plain leaves, SubTree ports, includes, a literal `${...}`,
# 4.10.0-only files, TryCatch, a trace that differs between the versions) and on the projects'
# files under 4.6.2; the interpreter runs every runnable file.
CPP_410 = {
    "btcpp/tests-4.10.0/gtest_subtree_L823.xml",  # loads on 4.6.2 only
    "btcpp/tests-4.10.0/gtest_port_type_rules_L665.xml",  # traces differ between the versions
    "btcpp/examples/subtrees/Talk.xml",
    "btcpp/trees/parent_include_child_include_sibling.xml",
    "plansys2/transport.xml",
    "btcpp/fuzzing/corpus1.xml",
    "btcpp/tests-4.10.0/gtest_try_catch_L117.xml",
    "btcpp/tests-4.10.0/gtest_try_catch_L391.xml",
}
# Our queue project (ORIGIN.md): tests/conformance/user-queues runs its feature on both engines
# and releases in one batched build each; the cpp engine runs two of its files here.
CPP_QUEUE = {
    "queue_project/src/mission_runner/trees/patrol_route.xml",
    "queue_project/src/mission_runner/trees/gps_survey.xml",
}
# Where btgen follows a later release on purpose (FORMAT.md): the real library refuses the
# file, btgen loads it.
DELIBERATE = {
    # 4.6.2's parser refuses a unary operator after a comparison (`A!=-1`): a parser bug that
    # 4.9.0 fixed; btgen parses it under 4.6.2 as well (lang/script/grammar462.py, FORMAT.md).
    ("btcpp/tests-4.10.0/script_parser_test_L497.xml", "4.6.2"),
}


def _recorded(rel: str, version: str) -> str | None:
    """What the real `version` did with the file: "trace", "refused", or None (not recorded:
    Nav2's trees, which need Nav2's C++ nodes; load_check.cpp records that they load)."""
    for what in ("trace", "refused"):
        if os.path.exists(os.path.join(HERE, EXPECTED[version], f"{_flat(rel)}.{what}")):
            return what
    return None


def _loads(rel: str, version: str) -> bool:
    return _recorded(rel, version) != "refused" or (rel, version) in DELIBERATE


def _options(rel: str, tmp_path) -> list[str]:
    """What the program does in C++ (ORIGIN.md): Nav2's models file; for files whose leaves
    are declared nowhere, the models `btgen models` infers (the first of the two commands)."""
    if rel.startswith("nav2/"):
        return ["--models", NAV2_MODELS]
    if rel.startswith(("btcpp/trees/", "btcpp/fuzzing/")):
        return []
    models = str(tmp_path / "inferred_models.xml")
    # 4.10.0's own test trees are 4.10.0 programs: TryCatch is its built-in, no model.
    version = ["--btcpp", "4.10.0"] if rel.startswith("btcpp/tests-4.10.0/") else []
    assert main(["models", os.path.join(HERE, rel), "-o", models, *version]) == 0
    return ["--models", models]


def test_every_real_file_is_listed():
    # (the projects kept in their own layout, checked by test_check_real.py, are not this file's)
    files = sorted(
        os.path.relpath(p, HERE)
        for top in ("nav2", "btcpp", "plansys2", "queue_project")
        for p in glob.glob(os.path.join(HERE, top, "**", "*.xml"), recursive=True)
    )
    assert files == sorted(ALL + REFUSED + [os.path.relpath(NAV2_MODELS, HERE)])
    assert len(NAV2) == 15 and len(RUNNABLE) == 48 and len(REFUSED) == 3
    for version in VERSIONS:
        recorded = sorted(os.listdir(os.path.join(HERE, EXPECTED[version])))
        assert recorded == sorted(f"{_flat(r)}.{_recorded(r, version)}" for r in list(RUNNABLE) + REFUSED)
        assert all(_recorded(r, version) == "refused" for r in REFUSED)


@pytest.mark.parametrize("rel,version", [(r, v) for r in ALL for v in VERSIONS if _loads(r, v)])
def test_validates_compiles_and_builds(rel, version, tmp_path, capsys):
    if shutil.which("g++") is None:
        pytest.skip("no g++")
    path = os.path.join(HERE, rel)
    opts = _options(rel, tmp_path) + ["--btcpp", version]
    assert main(["validate", "-q", path, *opts]) == 0, capsys.readouterr().err
    out = tmp_path / "out"
    assert main(["compile", path, "-o", str(out), *opts]) == 0, capsys.readouterr().err
    [source] = glob.glob(str(out / "*.cpp"))
    cppbuild.build([source], tmp_path / "m.o", cxx="g++", opt="-O0", mode="object", includes=[out])


def _runs() -> list[tuple[str, str, str]]:
    out = []
    for rel in sorted(RUNNABLE):
        # The cpp engine compiles a program per run: every file of the projects under 4.6.2,
        # the representatives (CPP_410) otherwise; the interpreter runs everything.
        cpp_462 = (not rel.startswith(("btcpp/tests-4.10.0/", "queue_project/")) or rel in CPP_410) or rel in CPP_QUEUE
        for engine in ("interp", "cpp"):
            if _recorded(rel, "4.6.2") == "trace" and (engine == "interp" or cpp_462):
                out.append((rel, engine, "4.6.2"))
            if _recorded(rel, "4.10.0") == "trace" and (engine == "interp" or rel in CPP_410):
                out.append((rel, engine, "4.10.0"))
    return out


@pytest.mark.parametrize("rel,engine,version", _runs())
def test_runs_as_the_real_library(rel, engine, version, tmp_path):
    opts = _options(rel, tmp_path) + ["--btcpp", version]
    scenario = os.path.join(HERE, "scenarios", RUNNABLE[rel] + ".scenario")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", os.path.join(HERE, rel), "--scenario", scenario]
        + ["--engine", engine, *opts],
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    expected = os.path.join(HERE, EXPECTED[version], _flat(rel) + ".trace")
    with open(expected, encoding="utf-8") as f:
        assert proc.stdout == f.read()


@pytest.mark.parametrize(
    "rel,version",
    [(r, v) for r in sorted(RUNNABLE) + REFUSED for v in VERSIONS if not _loads(r, v)],
)
def test_refused_as_by_the_real_library(rel, version, tmp_path, capsys):
    """The library's refusal (recorded) names a line or not; btgen refuses with located errors,
    one of them on that line."""
    path = os.path.join(HERE, rel)
    assert main(["validate", path, *_options(rel, tmp_path), "--btcpp", version]) == 1
    errors = [e for e in capsys.readouterr().err.splitlines() if e.strip() and ": warning: " not in e]
    assert errors and all(re.match(re.escape(path) + r":\d+:\d+: error: ", e) for e in errors), errors
    with open(os.path.join(HERE, EXPECTED[version], _flat(rel) + ".refused"), encoding="utf-8") as f:
        library = f.read()
    line = re.search(r"line (\d+)", library)
    if line:
        assert any(e.startswith(f"{path}:{line.group(1)}:") for e in errors), (library, errors)


@pytest.mark.parametrize("version", VERSIONS)
def test_tree_ids_naming_registered_nodes_are_refused(version, tmp_path, capsys):
    """corpus3.xml's refusal (<SubTree ID="SubTree">), recorded on 4.6.2 and 4.10.0 alike:
    `The attribute [ID] of tag <SubTree> must not use the name of a registered Node`, and the
    same for <BehaviorTree>, for built-ins and for nodes registered in C++ (declared in
    TreeNodesModel). btgen accepted these trees before."""
    mission = tmp_path / "m.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="MainTree">\n'
        '  <BehaviorTree ID="MainTree">\n'
        "    <Sequence>\n"
        '      <SubTree ID="MyLeaf"/>\n'
        '      <SubTree ID="Fine"/>\n'
        "    </Sequence>\n"
        "  </BehaviorTree>\n"
        '  <BehaviorTree ID="MyLeaf"><AlwaysSuccess/></BehaviorTree>\n'
        '  <BehaviorTree ID="Fine"><MyLeaf/></BehaviorTree>\n'
        '  <BehaviorTree ID="Sequence"><AlwaysSuccess/></BehaviorTree>\n'
        '  <TreeNodesModel><Action ID="MyLeaf"/></TreeNodesModel>\n'
        "</root>\n"
    )
    assert main(["validate", str(mission), "--btcpp", version]) == 1
    assert capsys.readouterr().err.splitlines() == [
        f"{mission}:4:20: error: the ID of <SubTree> is `MyLeaf`, a node declared in TreeNodesModel: "
        "BehaviorTree.CPP refuses a tree or SubTree ID that names a registered node (rename the tree)",
        f"{mission}:8:21: error: the ID of <BehaviorTree> is `MyLeaf`, a node declared in TreeNodesModel: "
        "BehaviorTree.CPP refuses a tree or SubTree ID that names a registered node (rename the tree)",
        f"{mission}:10:21: error: the ID of <BehaviorTree> is `Sequence`, a built-in node: "
        "BehaviorTree.CPP refuses a tree or SubTree ID that names a registered node (rename the tree)",
    ]
    # TryCatch is built in from 4.9.0 only: a tree of that name loads on 4.6.2.
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="MainTree">\n'
        '  <BehaviorTree ID="MainTree"><SubTree ID="TryCatch"/></BehaviorTree>\n'
        '  <BehaviorTree ID="TryCatch"><AlwaysSuccess/></BehaviorTree>\n'
        "</root>\n"
    )
    assert main(["validate", "-q", str(mission), "--btcpp", version]) == (0 if version == "4.6.2" else 1)


@pytest.mark.parametrize("version", VERSIONS)
def test_warnings_name_the_selected_version(version, tmp_path, capsys):
    """transport.xml's `${arg2}` literals: recorded as text on 4.6.2 and on 4.10.0 (the same
    trace); the warning named 4.6.2 under --btcpp 4.10.0 before."""
    rel = "plansys2/transport.xml"
    assert main(["validate", os.path.join(HERE, rel), *_options(rel, tmp_path), "--btcpp", version]) == 0
    warnings = [w for w in capsys.readouterr().err.splitlines() if "${" in w]
    assert len(warnings) == 2
    assert all(w.endswith(f"BehaviorTree.CPP {version} reads it as this literal text") for w in warnings)


@pytest.mark.parametrize("rel,version", sorted(DELIBERATE))
def test_deliberate_differences_load(rel, version, tmp_path, capsys):
    """The real library refused these (recorded); btgen loads them on purpose (DELIBERATE)."""
    assert _recorded(rel, version) == "refused"
    path = os.path.join(HERE, rel)
    assert main(["validate", "-q", path, *_options(rel, tmp_path), "--btcpp", version]) == 0, capsys.readouterr().err


def test_a_program_may_register_a_control_named_trycatch_under_4_6_2(tmp_path, capsys):
    """Under 4.6.2 `TryCatch` is no built-in: a program may register a Control of that name
    (the real 4.6.2 runs the registered node). btgen crashed lowering it (KeyError: the
    built-in's parameters were looked up) and would have run 4.10.0's TryCatch."""
    rel = "btcpp/tests-4.10.0/gtest_try_catch_L57.xml"
    models = tmp_path / "models.xml"
    assert main(["models", os.path.join(HERE, rel), "-o", str(models), "--btcpp", "4.6.2"]) == 0
    assert '<Control ID="TryCatch"/>' in models.read_text()
    # Under 4.10.0 it is the built-in: `btgen models` declared it all the same before.
    models410 = tmp_path / "models410.xml"
    assert main(["models", os.path.join(HERE, rel), "-o", str(models410), "--btcpp", "4.10.0"]) == 0
    assert "TryCatch" not in models410.read_text()
    out = tmp_path / "out"
    args = [os.path.join(HERE, rel), "--models", str(models), "--btcpp", "4.6.2"]
    assert main(["compile", *args, "-o", str(out)]) == 0, capsys.readouterr().err
    [header] = glob.glob(str(out / "*.hpp"))
    with open(header, encoding="utf-8") as f:
        text = f.read()
    assert "NodeKind::TryCatch" not in text and "NodeKind::UserControl" in text
