// btgen runtime: the node table a generated mission is made of.
//
// A generated mission is a constexpr array of NodeInfo in BehaviorTree.CPP's
// creation order (depth first, a SubTree node before the nodes of its tree),
// so a node's index is its BehaviorTree.CPP UID minus one.
#pragma once

#include <cstdint>
#include <string_view>

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
  SubTree,
  // built-in leaves
  AlwaysSuccess,
  AlwaysFailure,
  Sleep,
  // user leaves
  Action,
  Condition,
};

enum class LeafKind : std::uint8_t { Action, Condition };

inline constexpr std::uint16_t kNoNode = 0xFFFF;
inline constexpr std::uint32_t kNoSlot = 0xFFFFFFFFu;
inline constexpr std::uint16_t kNoModel = 0xFFFF;

// One node of a mission. Parameters are converted from the XML at generation
// time; their meaning depends on the kind:
//   Parallel              p0 successes needed, p1 failures that fail it,
//                         p2 1 when success_count was negative
//   ParallelAll           p0 failure threshold (from max_failures)
//   Repeat                p0 num_cycles (-1: for ever)
//   RetryUntilSuccessful  p0 num_attempts (-1: for ever)
//   RunOnce               p0 then_skip (0 or 1)
//   Timeout, Sleep        p0 msec
//   Delay                 p0 delay_msec
struct NodeInfo {
  NodeKind kind;
  std::uint16_t index;        // position in the table
  std::uint16_t uid;          // BehaviorTree.CPP UID (index + 1)
  std::uint16_t parent;       // kNoNode for the root
  std::uint32_t child_begin;  // first entry in the child table
  std::uint16_t child_count;
  std::uint16_t model;        // leaf model (Action/Condition), else kNoModel
  std::uint32_t slot;         // first counter slot, else kNoSlot
  std::uint32_t timer;        // timer slot, else kNoSlot
  std::int64_t p0;
  std::int64_t p1;
  std::int64_t p2;
  std::string_view id;        // registration ID: "Sequence", "SubTree", "FindBall", ...
  std::string_view name;      // name attribute, else the ID
  std::string_view source;    // "path:line:col" of the element
};

[[nodiscard]] constexpr bool is_control(NodeKind k) noexcept {
  return k <= NodeKind::WhileDoElse;
}

[[nodiscard]] constexpr bool is_decorator(NodeKind k) noexcept {
  return k >= NodeKind::Inverter && k <= NodeKind::SubTree;
}

[[nodiscard]] constexpr bool is_leaf(NodeKind k) noexcept {
  return k >= NodeKind::AlwaysSuccess;
}

}  // namespace btgen
