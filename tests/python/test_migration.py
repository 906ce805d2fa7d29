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


GUIDE = Path(ROOT) / "docs" / "migrating-from-btcpp.md"


def _blocks(lang: str) -> list[str]:
    """The guide's fenced code blocks of `lang`, their indentation removed."""
    import re
    import textwrap

    text = GUIDE.read_text(encoding="utf-8")
    return [textwrap.dedent(m.group(2)) for m in re.finditer(r"^( *)```" + lang + r"\n(.*?)^\1```", text, re.M | re.S)]


def _table_hooks() -> dict[str, list[str]]:
    """The btgen column of step 2's table, for each BehaviorTree.CPP node class: the hook
    signatures it names (`Status check(leaf::BatteryOk& node, const NodeInfo& info)`)."""
    import re

    out = {}
    for line in GUIDE.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        m = re.match(r"`class (\w+) : public BT::(\w+)", cells[0]) if len(cells) == 2 else None
        if m:
            out[m.group(2)] = re.findall(r"`((?:Status|void) \w+\([^`]*\))`", cells[1])
    return out


def test_the_guide_names_one_complete_set_of_hooks_per_node_class():
    hooks = _table_hooks()
    assert set(hooks) == {"ConditionNode", "StatefulActionNode", "SyncActionNode"}
    assert [h.split("(")[0] for h in hooks["ConditionNode"]] == ["Status check"]
    assert [h.split("(")[0] for h in hooks["StatefulActionNode"]] == [
        "Status onStart",
        "Status onRunning",
        "void onHalted",
    ]
    assert [h.split("(")[0] for h in hooks["SyncActionNode"]] == ["Status tick"]
    # the example and `btgen init` follow the same convention
    port = (EXAMPLE / "after" / "src" / "main.cpp").read_text()
    assert "Status tick(leaf::Say& node, const NodeInfo&)" in port and "onStart(leaf::Say" not in port
    from btgen.tools.init import MAIN

    assert "Status tick(leaf::Say& node, const NodeInfo&)" in MAIN and "onStart(leaf::Say" not in MAIN


def test_the_guides_table_and_snippets_compile(tmp_path):
    """The table's hooks, as the guide's Leaves block writes them, and its reading of an entry
    after the run, built against the docking mission's generated header (warning-free)."""
    from btgen.cli import main as btgen

    leaves = next(b for b in _blocks("cpp") if "struct Leaves" in b)
    for signatures in _table_hooks().values():
        for signature in signatures:
            assert signature in leaves, f"the table's `{signature}` is not in the compiled block"
    after_run = next(b for b in _blocks("cpp") if "mission.blackboard()" in b)
    out = tmp_path / "gen"
    assert (
        btgen(
            [
                "compile",
                str(EXAMPLE / "before" / "docking.xml"),
                "--models",
                str(EXAMPLE / "after" / "mission" / "models.xml"),
                "--entry",
                "dock=std::string",
                "--entry",
                "min_battery=int",
                "--namespace",
                "docking",
                "-o",
                str(out),
            ]
        )
        == 0
    )
    src = tmp_path / "guide.cpp"
    src.write_text(
        '#include <cstdio>\n#include <string>\n\n#include "docking.hpp"\n#include "robot.hpp"\n\n'
        + leaves
        + "\nint main() {\n  Robot robot;\n  Leaves leaves{robot, {}};\n  docking::Docking<Leaves> mission(leaves);\n"
        '  (void)mission.provide_dock("dock_3");\n  mission.provide_min_battery(20);\n'
        "  while (mission.tick() == Status::RUNNING) {\n  }\n"
        + "".join("  " + line + "\n" for line in after_run.splitlines())
        + "  return 0;\n}\n"
    )
    p = subprocess.run(
        ["g++", "-std=c++17", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fsyntax-only"]
        + ["-I", os.path.join(ROOT, "runtime", "include"), "-I", str(out), "-I", str(EXAMPLE / "before"), str(src)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert p.returncode == 0, p.stderr[-4000:]


def test_the_guides_cmake_snippet_defines_what_it_links():
    import re

    for block in _blocks("cmake"):
        defined = set(re.findall(r"(?:add_executable|add_library|btgen_add_mission)\((\w+)", block))
        for target in re.findall(r"target_link_libraries\((\w+)", block):
            assert target in defined, f"the guide links `{target}`, which its snippet never creates:\n{block}"
        linked = re.findall(r"target_link_libraries\(\w+ PRIVATE (\w+)\)", block)
        assert all(t in defined for t in linked)
