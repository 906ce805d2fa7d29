// Engine behaviour not covered by the recorded conformance cases: time
// (Sleep, Delay, Timeout on an injected clock), halt(), the trace writer,
// and properties of the generated tables.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "btgen/clock.hpp"
#include "btgen/trace.hpp"
#include "control_flow.hpp"
#include "test_leaves.hpp"
#include "timing.hpp"

namespace {

using btgen::Status;

// Work leaves of timing.xml: "Delayed" succeeds at once, "Slow" runs for ever.
struct TimingLeaves {
  int slow_halted = 0;
  int delayed_started = 0;
  template <class M>
  Status onStart(M&, const btgen::NodeInfo& n) {
    if (n.name == "Delayed") {
      ++delayed_started;
      return Status::SUCCESS;
    }
    return Status::RUNNING;
  }
  template <class M>
  Status onRunning(M&, const btgen::NodeInfo&) {
    return Status::RUNNING;
  }
  template <class M>
  void onHalted(M&, const btgen::NodeInfo& n) {
    if (n.name == "Slow") ++slow_halted;
  }
  template <class M>
  Status check(M&, const btgen::NodeInfo&) {
    return Status::SUCCESS;
  }
};

using Timing = timing::Timing<TimingLeaves, btgen::ManualClock, btgen_test::RecordingObserver>;

std::size_t index_of(std::string_view name) {
  for (const auto& n : Timing::nodes()) {
    if (n.name == name) return n.index;
  }
  ADD_FAILURE() << "no node " << name;
  return 0;
}

TEST(Time, SleepDelayTimeoutFollowTheInjectedClock) {
  TimingLeaves leaves;
  btgen_test::Recorder rec;
  Timing m(leaves, btgen::ManualClock{1000}, btgen_test::RecordingObserver{&rec});
  const std::size_t nap = index_of("Nap"), wait = index_of("Wait"), limit = index_of("Limit"), slow = index_of("Slow");

  EXPECT_EQ(m.tick(), Status::RUNNING);  // t=1000: Nap starts
  EXPECT_EQ(m.status(nap), Status::RUNNING);
  m.clock().advance(99);
  EXPECT_EQ(m.tick(), Status::RUNNING);  // t=1099: still asleep
  EXPECT_EQ(m.status(nap), Status::RUNNING);
  m.clock().advance(1);
  EXPECT_EQ(m.tick(), Status::RUNNING);  // t=1100: Nap done, Wait starts
  EXPECT_EQ(m.status(wait), Status::RUNNING);
  EXPECT_EQ(leaves.delayed_started, 0);
  m.clock().advance(49);
  EXPECT_EQ(m.tick(), Status::RUNNING);  // t=1149: still waiting
  EXPECT_EQ(leaves.delayed_started, 0);
  m.clock().advance(1);
  EXPECT_EQ(m.tick(), Status::RUNNING);  // t=1150: Delayed runs, Limit starts, Slow RUNNING
  EXPECT_EQ(leaves.delayed_started, 1);
  EXPECT_EQ(m.status(limit), Status::RUNNING);
  EXPECT_EQ(m.status(slow), Status::RUNNING);
  m.clock().advance(29);
  EXPECT_EQ(m.tick(), Status::RUNNING);  // t=1179: within the limit
  EXPECT_EQ(leaves.slow_halted, 0);
  m.clock().advance(1);
  EXPECT_EQ(m.tick(), Status::FAILURE);  // t=1180: the timeout halts Slow and fails
  EXPECT_EQ(leaves.slow_halted, 1);
  for (std::size_t i = 0; i < Timing::node_count(); ++i) EXPECT_EQ(m.status(i), Status::IDLE) << i;
  EXPECT_EQ(rec.dropped, 0u);
  // The last changes: Slow halted, Limit fails, then the Sequence, then the root reset.
  ASSERT_GE(rec.count, 4u);
  EXPECT_EQ(rec.events[rec.count - 1].to, Status::IDLE);
  EXPECT_EQ(rec.events[rec.count - 1].uid, 1);
}

TEST(Time, HaltStopsTheClocksAndRestartsThem) {
  TimingLeaves leaves;
  btgen_test::Recorder rec;
  Timing m(leaves, btgen::ManualClock{}, btgen_test::RecordingObserver{&rec});
  EXPECT_EQ(m.tick(), Status::RUNNING);
  m.clock().advance(60);
  m.halt();
  for (std::size_t i = 0; i < Timing::node_count(); ++i) EXPECT_EQ(m.status(i), Status::IDLE) << i;
  // Sleep starts over: 100 ms from now, not from the first tick.
  EXPECT_EQ(m.tick(), Status::RUNNING);
  m.clock().advance(60);
  EXPECT_EQ(m.tick(), Status::RUNNING);
  EXPECT_EQ(m.status(index_of("Nap")), Status::RUNNING);
}

TEST(Halt, HaltsRunningLeavesAndResetsEveryNode) {
  btgen_test::RandomLeaves leaves(1);
  control_flow::ControlFlow<btgen_test::RandomLeaves, btgen::ManualClock> m(leaves);
  bool saw_running_leaf = false;
  for (int i = 0; i < 200 && !saw_running_leaf; ++i) {
    (void)m.tick();
    for (const auto& n : m.nodes()) {
      if (n.kind == btgen::NodeKind::Action && m.status(n.index) == Status::RUNNING) saw_running_leaf = true;
    }
  }
  ASSERT_TRUE(saw_running_leaf);
  const auto halts = leaves.halts;
  m.halt();
  EXPECT_GT(leaves.halts, halts);
  for (std::size_t i = 0; i < m.node_count(); ++i) EXPECT_EQ(m.status(i), Status::IDLE) << i;
}

TEST(Tables, UidsFollowCreationOrderAndSubTreesAreInlined) {
  using M = control_flow::ControlFlow<btgen_test::InstantLeaves>;
  const auto& nodes = M::nodes();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    EXPECT_EQ(nodes[i].index, i);
    EXPECT_EQ(nodes[i].uid, i + 1);
    if (i > 0) {
      EXPECT_LT(nodes[i].parent, i);  // a parent is created before its children
    }
  }
  int fetches = 0;
  for (const auto& n : nodes) fetches += (n.kind == btgen::NodeKind::SubTree && n.name.substr(0, 5) == "Fetch");
  EXPECT_EQ(fetches, 2);
  static_assert(std::is_trivially_destructible_v<M>, "a mission owns no resources");
  static_assert(!std::is_polymorphic_v<M>, "the compile-time flavour has no virtual calls");
}

