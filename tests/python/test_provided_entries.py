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
    # (warnings: the library loads it and the scripts throw when they run, unless the program sets them)
    assert main(["validate", MISSION]) == 0
    err = capsys.readouterr().err
    assert "reads `server_timeout`, but nothing creates that blackboard entry" in err
    assert "reads `bt_loop_duration`, but nothing creates that blackboard entry" in err
    assert main(["validate", MISSION, *ENTRIES]) == 0
    assert "nothing creates" not in capsys.readouterr().err
    # on the root only, bt_loop_duration is not on Sub's blackboard (it is not autoremapped)
    entries = [e.replace("Sub:", "") for e in ENTRIES]
    assert main(["validate", MISSION, *entries]) == 0
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
        # (without the entries it compiles too: its scripts throw unless the program sets them,
        # as in BehaviorTree.CPP; a declaration that names no tree shows ENTRIES reach btgen)
        "btgen_mission_compiles(without m.xml ENTRIES Nope:x=int)\n"
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


# Issue 37: `goal` is the first entry a Nav2 port sets, and its type is the user's. The compiler
# crashed (exit 3, "'btgen.lang.kind.UserKind object' has no attribute 'startswith'") while
# validate said ok.
USER_TYPED_ENTRY = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><Go goal="{goal}"/></BehaviorTree>
  <TreeNodesModel>
    <Action ID="Go"><input_port name="goal" type="Pose2D"/></Action>
  </TreeNodesModel>
</root>
"""
POSE2D_HEADER = """#pragma once
#include <string_view>
namespace nav {
struct Pose2D { double x = 0, y = 0, theta = 0; };
inline bool convertFromString(std::string_view, Pose2D&) { return false; }
}  // namespace nav
"""
USER_TYPED_MAIN = r"""#include <cstdio>
#include "m.hpp"
struct Leaves {
  btgen::Status tick(m::leaf::Go& go, const btgen::NodeInfo&) {
    const auto goal = go.goal();
    if (!goal) {
      std::printf("no goal: %s\n", std::string(btgen::describe(goal.error())).c_str());
      return btgen::Status::FAILURE;
    }
    std::printf("goal %g %g %g\n", goal->x, goal->y, goal->theta);
    return btgen::Status::SUCCESS;
  }
};
int main(int argc, char**) {
  Leaves leaves;
  m::M<Leaves> mission(leaves);
  if (argc > 1) mission.provide_goal(nav::Pose2D{1.5, -2, 0.25});
  return mission.tick() == btgen::Status::SUCCESS ? 0 : 1;
}
"""


def test_an_entry_of_a_queue_type_compiles(tmp_path, capsys):
    # The same template line crashed on a queue kind ('QueueKind object' has no attribute 'startswith').
    mission = tmp_path / "q.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main"><LoopInt queue="{q}" value="{v}"><AlwaysSuccess/></LoopInt></BehaviorTree>\n'
        "</root>\n",
        encoding="utf-8",
    )
    entry = ["--entry", "q=std::shared_ptr<std::deque<int>>"]
    assert main(["validate", "-q", str(mission), *entry]) == 0
    assert main(["compile", str(mission), "-o", str(tmp_path / "out"), *entry]) == 0
    assert capsys.readouterr().err == ""


def test_an_entry_of_a_user_type(tmp_path, capsys):
    mission = tmp_path / "m.xml"
    mission.write_text(USER_TYPED_ENTRY, encoding="utf-8")
    (tmp_path / "nav").mkdir()
    (tmp_path / "nav" / "types.hpp").write_text(POSE2D_HEADER, encoding="utf-8")
    opts = ["--type", "Pose2D=nav::Pose2D@nav/types.hpp", "--entry", "goal=Pose2D"]
    assert main(["validate", "-q", str(mission), *opts]) == 0
    assert main(["compile", str(mission), "-o", str(tmp_path / "out"), *opts]) == 0
    assert capsys.readouterr().err == ""
    header = (tmp_path / "out" / "m.hpp").read_text(encoding="utf-8")
    assert "void provide_goal(const ::nav::Pose2D& value) noexcept" in header
    (tmp_path / "main.cpp").write_text(USER_TYPED_MAIN, encoding="utf-8")
    exe = tmp_path / "a.out"
    subprocess.run(
        ["c++", "-std=c++17", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0"]
        + ["-I", os.path.join(ROOT, "runtime", "include"), "-I", str(tmp_path), "-I", str(tmp_path / "out")]
        + [str(tmp_path / "main.cpp"), str(tmp_path / "out" / "m.cpp"), "-o", str(exe)],
        check=True,
    )
    provided = subprocess.run([str(exe), "provide"], capture_output=True, text=True, check=False)
    assert (provided.returncode, provided.stdout) == (0, "goal 1.5 -2 0.25\n")
    unset = subprocess.run([str(exe)], capture_output=True, text=True, check=False)
    assert (unset.returncode, unset.stdout) == (1, "no goal: the blackboard entry has no value yet\n")


NODE_MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><Spin node="{node}"/></BehaviorTree>
  <TreeNodesModel>
    <Action ID="Spin"><input_port name="node" type="rclcpp::Node::SharedPtr"/></Action>
  </TreeNodesModel>
</root>
"""
NODE_HEADER = """#pragma once
#include <memory>
#include <string>
namespace rclcpp {
struct Node {
  std::string name;
  using SharedPtr = std::shared_ptr<Node>;
};
}  // namespace rclcpp
"""
NODE_MAIN = r"""#include <cstdio>
#include <memory>
#include "m.hpp"
struct Leaves {
  btgen::Status tick(m::leaf::Spin& spin, const btgen::NodeInfo&) {
    const auto node = spin.node_1();  // (`node()` is the NodeInfo of every model)
    if (!node || !*node) return btgen::Status::FAILURE;
    std::printf("spinning %s, shared by %ld\n", (*node)->name.c_str(), static_cast<long>(node->use_count()));
    return btgen::Status::SUCCESS;
  }
};
int main() {
  Leaves leaves;
  auto node = std::make_shared<rclcpp::Node>(rclcpp::Node{"bt_navigator_with_a_long_name"});
  {
    m::M<Leaves> mission(leaves);
    mission.provide_node(node);
    if (mission.tick() != btgen::Status::SUCCESS) return 1;
    std::printf("held by %ld\n", static_cast<long>(node.use_count()));
  }
  std::printf("released: %ld\n", static_cast<long>(node.use_count()));
  return 0;
}
"""


