"""`btgen tests` on a Nav2 tree, on the real BehaviorTree.CPP with Nav2's own Controls and Decorators.

Nav2's PipelineSequence, RecoveryNode, RateController, DistanceController ... are C++ of Nav2
(nav2_behavior_tree's plugins): the suite loads them with `registerFromPlugin` (the CMake list
BTGEN_PLUGINS) and registers what they need through a registration file
(`--register scripts/nav2_oracle/gtests_register.cpp`: the ROS handles on the blackboard, the
scenario's inputs for the Decorators that read the robot's world). The plugins are built from
Nav2's own sources with the ROS 2 shim the conformance recordings use
(scripts/nav2_oracle/record.py --plugins-only; nothing of Nav2 is in this repository).

Needs BTGEN_BTCPP_PREFIX (a built BehaviorTree.CPP; BTGEN_BTCPP_VERSION=4.10.0 for that one)
and NAV2_MIRROR (a git dir of ros-navigation/navigation2): run by hand; docs/tests.md records
the results on every Nav2 tree of tests/real_files, on 4.6.2 and 4.10.0.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
NAV2 = ROOT / "tests" / "real_files" / "nav2"
SHIM = ROOT / "scripts" / "nav2_oracle"
PREFIX = os.environ.get("BTGEN_BTCPP_PREFIX", "")
MIRROR = os.environ.get("NAV2_MIRROR", "")


def _run(*cmd: str) -> subprocess.CompletedProcess:
    return subprocess.run(list(cmd), capture_output=True, text=True, check=False)


def test_a_nav2_tree_with_nav2_plugins(capsys, tmp_path):
    if not (PREFIX and os.path.isdir(os.path.join(PREFIX, "lib", "cmake", "behaviortree_cpp"))):
        pytest.skip("no BehaviorTree.CPP 4.6.2 to build against")
    if not (MIRROR and os.path.isdir(MIRROR)):
        pytest.skip("no Nav2 sources to build its plugins (NAV2_MIRROR)")
    version = os.environ.get("BTGEN_BTCPP_VERSION", "4.6.2")
    plugins = _run(
        sys.executable, str(SHIM / "record.py"), PREFIX, version, "--mirror", MIRROR, "--distros", "lyrical",
        "--plugins-only",
    )  # fmt: skip
    assert plugins.returncode == 0, plugins.stderr
    assert "librecovery_node-" in plugins.stdout and "libdistance_controller-" in plugins.stdout
    tree = NAV2 / "navigate_w_replanning_distance.xml"  # PipelineSequence, DistanceController
    out = tmp_path / "suite"
    args = ["tests", str(tree), "-o", str(out), "--btcpp", version, "--models", str(NAV2 / "nav2_tree_nodes.xml")]
    assert main([*args, "--register", str(SHIM / "gtests_register.cpp")]) == 0
    assert capsys.readouterr().out.startswith(f"{out}: 5 tests")
    # the Decorator's fact of the world is a scenario input, both ways in one of them
    assert "leaf DistanceController SUCCESS FAILURE SUCCESS" in "".join(
        p.read_text() for p in (out / "scenarios").glob("*.scenario")
    )
    build = tmp_path / "build"
    cfg = _run(
        "cmake", "-S", str(out), "-B", str(build), f"-DCMAKE_PREFIX_PATH={PREFIX}",
        f"-DBTGEN_PLUGINS={plugins.stdout.strip()}", f"-DBTGEN_INCLUDE_DIRS={SHIM}",
    )  # fmt: skip
    assert cfg.returncode == 0, cfg.stderr
    bld = _run("cmake", "--build", str(build), "-j1")
    assert bld.returncode == 0, bld.stdout + bld.stderr
    ok = _run("ctest", "--test-dir", str(build))
    assert "100% tests passed, 0 tests failed out of 5" in ok.stdout, ok.stdout
    # the tree edited (PipelineSequence -> Sequence): every test fails
    edited = tmp_path / "edited.xml"
    edited.write_text(tree.read_text().replace("PipelineSequence", "Sequence"))
    assert _run("cmake", "-S", str(out), "-B", str(build), f"-DBTGEN_MISSION={edited}").returncode == 0
    assert _run("cmake", "--build", str(build), "-j1").returncode == 0
    bad = _run("ctest", "--test-dir", str(build))
    assert "0% tests passed, 5 tests failed out of 5" in bad.stdout, bad.stdout
