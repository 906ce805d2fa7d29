"""A Leaves type with a missing or partial set of hooks: the first error the compiler prints is
one sentence naming the model and what to add (the generated mission class checks each
model's hooks, btgen/hooks.hpp), not the template errors of the calls."""

import os
import shutil
import subprocess

import pytest

from btgen.compiler import generate
from conftest import ROOT

pytestmark = pytest.mark.cpp

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <IsReady/>
      <Twice><ComputeTarget/></Twice>
      <MoveBase/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="MoveBase"/>
    <Action ID="ComputeTarget"/>
    <Condition ID="IsReady"/>
    <Decorator ID="Twice"/>
  </TreeNodesModel>
</root>
"""

COMPLETE = {
    "MoveBase": """
  Status onStart(leaf::MoveBase&, const NodeInfo&) { return Status::RUNNING; }
  Status onRunning(leaf::MoveBase&, const NodeInfo&) { return Status::SUCCESS; }
  void onHalted(leaf::MoveBase&, const NodeInfo&) {}""",
    "ComputeTarget": """
  Status tick(leaf::ComputeTarget&, const NodeInfo&) { return Status::SUCCESS; }""",
    "IsReady": """
  Status check(leaf::IsReady&, const NodeInfo&) { return Status::SUCCESS; }""",
    "Twice": """
  Status tick(control::Twice& m, const NodeInfo&) { return m.tick_child(0); }""",
}

SIG = "&, const btgen::NodeInfo&)`"
# (what replaces ComputeTarget's or another model's hooks, the sentence expected)
SHAPES = {
    "no_hook": (
        {"ComputeTarget": ""},
        "Leaves has no hook for the Action leaf::ComputeTarget: add `btgen::Status tick(leaf::ComputeTarget"
        + SIG
        + " (a SyncActionNode), or onStart, onRunning and onHalted (a StatefulActionNode)",
    ),
    "wrong_signature": (
        {"ComputeTarget": "\n  Status tick(leaf::ComputeTarget&) { return Status::SUCCESS; }"},
        "Leaves has no hook for the Action leaf::ComputeTarget: add `btgen::Status tick(leaf::ComputeTarget"
        + SIG
        + " (a SyncActionNode), or onStart, onRunning and onHalted (a StatefulActionNode)",
    ),
    "onstart_only": (  # the migration guide's old SyncActionNode row
        {"ComputeTarget": "\n  Status onStart(leaf::ComputeTarget&, const NodeInfo&) { return Status::SUCCESS; }"},
        "Leaves has onStart for the Action leaf::ComputeTarget but neither onRunning nor onHalted: add "
        "`btgen::Status onRunning(leaf::ComputeTarget" + SIG + " and `void onHalted(leaf::ComputeTarget" + SIG + ", "
        "or write onStart as `btgen::Status tick(leaf::ComputeTarget" + SIG + " (a SyncActionNode)",
    ),
    "no_onhalted": (
        {"MoveBase": COMPLETE["MoveBase"].replace("  void onHalted(leaf::MoveBase&, const NodeInfo&) {}", "")},
        "Leaves has onStart and onRunning for the Action leaf::MoveBase but no onHalted: add "
        "`void onHalted(leaf::MoveBase" + SIG,
    ),
    "no_onrunning": (
        {
            "MoveBase": COMPLETE["MoveBase"].replace(
                "  Status onRunning(leaf::MoveBase&, const NodeInfo&) { return Status::SUCCESS; }", ""
            )
        },
        "Leaves has onStart and onHalted for the Action leaf::MoveBase but no onRunning: add "
        "`btgen::Status onRunning(leaf::MoveBase" + SIG,
    ),
    "no_check": (
        {"IsReady": ""},
        "Leaves has no hook for the Condition leaf::IsReady: add `btgen::Status check(leaf::IsReady" + SIG,
    ),
    "no_user_tick": (
        {"Twice": ""},
        "Leaves has no hook for the Control or Decorator control::Twice: add `btgen::Status tick(control::Twice" + SIG,
    ),
}


def _main(hooks: dict) -> str:
    body = "".join(hooks.values())
    return f"""#include "m.hpp"

namespace leaf = m::leaf;
namespace control = m::control;
using btgen::NodeInfo;
using btgen::Status;

struct Leaves {{{body}
}};

int main() {{
  Leaves leaves;
  m::M<Leaves> mission(leaves);
  return mission.tick() == Status::SUCCESS ? 0 : 1;
}}
"""


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hooks")
    (folder / "m.xml").write_text(MISSION)
    header, source = generate(str(folder / "m.xml"), relative_to=str(folder))
    (folder / header.name).write_text(header.text)
    return folder


def _compilers():
    return [c for c in ("g++", "clang++") if shutil.which(c)]


def _build(compiler, folder, name, hooks):
    src = folder / f"{name}.cpp"
    src.write_text(_main(hooks))
    return subprocess.run(
        [compiler, "-std=c++17", "-fsyntax-only", "-I", os.path.join(ROOT, "runtime", "include"), "-I", str(folder)]
        + [str(src)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


@pytest.mark.parametrize("compiler", _compilers())
def test_complete_hooks_build(compiler, generated):
    p = _build(compiler, generated, "complete", COMPLETE)
    assert p.returncode == 0, p.stderr


@pytest.mark.parametrize("compiler", _compilers())
@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_first_error_is_one_sentence(compiler, shape, generated):
    change, sentence = SHAPES[shape]
    p = _build(compiler, generated, f"{shape}_{compiler}", {**COMPLETE, **change})
    assert p.returncode != 0
    first = next(line for line in p.stderr.splitlines() if ": error: " in line)
    message = first.split(": error: ", 1)[1]
    # g++: `static assertion failed: TEXT`; clang 14: `static_assert failed due to requirement '...' "TEXT"`
    # (later clangs: `static assertion failed due to requirement '...': TEXT`)
    gcc_style = message.startswith("static assertion failed") and message.endswith(": " + sentence)
    clang14 = message.startswith("static_assert failed due to requirement") and message.endswith(f'"{sentence}"')
    assert gcc_style or clang14, first