def test_an_entry_btgen_cannot_hold_is_an_error(tmp_path, capsys):
    """`--entry node=rclcpp::Node::SharedPtr` gave `provide_node(std::string_view)`: a type that is
    neither built in nor declared is an error at the type, in every command; declared with
    --type, the entry holds the C++ type (a std::shared_ptr: the mission shares ownership)."""
    mission = tmp_path / "m.xml"
    mission.write_text(NODE_MISSION, encoding="utf-8")
    entry = ["--entry", "node=rclcpp::Node::SharedPtr"]
    message = (
        "--entry:1:6: error: btgen cannot hold entry `node` of type `rclcpp::Node::SharedPtr`: it is not built in "
        "(int, unsigned, double, bool, std::string, BT::NodeStatus, a queue) and no --type declares it; declare the "
        "C++ type with --type rclcpp::Node::SharedPtr=CPP_TYPE@HEADER (any default-constructible, copyable type: a "
        "struct, a ROS message, a std::shared_ptr), or give the entry a built-in type\n"
    )
    for command in (["validate", "-q"], ["compile", "-o", str(tmp_path / "bad")], ["xsd"]):
        assert main([*command, str(mission), *entry]) == 1
        assert capsys.readouterr().err == message
    assert not (tmp_path / "bad").exists()
    typed = ["--type", "rclcpp::Node::SharedPtr=std::shared_ptr<rclcpp::Node>@rclcpp_node.hpp"]
    assert main(["compile", str(mission), "-o", str(tmp_path / "out"), *entry, *typed]) == 0
    header = (tmp_path / "out" / "m.hpp").read_text(encoding="utf-8")
    assert "void provide_node(const ::std::shared_ptr<rclcpp::Node>& value) noexcept" in header
    (tmp_path / "rclcpp_node.hpp").write_text(NODE_HEADER, encoding="utf-8")
    (tmp_path / "main.cpp").write_text(NODE_MAIN, encoding="utf-8")
    exe = tmp_path / "a.out"
    subprocess.run(
        ["c++", "-std=c++17", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0"]
        + ["-I", os.path.join(ROOT, "runtime", "include"), "-I", str(tmp_path), "-I", str(tmp_path / "out")]
        + [str(tmp_path / "main.cpp"), str(tmp_path / "out" / "m.cpp"), "-o", str(exe)],
        check=True,
    )
    run = subprocess.run([str(exe)], capture_output=True, text=True, check=False)
    assert (run.returncode, run.stdout) == (
        0,
        "spinning bt_navigator_with_a_long_name, shared by 3\nheld by 2\nreleased: 1\n",
    )
