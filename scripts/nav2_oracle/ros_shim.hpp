// Stand-ins for the few ROS 2 types and calls of Nav2's DistanceController, SpeedController,
// GoalUpdatedController and PathLongerOnApproach, so that record.py compiles those plugin
// sources unchanged against BehaviorTree.CPP alone. Each of these nodes reads one fact of the
// robot's world on every tick; here that fact is the scenario's answer for the node (its
// `leaf NAME ...` line: SUCCESS yes, FAILURE no), asked of the harness through
// btgen_nav2_input() at the one call where the node's code reads it:
//
//   DistanceController      nav2_util::geometry_utils::euclidean_distance (the robot's distance
//                           from the start pose): yes is far (1e9 m), no is 0
//   SpeedController         rclcpp::Time - rclcpp::Time (the time since the period began):
//                           yes is 1e9 s, no is 0 (the goals compare equal)
//   GoalUpdatedController   PoseStamped != PoseStamped (the goal changed) (BTGEN_SHIM_GOAL_INPUT)
//   PathLongerOnApproach    lyrical and kilted: nav2_util::isPathUpdated; jazzy: the first
//                           size() of the old path's poses in its own isPathUpdated (no: 0
//                           poses); yes makes the path updated, the robot near the goal and the
//                           new path longer (calculate_path_length: 1 m old, 10 m new)
//
// The robot's pose is always available (getCurrentPose succeeds), odometry says 0 m/s, and
// parameters keep their defaults. Every header that these sources include from ROS 2 (and
// Nav2's own bt_utils.hpp and json_utils.hpp, which include ROS 2) is one line including this
// file (record.py writes them). Nothing here is Nav2's code.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "behaviortree_cpp/bt_factory.h"
#include "behaviortree_cpp/decorator_node.h"
#include "behaviortree_cpp/json_export.h"

// The harness: the scenario's next answer for the node being ticked (1 yes), and a number that
// changes each time one of these nodes is ticked.
extern "C" int btgen_nav2_input();
extern "C" long btgen_nav2_serial();

namespace btgen_shim {
struct Logger {};
// The poses of the old path (PathLongerOnApproach), the first asked in the tick.
inline const void* g_old_poses = nullptr;
inline long g_size_tick = -1;  // the tick (btgen_nav2_serial) of the last first size()
}  // namespace btgen_shim

#define RCLCPP_DEBUG(...) (void)0
#define RCLCPP_INFO(...) (void)0
#define RCLCPP_WARN(...) (void)0
#define RCLCPP_ERROR(...) (void)0
#define RCLCPP_FATAL(...) (void)0

namespace builtin_interfaces::msg {
struct Time {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  bool operator==(const Time& o) const { return sec == o.sec && nanosec == o.nanosec; }
  bool operator!=(const Time& o) const { return !(*this == o); }
};
}  // namespace builtin_interfaces::msg

namespace std_msgs::msg {
struct Header {
  builtin_interfaces::msg::Time stamp;
  std::string frame_id;
  bool operator==(const Header& o) const { return stamp == o.stamp && frame_id == o.frame_id; }
  bool operator!=(const Header& o) const { return !(*this == o); }
};
}  // namespace std_msgs::msg

