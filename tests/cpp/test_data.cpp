// The data side of a generated mission (missions/data_side.xml, generated with
// STRING_CAPACITY 8): typed port getters and setters of user leaves, literal
// ports and defaults, the typed blackboard, scripts over it, and run-time
// errors (a string longer than its fixed capacity: the one deliberate
// difference from BehaviorTree.CPP) reported through the observer.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <string_view>

#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "data_side.hpp"

namespace {

using btgen::Status;
namespace leaf = data_side::leaf;

// What Consume read, copied out of the views (which live only during the hook).
struct Seen {
  bool called = false;
  btgen::Input<std::int32_t> count = btgen::PortError::kNotSet;
  std::string ratio_text;
  btgen::PortError ratio_error = btgen::PortError::kNone;
  double ratio = 0.0;
  std::string label;
  btgen::Input<bool> ok = btgen::PortError::kNotSet;
  std::string note;
  btgen::Input<std::uint32_t> limit = btgen::PortError::kNotSet;
  btgen::Input<Status> mode = btgen::PortError::kNotSet;
  btgen::Input<double> scale = btgen::PortError::kNotSet;
};

struct DataLeaves {
  std::string_view label = "abc";
  bool produce_ok = true;  // what the setters returned
  Seen outer, inner;

  Status onStart(leaf::Produce& m, const btgen::NodeInfo&) {
    produce_ok = m.set_count(3) && m.set_ratio(0.75) && m.set_label(label) && m.set_ok(true) &&
                 m.set_note(std::string_view("n1"));
    return Status::SUCCESS;
  }
  Status onStart(leaf::Consume& m, const btgen::NodeInfo& n) {
    Seen& s = n.name == "Inner" ? inner : outer;
    s.called = true;
    s.count = m.count();
    const auto text = m.ratio();  // untyped: std::string_view by default
    s.ratio_error = text.error();
    s.ratio_text = std::string(text.value());
    s.ratio = m.ratio<double>().value_or(-1.0);
    s.label = std::string(m.label().value());
    s.ok = m.ok();
    s.note = std::string(m.note().value());
    s.limit = m.limit();
    s.mode = m.mode();
    s.scale = m.scale();
    return Status::SUCCESS;
  }
  template <class M>
  Status onRunning(M&, const btgen::NodeInfo&) {
    return Status::SUCCESS;
  }
  template <class M>
  void onHalted(M&, const btgen::NodeInfo&) {}
};

// Records run-time errors in a fixed buffer (no allocation).
struct Errors {
  struct Entry {
    char where[96];
    char message[200];
    std::uint16_t uid;
  };
  Entry entries[8]{};
  int count = 0;
};

struct ErrorObserver {
  Errors* errors;
  void on_status_change(const btgen::NodeInfo&, Status, Status) noexcept {}
  void on_error(const btgen::RuntimeError& e) noexcept {
    if (errors->count >= 8) return;
    Errors::Entry& out = errors->entries[errors->count++];
    std::snprintf(out.where, sizeof out.where, "%.*s", static_cast<int>(e.where.size()), e.where.data());
    std::snprintf(out.message, sizeof out.message, "%.*s", static_cast<int>(e.message.size()), e.message.data());
    out.uid = e.node->uid;
  }
};

using Mission = data_side::DataSide<DataLeaves, btgen::ManualClock, ErrorObserver>;

TEST(DataSide, PortsReadAndWriteTheTypedBlackboard) {
  DataLeaves leaves;
  Errors errors;
  Mission mission(leaves, btgen::ManualClock{}, ErrorObserver{&errors});
  EXPECT_EQ(mission.tick(), Status::SUCCESS);
  EXPECT_EQ(errors.count, 0);
  EXPECT_TRUE(leaves.produce_ok);

  const Seen& s = leaves.outer;
  ASSERT_TRUE(s.called);
  EXPECT_EQ(*s.count, 3);
  EXPECT_EQ(s.ratio_text, "0.750000");  // a double read as text: std::to_string
  EXPECT_EQ(s.ratio, 0.75);
  EXPECT_EQ(s.label, "abc");
  EXPECT_TRUE(*s.ok);
  EXPECT_EQ(s.note, "n1");
  EXPECT_EQ(*s.limit, 17u);  // literal, converted by the generator
  EXPECT_EQ(*s.mode, Status::RUNNING);
  EXPECT_DOUBLE_EQ(*s.scale, 0.25);  // TreeNodesModel default

  // The SubTree instance: `target` remapped to `count`; `missing` never written.
  const Seen& in = leaves.inner;
  ASSERT_TRUE(in.called);
  EXPECT_EQ(*in.count, 3);
  EXPECT_EQ(in.ratio_error, btgen::PortError::kNoValue);
  EXPECT_EQ(in.label, "inner");
  EXPECT_TRUE(*in.ok);
  EXPECT_EQ(*in.limit, 5u);  // default

  // The blackboard is typed: its slots are plain members.
  const auto& bb = mission.blackboard();
  EXPECT_EQ(bb.count.value, 3);
  EXPECT_EQ(bb.count.seq, 1u);
  EXPECT_EQ(bb.label.value.view(), "abc");
  EXPECT_EQ(bb.log.value.view(), "abc+3");  // Script `log := label .. '+' .. count`
  EXPECT_EQ(decltype(bb.label.value)::capacity(), 8u);
}

TEST(DataSide, AComputedStringGetsItsKnownBoundAboveTheCapacity) {
  // `log := label .. '+' .. count`: label comes from robot code (the capacity, 8 bytes), count is
  // an integer (at most 20 bytes of text), so log needs 8 + 1 + 20 bytes, and gets them although
  // the capacity is 8 (a known bound is not cut to the capacity, or the executor would
  // fail where BehaviorTree.CPP succeeds).
  DataLeaves leaves;
  leaves.label = "abcdefgh";
  Errors errors;
  Mission mission(leaves, btgen::ManualClock{}, ErrorObserver{&errors});
  EXPECT_EQ(mission.tick(), Status::SUCCESS);
  EXPECT_EQ(errors.count, 0);
  EXPECT_EQ(mission.blackboard().log.value.view(), "abcdefgh+3");
  EXPECT_EQ(decltype(mission.blackboard().log.value)::capacity(), 29u);
}

TEST(DataSide, ASetterThatCannotStoreFailsItsNodeWhateverTheHookReturns) {
  DataLeaves leaves;
  leaves.label = "far too long";
  Errors errors;
  Mission mission(leaves, btgen::ManualClock{}, ErrorObserver{&errors});
  EXPECT_EQ(mission.tick(), Status::FAILURE);
  EXPECT_FALSE(leaves.produce_ok);
  EXPECT_FALSE(leaves.outer.called);  // Produce failed: the Sequence stopped
  ASSERT_EQ(errors.count, 1);
  EXPECT_STREQ(errors.entries[0].message, "output port `label` of `Produce` \"Produce\" cannot write `label`");
  EXPECT_EQ(errors.entries[0].uid, 2);
}

TEST(DataSide, ErrorsAreCountedWithoutAnObserver) {
  DataLeaves leaves;
  leaves.label = "far too long";  // the setter of `label` (8 bytes) fails
  data_side::DataSide<DataLeaves, btgen::ManualClock> mission(leaves);
  EXPECT_EQ(mission.tick(), Status::FAILURE);
  EXPECT_EQ(mission.errors(), 1u);
}

TEST(DataSide, NoAllocationReadingAndWritingPorts) {
  DataLeaves leaves;
  Errors errors;
  btgen_test::AllocationScope scope;
  {
    Mission mission(leaves, btgen::ManualClock{}, ErrorObserver{&errors});
    for (int i = 0; i < 1000; ++i) {
      leaves.label = i % 3 == 0 ? std::string_view("abcdefgh") : std::string_view("ab");
      (void)mission.tick();
    }
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
