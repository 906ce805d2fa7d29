"""`btgen tests --executor`: the suite's scenarios on btgen's compiled executor, from ctest.

The suite is configured with -DBTGEN_LIBRARY_TESTS=OFF (no BehaviorTree.CPP here), so ctest runs
only the executor entries: each runs `btgen run --engine cpp` on the scenario (one build of the
mission, cached) and compares the trace with executor/NNN.trace, the interpreter's.
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
    assert capsys.readouterr().out.startswith(f"{out}: 4 tests, 17 files")  # (with scenarios/: one per TEST)
    names = sorted(p.name for p in (out / "executor").iterdir())
    assert names == ["001.scenario", "001.trace", "002.scenario", "002.trace", "003.scenario", "003.trace"] + [
        "004.scenario",
        "004.trace",
        "check.cmake",
    ]
    cmake = (out / "CMakeLists.txt").read_text()
    assert cmake.count(".executor COMMAND") == 4 and "if(BTGEN_LIBRARY_TESTS)" in cmake
    build = tmp_path / "build"
    _configure(out, build)
    ok = _ctest(build)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert "100% tests passed, 0 tests failed out of 4" in ok.stdout
    # an expectation that is not the executor's trace fails, naming the line
    trace = out / "executor" / "002.trace"
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


@pytest.mark.parametrize("option", [["--entry", "speed=int"], ["--type", "Pose=geo::Pose@geo/pose.hpp"]])
def test_entry_and_type_are_refused(capsys, tmp_path, option):
    out = tmp_path / "suite"
    assert main(["tests", str(GUARD), "-o", str(out), *option]) == 1
    err = capsys.readouterr().err
    assert f"error: {option[0]}: not supported by `btgen tests` yet" in err and "Traceback" not in err
    assert not out.exists()
