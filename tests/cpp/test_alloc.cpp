// No heap allocation: constructing a mission object and ticking it.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "control_flow.hpp"
#include "test_leaves.hpp"
#ifdef BTGEN_TEST_HAVE_LAB_TOUR
#include "lab_tour.hpp"
#endif
#ifdef BTGEN_TEST_HAVE_PICK_PLACE_BALL
#include "pick_place_ball.hpp"
#endif
#ifdef BTGEN_TEST_HAVE_RECEPTION
#include "reception.hpp"
#endif

namespace {

using btgen_test::AllocationScope;
using btgen_test::PortLeaves;
using btgen_test::RandomLeaves;

constexpr int kTicks = 100000;

// Ticks `mission` kTicks times on a manual clock, halting now and then;
// returns how many ticks completed the root.
template <class Mission>
long drive(Mission& mission) {
  long completed = 0;
  for (int i = 0; i < kTicks; ++i) {
    mission.clock().advance(7);
    const btgen::Status s = mission.tick();
    completed += btgen::is_completed(s) ? 1 : 0;
    if (i % 1009 == 1008) mission.halt();
  }
  return completed;
}

TEST(Allocation, CounterSeesOperatorNewAndMalloc) {
  AllocationScope scope;
  // The pointer escapes to a volatile, so the compiler cannot elide the allocation.
  static int* volatile escaped = nullptr;
  escaped = new int(7);
  EXPECT_GE(scope.count(), 1u);
  delete escaped;
  if (btgen_test::counts_malloc()) {
    AllocationScope m;
    void* volatile raw = std::malloc(32);
    std::free(raw);
    EXPECT_EQ(m.count(), 1u);
  }
}

TEST(Allocation, ControlFlowMissionConstructAndTickAllocateNothing) {
  RandomLeaves leaves(0x5eed);
  AllocationScope scope;
  long completed = 0;
  {
    control_flow::ControlFlow<RandomLeaves, btgen::ManualClock> mission(leaves);
    completed = drive(mission);
  }
  EXPECT_EQ(scope.count(), 0u);
  // It really ran: leaves were started, resumed, halted and checked.
  EXPECT_GT(leaves.starts, 10000u);
  EXPECT_GT(leaves.runs, 10000u);
  EXPECT_GT(leaves.halts, 100u);
  EXPECT_GT(leaves.checks, 10000u);
  EXPECT_GT(completed, 0);
}

TEST(Allocation, MissionInStaticStorage) {
  static RandomLeaves leaves(11);
  static control_flow::ControlFlow<RandomLeaves, btgen::ManualClock> mission(leaves);
  AllocationScope scope;
  drive(mission);
  EXPECT_EQ(scope.count(), 0u);
}

class VirtualLeaves final : public control_flow::ControlFlowLeaves {
 public:
  explicit VirtualLeaves(std::uint64_t seed) : random_(seed) {}
#define BTGEN_TEST_ACTION(M)                                                                                           \
  btgen::Status onStart(control_flow::leaf::M& m, const btgen::NodeInfo& n) override { return random_.onStart(m, n); } \
  btgen::Status onRunning(control_flow::leaf::M& m, const btgen::NodeInfo& n) override {                               \
    return random_.onRunning(m, n);                                                                                    \
  }                                                                                                                    \
  void onHalted(control_flow::leaf::M& m, const btgen::NodeInfo& n) override { random_.onHalted(m, n); }
  BTGEN_TEST_ACTION(Move)
  BTGEN_TEST_ACTION(Grasp)
  BTGEN_TEST_ACTION(Calibrate)
#undef BTGEN_TEST_ACTION
  btgen::Status check(control_flow::leaf::IsBatteryOk& m, const btgen::NodeInfo& n) override {
    return random_.check(m, n);
  }
  btgen::Status check(control_flow::leaf::IsDone& m, const btgen::NodeInfo& n) override { return random_.check(m, n); }
  RandomLeaves random_;
};

TEST(Allocation, VirtualInterfaceAllocatesNothingEither) {
  VirtualLeaves leaves(3);
  AllocationScope scope;
  {
    control_flow::ControlFlowVirtual mission(leaves);
    for (int i = 0; i < kTicks; ++i) (void)mission.tick();
    mission.halt();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(leaves.random_.starts, 1000u);
}

#ifdef BTGEN_TEST_HAVE_LAB_TOUR
TEST(Allocation, LabTourAllocatesNothing) {
  RandomLeaves leaves(5);
  AllocationScope scope;
  {
    lab_tour::LabTour<RandomLeaves, btgen::ManualClock> mission(leaves);
    drive(mission);
  }
  EXPECT_EQ(scope.count(), 0u);
}

// The Lab Tour with its real ports: every hook reads the model's input ports
// and writes its output ports (location ids, the exhibit list, the answer).
TEST(Allocation, LabTourWithItsPortsAllocatesNothing) {
  PortLeaves leaves(21);
  using Mission = lab_tour::LabTour<PortLeaves, btgen::ManualClock>;
  std::printf("sizeof(lab_tour::LabTour<...>) = %zu bytes (blackboard %zu bytes) for %zu nodes\n", sizeof(Mission),
              sizeof(lab_tour::detail::Blackboard), Mission::node_count());
  AllocationScope scope;
  long completed = 0;
  {
    Mission mission(leaves);
    completed = drive(mission);
    EXPECT_EQ(mission.errors(), 0u);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(completed, 0);
  EXPECT_GT(leaves.reads, 10000u);  // ports really read ...
  EXPECT_GT(leaves.values, 1000u);  // ... with values the leaves wrote
  EXPECT_GT(leaves.writes, 1000u);
}
#endif

#ifdef BTGEN_TEST_HAVE_RECEPTION
TEST(Allocation, ReceptionWithItsPortsAllocatesNothing) {
  PortLeaves leaves(33);
  AllocationScope scope;
  {
    reception::Reception<PortLeaves, btgen::ManualClock> mission(leaves);
    drive(mission);
    EXPECT_EQ(mission.errors(), 0u);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(leaves.reads, 1000u);
  EXPECT_GT(leaves.writes, 1000u);
}
#endif

#ifdef BTGEN_TEST_HAVE_PICK_PLACE_BALL
TEST(Allocation, PickPlaceBallAllocatesNothing) {
  RandomLeaves leaves(9);
  AllocationScope scope;
  {
    pick_place_ball::PickPlaceBall<RandomLeaves, btgen::ManualClock> mission(leaves);
    drive(mission);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(leaves.starts, 1000u);
}
#endif

}  // namespace
