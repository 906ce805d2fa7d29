"""tests/conformance/oracle-diff/: the divergences differential testing against the real library
found (scripts/oracle_random.py, scripts/oracle_minimize.py; docs/testing.md), each shrunk to a
minimal mission and recorded on 4.6.2 and 4.10.0 (scripts/record_releases.py), through both
engines (release_cases.py): the trace, cut short where the library threw, and whether it failed.
"""

import os

import pytest

import release_cases as rc
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "oracle-diff")
CASES = rc.recorded(HERE)


def test_every_case_is_recorded_on_both_releases_and_says_what_it_shows():
    assert len(rc.stems(HERE)) >= 2
    assert len(CASES) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


@pytest.mark.parametrize("stem,version", CASES)
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("oracle_diff")).build()


@pytest.mark.parametrize("stem,version", CASES)
def test_compiled_executor(stem, version, batches):
    rc.check_cpp(batches, stem, version)
