"""`btgen tests --executor`: the suite's scenarios on btgen's compiled executor, from ctest.

The suite is configured with -DBTGEN_LIBRARY_TESTS=OFF (no BehaviorTree.CPP here), so ctest runs
only the executor entries: each runs `btgen run --engine cpp` on the scenario (one build of the
mission, cached) and compares the trace with executor/<TEST>.trace, the interpreter's.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
GUARD = ROOT / "tests" / "gtests" / "Guard.xml"
NAV2 = ROOT / "tests" / "real_files" / "nav2"


def _configure(src: Path, build: Path, *defs: str) -> None:
    cfg = subprocess.run(
        [
            "cmake",
            "-S",
            str(src),
            "-B",
            str(build),
            "-DBTGEN_LIBRARY_TESTS=OFF",
            f"-DBTGEN_COMMAND={sys.executable} -m btgen",
            *defs,
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert cfg.returncode == 0, cfg.stdout + cfg.stderr


def _ctest(build: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "generator")}
    cmd = ["ctest", "--test-dir", str(build), "--output-on-failure", *args]
    return subprocess.run(cmd, capture_output=True, text=True, check=False, env=env)


def test_the_suite_runs_on_the_compiled_executor(capsys, tmp_path):
    out = tmp_path / "suite"
    assert main(["tests", str(GUARD), "-o", str(out), "--executor"]) == 0
    # each scenario once (scenarios/<TEST>.scenario, read by the TEST's executor entry too)
    assert capsys.readouterr().out.startswith(f"{out}: 4 tests, 13 files")
    tests = sorted(p.stem for p in (out / "scenarios").iterdir())
    names = sorted(p.name for p in (out / "executor").iterdir())
    assert names == sorted([f"{t}.trace" for t in tests] + ["check.cmake"]) and len(tests) == 4
    cmake = (out / "CMakeLists.txt").read_text()
    assert cmake.count(".executor COMMAND") == 4 and "if(BTGEN_LIBRARY_TESTS)" in cmake
    for t in tests:
        assert f'"-DSCENARIO=${{CMAKE_CURRENT_SOURCE_DIR}}/scenarios/{t}.scenario"' in cmake
    build = tmp_path / "build"
    _configure(out, build)
    ok = _ctest(build)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert "100% tests passed, 0 tests failed out of 4" in ok.stdout
    # an expectation that is not the executor's trace fails, naming the line
    trace = out / "executor" / f"{tests[1]}.trace"
    lines = trace.read_text().splitlines()
    k = next(i for i, line in enumerate(lines) if "->" in line)
    lines[k] = lines[k].replace("IDLE -> RUNNING", "IDLE -> SUCCESS")
    trace.write_text("\n".join(lines) + "\n")
    bad = _ctest(build, "-R", "Guard.S02")
    assert bad.returncode != 0
    assert "tests failed out of 1" in bad.stdout and f"line {k + 1}: expected `" in bad.stdout


def test_run_options_are_carried(capsys, tmp_path):
    """--models, --main-tree and --btcpp reach `btgen run` as this command read the mission."""
    out = tmp_path / "suite"
    tree = NAV2 / "navigate_to_pose_w_bounds_check.xml"
    models = NAV2 / "nav2_tree_nodes.xml"
    args = ["tests", str(tree), "-o", str(out), "--executor", "--models", str(models), "--btcpp", "4.10.0"]
    assert main(args) == 0
    capsys.readouterr()
    cmake = (out / "CMakeLists.txt").read_text()
    assert f'set(BTGEN_RUN_OPTIONS "\\"--models\\" \\"{models}\\" \\"--btcpp\\" \\"4.10.0\\"")' in cmake


@pytest.mark.parametrize("bad", ['we"ird', "semi;colon"])
def test_paths_cmake_cannot_carry(capsys, tmp_path, bad):
    models = tmp_path / f"{bad}.xml"
    models.write_text((NAV2 / "nav2_tree_nodes.xml").read_text())
    out = tmp_path / "suite"
    tree = NAV2 / "navigate_to_pose_w_bounds_check.xml"
    assert main(["tests", str(tree), "-o", str(out), "--executor", "--models", str(models)]) == 1
    err = capsys.readouterr().err
    assert "error: --executor: " in err and "characters CMake cannot carry" in err
    assert not out.exists()


def test_enums_are_registered(capsys, tmp_path):
    """--enum reaches the library's suite (registerScriptingEnum before the tree is created) and
    the executor entries; a suite without it defines no enum."""
    mission = ROOT / "tests" / "gtests" / "Enums.xml"
    out = tmp_path / "suite"
    assert main(["tests", str(mission), "-o", str(out), "--enum", "Color=Red,Blue=3", "--executor"]) == 0
    capsys.readouterr()
    cpp = (out / "Enums_tests.cpp").read_text()
    assert '#define BTGEN_ENUMS { { "Red", 0 }, { "Blue", 3 } }' in cpp
    assert cpp.index("#define BTGEN_ENUMS") < cpp.index('#include "btgen_gtest_support.hpp"')
    support = (out / "btgen_gtest_support.hpp").read_text()
    assert "factory.registerScriptingEnum(name, value);" in support
    assert 'set(BTGEN_RUN_OPTIONS "\\"--enum\\" \\"Color=Red,Blue=3\\"")' in (out / "CMakeLists.txt").read_text()
    # the expectations are runs where `color == Blue` holds (3 == 3): Repaint is never ticked
    for trace in (out / "executor").glob("*.trace"):
        assert "Repaint" not in trace.read_text() and 'IsBlue" IDLE -> SUCCESS' in trace.read_text()
    plain = tmp_path / "plain"
    assert main(["tests", str(GUARD), "-o", str(plain)]) == 0
    assert "BTGEN_ENUMS" not in (plain / "Guard_tests.cpp").read_text()


def test_tree_libraries_are_registered(capsys, tmp_path):
    """--trees: the suite registers each library file (relative to DIR) before the mission and
    creates the main tree by name; the executor entries get the option too."""
    mission = ROOT / "tests" / "gtests" / "UsesLibrary.xml"
    library = ROOT / "tests" / "gtests" / "library"
    out = tmp_path / "suite"
    assert main(["tests", str(mission), "-o", str(out), "--trees", str(library), "--executor"]) == 0
    capsys.readouterr()
    cpp = (out / "UsesLibrary_tests.cpp").read_text()
    rel = os.path.relpath(library / "Docking.xml", out)
    assert f'#define BTGEN_TREES {{ "{rel}" }}' in cpp
    assert '{ "IsAligned", true, {} },' in cpp  # the library tree's leaves are scripted too
    cmake = (out / "CMakeLists.txt").read_text()
    assert '"BTGEN_MAIN_TREE=\\"Main\\""' in cmake and "BTGEN_SOURCE_DIR" in cmake
    assert f'\\"--trees\\" \\"{library}\\"' in cmake
    # (one C++ build a test file: the executor entries are run above, on Guard; this suite's
    # 8 of 8 on the real 4.6.2 and the executor are in docs/tests.md)


def test_root_entries_are_created_before_the_tree(capsys, tmp_path):
    """--entry NAME=TYPE: the suite creates the entry on the root blackboard, typed, before the
    tree (Entry.xml's script adds to it: without the int entry both engines stop with an error,
    so the expectation is the run with it); --type is accepted, and a user-type entry includes
    its header; the executor entries get both options."""
    mission = ROOT / "tests" / "gtests" / "Entry.xml"
    out = tmp_path / "suite"
    pose = "Pose=geo::Pose@geo/pose.hpp"
    args = ["tests", str(mission), "-o", str(out), "--entry", "level=int", "--executor"]
    assert main([*args, "--type", pose, "--entry", "where=Pose"]) == 0
    capsys.readouterr()
    cpp = (out / "Entry_tests.cpp").read_text()
    assert '  blackboard.createEntry("level", BT::TypeInfo::Create<int>());' in cpp
    assert '  blackboard.createEntry("where", BT::TypeInfo::Create<::geo::Pose>());' in cpp
    assert cpp.index('#include "geo/pose.hpp"') < cpp.index('#include "btgen_gtest_support.hpp"')
    assert "BTGEN_ENTRIES(*blackboard);" in (out / "btgen_gtest_support.hpp").read_text()
    cmake = (out / "CMakeLists.txt").read_text()
    assert '\\"--entry\\" \\"level=int\\" \\"--entry\\" \\"where=Pose\\" \\"--type\\"' in cmake
    for trace in (out / "executor").glob("*.trace"):  # the script reads the int: 3 + 1 == 4
        assert 'ScriptCondition "NextIsFour" IDLE -> SUCCESS' in trace.read_text()
    assert not list((out / "executor").glob("*.error"))
    # without --entry every run stops with the script's error, and the suite expects it there
    none = tmp_path / "none"
    assert main(["tests", str(mission), "-o", str(none), "--executor"]) == 0
    capsys.readouterr()
    errors = list((none / "executor").glob("*.error"))
    assert errors and all("cannot be applied to a string and a int" in e.read_text() for e in errors)
    plain = tmp_path / "plain"
    assert main(["tests", str(GUARD), "-o", str(plain)]) == 0
    assert "BTGEN_ENTRIES" not in (plain / "Guard_tests.cpp").read_text()


def test_an_entry_of_every_instance_of_a_tree_is_refused(capsys, tmp_path):
    out = tmp_path / "suite"
    mission = ROOT / "tests" / "gtests" / "Entry.xml"
    assert main(["tests", str(mission), "-o", str(out), "--entry", "level=int", "--entry", "Main:speed=int"]) == 1
    err = capsys.readouterr().err
    assert "<command-line>:1:" in err and "error: --entry Main:speed=int: an entry of every instance" in err
    assert "Traceback" not in err and not out.exists()


def test_register_files_reach_the_cmake_list(capsys, tmp_path):
    """--register FILE.cpp: the CMake list BTGEN_REGISTER (relative to DIR), compiled into the
    suite's executable, which then exports its symbols; the plugins' list is left to configure
    time (BTGEN_PLUGINS). A file that does not exist is a located error and nothing is written.
    (Built on the real library with Nav2's plugins by test_gtests_nav2.py.)"""
    register = ROOT / "scripts" / "nav2_oracle" / "gtests_register.cpp"
    out = tmp_path / "suite"
    assert main(["tests", str(GUARD), "-o", str(out), "--register", str(register)]) == 0
    capsys.readouterr()
    cmake = (out / "CMakeLists.txt").read_text()
    rel = os.path.relpath(register, out)
    assert f'set(BTGEN_REGISTER "{rel}" CACHE STRING' in cmake
    assert "add_executable(Guard_tests Guard_tests.cpp ${btgen_register_sources})" in cmake
    assert 'set(BTGEN_PLUGINS "" CACHE STRING' in cmake and "ENABLE_EXPORTS ON" in cmake
    support = (out / "btgen_gtest_support.hpp").read_text()
    assert "factory.registerFromPlugin(plugin);" in support and "hook.nodes(factory);" in support
    missing = tmp_path / "nope.cpp"
    other = tmp_path / "other"
    assert main(["tests", str(GUARD), "-o", str(other), "--register", str(missing)]) == 1
    err = capsys.readouterr().err
    assert f"error: --register {missing}: no such file" in err and not other.exists()
