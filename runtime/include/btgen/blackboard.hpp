// btgen runtime: the typed blackboard of a generated mission, and its error hook.
//
// BehaviorTree.CPP keeps a blackboard per tree instance: a map from key to a
// type-erased entry, looked up by string on every access. The generator
// resolves every key at compile time (SubTree remapping, _autoremap, {=},
// `@` root keys) to one entry, gives it a C++ type, and emits a struct with
// one Slot<T> member per entry. A Slot carries what 4.6.2's Entry does:
//
//   value      the value (T: std::int64_t, double, bool, Status,
//              FixedString<N> or FixedQueue<E, N>; NoValue when nothing
//              ever writes one)
//   seq        the update counter (Entry::sequence_id): +1 on every write;
//              what WasEntryUpdated, SkipUnlessUpdated and WaitValueUpdate
//              watch
//   exists     the entry exists (created when the tree was built, or by a
//              write; UnsetBlackboard removes it)
//   has_value  it holds a value (an entry created by a port has none yet)
//
// Run-time problems that 4.6.2 reports by throwing (a script reading an
// entry that does not exist, a conversion that fails, a string longer than
// its capacity) go to an ErrorSink as a RuntimeError; the node doing it
// fails. The mission forwards them to its Observer's on_error().
#pragma once

#include <cstdint>
#include <string_view>

#include "btgen/node.hpp"

namespace btgen {

// The value of an entry nothing ever writes (only its existence and update
// counter are observable).
struct NoValue {
  friend constexpr bool operator==(NoValue, NoValue) noexcept { return true; }
};

template <class T>
struct Slot {
  using value_type = T;
  T value{};
  std::uint64_t seq = 0;
  bool exists = false;
  bool has_value = false;

  // A write: the entry exists, holds a value, and its counter moves on.
  constexpr void mark_written() noexcept {
    exists = true;
    has_value = true;
    ++seq;
  }
  // UnsetBlackboard: the entry is gone; one created later starts afresh.
  constexpr void unset() noexcept {
    value = T{};
    seq = 0;
    exists = false;
    has_value = false;
  }
};

struct RuntimeError {
  const NodeInfo* node;      // the node that failed because of it
  std::string_view where;    // "path:line:col" of what failed (script character, port), or the node
  std::string_view message;  // what happened, without the location
  std::string_view detail;   // why, when known (e.g. btgen::describe(Errc)); may be empty
};

// Where generated code reports run-time errors: a function and its context
// (the mission object), so that reporting needs no virtual call, template
// or allocation.
class ErrorSink {
 public:
  using Fn = void (*)(void* context, const RuntimeError& error) noexcept;

  constexpr ErrorSink(Fn fn, void* context) noexcept : fn_(fn), context_(context) {}

  // Reports the error; returns -1 (what generated script functions return on error).
  int fail(const NodeInfo& node, std::string_view where, std::string_view message,
           std::string_view detail = {}) const noexcept {
    fn_(context_, RuntimeError{&node, where, message, detail});
    return -1;
  }

 private:
  Fn fn_;
  void* context_;
};

// The pre-, post- and halt-conditions of a node (NodeInfo::scripts bits),
// and the script-valued ports, as the generated script dispatcher numbers them.
enum class ScriptSlot : std::uint8_t {
  kFailureIf = 0,
  kSuccessIf = 1,
  kSkipIf = 2,
  kWhile = 3,
  kOnSuccess = 4,
  kOnFailure = 5,
  kPost = 6,
  kOnHalted = 7,
  kCode = 8,  // Script/ScriptCondition `code`, Precondition `if`
};

[[nodiscard]] constexpr std::uint16_t script_bit(ScriptSlot s) noexcept {
  return static_cast<std::uint16_t>(1u << static_cast<unsigned>(s));
}

}  // namespace btgen
