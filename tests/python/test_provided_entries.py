"""Entries the application provides (`--entry [TREE:]NAME=TYPE`): the blackboard entries a
program sets before the first tick, as Nav2 sets `node`, `server_timeout`, `bt_loop_duration`
and `wait_for_service_timeout`. Every command accepts them, and CMake's ENTRIES; the
generated mission has a setter for each (tests/provided_entries/main.cpp uses them)."""

import os
import shutil
import subprocess
import sys

import pytest

import cppbuild
from btgen.cli import main
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "provided_entries")
MISSION = os.path.join(HERE, "nav_entries.xml")
ENTRIES = [
    "--entry",
    "server_timeout=int",
    "--entry",
    "node=std::string",
    "--entry",
    "wait_for_service_timeout=int",
    "--entry",
    "Sub:bt_loop_duration=int",
]


def test_validate_needs_the_entries(capsys):
    assert main(["validate", "-q", MISSION]) == 1
    err = capsys.readouterr().err
    assert "reads `server_timeout`, but nothing creates that blackboard entry" in err
    assert "reads `bt_loop_duration`, but nothing creates that blackboard entry" in err
    assert main(["validate", "-q", MISSION, *ENTRIES]) == 0
    # on the root only, bt_loop_duration is not on Sub's blackboard (it is not autoremapped)
    entries = [e.replace("Sub:", "") for e in ENTRIES]
    assert main(["validate", "-q", MISSION, *entries]) == 1
    assert "reads `bt_loop_duration`" in capsys.readouterr().err


def test_bad_declarations(capsys):
    assert main(["validate", MISSION, "--entry", "x"]) == 1
    assert capsys.readouterr().err == (
        "--entry:1:1: error: `x` is not an entry declaration: write NAME=TYPE or TREE:NAME=TYPE "
        "(for example server_timeout=int)\n"
    )
    assert main(["validate", MISSION, "--entry", "Nope:x=int"]) == 1
    assert capsys.readouterr().err == "--entry:1:1: error: --entry Nope:x: the mission has no BehaviorTree `Nope`\n"
    assert main(["validate", MISSION, "--entry", "a=int", "--entry", "a=double"]) == 1
    assert "entry `a` is declared as int and as double" in capsys.readouterr().err


def test_interpreter_creates_them_without_value(tmp_path):
    # `btgen run` has no application: the entries exist, empty, and the script says so.
    scenario = tmp_path / "s.scenario"
    scenario.write_text("ticks 1\n")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", MISSION, "--scenario", str(scenario), *ENTRIES],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    assert "the left operand of `*` has no value" in proc.stderr


@pytest.mark.parametrize("compiler", ["g++", "clang++"])
def test_generated_setters(compiler, tmp_path):
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    assert main(["compile", MISSION, "-o", str(tmp_path), *ENTRIES]) == 0
    header = (tmp_path / "nav_entries.hpp").read_text(encoding="utf-8")
    assert "void provide_server_timeout(const std::int64_t& value) noexcept" in header
    assert "[[nodiscard]] bool provide_node(std::string_view value) noexcept" in header
    exe = tmp_path / "a.out"
    cppbuild.build(
        [os.path.join(HERE, "main.cpp"), tmp_path / "nav_entries.cpp"],
        exe,
        cxx=compiler,
        opt="-O0",
        includes=[tmp_path],
    )

    def run(*args):
        return subprocess.run([str(exe), *args], capture_output=True, text=True, check=True).stdout

    assert run("20") == "SUCCESS 1000\n"  # 20 * 2 == 40, the port read the provided 1000
    assert run("21") == "FAILURE -1\n"
    assert run() == "FAILURE -1\n"  # not provided: the script reads no value and fails


def test_cmake_entries(tmp_path, repo_root):
    if shutil.which("cmake") is None:
        pytest.skip("cmake is not installed")
    shutil.copy(MISSION, tmp_path / "m.xml")
    decls = " ".join(e for e in ENTRIES if e != "--entry")
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(p CXX)\n"
        f'include("{repo_root}/cmake/btgen.cmake")\n'
        f"btgen_mission_compiles(with m.xml ENTRIES {decls})\n"
        "btgen_mission_compiles(without m.xml)\n"
        'message(STATUS "RESULT ${with} ${without}")\n'
    )
    proc = subprocess.run(
        ["cmake", "-S", str(tmp_path), "-B", str(tmp_path / "build"), f"-DPython3_EXECUTABLE={sys.executable}"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert "RESULT TRUE FALSE" in proc.stdout
