// A registration file for `btgen tests --register` (a btgen_tests::Hook): what a GoogleTest
// suite of a Nav2 tree needs besides Nav2's own plugins (CMake list BTGEN_PLUGINS: the
// libraries record.py builds from Nav2's sources with ros_shim.hpp and clock_shim.hpp).
//
// - the clock the plugins read through clock_shim.hpp: it never moves (the suite is tick-exact,
//   as a scenario without `clock_ms` runs on btgen's engines);
// - the ROS handles the Decorators' constructors take from the blackboard (ros_shim.hpp's
//   stand-ins): `node`, `tf_buffer`, `odom_smoother`;
// - the fact of the world DistanceController, SpeedController, GoalUpdatedController and
//   PathLongerOnApproach read on each tick: the test's scenario input for the node being
//   ticked (its `leaf NAME SUCCESS|FAILURE` line: yes/no), as the recorder's harness answers it.
//
// - GoalUpdater, which record.py does not build (a topic subscription): a stand-in with btgen's
//   model of it (docs/nav2.md: no goal arrives on its topic in a scenario, so it ticks its child
//   and returns its status; no goal is written), registered only when no plugin gave one.
//
// Build the suite with -DBTGEN_INCLUDE_DIRS=<this folder> (ros_shim.hpp). Nothing here is Nav2's code.
#include <set>
#include <string>

#include "btgen_gtest_support.hpp"
#include "ros_shim.hpp"

namespace
{
std::string g_current;  // the Decorator being ticked
long g_serial = 0;      // changes at each tick of one of them

class GoalUpdaterStandIn : public BT::DecoratorNode
{
public:
  GoalUpdaterStandIn(const std::string& name, const BT::NodeConfig& config) : DecoratorNode(name, config) {}
  static BT::PortsList providedPorts()
  {
    return {BT::InputPort("input_goal"), BT::InputPort("input_goals"), BT::OutputPort("output_goal"),
            BT::OutputPort("output_goals")};
  }

private:
  BT::NodeStatus tick() override { return child_node_->executeTick(); }  // as Nav2's, with no new goal
};

void nodes(BT::BehaviorTreeFactory& factory)
{
  if(factory.builders().count("GoalUpdater") == 0)
    factory.registerNodeType<GoalUpdaterStandIn>("GoalUpdater");
}

void blackboard(BT::Blackboard& bb)
{
  bb.set("node", std::make_shared<rclcpp::Node>());
  bb.set("tf_buffer", std::make_shared<tf2_ros::Buffer>());
  bb.set("odom_smoother", std::make_shared<nav2_util::OdomSmoother>());
}

void attach(BT::Tree& tree)
{
  tree.applyVisitor([](BT::TreeNode* node) {
    static const std::set<std::string> ids{"DistanceController", "SpeedController", "GoalUpdatedController",
                                           "PathLongerOnApproach"};
    if(ids.count(node->registrationName()) != 0)
      node->setPreTickFunction([](BT::TreeNode& n) {
        g_current = n.name();
        ++g_serial;
        return BT::NodeStatus::IDLE;
      });
  });
}

btgen_tests::AddHook nav2({&nodes, &blackboard, &attach});
}  // namespace

extern "C" {
long long btgen_nav2_clock_ns = 0;  // read by the plugins through clock_shim.hpp
int btgen_nav2_input()
{
  return btgen_tests::scriptedInput(g_current) ? 1 : 0;
}
long btgen_nav2_serial()
{
  return g_serial;
}
}
