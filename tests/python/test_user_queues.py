"""Queue ports of the mission's own leaves (BT::SharedQueue<T>, issue 44): a user node fills a
queue and a Loop consumes it. tests/conformance/user-queues/ holds missions whose scenario sets a
leaf's queue port (`queue NAME PORT ITEM ...`, tests/conformance/FORMAT.md), recorded on the real
4.6.2 and 4.10.0 with scripts/queue_oracle/harness.cpp, run through both engines; and SetBlackboard
copies of a queue entry, which the interpreter follows and the C++ back end still refuses
(REFUSED: strict expected failures). The C++ interface of such ports: test_queue_view.py."""

import os

import pytest

import release_cases as rc
from btgen import pipeline
from btgen.diagnostics import UserError
from btgen.ir.lower import lower
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


def test_the_copies_are_refused_located():
    """(until the C++ back end shares a deque between entries: the refusal names the copy)"""
    for stem in ("copy_queue_shares_it", "copy_queue_then_refill"):
        with pytest.raises(UserError) as e:
            lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions()))
        message = str(e.value.diagnostics[0])
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            line = next(n for n, text in enumerate(f, start=1) if "<SetBlackboard" in text)
        assert f"{stem}.xml:{line}:29: error: " in message, message
        assert "BehaviorTree.CPP would share one queue between both entries" in message


# What the C++ back end still refuses (docs/btcpp-versions.md): both releases copy a queue entry's
# shared pointer, so the copy and its source are one deque until either is set anew; the C++ back
# end keeps every queue in its own entry.
_SHARED = "refused: a SetBlackboard copy of a queue entry (one deque shared by both entries)"
REFUSED = {(s, v): _SHARED for s in ("copy_queue_shares_it", "copy_queue_then_refill") for v in rc.VERSIONS}


def _cases(refused=None):
    out = []
    for stem, version in rc.recorded(HERE):
        why = (refused or {}).get((stem, version))
        marks = [pytest.mark.xfail(strict=True, reason=why)] if why is not None else []
        out.append(pytest.param(stem, version, marks=marks, id=f"{stem}-{version}"))
    return out


def _compiles(stem: str, version: str) -> bool:
    try:
        lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version)))
    except UserError:
        return False
    return True


@pytest.mark.parametrize("stem,version", _cases())
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("user_queues"), _compiles).build()


@pytest.mark.parametrize("stem,version", _cases(REFUSED))
def test_compiled_executor(stem, version, batches):
    assert _compiles(stem, version), "the C++ back end refuses it"
    rc.check_cpp(batches, stem, version)


def test_the_hex_case_differs_between_the_releases():
    """(the recordings show the release's conversion of a scenario item: 0x1p3 is 8 or 0)"""
    last = [rc.expected(HERE, "fill_loop_double_hex", v)[0].splitlines()[-1] for v in rc.VERSIONS]
    assert last == ["result SUCCESS", "result FAILURE"]
