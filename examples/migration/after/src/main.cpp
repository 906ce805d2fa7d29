// The docking robot ported to btgen: ../before/main.cpp with BehaviorTree.CPP's glue replaced.
//
//   BehaviorTree.CPP                         btgen
//   class X : ConditionNode { tick() }       Status check(leaf::X&, const NodeInfo&)
//   class X : StatefulActionNode             onStart / onRunning / onHalted(leaf::X&, ...)
//   class X : SyncActionNode { tick() }      Status tick(leaf::X&, const NodeInfo&) alone
//   constructor argument Robot&              a member of Leaves (any state the leaves need)
//   getInput<T>("goal")                      node.goal()            (typed by the models file)
//   setOutput("arrived_at", v)               node.set_arrived_at(v)
//   registerNodeType<X>("X", ...)            nothing: the models file and these overloads
//   createTreeFromFile(xml, blackboard)      docking::Docking<Leaves> mission(leaves), at build time
//   blackboard->set("dock", ...)             mission.provide_dock(...)  (CMake ENTRIES)
//   tree.tickExactlyOnce()                   mission.tick()
//   tree.tickWhileRunning()                  while (mission.tick() == Status::RUNNING) {}
//   tree.tickOnce()                          mission.tick(), but see the guide: tickOnce ticks
//                                            again at once after a wake-up signal
#include <cstdio>
#include <string>

#include "docking.hpp"  // generated from ../before/docking.xml by btgen_add_mission
#include "robot.hpp"

namespace {

namespace leaf = docking::leaf;
using btgen::NodeInfo;
using btgen::Status;

struct Leaves {
  Robot& robot;
  std::string goal;

  Status check(leaf::BatteryOk& node, const NodeInfo&) {
    const auto min = node.min();
    if (!min) return Status::FAILURE;
    std::printf("robot: battery %d%% (min %d)\n", robot.battery_percent, static_cast<int>(*min));
    return robot.battery_percent >= *min ? Status::SUCCESS : Status::FAILURE;
  }

  Status onStart(leaf::MoveTo& node, const NodeInfo&) {
    const auto g = node.goal();
    if (!g || !robot.start_drive(std::string(*g))) return Status::FAILURE;
    goal = std::string(*g);
    return Status::RUNNING;
  }
  Status onRunning(leaf::MoveTo& node, const NodeInfo&) {
    if (!robot.arrived()) return Status::RUNNING;
    return node.set_arrived_at(goal) ? Status::SUCCESS : Status::FAILURE;
  }
  void onHalted(leaf::MoveTo&, const NodeInfo&) { robot.stop(); }

  // A SyncActionNode: tick() alone, SUCCESS or FAILURE, called each time the node is ticked.
  Status tick(leaf::Say& node, const NodeInfo&) {
    const auto message = node.message();
    if (!message) return Status::FAILURE;
    robot.say("docked at " + std::string(*message));
    return Status::SUCCESS;
  }
};

}  // namespace

int main() {
  Robot robot;
  Leaves leaves{robot, {}};
  docking::Docking<Leaves> mission(leaves);       // the whole tree and its blackboard, no heap
  if (!mission.provide_dock("dock_3")) return 2;  // false: longer than the entry's string capacity
  mission.provide_min_battery(20);

  // tickWhileRunning(): tick until the mission finishes (a robot paces this loop, as the
  // sleep between BehaviorTree.CPP's ticks does).
  Status status = Status::RUNNING;
  while (status == Status::RUNNING) status = mission.tick();
  std::printf("result %s\n", std::string(btgen::to_string(status)).c_str());
  return status == Status::SUCCESS ? 0 : 1;
}
