"""Queue ports of the mission's own leaves (BT::SharedQueue<T>, issue 44): a user node fills a
queue and a Loop consumes it. tests/conformance/user-queues/ holds missions whose scenario sets a
leaf's queue port (`queue NAME PORT ITEM ...`, tests/conformance/FORMAT.md), recorded on the real
4.6.2 and 4.10.0 with scripts/queue_oracle/harness.cpp, run through both engines; and SetBlackboard
copies of a queue entry (one deque shared by both entries; a pool of queues in the C++). The C++
interface of such ports: test_queue_view.py."""

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


SHARED_WITH_A_LITERAL = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <FillQueue q="{q}"/>
      <SetBlackboard value="a;b" output_key="q"/>
      <SetBlackboard value="{q}" output_key="r"/>
      <LoopString queue="{r}" value="{v}"><AlwaysSuccess/></LoopString>
      <LoopString queue="{q}" value="{v}"><AlwaysSuccess/></LoopString>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="FillQueue">
      <output_port name="q" type="BT::SharedQueue&lt;std::string&gt;"/>
    </Action>
  </TreeNodesModel>
</root>
"""


def test_a_shared_queue_written_otherwise_is_refused_located(tmp_path):
    """Entries that copies connect share one pool of queues in the C++; a queue port of a user
    node and a copy write them. Another writer (here a SetBlackboard literal, parsed into the
    entry) is refused at that writer, as a limit of the C++ back end; the interpreter runs it."""
    path = tmp_path / "m.xml"
    path.write_text(SHARED_WITH_A_LITERAL, encoding="utf-8")
    with pytest.raises(UserError) as e:
        lower(pipeline.load(str(path), pipeline.CompileOptions()))
    message = str(e.value.diagnostics[0])
    assert message.startswith(f"{path}:5:")
    assert "writes the queue entry `q`, which a SetBlackboard copy shares with another entry" in message
    assert message.endswith("not supported by the C++ back end yet")


def _cases():
    return [pytest.param(stem, version, id=f"{stem}-{version}") for stem, version in rc.recorded(HERE)]


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


@pytest.mark.parametrize("stem,version", _cases())
def test_compiled_executor(stem, version, batches):
    assert _compiles(stem, version), "the C++ back end refuses it"
    rc.check_cpp(batches, stem, version)


def test_the_hex_case_differs_between_the_releases():
    """(the recordings show the release's conversion of a scenario item: 0x1p3 is 8 or 0)"""
    last = [rc.expected(HERE, "fill_loop_double_hex", v)[0].splitlines()[-1] for v in rc.VERSIONS]
    assert last == ["result SUCCESS", "result FAILURE"]