namespace geometry_msgs::msg {
struct Point {
  double x = 0, y = 0, z = 0;
  bool operator==(const Point& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator!=(const Point& o) const { return !(*this == o); }
};
struct Quaternion {
  double x = 0, y = 0, z = 0, w = 1;
  bool operator==(const Quaternion& o) const { return x == o.x && y == o.y && z == o.z && w == o.w; }
  bool operator!=(const Quaternion& o) const { return !(*this == o); }
};
struct Pose {
  Point position;
  Quaternion orientation;
  bool operator==(const Pose& o) const { return position == o.position && orientation == o.orientation; }
  bool operator!=(const Pose& o) const { return !(*this == o); }
};
struct PoseStamped {
  std_msgs::msg::Header header;
  Pose pose;
  bool operator==(const PoseStamped&) const { return true; }
#ifdef BTGEN_SHIM_GOAL_INPUT
  bool operator!=(const PoseStamped&) const { return btgen_nav2_input() != 0; }  // the goal changed
#else
  bool operator!=(const PoseStamped&) const { return false; }
#endif
};
struct Vector3 {
  double x = 0, y = 0, z = 0;
};
struct Twist {
  Vector3 linear, angular;
};
inline void to_json(nlohmann::json& j, const PoseStamped&) { j = nlohmann::json::object(); }
inline void from_json(const nlohmann::json&, PoseStamped&) {}
}  // namespace geometry_msgs::msg

namespace btgen_shim {
// A path's poses: one pose, so that a path is never empty; size() is where jazzy's
// PathLongerOnApproach reads whether the path was updated.
struct Poses : std::vector<geometry_msgs::msg::PoseStamped> {
  Poses() : std::vector<geometry_msgs::msg::PoseStamped>(1) {}
  std::size_t size() const {
    if (g_size_tick != btgen_nav2_serial()) {  // the old path's, the first asked in isPathUpdated
      g_size_tick = btgen_nav2_serial();
      g_old_poses = this;
      return btgen_nav2_input() != 0 ? 1 : 0;
    }
    return this == g_old_poses ? 1 : 2;
  }
};
}  // namespace btgen_shim

namespace nav_msgs::msg {
struct Goals {
  std_msgs::msg::Header header;
  std::vector<geometry_msgs::msg::PoseStamped> goals;
  bool operator==(const Goals&) const { return true; }
  bool operator!=(const Goals&) const { return false; }
};
struct Path {
  std_msgs::msg::Header header;
  btgen_shim::Poses poses;
};
struct Odometry {};
inline void to_json(nlohmann::json& j, const Goals&) { j = nlohmann::json::object(); }
inline void from_json(const nlohmann::json&, Goals&) {}
inline void to_json(nlohmann::json& j, const Path&) { j = nlohmann::json::object(); }
inline void from_json(const nlohmann::json&, Path&) {}
}  // namespace nav_msgs::msg

namespace rclcpp {
struct Duration {
  double s = 0;
  double seconds() const { return s; }
};
struct Time {
  Time() = default;
  explicit Time(const builtin_interfaces::msg::Time&) {}
  double seconds() const { return 0; }
  bool operator>=(const Time&) const { return true; }
};
// The time since the period began: the node's answer (yes: the period has passed).
inline Duration operator-(const Time&, const Time&) { return Duration{btgen_nav2_input() != 0 ? 1e9 : 0.0}; }
struct Node {
  using SharedPtr = std::shared_ptr<Node>;
  btgen_shim::Logger get_logger() const { return {}; }
  Time now() const { return {}; }
  template <class T>
  bool get_parameter(const std::string&, T&) const {
    return false;
  }
  template <class T>
  bool get_parameter_or(const std::string&, T& value, const T& fallback) const {
    value = fallback;
    return false;
  }
};
}  // namespace rclcpp

namespace tf2_ros {
struct Buffer {
  using SharedPtr = std::shared_ptr<Buffer>;
};
}  // namespace tf2_ros

namespace nav2 {
using LifecycleNode = rclcpp::Node;
using TransformBuffer = tf2_ros::Buffer;
}  // namespace nav2

namespace nav2_util {
// The robot's pose: always available.
inline bool getCurrentPose(geometry_msgs::msg::PoseStamped&, const tf2_ros::Buffer&, const std::string& = "map",
                           const std::string& = "base_link", double = 0.1, rclcpp::Time = rclcpp::Time()) {
  return true;
}
struct OdomSmoother {
  geometry_msgs::msg::Twist getTwist() const { return {}; }
};
inline bool isPathUpdated(nav_msgs::msg::Path&, nav_msgs::msg::Path& old_path) {
  btgen_shim::g_old_poses = &old_path.poses;
  return btgen_nav2_input() != 0;
}
namespace geometry_utils {
// The robot's distance from the start pose: the node's answer (yes: far).
inline double euclidean_distance(const geometry_msgs::msg::Pose&, const geometry_msgs::msg::Pose&, bool = false) {
  return btgen_nav2_input() != 0 ? 1e9 : 0.0;
}
inline double calculate_path_length(const nav_msgs::msg::Path& path, std::size_t = 0) {
  return &path.poses == btgen_shim::g_old_poses ? 1.0 : 10.0;
}
}  // namespace geometry_utils
}  // namespace nav2_util

// Nav2's bt_utils.hpp: getInputOrBlackboard and deconflictPortAndParamFrame, as documented.
namespace BT {
template <typename T>
inline bool getInputPortOrBlackboard(const BT::TreeNode& bt_node, const BT::Blackboard& blackboard,
                                     const std::string& param_name, T& value) {
  if (bt_node.getInput<T>(param_name, value)) return true;
  return blackboard.get<T>(param_name, value);
}
template <typename T1, typename T2 = BT::TreeNode>
T1 deconflictPortAndParamFrame(rclcpp::Node::SharedPtr, std::string param_name, const T2* behavior_tree_node) {
  T1 value{};
  (void)behavior_tree_node->getInput(param_name, value);
  return value;
}
}  // namespace BT
#define getInputOrBlackboard(name, value) getInputPortOrBlackboard(*this, *(this->config().blackboard), name, value);
