"""The migration guide's example (docs/migrating-from-btcpp.md, examples/migration): a
BehaviorTree.CPP 4.6.2 program and its btgen port print the same lines.

`before/output.txt` is what the BehaviorTree.CPP program printed, built against the real library
at tag 4.6.2 (`before/CMakeLists.txt`), and `after/mission/models.xml` is what it wrote with
`--models` (`BT::writeTreeNodesModelXML`). The port is built here with the checkout's CMake
package and must print those lines. The BehaviorTree.CPP side is built too when a 4.6.2 install
is named by BTGEN_BTCPP_PREFIX (neither PyPI's bindings nor Debian ship its headers).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

EXAMPLE = Path(ROOT) / "examples" / "migration"


def _generator():
    return ["-G", "Ninja"] if shutil.which("ninja") else []


def _run(cmd, cwd):
    proc = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, timeout=900, check=False)
    assert proc.returncode == 0, f"{cmd}: {proc.stdout[-3000:]}{proc.stderr[-3000:]}"
    return proc


def test_the_models_file_is_what_behaviortree_cpp_wrote_and_btgen_reads():
    mission = EXAMPLE / "before" / "docking.xml"
    models = EXAMPLE / "after" / "mission" / "models.xml"
    assert models.read_text().startswith('<root BTCPP_format="4">\n    <TreeNodesModel>')
    entries = ["--entry", "dock=std::string", "--entry", "min_battery=int"]
    proc = _run([sys.executable, "-m", "btgen", "validate", mission, "--models", models, *entries], ROOT)
    assert proc.stdout.endswith("ok (1 tree, main `Dock`)\n")


def test_the_port_prints_what_the_behaviortree_cpp_program_printed(tmp_path):
    build = tmp_path / "after"
    python_bin = Path(sys.executable).parent
    _run(
        [
            "cmake",
            "-S",
            EXAMPLE / "after",
            "-B",
            build,
            *_generator(),
            f"-Dbtgen_DIR={Path(ROOT) / 'cmake'}",
            f"-DBTGEN_EXECUTABLE={python_bin / 'btgen'}",
        ],
        tmp_path,
    )
    _run(["cmake", "--build", build], tmp_path)
    run = _run([build / "docking_btgen"], tmp_path)
    assert run.stdout == (EXAMPLE / "before" / "output.txt").read_text()
    assert run.stdout.endswith("result SUCCESS\n") and run.stdout.count("driving to dock_3") == 2


@pytest.mark.skipif(
    not os.environ.get("BTGEN_BTCPP_PREFIX"),
    reason="no BehaviorTree.CPP 4.6.2 to build against (set BTGEN_BTCPP_PREFIX to its install prefix)",
)
def test_the_behaviortree_cpp_program_prints_the_recorded_lines(tmp_path):
    prefix = Path(os.environ["BTGEN_BTCPP_PREFIX"])
    build = tmp_path / "before"
    _run(
        [
            "cmake",
            "-S",
            EXAMPLE / "before",
            "-B",
            build,
            *_generator(),
            f"-Dbehaviortree_cpp_DIR={prefix / 'lib' / 'cmake' / 'behaviortree_cpp'}",
        ],
        tmp_path,
    )
    _run(["cmake", "--build", build], tmp_path)
    assert _run([build / "docking_btcpp"], tmp_path).stdout == (EXAMPLE / "before" / "output.txt").read_text()
    models = _run([build / "docking_btcpp", "--models"], tmp_path).stdout
    assert models == (EXAMPLE / "after" / "mission" / "models.xml").read_text()
