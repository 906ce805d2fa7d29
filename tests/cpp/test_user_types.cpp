// User port types (btgen compile --type Pose2D=nav::Pose2D@nav/pose2d.hpp; TYPES in
// btgen_add_mission): missions/user_types.xml holds a Pose2D literal, a leaf writing a Pose2D
// output port, a SubTree reading it through a remapping, a SetBlackboard copy of it, the
// same SubTree given a constant, and a SetBlackboard literal.
#include <gtest/gtest.h>

#include <type_traits>
#include <vector>

#include "btgen/clock.hpp"
#include "btgen/testing/alloc_counter.hpp"
#include "nav/pose2d.hpp"
#include "user_types.hpp"

namespace {

using user_types::leaf::ComputeGoal;
using user_types::leaf::MoveTo;

struct PoseLeaves {
  std::vector<nav::Pose2D> goals;  // reserved by the test: no allocation while ticking
  int misses = 0;
  btgen::Status tick(MoveTo& m, const btgen::NodeInfo&) {
    const btgen::Input<nav::Pose2D> goal = m.goal();
    if (!goal) {
      ++misses;
      return btgen::Status::FAILURE;
    }
    goals.push_back(*goal);
    return btgen::Status::SUCCESS;
  }
  btgen::Status tick(ComputeGoal& m, const btgen::NodeInfo&) {
    return m.set_goal(nav::Pose2D{3.0, 4.0, -1.0}) ? btgen::Status::SUCCESS : btgen::Status::FAILURE;
  }
};

struct CountingObserver {
  int* errors;
  void on_status_change(const btgen::NodeInfo&, btgen::Status, btgen::Status) noexcept {}
  void on_error(const btgen::RuntimeError&) noexcept { ++*errors; }
};

using Mission = user_types::UserTypes<PoseLeaves, btgen::ManualClock, CountingObserver>;

static_assert(std::is_same_v<decltype(std::declval<MoveTo&>().goal()), btgen::Input<nav::Pose2D>>,
              "a Pose2D input port reads a nav::Pose2D");
static_assert(std::is_same_v<decltype(std::declval<Mission&>().blackboard().target.value), nav::Pose2D>,
              "a Pose2D entry holds the value itself");

bool same(const nav::Pose2D& a, const nav::Pose2D& b) { return a.x == b.x && a.y == b.y && a.theta == b.theta; }

TEST(UserTypes, LiteralConvertsOnceAtConstructionAndValuesFlowAcrossTheSubTree) {
  PoseLeaves leaves;
  leaves.goals.reserve(64);
  int errors = 0;
  const int calls_before = nav::convert_calls;
  Mission mission(leaves, btgen::ManualClock{}, CountingObserver{&errors});
  EXPECT_EQ(nav::convert_calls - calls_before, 3);  // the literals and the SubTree constant, at construction
  EXPECT_EQ(errors, 0);
  EXPECT_EQ(mission.errors(), 0u);
  for (int round = 0; round < 5; ++round) {
    ASSERT_EQ(mission.tick(), btgen::Status::SUCCESS);
  }
  EXPECT_EQ(nav::convert_calls - calls_before, 3);  // never again while ticking
  ASSERT_EQ(leaves.goals.size(), 25u);
  EXPECT_EQ(leaves.misses, 0);
  const nav::Pose2D home{1.5, -2.0, 0.25};
  const nav::Pose2D planned{3.0, 4.0, -1.0};
  const nav::Pose2D fixed{0.0, 1.0, 2.0};
  const nav::Pose2D set{7.0, 8.0, 9.0};
  for (std::size_t i = 0; i < leaves.goals.size(); i += 5) {
    EXPECT_TRUE(same(leaves.goals[i], home));         // the literal
    EXPECT_TRUE(same(leaves.goals[i + 1], planned));  // through the SubTree's remapping
    EXPECT_TRUE(same(leaves.goals[i + 2], planned));  // the SetBlackboard copy
    EXPECT_TRUE(same(leaves.goals[i + 3], fixed));    // the SubTree's constant
    EXPECT_TRUE(same(leaves.goals[i + 4], set));      // the SetBlackboard literal
  }
  EXPECT_TRUE(same(mission.blackboard().target.value, set));
  EXPECT_EQ(mission.blackboard().target.seq, 10u);
  EXPECT_EQ(errors, 0);
}

TEST(UserTypes, NoAllocationAtConstructionOrTick) {
  PoseLeaves leaves;
  leaves.goals.reserve(5 * 1000);
  int errors = 0;
  btgen_test::AllocationScope scope;
  {
    Mission mission(leaves, btgen::ManualClock{}, CountingObserver{&errors});
    for (int i = 0; i < 1000; ++i) (void)mission.tick();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(leaves.goals.size(), 5000u);
  EXPECT_EQ(errors, 0);
}

}  // namespace