std::string run_to_text(void (*body)(std::FILE*)) {
  std::FILE* f = std::tmpfile();
  body(f);
  std::fflush(f);
  std::rewind(f);
  std::string out;
  char buf[512];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  std::fclose(f);
  return out;
}

TEST(Trace, EscapesNamesAsTheFormatSays) {
  char buf[64];
  const std::string_view in = "a\"b\\c\nd\re\tf\x01g\x7f\xc3\xa9";
  const std::size_t n = btgen::escape_name(in, buf, sizeof buf);
  EXPECT_EQ(std::string(buf, n), "a\\\"b\\\\c\\nd\\re\\tf\\x01g\\x7F\xc3\xa9");
  EXPECT_EQ(btgen::escape_name("\x1f", buf, 0), 4u);  // size needed, nothing written
}

TEST(Trace, WriterPrintsOneLinePerChange) {
  const std::string text = run_to_text([](std::FILE* f) {
    static constexpr btgen::NodeInfo node{
        btgen::NodeKind::Action, 4,          5, 0, 0, 0, 0, btgen::kNoSlot, btgen::kNoSlot, 0, 0, 0, 0, "FindBall",
        "my \"ball\"",           "x.xml:1:1"};
    btgen::TraceWriter w(f);
    w.on_status_change(node, Status::IDLE, Status::RUNNING);
    w.on_status_change(node, Status::RUNNING, Status::SUCCESS);
  });
  EXPECT_EQ(text,
            "5 FindBall \"my \\\"ball\\\"\" IDLE -> RUNNING\n"
            "5 FindBall \"my \\\"ball\\\"\" RUNNING -> SUCCESS\n");
}

TEST(Trace, LongNamesNeedNoBuffer) {
  const std::string text = run_to_text([](std::FILE* f) {
    static const std::string name(1000, '"');
    const btgen::NodeInfo node{btgen::NodeKind::Action,
                               0,
                               1,
                               btgen::kNoNode,
                               0,
                               0,
                               0,
                               btgen::kNoSlot,
                               btgen::kNoSlot,
                               0,
                               0,
                               0,
                               0,
                               "X",
                               name,
                               "x.xml:1:1"};
    btgen::TraceWriter(f).on_status_change(node, Status::IDLE, Status::FAILURE);
  });
  std::string expected = "1 X \"";
  for (int i = 0; i < 1000; ++i) expected += "\\\"";
  expected += "\" IDLE -> FAILURE\n";
  EXPECT_EQ(text, expected);
}

}  // namespace
