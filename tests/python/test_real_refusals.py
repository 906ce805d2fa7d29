"""tests/conformance/real-refusals/: what the C++ back end refused in real projects' files although
BehaviorTree.CPP loads and runs them (issue 44), each reproduced by a small mission of our own and
recorded on the real 4.6.2 and 4.10.0 (traces cut short where the library threw), through both
engines:

- MoveIt Pro's move_to_and_detect_tag_*: a script joins or copies an entry that only an untyped
  port names (it exists, with no value): the script throws when it runs;
- MoveIt Pro's errorcheckvectorsize and plan_and_execute_with_position_only: a Precondition reads
  an entry nothing creates (the main tree's own SubTree model declares it, which no caller gives):
  it throws when it runs, and a run that never reaches it goes on;
- tuper_btcpp's follower.xml, a tree of it run as the main tree: a `_skipIf` reads an entry only
  its caller creates (4.10.0 refuses the file: its scripts quote with `"`).

Each compiles now (a warning of the program, which `btgen check` reports at its rule's level)."""

import os

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
