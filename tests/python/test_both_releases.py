"""tests/conformance/both-releases/: missions recorded on the real 4.6.2 and 4.10.0 whose traces
end where the library threw, through both engines (release_cases.py).

They hold what the C++ back end used to refuse at compile time although the library runs them:
an IfThenElse or WhileDoElse whose condition can be skipped, which 4.6.2 may keep running on a
stale SUCCESS, and which throws (after WhileDoElse resets its children) only on a run where the
condition does answer SKIPPED. And load rules btgen refused although the library loads them
(issue 38): an element name with a colon (`<arm:Grasp/>`, refused by 4.10.0), a node ID with a
space or a colon in the generic form, `entry="{}"` on SkipUnlessUpdated, WaitValueUpdate and
WasEntryUpdated.
"""

import os

import pytest

import release_cases as rc
from btgen import pipeline
from btgen.ir.lower import lower
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "both-releases")
CASES = rc.recorded(HERE)


def test_every_case_is_recorded_on_both_releases():
    assert len(rc.stems(HERE)) >= 5
    assert len(CASES) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


@pytest.mark.parametrize("version", rc.VERSIONS)
def test_the_c_back_end_compiles_every_case(version):
    """Every case the library loads on this release (it refuses some: `colon_element_name` on 4.10.0)."""
    for stem in rc.stems(HERE):
        if rc.expected(HERE, stem, version) == ("", True):
            assert not rc.loads(HERE, stem, version), stem
            continue
        lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version)))


def test_462_keeps_the_stale_success():
    trace, failed = rc.expected(HERE, "whiledoelse_stale_success", "4.6.2")
    assert not failed and trace.endswith("result SUCCESS\n")
    assert rc.expected(HERE, "whiledoelse_stale_success", "4.10.0")[1]


@pytest.mark.parametrize("stem,version", CASES)
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("both")).build()


@pytest.mark.parametrize("stem,version", CASES)
def test_compiled_executor(stem, version, batches):
    rc.check_cpp(batches, stem, version)
