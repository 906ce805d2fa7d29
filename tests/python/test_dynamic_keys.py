"""tests/conformance/dynamic-keys/: `SetBlackboard output_key="{key}"` (and `UnsetBlackboard
key="{key}"`), the key read from an entry when the node runs (issue 44; found on a real
project's file), recorded on the real 4.6.2 and 4.10.0 (traces cut short where the library
threw), through both engines."""

import os

import pytest

import release_cases as rc
from btgen import pipeline
from btgen.diagnostics import UserError
from btgen.ir.lower import lower
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "dynamic-keys")
CASES = rc.recorded(HERE)


def test_every_case_is_recorded_on_both_releases():
    assert len(rc.stems(HERE)) >= 6
    assert len(CASES) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


@pytest.mark.parametrize("version", rc.VERSIONS)
def test_the_c_back_end_compiles_every_case(version):
    for stem in rc.stems(HERE):
        lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version)))


@pytest.mark.parametrize("stem,version", CASES)
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("dynkeys")).build()


@pytest.mark.parametrize("stem,version", CASES)
def test_compiled_executor(stem, version, batches):
    rc.check_cpp(batches, stem, version)


@pytest.mark.parametrize("cxx,version", [("g++", "4.6.2"), ("clang++", "4.10.0")])
def test_generated_code_is_warning_free(cxx, version, tmp_path):
    """-Wall -Wextra -Wpedantic -Werror over every case's generated .cpp (one release per compiler)."""
    import cppbuild
    from btgen.backend_cpp.emit import render

    if not cppbuild.have(cxx):
        pytest.skip(f"no {cxx}")
    sources = []
    for stem in rc.stems(HERE):
        for out in render(
            lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version))),
            stem,
            str(tmp_path),
        ):
            (tmp_path / out.name).write_text(out.text, encoding="utf-8")
            if out.name.endswith(".cpp"):
                sources.append(tmp_path / out.name)
    cppbuild.syntax_check(sources, cxx=cxx, cwd=tmp_path)


def _refusal(tmp_path, body: str) -> str:
    path = tmp_path / "m.xml"
    path.write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <Sequence>\n      '
        + body
        + "\n    </Sequence>\n  </BehaviorTree>\n</root>\n"
    )
    with pytest.raises(UserError) as e:
        lower(pipeline.load(str(path), pipeline.CompileOptions()))
    return str(e.value.diagnostics[0])


def test_a_key_with_a_value_btgen_cannot_know_is_refused_where_it_is_read(tmp_path):
    """The C++ back end follows a key read from an entry when every value that entry is given is a
    literal; an appended text is refused, at the `output_key` attribute, naming the write."""
    msg = _refusal(
        tmp_path, """<Script code="k := 'a'; k += 'b'"/>\n      <SetBlackboard value="1" output_key="{k}"/>"""
    )
    assert msg.startswith(f"{tmp_path / 'm.xml'}:5:44: error: port `output_key` of"), msg
    assert "`k += 'b'`" in msg and "a value btgen cannot know before the run" in msg


def test_a_key_held_by_a_number_entry_is_refused(tmp_path):
    msg = _refusal(tmp_path, """<Script code="k := 5"/>\n      <SetBlackboard value="1" output_key="{k}"/>""")
    assert "cannot know before the run" in msg, msg


def test_a_key_naming_the_key_entry_of_a_set_blackboard_is_refused(tmp_path):
    msg = _refusal(tmp_path, """<Script code="k := 'k'"/>\n      <SetBlackboard value="k" output_key="{k}"/>""")
    assert "holds the key of a SetBlackboard" in msg, msg


ALLOC_MAIN = r"""
#include <cstdio>

#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "key_switches_between_entries.hpp"

namespace {
struct Leaves {
  int calls = 0;
  btgen::Status check(key_switches_between_entries::leaf::Pick&, const btgen::NodeInfo&) {
    return (calls++ % 3 == 0) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
};
}  // namespace

int main() {
  Leaves leaves;
  btgen_test::AllocationScope scope;
  long completed = 0;
  {
    key_switches_between_entries::KeySwitchesBetweenEntries<Leaves, btgen::ManualClock> mission(leaves);
    for (int i = 0; i < 20000; ++i) completed += btgen::is_completed(mission.tick()) ? 1 : 0;
  }
  const std::size_t allocations = scope.count();  // (before printf, whose buffer may allocate)
  std::printf("allocations %zu completed %ld picks %d\n", allocations, completed, leaves.calls);
  return allocations == 0 && completed > 0 ? 0 : 1;
}
"""


def test_a_key_read_at_run_time_allocates_nothing(tmp_path):
    """Construct the mission and tick it 20,000 times, the key switching between entries: no
    heap allocation (btgen_test::AllocationScope counts operator new and malloc)."""
    import subprocess

    import cppbuild
    from btgen.backend_cpp.emit import render

    stem = "key_switches_between_entries"
    for out in render(lower(pipeline.load(os.path.join(HERE, stem + ".xml"))), stem, str(tmp_path)):
        (tmp_path / out.name).write_text(out.text, encoding="utf-8")
    (tmp_path / "main.cpp").write_text(ALLOC_MAIN, encoding="utf-8")
    counter = os.path.join(ROOT, "runtime", "src", "testing", "alloc_counter.cpp")
    exe = cppbuild.build(
        [tmp_path / "main.cpp", counter], tmp_path / "alloc", opt="-O2", includes=[tmp_path], cwd=tmp_path
    )
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.startswith("allocations 0 completed "), proc.stdout
