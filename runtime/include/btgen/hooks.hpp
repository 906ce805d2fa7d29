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
struct has_on_running : std::false_type {};
template <class Leaves, class Model>
struct has_on_running<
    Leaves, Model,
    std::void_t<decltype(std::declval<Leaves&>().onRunning(std::declval<Model&>(), std::declval<const NodeInfo&>()))>>
    : std::true_type {};

template <class Leaves, class Model, class = void>
struct has_on_halted : std::false_type {};
template <class Leaves, class Model>
struct has_on_halted<
    Leaves, Model,
    std::void_t<decltype(std::declval<Leaves&>().onHalted(std::declval<Model&>(), std::declval<const NodeInfo&>()))>>
    : std::true_type {};

template <class Leaves, class Model, class = void>
struct has_check : std::false_type {};
template <class Leaves, class Model>
struct has_check<
    Leaves, Model,
    std::void_t<decltype(std::declval<Leaves&>().check(std::declval<Model&>(), std::declval<const NodeInfo&>()))>>
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

// The hooks Leaves has for an Action model: none, a complete set (tick() alone, or onStart with
// onRunning and onHalted), or onStart without one or both of the others.
enum class ActionHooks { kNone, kComplete, kNoOnRunning, kNoOnHalted, kNoOnRunningNorOnHalted };

template <class Leaves, class Model>
[[nodiscard]] constexpr ActionHooks action_hooks() noexcept {
  constexpr bool start = hooks_detail::has_on_start<Leaves, Model>::value;
  constexpr bool running = hooks_detail::has_on_running<Leaves, Model>::value;
  constexpr bool halted = hooks_detail::has_on_halted<Leaves, Model>::value;
  if (!start) return hooks_detail::has_tick<Leaves, Model>::value ? ActionHooks::kComplete : ActionHooks::kNone;
  if (running && halted) return ActionHooks::kComplete;
  if (halted) return ActionHooks::kNoOnRunning;
  return running ? ActionHooks::kNoOnHalted : ActionHooks::kNoOnRunningNorOnHalted;
}

template <class Leaves, class Model>
inline constexpr bool has_on_running_hook = hooks_detail::has_on_running<Leaves, Model>::value;
template <class Leaves, class Model>
inline constexpr bool has_on_halted_hook = hooks_detail::has_on_halted<Leaves, Model>::value;
template <class Leaves, class Model>
inline constexpr bool has_check_hook = hooks_detail::has_check<Leaves, Model>::value;
template <class Leaves, class Model>
inline constexpr bool has_tick_hook = hooks_detail::has_tick<Leaves, Model>::value;

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

// The checks a generated mission class makes of its Leaves type, one line per model in its
// body: a missing or partial set of hooks is then the first error the compiler prints (when
// the mission class is instantiated, before any hook call), one sentence naming the model and
// what to add, rather than the template errors of the calls. A static_assert message is a
// literal, hence macros (the model's name is pasted into it).
#define BTGEN_ACTION_HOOKS(M)                                                                                    \
  static_assert(::btgen::action_hooks<Leaves, M>() != ::btgen::ActionHooks::kNone,                               \
                "Leaves has no hook for the Action " #M ": add `btgen::Status tick(" #M                          \
                "&, const btgen::NodeInfo&)` (a SyncActionNode), or onStart, onRunning and onHalted (a "         \
                "StatefulActionNode)");                                                                          \
  static_assert(::btgen::action_hooks<Leaves, M>() != ::btgen::ActionHooks::kNoOnRunningNorOnHalted,             \
                "Leaves has onStart for the Action " #M                                                          \
                " but neither onRunning nor onHalted: add `btgen::Status "                                       \
                "onRunning(" #M "&, const btgen::NodeInfo&)` and `void onHalted(" #M                             \
                "&, const btgen::NodeInfo&)`, or write onStart as `btgen::Status tick(" #M                       \
                "&, const btgen::NodeInfo&)` (a SyncActionNode)");                                               \
  static_assert(::btgen::action_hooks<Leaves, M>() != ::btgen::ActionHooks::kNoOnRunning,                        \
                "Leaves has onStart and onHalted for the Action " #M                                             \
                " but no onRunning: add `btgen::Status "                                                         \
                "onRunning(" #M "&, const btgen::NodeInfo&)`");                                                  \
  static_assert(::btgen::action_hooks<Leaves, M>() != ::btgen::ActionHooks::kNoOnHalted,                         \
                "Leaves has onStart and onRunning for the Action " #M " but no onHalted: add `void onHalted(" #M \
                "&, const btgen::NodeInfo&)`")
#define BTGEN_CONDITION_HOOK(M)                                                                \
  static_assert(::btgen::has_check_hook<Leaves, M>, "Leaves has no hook for the Condition " #M \
                                                    ": add `btgen::Status check(" #M "&, const btgen::NodeInfo&)`")
#define BTGEN_USER_NODE_HOOK(M)                                                                          \
  static_assert(::btgen::has_tick_hook<Leaves, M>, "Leaves has no hook for the Control or Decorator " #M \
                                                   ": add `btgen::Status tick(" #M "&, const btgen::NodeInfo&)`")
