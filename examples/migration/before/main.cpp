// The docking robot as a BehaviorTree.CPP 4.6.2 program: node classes holding a handle to the
// robot, registered with the factory, the tree loaded from XML at start-up with a blackboard
// the program fills first, and ticked until it finishes.
//
//   ./docking_btcpp             run the mission
//   ./docking_btcpp --models    print the node models (BT::writeTreeNodesModelXML): btgen's
//                               models file, ../after/mission/models.xml
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/xml_parsing.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "robot.hpp"

class BatteryOk : public BT::ConditionNode {
 public:
  BatteryOk(const std::string& name, const BT::NodeConfig& config, Robot& robot)
      : BT::ConditionNode(name, config), robot_(robot) {}
  static BT::PortsList providedPorts() { return {BT::InputPort<int>("min", "lowest battery level, percent")}; }
  BT::NodeStatus tick() override {
    const auto min = getInput<int>("min");
    if (!min) return BT::NodeStatus::FAILURE;
    std::printf("robot: battery %d%% (min %d)\n", robot_.battery_percent, *min);
    return robot_.battery_percent >= *min ? BT::NodeStatus::SUCCESS : BT::NodeStatus::FAILURE;
  }

 private:
  Robot& robot_;
};

class MoveTo : public BT::StatefulActionNode {
 public:
  MoveTo(const std::string& name, const BT::NodeConfig& config, Robot& robot)
      : BT::StatefulActionNode(name, config), robot_(robot) {}
  static BT::PortsList providedPorts() {
    return {BT::InputPort<std::string>("goal", "where to drive"),
            BT::OutputPort<std::string>("arrived_at", "where the robot stopped")};
  }
  BT::NodeStatus onStart() override {
    const auto goal = getInput<std::string>("goal");
    if (!goal || !robot_.start_drive(*goal)) return BT::NodeStatus::FAILURE;
    goal_ = *goal;
    return BT::NodeStatus::RUNNING;
  }
  BT::NodeStatus onRunning() override {
    if (!robot_.arrived()) return BT::NodeStatus::RUNNING;
    setOutput("arrived_at", goal_);
    return BT::NodeStatus::SUCCESS;
  }
  void onHalted() override { robot_.stop(); }

 private:
  Robot& robot_;
  std::string goal_;
};

class Say : public BT::SyncActionNode {
 public:
  Say(const std::string& name, const BT::NodeConfig& config, Robot& robot)
      : BT::SyncActionNode(name, config), robot_(robot) {}
  static BT::PortsList providedPorts() { return {BT::InputPort<std::string>("message", "what to say")}; }
  BT::NodeStatus tick() override {
    const auto message = getInput<std::string>("message");
    if (!message) return BT::NodeStatus::FAILURE;
    robot_.say("docked at " + *message);
    return BT::NodeStatus::SUCCESS;
  }

 private:
  Robot& robot_;
};

int main(int argc, char** argv) {
  Robot robot;
  BT::BehaviorTreeFactory factory;
  factory.registerNodeType<BatteryOk>("BatteryOk", std::ref(robot));
  factory.registerNodeType<MoveTo>("MoveTo", std::ref(robot));
  factory.registerNodeType<Say>("Say", std::ref(robot));
  if (argc > 1 && std::strcmp(argv[1], "--models") == 0) {
    std::printf("%s\n", BT::writeTreeNodesModelXML(factory).c_str());
    return 0;
  }

  // Values the program sets before the first tick (as Nav2 sets `node`, `server_timeout`, ...).
  auto blackboard = BT::Blackboard::create();
  blackboard->set("dock", std::string("dock_3"));
  blackboard->set("min_battery", 20);
  auto tree = factory.createTreeFromFile(DOCKING_XML, blackboard);

  const BT::NodeStatus status = tree.tickWhileRunning(std::chrono::milliseconds(10));
  std::printf("result %s\n", BT::toStr(status).c_str());
  return status == BT::NodeStatus::SUCCESS ? 0 : 1;
}
