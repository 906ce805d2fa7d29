"""The C++ interface of a user leaf's queue ports (runtime/include/btgen/queue_view.hpp): a
robot's parser fills a queue<string> through the view its setter gives, another leaf reads and
changes the shared queue through its getter, a third counts it through a SetBlackboard copy
(one deque: it and the Loop over the copy see the change); a queue<int> is set from a range of
numbers, and from texts that do not convert; a queue that does not fit its capacity is reported
and nothing is stored. Built once, with g++ -O1, -Werror, ASan and UBSan (clang++ checks the
same sources with -Werror), and the tick allocates nothing. Then the scenario's `queue` lines:
refused, located, when they cannot set a queue."""

import shutil
import subprocess
from pathlib import Path

import pytest

import cppbuild
from btgen.cli import main
from btgen.diagnostics import UserError
from btgen.interp.scenario import parse_scenario_text
from btgen.tools import mcu
from conftest import ROOT

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="sum := 0"/>
      <ParseWaypoints raw="kitchen;hall;dock" waypoint_queue="{queue}"/>
      <SetBlackboard value="{queue}" output_key="route"/>
      <SkipFirst queue="{queue}"/>
      <CountWaypoints queue="{route}" count="{count}"/>
      <LoopString queue="{route}" value="{wp}" if_empty="SUCCESS">
        <MoveTo goal="{wp}"/>
      </LoopString>
      <FillCounts name="ints" counts="{counts}"/>
      <SetBlackboard value="{counts}" output_key="more"/>
      <LoopInt queue="{more}" value="{n}" if_empty="SUCCESS">
        <Script code="sum += n"/>
      </LoopInt>
      <LoopInt name="AlreadyEmpty" queue="{counts}" value="{n}" if_empty="SUCCESS">
        <Script code="sum += 100"/>
      </LoopInt>
      <Fallback>
        <FillCounts name="texts_bad" counts="{counts}"/>
        <FillCounts name="too_many" counts="{counts}"/>
        <ParseWaypoints name="parse_too_many" raw="a;b;c;d" waypoint_queue="{queue}"/>
        <AlwaysSuccess/>
      </Fallback>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="ParseWaypoints">
      <input_port name="raw" type="std::string"/>
      <output_port name="waypoint_queue" type="std::shared_ptr&lt;std::deque&lt;std::string&gt;&gt;"/>
    </Action>
    <Action ID="SkipFirst">
      <inout_port name="queue" type="BT::SharedQueue&lt;std::string&gt;"/>
    </Action>
    <Action ID="CountWaypoints">
      <input_port name="queue" type="BT::SharedQueue&lt;std::string&gt;"/>
      <output_port name="count" type="int"/>
    </Action>
    <Action ID="FillCounts">
      <output_port name="counts" type="BT::SharedQueue&lt;int&gt;"/>
    </Action>
    <Action ID="MoveTo">
      <input_port name="goal" type="std::string"/>
    </Action>
  </TreeNodesModel>
</root>
"""

MAIN = r"""#include <array>
#include <cstdio>
#include <string_view>
#include <type_traits>

#include "btgen/testing/alloc_counter.hpp"
#include "queues.hpp"

namespace leaf = queues::leaf;

