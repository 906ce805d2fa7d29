"""tests/conformance/real-refusals/: what the C++ back end refused in real projects' files although
BehaviorTree.CPP loads and runs them (issue 44), each reproduced by a small mission of our own and
recorded on the real 4.6.2 and 4.10.0 (traces cut short where the library threw), through both
engines:

- MoveIt Pro's move_to_and_detect_tag_*: a script joins or copies an entry that only an untyped
  port names (it exists, with no value): the script throws when it runs;
- MoveIt Pro's errorcheckvectorsize and plan_and_execute_with_position_only: a Precondition reads
  an entry nothing creates (the main tree's own SubTree model declares it, which no caller gives):
  it throws when it runs, and a run that never reaches it goes on;
- of our own, the same kind: `x += 1` of an entry nothing creates (the C++ back end refused it
  too; the library throws "does not exist yet" where it runs);
- tuper_btcpp's follower.xml, a tree of it run as the main tree: a `_skipIf` reads an entry only
  its caller creates (4.10.0 refuses the file: its scripts quote with `"`).

Each compiles now (a warning of the program, which `btgen check` reports at its rule's level)."""

import os
import shutil

import pytest

import release_cases as rc
from btgen import pipeline
from btgen.tools.check.codes import classify
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "real-refusals")


def _cases():
    return [pytest.param(stem, version, id=f"{stem}-{version}") for stem, version in rc.recorded(HERE)]


def test_every_case_is_recorded_on_both_releases():
    assert len(rc.stems(HERE)) >= 8
    assert len(rc.recorded(HERE)) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


@pytest.mark.parametrize("stem,version", _cases())
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("realref"), lambda stem, version: True).build()


@pytest.mark.parametrize("stem,version", _cases())
def test_compiled_executor(stem, version, batches):
    rc.check_cpp(batches, stem, version)


@pytest.mark.parametrize(
    "stem,code",
    [("precondition_reads_own_model_port", "E503"), ("precondition_reads_missing_not_run", "E503")],
)
def test_the_program_warns_where_the_script_will_throw(stem, code):
    """Not a refusal, but said: the program's warning, which `btgen check` classifies as before."""
    opts = pipeline.CompileOptions()
    program = pipeline.program(pipeline.load(os.path.join(HERE, stem + ".xml"), opts), opts)
    assert [d.severity for d in program.warnings] == ["warning"]
    assert "nothing creates that blackboard entry" in program.warnings[0].message
    assert classify(program.warnings[0].message, "error", "loader") == code


def test_check_keeps_the_read_as_an_error(tmp_path, capsys):
    """`btgen check` reports the read at E503's level, alone or beside an error of the C++ back end."""
    from btgen.cli import main

    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Main"><Sequence><Script code="y := nope"/>'
        '<SetBlackboard output_key="a" value="{b}"/><SetBlackboard output_key="b" value="{a}"/>'
        "</Sequence></BehaviorTree></root>\n",
        encoding="utf-8",
    )
    shutil.copy(os.path.join(HERE, "precondition_reads_missing_after_failure.xml"), tmp_path / "p.xml")
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        assert main(["check", "m.xml", "p.xml"]) == 1
    finally:
        os.chdir(old)
    captured = capsys.readouterr()
    out = captured.out + captured.err
    assert 'm.xml:1:77: error: `code` of `Script` "Script" reads `nope`, but nothing creates' in out
    assert 'p.xml:8:44: error: `if` of `Precondition` "Precondition" reads `execute_trajectories`' in out
    assert out.count("[E503]") == 4, out  # (and the two entries of unknown type)


@pytest.mark.parametrize("cxx,version", [("g++", "4.6.2"), ("clang++", "4.10.0")])
def test_generated_code_is_warning_free(cxx, version, tmp_path):
    """-Wall -Wextra -Wpedantic -Werror over the generated .cpp of each kind of case (a join and a
    copy of an entry with no value, a read of an entry nothing creates; kept to three: seconds)."""
    import cppbuild
    from btgen.backend_cpp.emit import render
    from btgen.ir.lower import lower

    if not cppbuild.have(cxx):
        pytest.skip(f"no {cxx}")
    sources = []
    for stem in (
        "script_joins_untyped_port_entry_not_run",
        "script_copies_untyped_port_entry",
        "skipif_reads_missing_entry",
    ):
        if not rc.loads(HERE, stem, version):
            stem = "precondition_reads_own_model_port"  # (4.10.0 refuses the `"` of that file)
        opts = pipeline.CompileOptions(btcpp=version)
        for out in render(lower(pipeline.load(os.path.join(HERE, stem + ".xml"), opts)), stem, str(tmp_path)):
            (tmp_path / out.name).write_text(out.text, encoding="utf-8")
            if out.name.endswith(".cpp"):
                sources.append(tmp_path / out.name)
    assert len(sources) == 3
    cppbuild.syntax_check(sources, cxx=cxx, cwd=tmp_path)


ALLOC_MAIN = r"""
#include <cstdio>

#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "script_joins_untyped_port_entry_not_run.hpp"

namespace m = script_joins_untyped_port_entry_not_run;

namespace {
struct Leaves {
  int calls = 0;
  btgen::Status tick(m::leaf::MakePose&, const btgen::NodeInfo&) { return btgen::Status::SUCCESS; }
  btgen::Status check(m::leaf::Ready&, const btgen::NodeInfo&) {
    return (calls++ % 2 == 0) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  btgen::Status onStart(m::leaf::Wait&, const btgen::NodeInfo&) { return btgen::Status::RUNNING; }
  btgen::Status onRunning(m::leaf::Wait&, const btgen::NodeInfo&) { return btgen::Status::RUNNING; }
  void onHalted(m::leaf::Wait&, const btgen::NodeInfo&) {}
};
}  // namespace

int main() {
  Leaves leaves;
  btgen_test::AllocationScope scope;
  unsigned long long errors = 0;
  {
    m::ScriptJoinsUntypedPortEntryNotRun<Leaves, btgen::ManualClock> mission(leaves);
    for (int i = 0; i < 20000; ++i) (void)mission.tick();
    errors = mission.errors();
  }
  const std::size_t allocations = scope.count();  // (before printf, whose buffer may allocate)
  std::printf("allocations %zu errors %llu\n", allocations, errors);
  return allocations == 0 && errors > 0 ? 0 : 1;
}
"""


def test_the_join_that_throws_allocates_nothing(tmp_path):
    """20,000 ticks, the script joining an entry with no value every other tick (a run-time error
    each time, counted by errors()): no heap allocation (btgen_test::AllocationScope)."""
    import subprocess

    import cppbuild
    from btgen.backend_cpp.emit import render
    from btgen.ir.lower import lower

    stem = "script_joins_untyped_port_entry_not_run"
    for out in render(lower(pipeline.load(os.path.join(HERE, stem + ".xml"))), stem, str(tmp_path)):
        (tmp_path / out.name).write_text(out.text, encoding="utf-8")
    (tmp_path / "main.cpp").write_text(ALLOC_MAIN, encoding="utf-8")
    counter = os.path.join(ROOT, "runtime", "src", "testing", "alloc_counter.cpp")
    exe = cppbuild.build(
        [tmp_path / "main.cpp", counter], tmp_path / "alloc", opt="-O2", includes=[tmp_path], cwd=tmp_path
    )
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.startswith("allocations 0 errors "), proc.stdout
