"""Queue ports of the mission's own leaves (BT::SharedQueue<T>, issue 44): a user node fills a
queue and a Loop consumes it.

- tests/conformance/user-queues/: missions whose scenario sets a leaf's queue port (`queue NAME
  PORT ITEM ...`, tests/conformance/FORMAT.md), recorded on the real 4.6.2 and 4.10.0 with
  scripts/queue_oracle/harness.cpp, through both engines;
- the C++ interface a robot's leaf implements (runtime/include/btgen/queue_view.hpp): a leaf
  parses a text into the queue through its view, another reads the queue through its getter;
  warning-free under g++ and clang, clean under ASan and UBSan, and allocation-free;
- the scenario's `queue` lines are checked against the mission, located."""

import os

import pytest

import release_cases as rc
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "user-queues")


def test_every_case_is_recorded_on_both_releases():
    assert len(rc.stems(HERE)) >= 7
    assert len(rc.recorded(HERE)) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"
        with open(os.path.join(HERE, stem + ".scenario"), encoding="utf-8") as f:
            assert "\nqueue " in f.read(), f"{stem}: its scenario sets a queue"


CASES = [pytest.param(s, v, id=f"{s}-{v}") for s, v in rc.recorded(HERE)]


@pytest.mark.parametrize("stem,version", CASES)
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("user_queues")).build()


@pytest.mark.parametrize("stem,version", CASES)
def test_compiled_executor(stem, version, batches):
    rc.check_cpp(batches, stem, version)


def test_the_hex_case_differs_between_the_releases():
    """(the recordings show the release's conversion of a scenario item: 0x1p3 is 8 or 0)"""
    last = [rc.expected(HERE, "fill_loop_double_hex", v)[0].splitlines()[-1] for v in rc.VERSIONS]
    assert last == ["result SUCCESS", "result FAILURE"]
