"""tests/conformance/changing-types/: SetBlackboard copies between entries a port typed and entries
whose type changes at run time (issue 44, item d), a Loop writing into such an entry (item b),
and scripts storing a value of changing type
into an int entry a port declared (item c: `script_store_dynamic_into_int_*`, a boolean, whole
and fractional numbers, a number's text and other text), recorded on the real 4.6.2 and 4.10.0
(traces cut short where the library threw), through both engines.

KNOWN: recordings neither engine follows yet; REFUSED: missions the C++ back end still refuses;
each a strict expected failure with its reason."""

import os

import pytest

import release_cases as rc
from btgen import pipeline
from btgen.diagnostics import UserError
from btgen.ir.lower import lower
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "changing-types")
KNOWN: dict[tuple[str, str], str] = {}
# What the C++ back end still refuses of these recordings: nothing (typed writes into entries
# of changing type: test_typed_writes.py; copies of changing type into typed entries:
# test_dyncopy.py). A case added here that it refuses gets a strict xfail with the reason.
REFUSED: dict[tuple[str, str], str] = {}


def _cases(refused=None):
    out = []
    for stem, version in rc.recorded(HERE):
        why = KNOWN.get((stem, version)) or (refused or {}).get((stem, version))
        marks = [pytest.mark.xfail(strict=True, reason=why)] if why is not None else []
        out.append(pytest.param(stem, version, marks=marks, id=f"{stem}-{version}"))
    return out


def test_every_case_is_recorded_on_both_releases():
    assert len(rc.stems(HERE)) >= 12
    assert len(rc.recorded(HERE)) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


@pytest.mark.parametrize("stem,version", _cases())
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("changing"), _compiles).build()


def _compiles(stem: str, version: str) -> bool:
    try:
        lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version)))
    except UserError:
        return False
    return True


@pytest.mark.parametrize("stem,version", _cases(REFUSED))
def test_compiled_executor(stem, version, batches):
    assert _compiles(stem, version), "the C++ back end refuses it"
    rc.check_cpp(batches, stem, version)
