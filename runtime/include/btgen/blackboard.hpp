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
//   entry_type the entry's own type, where 4.10.0's SetBlackboard asks it
//              (EntryType; 4.6.2 never reads it)
//
// Run-time problems that 4.6.2 reports by throwing (a script reading an
// entry that does not exist, a conversion that fails, a string longer than
// its capacity) go to an ErrorSink as a RuntimeError; the node doing it
// fails. The mission forwards them to its Observer's on_error().
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "btgen/node.hpp"

namespace btgen {

// The value of an entry nothing ever writes (only its existence and update
// counter are observable).
struct NoValue {
  friend constexpr bool operator==(NoValue, NoValue) noexcept { return true; }
};

// The type of an entry that no port declared, as BehaviorTree.CPP 4.7.0 and
// later keep it at run time (Semantics::setblackboard_converts_to_entry_type):
// SetBlackboard converts a string with the entry's own converter, which an
// untyped entry lacks. Only SetBlackboard reads it; every writer keeps it.
enum class EntryType : std::uint8_t {
  kUntyped = 0,  // created without a type (a Script, an untyped port, a SubTree literal)
  kTyped = 1,    // given a type: created by SetBlackboard, or written through a port
  kBtAny = 2,    // typed BT::Any by a string SetBlackboard left empty: the next one throws
};

template <class T>
struct Slot {
  using value_type = T;
  T value{};
  std::uint64_t seq = 0;
  bool exists = false;
  bool has_value = false;
  EntryType entry_type = EntryType::kUntyped;
  // When a script created the entry, on the mission's count of such creations (Blackboard::
  // births_; 0: it exists from load on, or nothing counts): the order BehaviorTree.CPP's
  // storage keeps, which storage_order() replays for Blackboard::debugMessage.
  std::uint32_t born = 0;

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
    entry_type = EntryType::kUntyped;
    born = 0;
  }
};

// The order libstdc++'s unordered_map keeps a blackboard's entries in (lang/hashorder.py is
// the reference): entry i (std::hash of its key `hash[i]`) is in it when `present[i]`; those
// with `born[i]` 0 were inserted first, in index order, the others then by `born`. Each goes
// before the first node of its bucket, or to the front when its bucket is empty; an insertion
// that would exceed the bucket count rehashes (13, 29, 59 ... buckets), re-inserting the nodes
// in list order. Writes the order into `out`; returns how many entries it holds.
template <std::size_t N>
std::size_t storage_order(const std::uint64_t (&hash)[N], const bool (&present)[N], const std::uint32_t (&born)[N],
                          std::uint16_t (&out)[N]) noexcept {
  constexpr std::uint64_t kBuckets[] = {13, 29, 59, 127, 257, 541, 1109, 2357, 5087, 10273, 20753, 42043, 85229};
  std::uint16_t seq[N] = {};
  std::size_t n = 0;
  for (std::size_t i = 0; i < N; ++i) {
    if (present[i] && born[i] == 0) seq[n++] = static_cast<std::uint16_t>(i);
  }
  const std::size_t first_born = n;
  for (std::size_t i = 0; i < N; ++i) {
    if (present[i] && born[i] != 0) seq[n++] = static_cast<std::uint16_t>(i);
  }
  for (std::size_t a = first_born + 1; a < n; ++a) {  // by birth (insertion sort: few entries)
    const std::uint16_t k = seq[a];
    std::size_t b = a;
    for (; b > first_born && born[seq[b - 1]] > born[k]; --b) seq[b] = seq[b - 1];
    seq[b] = k;
  }
  std::uint64_t buckets = 0;
  std::size_t size = 0;
  const auto place = [&](std::uint16_t k, std::uint64_t count) noexcept {
    std::size_t at = 0;
    for (std::size_t i = 0; i < size; ++i) {
      if (hash[out[i]] % count == hash[k] % count) {
        at = i;
        break;
      }
    }
    for (std::size_t i = size; i > at; --i) out[i] = out[i - 1];
    out[at] = k;
    ++size;
  };
  for (std::size_t s = 0; s < n; ++s) {
    if (buckets == 0) {
      buckets = kBuckets[0];
    } else if (size + 1 > buckets) {
      std::uint64_t next = buckets;
      for (const std::uint64_t c : kBuckets) {
        if (c >= 2 * buckets) {
          next = c;
          break;
        }
      }
      buckets = next;
      std::uint16_t old[N] = {};
      const std::size_t old_size = size;
      for (std::size_t i = 0; i < old_size; ++i) old[i] = out[i];
      size = 0;
      for (std::size_t i = 0; i < old_size; ++i) place(old[i], buckets);
    }
    place(seq[s], buckets);
  }
  return size;
}

// SetBlackboard of a string into an entry no port declared, from BehaviorTree.CPP
// 4.7.0 (Semantics::setblackboard_converts_to_entry_type): the library converts the
// text with the entry's own converter. A missing entry is created first, of type
// `created`. Returns 1 when the entry takes the text (it is typed: std::string), 0
// when it has no converter (untyped): it is left empty but updated, and becomes
// typed BT::Any if it is stored on the node's own blackboard (`local`; one reached
// through a SubTree remapping keeps its type); -1 when it is typed BT::Any, whose
// converter throws.
template <class T>
[[nodiscard]] constexpr int set_string_410(Slot<T>& slot, EntryType created, bool local) noexcept {
  if (!slot.exists) {
    slot.exists = true;
    slot.entry_type = created;
  }
  switch (slot.entry_type) {
    case EntryType::kTyped: return 1;
    case EntryType::kUntyped:
      slot.value = T{};
      slot.has_value = false;
      ++slot.seq;
      if (local) slot.entry_type = EntryType::kBtAny;
      return 0;
    case EntryType::kBtAny: return -1;
  }
  return -1;
}

struct RuntimeError {
  const NodeInfo* node;      // the node that failed because of it
  std::string_view where;    // "path:line:col" of what failed (script character, port), or the node
  std::string_view message;  // what happened, without the location
  std::string_view detail;   // why, when known (e.g. btgen::describe(Errc)); may be empty
  std::string_view printed;  // what the library prints on stdout before it throws (a trace's lines), or empty
};

// Where generated code reports run-time errors: a function and its context
// (the mission object), so that reporting needs no virtual call, template
// or allocation.
class ErrorSink {
 public:
  using Fn = void (*)(void* context, const RuntimeError& error) noexcept;

  constexpr ErrorSink(Fn fn, void* context) noexcept : fn_(fn), context_(context) {}

  // Reports the error; returns -1 (what generated script functions return on error).
  int fail(const NodeInfo& node, std::string_view where, std::string_view message, std::string_view detail = {},
           std::string_view printed = {}) const noexcept {
    fn_(context_, RuntimeError{&node, where, message, detail, printed});
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
