// A simulated robot running Nav2's own default tree, navigate_to_pose_w_replanning_and_recovery.xml,
// compiled by btgen with Nav2's nav2_tree_nodes.xml: Nav2's PipelineSequence, RecoveryNode,
// RateController and RoundRobin are built in; only the leaves are written here.
//
// The robot drives down a corridor to cell 20, one cell per tick (100 ms of the mission's
// clock). The planner fails once (a global costmap clearing helps); a person stands at cell 8,
// so following the path fails there until the robot has spun once (the person walks away).
// Exit status 0 when the mission succeeds at the goal after exactly those recoveries.
//
// Built and run by tests/python/test_nav2_example.py; by hand (README.md here):
//   btgen compile tests/real_files/nav2/navigate_to_pose_w_replanning_and_recovery.xml
//       --models tests/real_files/nav2/nav2_tree_nodes.xml -o build/
//   c++ -std=c++17 -Iruntime/include -Ibuild examples/nav2/robot.cpp
//       build/navigate_to_pose_w_replanning_and_recovery.cpp -o nav2_robot
#include <cstdio>
#include <string>
#include <string_view>

#include "navigate_to_pose_w_replanning_and_recovery.hpp"

namespace {

namespace nav = navigate_to_pose_w_replanning_and_recovery;
using btgen::NodeInfo;
using btgen::Status;

class Robot : public nav::NavigateToPoseWReplanningAndRecoveryLeaves {
 public:
  static constexpr int kGoal = 20;
  static constexpr int kPerson = 8;

  int pos = 0;
  int plans = 0;
  int blocked = 0;
  int global_clears = 0;
  int local_clears = 0;
  int spins = 0;
  int now = 0;  // the tick being run

  void say(const char* what) const { std::printf("tick %2d  cell %2d  %s\n", now, pos, what); }

  // Nav2's selectors publish which plugin to use: nothing to choose here.
  Status tick(nav::leaf::ProgressCheckerSelector&, const NodeInfo&) override { return Status::SUCCESS; }
  Status tick(nav::leaf::GoalCheckerSelector&, const NodeInfo&) override { return Status::SUCCESS; }
  Status tick(nav::leaf::PathHandlerSelector&, const NodeInfo&) override { return Status::SUCCESS; }
  Status tick(nav::leaf::ControllerSelector&, const NodeInfo&) override { return Status::SUCCESS; }
  Status tick(nav::leaf::PlannerSelector&, const NodeInfo&) override { return Status::SUCCESS; }

  // Planning: the second request fails (a stale costmap); the recovery clears it and plans again.
  Status tick(nav::leaf::ComputePathToPose& m, const NodeInfo&) override {
    ++plans;
    if (plans == 2) {
      say("plan failed");
      return Status::FAILURE;
    }
    say("planned a path");
    return m.set_path("corridor") ? Status::SUCCESS : Status::FAILURE;
  }
  Status check(nav::leaf::GlobalUpdatedGoal&, const NodeInfo&) override { return Status::FAILURE; }
  Status check(nav::leaf::IsGoalNearby&, const NodeInfo&) override {
    return plans > 0 && kGoal - pos <= 4 ? Status::SUCCESS : Status::FAILURE;
  }
  Status tick(nav::leaf::TruncatePathLocal&, const NodeInfo&) override { return Status::SUCCESS; }
  Status tick(nav::leaf::ValidatePath&, const NodeInfo&) override { return Status::SUCCESS; }

  // Following: one cell per tick; the person at cell 8 blocks the way until the robot spins.
  Status onStart(nav::leaf::FollowPath& m, const NodeInfo& n) override { return onRunning(m, n); }
  Status onRunning(nav::leaf::FollowPath&, const NodeInfo&) override {
    if (pos == kPerson && spins == 0) {
      ++blocked;
      say("blocked: following the path failed");
      return Status::FAILURE;
    }
    ++pos;
    return pos >= kGoal ? Status::SUCCESS : Status::RUNNING;
  }
  void onHalted(nav::leaf::FollowPath&, const NodeInfo&) override {}

  // Recoveries.
  Status check(nav::leaf::WouldAPlannerRecoveryHelp&, const NodeInfo&) override { return Status::SUCCESS; }
  Status check(nav::leaf::WouldAControllerRecoveryHelp&, const NodeInfo&) override { return Status::SUCCESS; }
  Status check(nav::leaf::GoalUpdated&, const NodeInfo&) override { return Status::FAILURE; }
  Status tick(nav::leaf::ClearEntireCostmap&, const NodeInfo& n) override {
    const bool global = std::string_view(n.name).find("Global") != std::string_view::npos;
    ++(global ? global_clears : local_clears);
    say(global ? "cleared the global costmap" : "cleared the local costmap");
    return Status::SUCCESS;
  }
  int spin_ticks = 0;
  Status onStart(nav::leaf::Spin&, const NodeInfo&) override {
    say("spinning");
    spin_ticks = 3;
    return Status::RUNNING;
  }
  Status onRunning(nav::leaf::Spin&, const NodeInfo&) override {
    if (--spin_ticks > 0) return Status::RUNNING;
    ++spins;
    say("spun: the person walked away");
    return Status::SUCCESS;
  }
  void onHalted(nav::leaf::Spin&, const NodeInfo&) override {}
  Status tick(nav::leaf::Wait&, const NodeInfo&) override { return Status::SUCCESS; }
  Status tick(nav::leaf::BackUp&, const NodeInfo&) override { return Status::SUCCESS; }
};

}  // namespace

int main() {
  Robot robot;
  nav::NavigateToPoseWReplanningAndRecovery<Robot, btgen::ManualClock> mission(robot);
  Status status = Status::RUNNING;
  while (status == Status::RUNNING && robot.now < 200) {
    ++robot.now;
    status = mission.tick();
    mission.clock().advance(100);
  }
  std::printf("%s at cell %d after %d ticks: %d plans, %d blocked, %d global and %d local clearings, %d spins\n",
              status == Status::SUCCESS ? "SUCCESS" : "FAILURE", robot.pos, robot.now, robot.plans, robot.blocked,
              robot.global_clears, robot.local_clears, robot.spins);
  return status == Status::SUCCESS && robot.pos == Robot::kGoal && robot.spins == 1 ? 0 : 1;
}
