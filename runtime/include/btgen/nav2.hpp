// btgen runtime: Nav2's Decorators that read one fact from ROS 2 (the generator's lang/nav2.py
// ENV_INPUTS): DistanceController (the robot travelled `distance`), SpeedController (the
// period its speed sets passed, or the goal changed), GoalUpdatedController (the goal
// changed), PathLongerOnApproach (the new path is much longer near the goal), and
// GoalUpdater (no input: no newer goal arrives on its topic here).
//
// That fact is an input of the environment: the engine asks Leaves for it, one answer each
// time the node consults it, with
//
//   btgen::Status nav2_input(const btgen::NodeInfo& node);   // SUCCESS: yes, FAILURE: no
//
// (the node's name, uid and ID tell which). The scenario runners script it under the node's
// name as a Condition's results; robot code answers it from tf2, odometry or the goal. The
// control logic around it is Nav2's, as in the interpreter (interp/nav2.py).
#pragma once

#include <cstdint>
#include <type_traits>
#include <utility>

#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "btgen/user_node.hpp"

namespace btgen {

namespace nav2_detail {
template <class Leaves, class = void>
struct has_input : std::false_type {};
template <class Leaves>
struct has_input<Leaves, std::void_t<decltype(std::declval<Leaves&>().nav2_input(std::declval<const NodeInfo&>()))>>
    : std::true_type {};
}  // namespace nav2_detail

template <class Leaves>
inline constexpr bool has_nav2_input_hook = nav2_detail::has_input<Leaves>::value;

// The answer of Leaves for a node's input (FAILURE when Leaves has no hook: a mission with such
// a node checks that it has one, BTGEN_NAV2_INPUT_HOOK).
template <class Leaves>
[[nodiscard]] Status nav2_input(Leaves& leaves, const NodeInfo& node) {
  if constexpr (has_nav2_input_hook<Leaves>) {
    return leaves.nav2_input(node);
  } else {
    (void)leaves, (void)node;
    return Status::FAILURE;
  }
}

[[nodiscard]] constexpr bool is_nav2_env_node(NodeKind k) noexcept { return k >= NodeKind::DistanceController; }

// tick() of one of these nodes. `first` is its counter (DistanceController, SpeedController:
// the first tick of a run is pending; PathLongerOnApproach: the node was ticked before);
// `input()` consults the environment (true: yes), once on every tick, where Nav2 reads the fact.
template <class Input>
[[nodiscard]] Status nav2_env_tick(NodeKind kind, const ChildOps& ops, std::int32_t& first, Input&& input) {
  // !BT::isStatusActive(status())
  const bool inactive = ops.status() == Status::IDLE || ops.status() == Status::SKIPPED;
  switch (kind) {
    case NodeKind::DistanceController:
    case NodeKind::SpeedController: {
      if (inactive) first = 1;
      ops.set_status(Status::RUNNING);
      const bool yes = input();
      if (first != 0 || ops.child_status(0) == Status::RUNNING || yes) {
        first = 0;
        return ops.tick_child(0);
      }
      return ops.status();
    }
    case NodeKind::GoalUpdatedController: {
      ops.set_status(Status::RUNNING);
      const bool updated = input() || inactive;
      if (ops.child_status(0) == Status::RUNNING || updated) return ops.tick_child(0);
      return ops.status();
    }
    case NodeKind::PathLongerOnApproach: {
      ops.set_status(Status::RUNNING);
      if (!input() || first == 0) {  // (first: 0 until the node's first tick is over)
        first = 1;
        return Status::SUCCESS;  // a RUNNING child is left as it is
      }
      const Status cs = ops.tick_child(0);
      if (cs == Status::SUCCESS || cs == Status::FAILURE) ops.halt_child(0);  // resetChild()
      return cs;
    }
    case NodeKind::GoalUpdater: return ops.tick_child(0);
    default: return Status::FAILURE;
  }
}

}  // namespace btgen

// The check a generated mission class with one of these nodes makes of its Leaves type.
#define BTGEN_NAV2_INPUT_HOOK                                                                         \
  static_assert(::btgen::has_nav2_input_hook<Leaves>,                                                 \
                "Leaves has no hook for the inputs of Nav2's DistanceController, SpeedController, "   \
                "GoalUpdatedController or PathLongerOnApproach: add `btgen::Status nav2_input(const " \
                "btgen::NodeInfo&)` (SUCCESS: yes, FAILURE: no)")
