// btgen runtime: what every generated mission header shares, so that the header holds only
// what is the mission's own.
//
//   BTGEN_SPEC_DEFAULT_SCRIPT & co.  the data operations of a mission that has none of a kind
//                                    (no scripts, no SetBlackboard, no Switch, ...), a line
//                                    each in the generated Spec
//   btgen::port::set_output          a port setter's store, reporting a failed one
//   btgen::VirtualLeaves and         the class of virtual hooks (<Mission>Leaves) for robot
//   BTGEN_VIRTUAL_ACTION & co.       code that prefers virtual calls: one line per model
//
// The virtual hooks are macros, one per model, in one flat class, rather than a chain of
// class templates (one per model, each deriving from the last and bringing its base's
// hooks in with using-declarations): every class of such a chain has its own vtable holding
// all the entries before it, so its size and its build time grow with the square of the
// models (measured: +0.1 s for 33 models, +1.7 s for 150, and no build at all past the
// compilers' template depth of about 450), and a chain of independent bases would make every
// virtual call adjust `this` through a thunk.
#pragma once

#include <cstdint>
#include <string_view>

#include "btgen/blackboard.hpp"
#include "btgen/node.hpp"
#include "btgen/port.hpp"
#include "btgen/queue_view.hpp"  // the queue ports of user leaves
#include "btgen/status.hpp"
#include "btgen/user_node.hpp"
#include "btgen/value.hpp"

namespace btgen {

namespace port {

// A port setter's store (setOutput): btgen::port::write, and a failed one reported as
// `message` at `where` with the reason (btgen::describe); true when the value was stored.
template <bool kFromChars, class S, class V>
bool set_output(Slot<S>& slot, Declared d, const V& value, const ErrorSink& err, const NodeInfo& node,
                std::string_view where, std::string_view message) noexcept {
  const Errc e = write<kFromChars>(slot, d, value);
  if (e == Errc::kOk) return true;
  (void)err.fail(node, where, message, describe(e));
  return false;
}

}  // namespace port

// The base of a mission's class of virtual hooks (<Mission>Leaves): robot code derives from
// that class and overrides the hooks of its models.
class VirtualLeaves {
 public:
  virtual ~VirtualLeaves() = default;

 protected:
  VirtualLeaves() = default;
  VirtualLeaves(const VirtualLeaves&) = default;
  VirtualLeaves& operator=(const VirtualLeaves&) = default;
};

}  // namespace btgen

// The virtual hooks of one model, a line each in the body of <Mission>Leaves.
//
// An Action M: override tick() (a SyncActionNode), or onStart, onRunning and onHalted (a
// StatefulActionNode); the defaults of the latter run tick() as the engine runs a
// SyncActionNode, and tick()'s default reports that the model has no implementation and fails.
#define BTGEN_VIRTUAL_ACTION(M)                                                                             \
  virtual ::btgen::Status tick(M& m, const ::btgen::NodeInfo&) { return ::btgen::no_implementation(m); }    \
  virtual ::btgen::Status onStart(M& m, const ::btgen::NodeInfo& n) { return m.sync_result(tick(m, n)); }   \
  virtual ::btgen::Status onRunning(M& m, const ::btgen::NodeInfo& n) { return m.sync_result(tick(m, n)); } \
  virtual void onHalted(M&, const ::btgen::NodeInfo&) {}                                                    \
  static_assert(M::kKind == ::btgen::LeafKind::Action, "BTGEN_VIRTUAL_ACTION(" #M "): not an Action model")
// A Condition C: check() (pure).
#define BTGEN_VIRTUAL_CONDITION(C)                                            \
  virtual ::btgen::Status check(C& model, const ::btgen::NodeInfo& node) = 0; \
  static_assert(C::kKind == ::btgen::LeafKind::Condition, "BTGEN_VIRTUAL_CONDITION(" #C "): not a Condition model")
// A Control or Decorator X of the mission: tick() (pure) and halt() (the node's own part of
// halt(); nothing by default).
#define BTGEN_VIRTUAL_USER_NODE(X)                                                                  \
  virtual ::btgen::Status tick(X& model, const ::btgen::NodeInfo& node) = 0;                        \
  virtual void halt(X&, const ::btgen::NodeInfo&) {}                                                \
  static_assert(X::kKind == ::btgen::LeafKind::Control || X::kKind == ::btgen::LeafKind::Decorator, \
                "BTGEN_VIRTUAL_USER_NODE(" #X "): not a Control or Decorator model")

// The data operations of the generated Spec (btgen::Engine calls them) for a mission that has
// none of the kind, a line each in the body of Spec. (Macros, not a base class the Spec
// derives from: with inherited ones g++ -O2 inlines the tick differently, measured 404 -> 450
// instructions per Lab Tour tick.)
//
// The compiled script of node `n` for `which`: 1 or 0 (a condition's truth; 1 for other
// scripts), -1 after an error was reported. None: 1.
#define BTGEN_SPEC_DEFAULT_SCRIPT                                                                                     \
  static int script(Blackboard&, const ::btgen::NodeInfo&, const ::btgen::ErrorSink&, ::btgen::ScriptSlot) noexcept { \
    return 1;                                                                                                         \
  }
// SetBlackboard and UnsetBlackboard: the node's status.
#define BTGEN_SPEC_DEFAULT_DATA_LEAF                                                                            \
  static ::btgen::Status data_leaf(Blackboard&, const ::btgen::NodeInfo&, const ::btgen::ErrorSink&) noexcept { \
    return ::btgen::Status::FAILURE;                                                                            \
  }
// Repeat num_cycles, RetryUntilSuccessful num_attempts, Timeout/Sleep msec and Delay delay_msec
// given as `{key}` (NodeInfo p1 is 1): the entry's value into `out`; 1, or -1 after reporting
// the error.
#define BTGEN_SPEC_DEFAULT_READ_PARAM                                                           \
  static int read_param(const Blackboard&, const ::btgen::ErrorSink&, const ::btgen::NodeInfo&, \
                        std::int64_t&) noexcept {                                               \
    return -1;                                                                                  \
  }
// The update counter of the entry WasEntryUpdated, SkipUnlessUpdated or WaitValueUpdate
// watches; -1 when the entry does not exist.
#define BTGEN_SPEC_DEFAULT_ENTRY_SEQ \
  static std::int64_t entry_seq(const Blackboard&, const ::btgen::NodeInfo&) noexcept { return -1; }
// SwitchN: the child to tick (the last one is the default).
#define BTGEN_SPEC_DEFAULT_SWITCH_CASE                                             \
  static int switch_case(const Blackboard&, const ::btgen::NodeInfo& n) noexcept { \
    return static_cast<int>(n.child_count) - 1;                                    \
  }
// LoopInt/LoopBool/LoopDouble/LoopString: pop the next element into the value port: 1, or 0
// when the queue is empty, -1 after an error was reported. `restart` (the loop starts from
// IDLE) refills a literal queue.
#define BTGEN_SPEC_DEFAULT_LOOP_POP \
  static int loop_pop(Blackboard&, const ::btgen::NodeInfo&, const ::btgen::ErrorSink&, bool) noexcept { return 0; }
