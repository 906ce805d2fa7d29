"""examples/nav2: Nav2's navigate_to_pose_w_replanning_and_recovery.xml compiled with Nav2's
models file (its Controls and Decorators built in), its leaves a simulated robot that plans,
follows, fails and recovers; built and run end to end."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
TREE = ROOT / "tests" / "real_files" / "nav2" / "navigate_to_pose_w_replanning_and_recovery.xml"
MODELS = ROOT / "tests" / "real_files" / "nav2" / "nav2_tree_nodes.xml"


def test_the_simulated_robot_reaches_the_goal_after_recovering(tmp_path, capsys):
    cxx = os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++")
    if cxx is None:
        pytest.skip("no C++ compiler")
    out = tmp_path / "build"
    assert main(["compile", str(TREE), "--models", str(MODELS), "-o", str(out)]) == 0, capsys.readouterr().err
    exe = tmp_path / "nav2_robot"
    subprocess.run(
        [cxx, "-std=c++17", "-O1", "-Wall", "-Wextra", "-Wpedantic", "-Werror"]
        + [f"-I{ROOT / 'runtime' / 'include'}", f"-I{out}", str(ROOT / "examples" / "nav2" / "robot.cpp")]
        + [str(out / "navigate_to_pose_w_replanning_and_recovery.cpp"), "-o", str(exe)],
        check=True,
    )
    r = subprocess.run([str(exe)], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    # the story, in the order Nav2's tree makes it happen: blocked, the FollowPath recovery (clear
    # the local costmap) once, then the tree's recoveries in RoundRobin order (clearing, then a
    # spin); the planner's failure is recovered by clearing the global costmap.
    assert lines[0] == "tick  1  cell  0  planned a path"
    assert [ln[18:] for ln in lines if ln.startswith("tick  9")][:3] == [
        "blocked: following the path failed",
        "cleared the local costmap",
        "blocked: following the path failed",
    ]
    assert "plan failed" in r.stdout and "spun: the person walked away" in r.stdout
    assert lines[-1] == (
        "SUCCESS at cell 20 after 23 ticks: 4 plans, 4 blocked, 2 global and 3 local clearings, 1 spins"
    )
