"""The text-to-number conversion table of both releases, through both engines.

tests/conformance/conversions/ holds one mission per (site, text) (scripts/conversion_cases.py):
a text converted to a number by a LoopDouble or LoopInt literal queue, a SetBlackboard into a
double entry, a LoopDouble queue read from a string entry or a script storing a string, and
ScriptConditions that reveal the value read. `<release>/<stem>.trace` is what the real
BehaviorTree.CPP of that release printed (cut short where it threw), `<release>/<stem>.error`
its message when it threw. The interpreter and the compiled executor must print the same
trace, and fail exactly where the library failed (with btgen's own message).
"""

import os
import sys

import pytest

import release_cases as rc
from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "scripts"))

import conversion_cases

HERE = os.path.join(ROOT, "tests", "conformance", "conversions")
STEMS = rc.stems(HERE)
# A SetBlackboard copy of a string entry into a double entry: 4.6.2 copies the string as it is
# (`dst->value = src->value`), so the entry then holds a string (its scripts' arithmetic
# throws); 4.10.0 converts it. Both engines follow (the 13 set_copy_* cases of 4.6.2).
CASES = rc.recorded(HERE)


def test_the_table_is_complete():
    """Every mission the script writes is here, recorded on both releases."""
    assert sorted(stem for stem, _, _ in conversion_cases.cases()) == STEMS
    for stem, site, text in conversion_cases.cases():
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read() == conversion_cases.mission(site, text), f"{stem}: rerun scripts/conversion_cases.py"
    assert len(CASES) == 2 * len(STEMS)
    with open(os.path.join(HERE, "INDEX.md"), encoding="utf-8") as f:
        assert f.read() == conversion_cases.index(), "rerun scripts/conversion_cases.py --index"


def test_the_releases_differ_where_the_issue_says():
    """The case of the issue: `0x1p3` in a LoopDouble queue is 8.0 for 4.6.2 (std::stod) and
    0.0 for 4.10.0 (std::from_chars stops at `x`)."""
    stem = next(s for s, site, text in conversion_cases.cases() if site == "loop_literal" and text == "0x1p3")
    assert conversion_cases.reading("4.6.2", stem, "0x1p3", False) == "8.0"
    assert conversion_cases.reading("4.10.0", stem, "0x1p3", False) == "0.0"


@pytest.mark.parametrize("stem,version", CASES)
def test_interpreter_reads_as_the_release(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    """One executable per release holding every mission of the table."""
    return rc.Batches(HERE, tmp_path_factory.mktemp("conversions")).build()


@pytest.mark.parametrize("stem,version", CASES)
def test_compiled_executor_reads_as_the_release(stem, version, batches):
    rc.check_cpp(batches, stem, version)