struct Leaves {
  // A robot's parser: the text's items pushed into a new queue through its view.
  btgen::Status tick(leaf::ParseWaypoints& m, const btgen::NodeInfo&) {
    const auto raw = m.raw();
    if (!raw) return btgen::Status::FAILURE;
    const btgen::QueueView<std::string_view> q = m.set_waypoint_queue();
    std::string_view text = *raw;
    while (!text.empty()) {
      const std::size_t end = text.find(';');
      if (!q.push_back(text.substr(0, end))) return m.fail("more waypoints than the queue holds");
      text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
    }
    return btgen::Status::SUCCESS;
  }
  // Reads the shared queue and changes it: the Loop below sees the change.
  btgen::Status tick(leaf::SkipFirst& m, const btgen::NodeInfo&) {
    const auto q = m.queue();
    if (!q) return btgen::Status::FAILURE;
    std::printf("skip %.*s of %zu (capacity %zu)\n", static_cast<int>(q->front().size()), q->front().data(),
                q->size(), q->capacity());
    q->pop_front();
    return btgen::Status::SUCCESS;
  }
  btgen::Status tick(leaf::CountWaypoints& m, const btgen::NodeInfo&) {
    const auto q = m.queue();
    if (!q) return btgen::Status::FAILURE;
    for (std::size_t i = 0; i < q->size(); ++i) {
      std::printf("item %zu: %.*s\n", i, static_cast<int>((*q)[i].size()), (*q)[i].data());
    }
    return m.set_count(static_cast<std::int32_t>(q->size())) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  btgen::Status tick(leaf::FillCounts& m, const btgen::NodeInfo& n) {
    if (n.name == "ints") {
      const std::array<std::int32_t, 3> values = {4, 5, 6};
      return m.set_counts(values) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
    }
    if (n.name == "texts_bad") {
      const std::array<std::string_view, 2> texts = {"7", "x"};
      return m.set_counts(texts) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
    }
    const std::array<std::int32_t, 5> many = {1, 2, 3, 4, 5};
    return m.set_counts(many) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
  btgen::Status tick(leaf::MoveTo& m, const btgen::NodeInfo&) {
    const auto g = m.goal();
    std::printf("move to %.*s\n", static_cast<int>(g->size()), g->data());
    return btgen::Status::SUCCESS;
  }
};

struct Print {
  void on_status_change(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept {}
  void on_error(const btgen::RuntimeError& e) noexcept {
    std::printf("error: %.*s", static_cast<int>(e.message.size()), e.message.data());
    if (!e.detail.empty()) std::printf(": %.*s", static_cast<int>(e.detail.size()), e.detail.data());
    std::printf("\n");
  }
};

int main() {
  std::printf("start\n");  // (stdout's buffer is allocated here, before the count)
  Leaves leaves;
  queues::Queues<Leaves, btgen::ManualClock, Print> mission(leaves);
  const std::size_t before = btgen_test::allocation_count();
  btgen::Status s = mission.tick();
  for (int i = 1; i < 10 && s == btgen::Status::RUNNING; ++i) s = mission.tick();
  const std::size_t allocations = btgen_test::allocation_count() - before;
  std::printf("tick %s, errors %d\n", s == btgen::Status::SUCCESS ? "SUCCESS" : "not SUCCESS",
              static_cast<int>(mission.errors()));
  std::printf("count %d sum %d\n", static_cast<int>(mission.blackboard().count.value),
              static_cast<int>(mission.blackboard().sum.value));
  std::printf("allocations %zu\n", allocations);
  // What Groot2's blackboard view sees: every queue entry's items (shared ones from their pool).
  std::size_t items = 0, entries = 0;
  queues::Queues<Leaves, btgen::ManualClock, Print>::Groot2::visit_blackboard(
      mission.blackboard(), [&](std::size_t, std::string_view key, const auto& slot) {
        using T = typename std::decay_t<decltype(slot)>::value_type;
        if constexpr (btgen::port::is_fixed_queue<T>::value) {
          ++entries;
          items += slot.value.size();
          std::printf("%.*s: %zu\n", static_cast<int>(key.size()), key.data(), slot.value.size());
        }
      });
  std::printf("queue entries %zu, items %zu\n", entries, items);
  return 0;
}
"""

EXPECTED = "".join(
    f"{line}\n"
    for line in [
        "start",
        "skip kitchen of 3 (capacity 3)",
        "item 0: hall",
        "item 1: dock",
        "move to hall",
        "move to dock",
        'error: output port `counts` of `FillCounts` "texts_bad" cannot write `counts` (at most 3 elements): '
        "not a valid value of the type",
        'error: output port `counts` of `FillCounts` "too_many" cannot write `counts` (at most 3 elements): '
        "longer than the capacity btgen gave it",
        "error: more waypoints than the queue holds",
        "tick SUCCESS, errors 3",
        "count 2 sum 15",
        "allocations 0",
        # Groot2's view: `counts` and `more` are one deque, emptied by the loop over `more` (the
        # failed sets stored nothing); `queue` holds what parse_too_many pushed before it failed
        # (a new queue, no longer `route`'s, which the loop emptied)
        "counts: 0",
        "more: 0",
        "queue: 3",
        "route: 0",
        "queue entries 4, items 3",
    ]
)


def test_leaves_fill_read_and_change_queues(tmp_path, capsys):
    if shutil.which("g++") is None:
        pytest.skip("no g++")
    (tmp_path / "queues.xml").write_text(MISSION, encoding="utf-8")
    (tmp_path / "main.cpp").write_text(MAIN, encoding="utf-8")
    out = tmp_path / "out"
    assert main(["validate", "-q", str(tmp_path / "queues.xml"), "--queue-capacity", "3"]) == 0
    assert main(["compile", str(tmp_path / "queues.xml"), "-o", str(out), "--queue-capacity", "3"]) == 0
    capsys.readouterr()
    header = (out / "queues.hpp").read_text(encoding="utf-8")
    assert "btgen::Input<btgen::QueueView<std::string_view>> queue() const noexcept" in header
    assert "btgen::QueueView<std::int32_t> set_counts() const noexcept" in header
    # `queue` and `route`, `counts` and `more` are one deque each (SetBlackboard copies the pointer)
    assert "btgen::QueuePool<btgen::FixedQueue<btgen::FixedString<128>, 3>, 2> qpool0_" in header
    assert "btgen::QueuePool<btgen::FixedQueue<std::int64_t, 3>, 2> qpool1_" in header
    sources = [tmp_path / "main.cpp", out / "queues.cpp"]
    if shutil.which("clang++") is not None:
        cppbuild.syntax_check(sources, cxx="clang++", includes=[out])
    alloc = Path(ROOT) / "runtime" / "src" / "testing" / "alloc_counter.cpp"
    exe = cppbuild.build(
        [*sources, alloc],
        tmp_path / "run",
        cxx="g++",
        opt="-O1",
        flags=["-fsanitize=address,undefined", "-fno-sanitize-recover=all"],
        includes=[out],
    )
    run = subprocess.run([str(exe)], capture_output=True, text=True, check=False)
    assert (run.returncode, run.stderr) == (0, "")
    assert run.stdout == EXPECTED


# ---------------------------------------------------------------- the scenario's `queue` lines
LOOP = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <FillCounts counts="{counts}"/>
      <CountWaypoints queue="{queue}" count="{n}"/>
      <LoopInt queue="{counts}" value="{n}"><AlwaysSuccess/></LoopInt>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="FillCounts">
      <output_port name="counts" type="BT::SharedQueue&lt;int&gt;"/>
    </Action>
    <Action ID="CountWaypoints">
      <input_port name="queue" type="BT::SharedQueue&lt;std::string&gt;"/>
      <output_port name="count" type="int"/>
    </Action>
  </TreeNodesModel>
</root>
"""


@pytest.mark.parametrize(
    "line, message",
    [
        (
            "queue FillCounts counts 1 x 3",
            "1:27: error: item `x` of queue port `counts` (queue<int>) of leaf `FillCounts`: `x` is not a valid int",
        ),
        (
            "queue FillCounts count 1",
            "1:18: error: `count` of leaf `FillCounts` is no output queue port: model "
            "`FillCounts` declares no such port",
        ),
        (
            "queue CountWaypoints queue a",
            "1:22: error: `queue` of leaf `CountWaypoints` is no output queue port: "
            "model `CountWaypoints` declares it input port of type queue<string>",
        ),
        (
            "queue CountWaypoints count 1",
            "1:22: error: `count` of leaf `CountWaypoints` is no output queue port: "
            "model `CountWaypoints` declares it output port of type int",
        ),
        (
            "queue FillCounts counts 1\nqueue FillCounts counts 2",
            "2:18: error: queue port `counts` of leaf `FillCounts` is listed twice (first at line 1)",
        ),
        ("queue FillCounts", "1:1: error: `queue` needs a leaf name, its queue port and the queue's items"),
    ],
    ids=["item", "no-port", "input-port", "not-a-queue", "twice", "short"],
)
def test_queue_lines_that_cannot_set_a_queue_are_refused(line, message, tmp_path, capsys):
    (tmp_path / "m.xml").write_text(LOOP, encoding="utf-8")
    (tmp_path / "s.scenario").write_text(line + "\n", encoding="utf-8")
    assert main(["run", str(tmp_path / "m.xml"), "--scenario", str(tmp_path / "s.scenario")]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"s.scenario:{message}" in captured.err


def test_a_queue_line_of_no_leaf_is_a_warning(tmp_path, capsys):
    (tmp_path / "m.xml").write_text(LOOP, encoding="utf-8")
    # (FillCounts then sets nothing: the Loop finds `counts` with no value, an error of the run)
    (tmp_path / "s.scenario").write_text("ticks 1\nqueue FillCount counts 1\n", encoding="utf-8")
    assert main(["run", str(tmp_path / "m.xml"), "--scenario", str(tmp_path / "s.scenario")]) == 1
    err = capsys.readouterr().err
    assert "s.scenario:2:7: warning: leaf `FillCount` of a `queue` line matches no Action or Condition" in err
    assert "(did you mean `FillCounts`?)" in err


def test_a_microcontroller_image_refuses_queue_lines():
    """(btgen::StaticScenario, compiled into a board's image, holds statuses only)"""
    scenario = parse_scenario_text("ticks 2\nqueue FillCounts counts 1\n", "s.scenario")
    with pytest.raises(UserError) as e:
        mcu.scenario_cpp(scenario, "kScenario")
    assert str(e.value.diagnostics[0]).startswith(
        "s.scenario:2:7: error: the `queue` line of `FillCounts` is not supported on a microcontroller image"
    )
