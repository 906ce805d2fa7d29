// btgen runtime: which hooks the robot's Leaves type gives an Action model.
//
// An Action model M is implemented in one of two styles, chosen per model
// by what the Leaves type declares (detected at compile time):
//
//   BehaviorTree.CPP StatefulActionNode: all three of
//     btgen::Status onStart(leaf::M&, const btgen::NodeInfo&);
//     btgen::Status onRunning(leaf::M&, const btgen::NodeInfo&);
//     void onHalted(leaf::M&, const btgen::NodeInfo&);
//
//   BehaviorTree.CPP SyncActionNode: only
//     btgen::Status tick(leaf::M&, const btgen::NodeInfo&);
//   returning SUCCESS or FAILURE. It is called every time the node is
//   ticked; it never runs for longer than that call, so it is never halted.
//   RUNNING is a contract violation (4.6.2 throws "SyncActionNode MUST never
//   return RUNNING"): reported as a btgen::RuntimeError, and the node fails.
//
// When Leaves has onStart for M, M is stateful (a generic
// `template <class M> Status onStart(M&, ...)` makes every model stateful).
//
// A Control or Decorator model C of the mission (btgen/user_node.hpp) has
//     btgen::Status tick(control::C&, const btgen::NodeInfo&);
// and optionally
//     void halt(control::C&, const btgen::NodeInfo&);
// (the node's own part of halt(): its children are already halted).
#pragma once

#include <string_view>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen {

namespace hooks_detail {

template <class Leaves, class Model, class = void>
struct has_on_start : std::false_type {};
template <class Leaves, class Model>
struct has_on_start<
    Leaves, Model,
    std::void_t<decltype(std::declval<Leaves&>().onStart(std::declval<Model&>(), std::declval<const NodeInfo&>()))>>
    : std::true_type {};

template <class Leaves, class Model, class = void>
struct has_tick : std::false_type {};
template <class Leaves, class Model>
struct has_tick<
    Leaves, Model,
    std::void_t<decltype(std::declval<Leaves&>().tick(std::declval<Model&>(), std::declval<const NodeInfo&>()))>>
    : std::true_type {};

template <class Leaves, class Model, class = void>
struct has_halt : std::false_type {};
template <class Leaves, class Model>
struct has_halt<
    Leaves, Model,
    std::void_t<decltype(std::declval<Leaves&>().halt(std::declval<Model&>(), std::declval<const NodeInfo&>()))>>
    : std::true_type {};

}  // namespace hooks_detail

// True when Leaves has the optional halt() hook of a user Control/Decorator model.
template <class Leaves, class Model>
inline constexpr bool has_halt_hook = hooks_detail::has_halt<Leaves, Model>::value;

// True when Leaves implements Action model `Model` as a SyncActionNode (tick() alone).
template <class Leaves, class Model>
inline constexpr bool is_sync_action =
    !hooks_detail::has_on_start<Leaves, Model>::value && hooks_detail::has_tick<Leaves, Model>::value;

// True when Leaves implements Action model `Model` one way or the other.
template <class Leaves, class Model>
inline constexpr bool has_action_hooks =
    hooks_detail::has_on_start<Leaves, Model>::value || hooks_detail::has_tick<Leaves, Model>::value;

// The message a SyncActionNode's RUNNING is reported with (BehaviorTree.CPP 4.6.2's).
inline constexpr std::string_view kSyncActionRunning = "SyncActionNode MUST never return RUNNING";

// What the engine makes of a SyncActionNode's tick() result.
[[nodiscard]] inline Status sync_result(Status s, const ErrorSink& err, const NodeInfo& node) noexcept {
  if (s == Status::RUNNING) {
    (void)err.fail(node, node.source, kSyncActionRunning);
    return Status::FAILURE;
  }
  return s;
}

}  // namespace btgen
