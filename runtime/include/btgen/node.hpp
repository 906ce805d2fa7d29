// btgen runtime: the node table a generated mission is made of.
//
// A generated mission is a constexpr array of NodeInfo in BehaviorTree.CPP's
// creation order (depth first, a SubTree node before the nodes of its tree),
// so a node's index is its BehaviorTree.CPP UID minus one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "btgen/status.hpp"

namespace btgen {

// Every node kind the C++ back end executes. The names are the
// BehaviorTree.CPP registration IDs; Action and Condition are the user's
// leaves (TreeNodesModel), called through the generated leaf hooks.
enum class NodeKind : std::uint8_t {
  // controls
  Sequence,
  AsyncSequence,
  SequenceWithMemory,
  ReactiveSequence,
  Fallback,
  AsyncFallback,
  ReactiveFallback,
  Parallel,
  ParallelAll,
  IfThenElse,
  WhileDoElse,
  Switch,    // Switch2 .. Switch6
  TryCatch,  // BehaviorTree.CPP 4.9.0 and later
  // decorators
  Inverter,
  ForceSuccess,
  ForceFailure,
  Repeat,
  RetryUntilSuccessful,
  KeepRunningUntilFailure,
  RunOnce,
  Timeout,
  Delay,
  Precondition,
  Loop,  // LoopInt, LoopBool, LoopDouble, LoopString
  SkipUnlessUpdated,
  WaitValueUpdate,
  SubTree,
  // built-in leaves
  AlwaysSuccess,
  AlwaysFailure,
  Sleep,
  Script,
  ScriptCondition,
  SetBlackboard,
  UnsetBlackboard,
  WasEntryUpdated,
  // user leaves
  Action,
  Condition,
  // the mission's own Controls and Decorators (TreeNodesModel), run by the
  // user's tick() hook (btgen/user_node.hpp)
  UserControl,
  UserDecorator,
  // Nav2's Controls and Decorators that need only BehaviorTree.CPP (btgen/nav2 in the
  // generator: built in when a mission selects Nav2's nodes)
  PipelineSequence,
  RecoveryNode,
  RoundRobin,
  NonblockingSequence,
  PersistentSequence,
  RateController,
  SingleTrigger,
  // Nav2's Decorators with an input of the environment (btgen/nav2.hpp)
  DistanceController,
  SpeedController,
  GoalUpdatedController,
  PathLongerOnApproach,
  GoalUpdater,
};

// The kind of a model of TreeNodesModel (the generated model classes' kKind).
enum class LeafKind : std::uint8_t { Action, Condition, Control, Decorator };

inline constexpr std::uint16_t kNoNode = 0xFFFF;
inline constexpr std::uint32_t kNoSlot = 0xFFFFFFFFu;
inline constexpr std::uint16_t kNoModel = 0xFFFF;

// The text of a node: its registration ID, name and source position, for
// traces, run-time errors, scenario runners and Groot2. A build for a small
// microcontroller that wants none of that can leave it out with
// -DBTGEN_NODE_TEXT=0: NodeText is then an empty type that reads as "" (the
// generated tables' strings are no longer referenced, so the linker drops
// them, and each row is 16 bytes smaller on a 32-bit target). Traces then
// print empty IDs and names and run-time errors no position; the statuses and
// everything else are unchanged.
#ifndef BTGEN_NODE_TEXT
#define BTGEN_NODE_TEXT 1
#endif
#if BTGEN_NODE_TEXT
using NodeText = std::string_view;
#else
struct NodeText {
  constexpr NodeText() noexcept = default;
  constexpr NodeText(std::string_view) noexcept {}  // NOLINT: implicit, as the generated rows give it
  constexpr operator std::string_view() const noexcept { return {}; }  // NOLINT
  [[nodiscard]] constexpr const char* data() const noexcept { return ""; }
  [[nodiscard]] constexpr std::size_t size() const noexcept { return 0; }
  [[nodiscard]] constexpr bool empty() const noexcept { return true; }
};
#endif

// One node of a mission. Parameters are converted from the XML at generation
// time; their meaning depends on the kind:
//   Parallel              p0 successes needed, p1 failures that fail it,
//                         p2 1 when success_count was negative; p2 bit 2 (kParallelReads): the
//                         thresholds are `{key}`s read on every tick (Spec::read_param)
//   ParallelAll           p0 failure threshold (from max_failures)
//   Repeat                p0 num_cycles (-1: for ever)
//   RetryUntilSuccessful  p0 num_attempts (-1: for ever)
//   RunOnce               p0 then_skip (0 or 1); p1 1: read it as `{key}` (Spec::read_param)
//   Timeout, Sleep        p0 msec
//   Delay                 p0 delay_msec
//   Switch                p0 number of cases (the last child is the default)
//   Precondition          p0 the `else` status; p1 1: read on every tick (Spec::read_param): a
//                         `{key}`, or a literal that is no NodeStatus (the read throws)
//   Loop                  p0 the `if_empty` status; p1 1: it is no NodeStatus (Spec::read_param throws)
//   TryCatch              p0 catch_on_halt (0 or 1); p1 1: read it as `{key}` (Spec::read_param)
//   RecoveryNode          p0 number_of_retries; p1 1: read it as `{key}` on every tick
//   PersistentSequence    p0 current_child_idx (a literal); p1 1: read it as `{key}` on every tick
//   RoundRobin            p0 wrap_around (0 or 1; 1 before Nav2 lyrical, which always wrapped)
//   RateController        p0 hz, the bits of a double
// `scripts` has a bit per pre/post condition the node has (btgen::ScriptSlot:
// _failureIf, _successIf, _skipIf, _while, _onSuccess, _onFailure, _post,
// _onHalted); the generated Spec::script() runs them.
struct NodeInfo {
  NodeKind kind;
  std::uint16_t index;        // position in the table
  std::uint16_t uid;          // BehaviorTree.CPP UID (index + 1)
  std::uint16_t parent;       // kNoNode for the root
  std::uint32_t child_begin;  // first entry in the child table
  std::uint16_t child_count;
  std::uint16_t model;    // user model (Action/Condition/Control/Decorator), else kNoModel
  std::uint32_t slot;     // first counter slot, else kNoSlot
  std::uint32_t timer;    // 64-bit slot: start time, or the update counter seen; else kNoSlot
  std::uint16_t scripts;  // pre/post conditions present (1 << ScriptSlot)
  std::int64_t p0;
  std::int64_t p1;
  std::int64_t p2;
  NodeText id;      // registration ID: "Sequence", "SubTree", "FindBall", ...
  NodeText name;    // name attribute, else the ID
  NodeText source;  // "path:line:col" of the element
};

// NodeInfo::p2 bit of a Parallel whose thresholds are `{key}`s (data/records.py PARALLEL_READS).
inline constexpr std::int64_t kParallelReads = 2;

[[nodiscard]] constexpr bool is_nav2(NodeKind k) noexcept { return k >= NodeKind::PipelineSequence; }

[[nodiscard]] constexpr bool is_control(NodeKind k) noexcept {
  return k <= NodeKind::WhileDoElse || k == NodeKind::UserControl ||
         (k >= NodeKind::PipelineSequence && k <= NodeKind::PersistentSequence);
}

[[nodiscard]] constexpr bool is_decorator(NodeKind k) noexcept {
  return (k >= NodeKind::Inverter && k <= NodeKind::SubTree) || k == NodeKind::UserDecorator ||
         k == NodeKind::RateController || k == NodeKind::SingleTrigger || k >= NodeKind::DistanceController;
}

// A node whose results a scenario scripts under its name: a user Action or Condition, or a Nav2
// Decorator's input of the environment (btgen/nav2.hpp; SUCCESS or FAILURE, as a Condition).
[[nodiscard]] constexpr bool is_scripted(NodeKind k) noexcept {
  return k == NodeKind::Action || k == NodeKind::Condition ||
         (k >= NodeKind::DistanceController && k <= NodeKind::PathLongerOnApproach);
}
[[nodiscard]] constexpr bool is_condition_like(NodeKind k) noexcept {
  return k == NodeKind::Condition || (k >= NodeKind::DistanceController && k <= NodeKind::PathLongerOnApproach);
}

[[nodiscard]] constexpr bool is_leaf(NodeKind k) noexcept {
  return k >= NodeKind::AlwaysSuccess && k <= NodeKind::Condition;
}

// What NodeInfo::p0..p2 hold: a node's port literals, converted when btgen compiles the
// mission (generator/btgen/ir/lower.py, `params`). The engine reads them by meaning.
namespace param {

// Repeat `num_cycles`, RetryUntilSuccessful `num_attempts`: -1 for no limit.
[[nodiscard]] constexpr std::int64_t max_cycles(const NodeInfo& n) noexcept { return n.p0; }

// RunOnce `then_skip`: SKIPPED after the first run, else the first run's status again.
[[nodiscard]] constexpr bool then_skip(const NodeInfo& n) noexcept { return n.p0 != 0; }

// TryCatch `catch_on_halt` (a literal): a halt in the try block ticks the catch child.
[[nodiscard]] constexpr bool catch_on_halt(const NodeInfo& n) noexcept { return n.p0 != 0; }

// Timeout and Sleep `msec`, Delay `delay_msec`.
[[nodiscard]] constexpr std::int64_t duration_ms(const NodeInfo& n) noexcept { return n.p0; }

// Precondition `else`, Loop* `if_empty`: the status returned instead of ticking the child.
[[nodiscard]] constexpr Status otherwise(const NodeInfo& n) noexcept { return static_cast<Status>(n.p0); }

// Parallel: the successes and the failures that decide (negative counts made absolute), and
// whether `success_count` was negative (4.6.2 then counts skipped children as successes).
[[nodiscard]] constexpr std::int64_t success_threshold(const NodeInfo& n) noexcept { return n.p0; }
[[nodiscard]] constexpr std::int64_t failure_threshold(const NodeInfo& n) noexcept { return n.p1; }
[[nodiscard]] constexpr bool success_count_relative(const NodeInfo& n) noexcept { return (n.p2 & 1) != 0; }

// ParallelAll `max_failures` (made absolute).
[[nodiscard]] constexpr std::int64_t max_failures(const NodeInfo& n) noexcept { return n.p0; }

// Nav2's RecoveryNode `number_of_retries` (a literal).
[[nodiscard]] constexpr std::int64_t number_of_retries(const NodeInfo& n) noexcept { return n.p0; }

// Nav2's RoundRobin `wrap_around`.
[[nodiscard]] constexpr bool wrap_around(const NodeInfo& n) noexcept { return n.p0 != 0; }

// Nav2's RateController `hz` (a double kept in p0's bits).
[[nodiscard]] inline double hz(const NodeInfo& n) noexcept {
  double v = 0.0;
  std::memcpy(&v, &n.p0, sizeof v);
  return v;
}

}  // namespace param

}  // namespace btgen
