// btgen runtime: the table-driven executor every generated mission uses.
//
// A generated mission supplies a `Spec`: constexpr tables (nodes in
// BehaviorTree.CPP creation order, child lists, capacities) and the leaf
// dispatch functions that call the user's hooks. Engine<Spec, ...> holds the
// mission's whole state in fixed-size arrays sized by the generator, ticks it
// with BehaviorTree.CPP 4.6.2 semantics (Tree::tickExactlyOnce) and halts it
// (Tree::haltTree). No heap, no exceptions, no RTTI; recursion only in the
// straight-line ticks, at most kCompiledDepth (48) calls deep: the
// interpreter and halts walk explicit stacks whose depth is the tree's depth.
// The interpreter is entered again (one C++ call level each, on the same
// explicit stacks) for the children of a mission's own Control or Decorator,
// and for the catch child a TryCatch (4.9.0, catch_on_halt) ticks inside its
// halt: those nest no deeper than the tree.
//
// Each built-in node is written as a small state machine: `enter` starts its
// tick, `resume` continues it with the status its child just returned; both
// answer "tick this child next" or "return this status". That is
// BehaviorTree.CPP's recursive executeTick() unrolled onto the explicit stack
// (the table interpreter). The first nodes of the tree (see
// BTGEN_STRAIGHT_LINE_BUDGET) tick as straight-line code instead: the same
// state machines instantiated per node shape (equal subtrees share one), so
// their kind and children are compile-time constants (tick_node below).
//
// The data side is the Spec's: its Blackboard (one typed slot per entry,
// held here), and the generated functions that run the mission's compiled
// scripts and read and write the slots. The engine calls them where 4.6.2
// runs a script or touches the blackboard. Run-time errors they report go
// to the Observer's on_error() (when it has one) and fail the node.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/clock.hpp"
#include "btgen/leaf_dispatch.hpp"
#include "btgen/nav2.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"
#include "btgen/user_node.hpp"

// How much of a mission ticks as straight-line code (Engine::tick_node):
// the shapes first met in creation order (the root and the part of the tree
// drawn first) while the weights of the shapes before them add up to less
// than this, a shape weighing 1 (6 when it runs scripts) plus its children;
// a node of a shape met before is free (its code is shared). 0: none. The
// others run on the table interpreter.
// Straight line costs 6 to 18 instructions per visited node instead of 78,
// and g++ -O2 some milliseconds per distinct node instead of almost
// nothing: the budget keeps the build of a large mission fast. A Spec may set its own
// (`static constexpr std::size_t kStraightLineBudget`; 0: all interpreted).
#ifndef BTGEN_STRAIGHT_LINE_BUDGET
#define BTGEN_STRAIGHT_LINE_BUDGET 1000
#endif

namespace btgen {

namespace engine_detail {
template <class O, class = void>
struct has_on_error : std::false_type {};
template <class O>
struct has_on_error<O, std::void_t<decltype(std::declval<O&>().on_error(std::declval<const RuntimeError&>()))>>
    : std::true_type {};
// An observer that may force a node's status (btgen::MonitorObserver: Groot2's REPLACE hooks).
template <class O, class = void>
struct has_forced_status : std::false_type {};
template <class O>
struct has_forced_status<O, std::void_t<decltype(std::declval<O&>().forced_status(std::declval<const NodeInfo&>()))>>
    : std::true_type {};
// An observer that may also force a node's result after its tick (4.10.0's POST hooks).
template <class O, class = void>
struct has_post_forced_status : std::false_type {};
template <class O>
struct has_post_forced_status<
    O, std::void_t<decltype(std::declval<O&>().post_forced_status(std::declval<const NodeInfo&>()))>> : std::true_type {
};
template <class S, class = void>
struct straight_line_budget : std::integral_constant<std::size_t, BTGEN_STRAIGHT_LINE_BUDGET> {};
template <class S>
struct straight_line_budget<S, std::void_t<decltype(S::kStraightLineBudget)>>
    : std::integral_constant<std::size_t, S::kStraightLineBudget> {};
// A Spec with shape tables (Spec::kShape, kShapeRep: straight-line code shared by equal subtrees).
template <class S, class = void>
struct has_shapes : std::false_type {};
template <class S>
struct has_shapes<S, std::void_t<decltype(S::kShape), decltype(S::kShapeRep), decltype(S::kShapeUses),
                                 decltype(S::kTotalWeight), decltype(S::kRepNode), decltype(S::kRepWeightBefore),
                                 decltype(S::kHasDeepShape), decltype(S::kHasUserControlFlow)>> : std::true_type {};
// A Spec with a table of compiled scripts (Spec::kScripts, each a function and its node's
// error sites; kScriptFirst[i] is node i's first): straight-line code calls them directly.
template <class S, class = void>
struct has_script_table : std::false_type {};
template <class S>
struct has_script_table<S, std::void_t<decltype(S::kScripts), decltype(S::kScriptFirst)>> : std::true_type {};
// A Spec whose mission has a Nav2 PersistentSequence writing its place into an entry.
template <class S, class = void>
struct has_write_index : std::false_type {};
template <class S>
struct has_write_index<
    S, std::void_t<decltype(S::write_index(std::declval<typename S::Blackboard&>(), std::declval<const ErrorSink&>(),
                                           std::declval<const NodeInfo&>(), std::int64_t{}))>> : std::true_type {};
// A Spec with literals of user port types to convert at construction (btgen/user_type.hpp).
template <class S, class = void>
struct has_init : std::false_type {};
template <class S>
struct has_init<
    S, std::void_t<decltype(S::init(std::declval<typename S::Blackboard&>(), std::declval<const ErrorSink&>()))>>
    : std::true_type {};
}  // namespace engine_detail

// Spec requirements (the generator writes them):
//   static constexpr std::size_t kNodeCount, kChildCount, kCounterCount,
//                                kTimerCount, kMaxDepth;
//   static constexpr bool kHasParallel;
//   static constexpr std::array<NodeInfo, kNodeCount> kNodes;
//   static constexpr std::array<std::uint16_t, kChildCount> kChildren;
//   static constexpr std::array<std::uint16_t, kNodeCount> kShape;     // node -> its shape
//   static constexpr std::array<std::uint16_t, kShapeCount> kShapeRep; // shape -> first node (kNoNode: interpreted)
//   static constexpr std::array<std::uint32_t, kShapeCount> kShapeUses;  // shape -> its nodes
//   static constexpr std::size_t kTotalWeight;                          // all nodes' weights
//   static constexpr std::array<std::uint16_t, R> kRepNode;             // first node of each shape
//   static constexpr std::array<std::uint32_t, R> kRepWeightBefore;     // weight of the ones before
//   static constexpr bool kHasDeepShape, kHasUserControlFlow;
//     (without the shape tables every node runs on the interpreter)
//   struct Blackboard;  (default-constructible: the entries as the tree is built)
//   using BB = Blackboard; using ES = const ErrorSink;
//   template <std::uint16_t M> using Model;   // the leaf model class numbered M
//   template <class H, class... A> static constexpr decltype(auto) visit_action(std::uint16_t, A&...);
//     (and visit_condition, visit_user_node: H::call<the model class of that number>(A...);
//     btgen/leaf_dispatch.hpp's LeafHooks calls the hooks through these)
//   static int script(BB&, const NodeInfo&, ES&, ScriptSlot);   // 1/0 (truth), -1 error
//   static Status data_leaf(BB&, const NodeInfo&, ES&);        // SetBlackboard, UnsetBlackboard
//   static std::int64_t entry_seq(const BB&, const NodeInfo&); // update counter; -1: no entry
//   static int read_param(const BB&, const ErrorSink&, const NodeInfo&, std::int64_t&);  // {key} counts
//   static int switch_case(const BB&, const NodeInfo&);        // child to tick (the last: default)
//   static int loop_pop(BB&, const NodeInfo&, ES&, bool restart);  // 1 popped, 0 empty, -1 error
// and, optionally (missions with literals of user port types),
//   static void init(BB&, ES&);  // converts them, once, in the constructor; reports failures
template <class Spec, class Leaves, class Clock = SteadyClock, class Observer = NoObserver>
class Engine {
 public:
  using Blackboard = typename Spec::Blackboard;
  using Hooks = LeafHooks<Spec, Leaves>;
  using MissionSpec = Spec;
  // The BehaviorTree.CPP release the mission follows: one constexpr flag per difference
  // (btgen's lang/versions.py names them; the generated header defines them).
  using Sem = typename Spec::Semantics;
  static_assert(Sem::kBtcppVersion == 40602 || Sem::kBtcppVersion == 41000,
                "the mission header was generated for a BehaviorTree.CPP release this runtime does not know");

  static constexpr std::size_t kNodeCount = Spec::kNodeCount;
  static constexpr std::size_t kMaxDepth = Spec::kMaxDepth;

  static_assert(kNodeCount >= 1, "a mission has at least one node");
  static_assert(kNodeCount <= kNoNode, "node indices are 16-bit (0 to 65534; 65535 is kNoNode)");
  static_assert(kMaxDepth >= 1 && kMaxDepth <= kNodeCount, "tree depth out of range");

  // A mission with literals of user port types (btgen compile --type) converts
  // them here, once; each that does not convert is reported to the Observer's
  // on_error() and counted by errors().
  constexpr explicit Engine(Leaves& leaves, Clock clock = Clock{}, Observer observer = Observer{}) noexcept
      : leaves_(&leaves), clock_(clock), observer_(observer) {
    if constexpr (engine_detail::has_init<Spec>::value) Spec::init(bb_, sink());
  }

  // One tick of the root, as BT::Tree::tickExactlyOnce(): when the root
  // returns SUCCESS or FAILURE it is reset to IDLE before returning.
  [[nodiscard]] Status tick() noexcept {
    const Status s = execute();
    if (is_completed(s)) reset_status(0);
    return s;
  }

  // Halts the whole tree, as BT::Tree::haltTree(): RUNNING leaves get
  // onHalted, every node returns to IDLE.
  void halt() noexcept {
    halt_node(0);
    for (std::size_t i = 0; i < kNodeCount; ++i) halt_node(static_cast<std::uint16_t>(i));
    reset_status(0);
  }

  [[nodiscard]] Status status() const noexcept { return status_[0]; }
  [[nodiscard]] Status status(std::size_t index) const noexcept { return status_[index]; }

  [[nodiscard]] static constexpr std::size_t node_count() noexcept { return kNodeCount; }
  [[nodiscard]] static constexpr const NodeInfo& node(std::size_t index) noexcept { return Spec::kNodes[index]; }
  [[nodiscard]] static constexpr const std::array<NodeInfo, kNodeCount>& nodes() noexcept { return Spec::kNodes; }

  [[nodiscard]] Leaves& leaves() noexcept { return *leaves_; }
  // The mission's typed blackboard: one btgen::Slot member per entry.
  [[nodiscard]] Blackboard& blackboard() noexcept { return bb_; }
  [[nodiscard]] const Blackboard& blackboard() const noexcept { return bb_; }
  // How many run-time errors were reported so far (each failed its node).
  [[nodiscard]] std::uint64_t errors() const noexcept { return errors_; }
  // What the object's size is made of: the nodes' state (statuses, counters,
  // timers, Parallel flags, the interpreter's and halts' stacks: all of it
  // sized by the tree) and the blackboard (its entries); the rest is a few
  // words (leaves, clock, observer, error count).
  [[nodiscard]] static constexpr std::size_t node_state_bytes() noexcept {
    return sizeof(status_) + sizeof(counters_) + sizeof(timers_) + sizeof(done_) + sizeof(stack_) + sizeof(halt_stack_);
  }
  [[nodiscard]] static constexpr std::size_t blackboard_bytes() noexcept { return sizeof(Blackboard); }
  [[nodiscard]] Clock& clock() noexcept { return clock_; }
  [[nodiscard]] const Clock& clock() const noexcept { return clock_; }
  [[nodiscard]] Observer& observer() noexcept { return observer_; }

 private:
  // ------------------------------------------------------------- data side
  static void report(void* context, const RuntimeError& error) noexcept {
    auto* self = static_cast<Engine*>(context);
    ++self->errors_;
    if constexpr (engine_detail::has_on_error<Observer>::value) self->observer_.on_error(error);
  }
  [[nodiscard]] ErrorSink sink() noexcept { return ErrorSink(&Engine::report, this); }

  // A compiled script of node `n`: 1 or 0 (a condition's truth; 1 for
  // other scripts), -1 after an error was reported.
  int run_script(const NodeInfo& n, ScriptSlot which) noexcept {
    const ErrorSink es = sink();
    return Spec::script(bb_, n, es, which);
  }
  static constexpr bool has(const NodeInfo& n, ScriptSlot which) noexcept {
    return (n.scripts & script_bit(which)) != 0;
  }
  // The script bits any node of the mission has: a mission without pre- or
  // post-conditions compiles their checks away.
  static constexpr std::uint16_t mission_scripts() noexcept {
    std::uint16_t bits = 0;
    for (const NodeInfo& n : Spec::kNodes) bits = static_cast<std::uint16_t>(bits | n.scripts);
    return bits;
  }
  static constexpr std::uint16_t kMissionScripts = mission_scripts();
  // Whether a node applies the wake-up rule (needs Frame::child_prev, the
  // status its child had before this tick): else that read is compiled away.
  static constexpr bool mission_wakes_up() noexcept {
    for (const NodeInfo& n : Spec::kNodes) {
      if (n.kind == NodeKind::AsyncSequence || n.kind == NodeKind::SequenceWithMemory ||
          n.kind == NodeKind::AsyncFallback || n.kind == NodeKind::Repeat || n.kind == NodeKind::RetryUntilSuccessful) {
        return true;
      }
    }
    return false;
  }
  static constexpr bool kWakeUp = mission_wakes_up();
  // Whether a TryCatch may tick its catch child inside its halt (catch_on_halt="true" or
  // `{key}`: NodeInfo p0 or p1): else halts never tick and that code is compiled away.
  static constexpr bool mission_catches_on_halt() noexcept {
    for (const NodeInfo& n : Spec::kNodes) {
      if (n.kind == NodeKind::TryCatch && (n.p0 != 0 || n.p1 != 0)) return true;
    }
    return false;
  }
  static constexpr bool kCatchOnHalt = mission_catches_on_halt();
  static constexpr std::uint16_t kPreBits =
      static_cast<std::uint16_t>(script_bit(ScriptSlot::kFailureIf) | script_bit(ScriptSlot::kSuccessIf) |
                                 script_bit(ScriptSlot::kSkipIf) | script_bit(ScriptSlot::kWhile));
  static constexpr std::uint16_t kPostBits = static_cast<std::uint16_t>(
      script_bit(ScriptSlot::kOnSuccess) | script_bit(ScriptSlot::kOnFailure) | script_bit(ScriptSlot::kPost));

  // TreeNode::checkPreConditions (4.6.2): all of them from IDLE, in the
  // order _failureIf, _successIf, _skipIf, _while; only _while when
  // RUNNING, which halts the node when false. IDLE: no decision, tick it.
  Status pre_conditions(std::uint16_t id, const NodeInfo& n) noexcept {
    const Status st = status_[id];
    if (st == Status::IDLE) {
      constexpr ScriptSlot kOrder[] = {ScriptSlot::kFailureIf, ScriptSlot::kSuccessIf, ScriptSlot::kSkipIf,
                                       ScriptSlot::kWhile};
      constexpr Status kDecides[] = {Status::FAILURE, Status::SUCCESS, Status::SKIPPED, Status::IDLE};
      for (std::size_t k = 0; k < 4; ++k) {
        if (!has(n, kOrder[k])) continue;
        const int r = run_script(n, kOrder[k]);
        if (r < 0) return Status::FAILURE;
        if (kOrder[k] == ScriptSlot::kWhile) {
          if (r == 0) return Status::SKIPPED;
        } else if (r == 1) {
          return kDecides[k];
        }
      }
    } else if (st == Status::RUNNING && has(n, ScriptSlot::kWhile)) {
      const int r = run_script(n, ScriptSlot::kWhile);
      if (r <= 0) {
        halt_node(id);
        return r < 0 ? Status::FAILURE : Status::SKIPPED;
      }
    }
    return Status::IDLE;
  }

  // TreeNode::checkPostConditions: _onSuccess or _onFailure, then _post. A
  // script that fails makes the node fail.
  Status post_conditions(const NodeInfo& n, Status s) noexcept {
    bool ok = true;
    if (s == Status::SUCCESS && has(n, ScriptSlot::kOnSuccess)) ok = run_script(n, ScriptSlot::kOnSuccess) >= 0;
    if (s == Status::FAILURE && has(n, ScriptSlot::kOnFailure)) ok = run_script(n, ScriptSlot::kOnFailure) >= 0;
    if (ok && has(n, ScriptSlot::kPost)) ok = run_script(n, ScriptSlot::kPost) >= 0;
    return ok ? s : Status::FAILURE;
  }

  // A user hook that reported an error (a port write that failed) fails its node.
  Status guarded(Status s, std::uint64_t errors_before) const noexcept {
    return errors_ == errors_before ? sanitize(s) : Status::FAILURE;
  }

  // One node being ticked. `pos` is the child position it is working on,
  // `aux` a per-tick local (skipped count, "all skipped" flag), `child_prev`
  // the status the child had before this tick (the wake-up rule needs it).
  struct Frame {
    std::uint16_t node;
    std::uint16_t pos;
    std::uint16_t aux;
    Status child_prev;
    std::uint8_t decorator;  // 1: a decorator (finish() resets its completed child)
  };
  struct HaltFrame {
    std::uint16_t node;
    std::uint16_t pos;
  };
  // Either "tick child `child` next" or "return `status`".
  struct Step {
    std::uint16_t child;
    Status status;
  };

  static constexpr Step descend(std::uint16_t c) noexcept { return Step{c, Status::IDLE}; }
  static constexpr Step done(Status s) noexcept { return Step{kNoNode, s}; }

  static constexpr const NodeInfo& info(std::size_t n) noexcept { return Spec::kNodes[n]; }
  // The i-th child of `n` (i < n.child_count). The index is clamped only in
  // tiny child tables: there it keeps g++ -O2 from warning (-Warray-bounds)
  // about a branch for a third child it cannot prove dead when the whole
  // mission has exactly two parent-to-child edges; in larger ones the clamp
  // cost 10 instructions per visited node (bench/missions/balanced_1000.xml).
  static constexpr std::uint16_t child(const NodeInfo& n, std::size_t i) noexcept {
    constexpr std::size_t size = Spec::kChildren.size();
    if constexpr (size == 0) {
      (void)n;
      (void)i;
      return kNoNode;
    } else if constexpr (size <= 16) {
      const std::size_t k = std::size_t{n.child_begin} + i;
      return Spec::kChildren[k < size ? k : size - 1];
    } else {
      return Spec::kChildren.data()[std::size_t{n.child_begin} + i];
    }
  }
  std::int32_t& counter(const NodeInfo& n, std::size_t k) noexcept { return counters_[n.slot + k]; }

  // A Repeat's or RetryUntilSuccessful's count, a Timeout's, Delay's or Sleep's duration given
  // as `{key}` (NodeInfo p1 is 1): Spec::read_param reads the entry when 4.6.2's node calls
  // getInput, and the value in use lives in the counter after the node's own (lower.py
  // PARAM_NODES); an unsigned duration keeps its bits there.
  static constexpr std::size_t param_counter(NodeKind k) noexcept {
    return k == NodeKind::Delay ? 1 : k == NodeKind::Sleep ? 0 : 2;
  }
  // Reads it (false after reporting the error to `es`); `keep`: the value becomes the one in use.
  bool read_param(const NodeInfo& n, bool keep, const ErrorSink& es) noexcept {
    if (n.p1 == 0) return true;
    std::int64_t v = 0;
    if (Spec::read_param(bb_, es, n, v) < 0) return false;
    if (keep) counter(n, param_counter(n.kind)) = static_cast<std::int32_t>(static_cast<std::uint32_t>(v));
    return true;
  }
  bool read_param(const NodeInfo& n, bool keep) noexcept { return read_param(n, keep, sink()); }
  // Reads it where the library ignores getInput's error (RetryUntilSuccessful's re-read after a
  // failure, 4.7.0 and later): a value that reads becomes the one in use, else nothing changes.
  void reread_param(const NodeInfo& n) noexcept {
    (void)read_param(n, true, ErrorSink([](void*, const RuntimeError&) noexcept {}, nullptr));
  }
  std::int64_t max_cycles(const NodeInfo& n) noexcept { return n.p1 != 0 ? counter(n, 2) : param::max_cycles(n); }
  std::int64_t duration_ms(const NodeInfo& n) noexcept {
    return n.p1 != 0 ? static_cast<std::int64_t>(static_cast<std::uint32_t>(counter(n, param_counter(n.kind))))
                     : param::duration_ms(n);
  }
  std::uint64_t& timer(const NodeInfo& n) noexcept { return timers_[n.timer]; }
  std::uint64_t elapsed(const NodeInfo& n) noexcept { return clock_.now_ms() - timers_[n.timer]; }
  static constexpr bool reached(std::uint64_t elapsed_ms, std::int64_t limit) noexcept {
    return limit <= 0 || elapsed_ms >= static_cast<std::uint64_t>(limit);
  }

  // ------------------------------------------------------------- statuses
  void set_status(std::size_t n, Status s) noexcept {
    const Status prev = status_[n];
    status_[n] = s;
    if (prev != s) observer_.on_status_change(info(n), prev, s);
  }
  void reset_status(std::size_t n) noexcept { set_status(n, Status::IDLE); }

  // A status the observer forces on node `id` instead of its tick (Groot2's REPLACE hook,
  // 4.6.2's pre-tick callback: asked after the pre-conditions, only when the node is not
  // completed; SUCCESS or FAILURE replaces tick(), which is not called, and nothing is
  // halted), or IDLE: tick it. Observers without forced_status() compile this away.
  // Each visit tests observer_.hooked(id) inline (a null test and a relaxed load); the
  // rest is out of line and cold, so that the straight-line code grows as little as it
  // can (g++ inlines less in larger functions: docs/groot2.md has the measured cost).
  static constexpr bool kHooks = engine_detail::has_forced_status<Observer>::value;
  [[gnu::noinline, gnu::cold]] Status forced_slow(std::size_t id) noexcept {
    if constexpr (kHooks) {
      if (!is_completed(status_[id])) return observer_.forced_status(info(id));
    }
    (void)id;
    return Status::IDLE;
  }
  // 4.10.0's post-tick callback (Sem::groot2_post_hooks; Groot2's POST hooks): asked on
  // each visit after the node's tick and post-conditions, whatever it returned (a
  // pre-condition's or a PRE hook's result too), before its status is set; SUCCESS or
  // FAILURE replaces the result. The same inline test as hooked(), on a second table;
  // 4.6.2 missions compile it away.
  static constexpr bool kPostHooks = Sem::groot2_post_hooks && engine_detail::has_post_forced_status<Observer>::value;
  [[gnu::always_inline]] Status post_hook(std::size_t id, Status s) noexcept {
    if constexpr (kPostHooks) {
      if (__builtin_expect(observer_.post_hooked(id), 0)) return post_slow(id, s);
    }
    (void)id;
    return s;
  }
  [[gnu::noinline, gnu::cold]] Status post_slow(std::size_t id, Status s) noexcept {
    if constexpr (kPostHooks) {
      const Status h = observer_.post_forced_status(info(id));
      if (h != Status::IDLE) return h;
    }
    (void)id;
    return s;
  }
  // A node without pre- or post-conditions replaced by its hook: its status set (after its
  // POST hook, 4.10.0), a decorator's completed child reset (DecoratorNode::executeTick), as
  // finish() does.
  [[gnu::noinline, gnu::cold]] Status replaced(std::size_t id) noexcept {
    Status h = forced_slow(id);
    if (h != Status::IDLE) {
      h = post_hook(id, h);
      set_status(id, h);
      const NodeInfo& n = info(id);
      if (is_decorator(n.kind) && n.child_count == 1 && is_completed(status_[child(n, 0)])) reset_status(child(n, 0));
    }
    return h;
  }

  // Completed-child flags of Parallel / ParallelAll, one bit per node.
  bool is_done(std::uint16_t n) const noexcept {
    if constexpr (Spec::kHasParallel) {
      return (done_[n / 32] >> (n % 32)) & 1u;
    } else {
      (void)n;
      return false;
    }
  }
  void set_done(std::uint16_t n, bool v) noexcept {
    if constexpr (Spec::kHasParallel) {
      const std::uint32_t bit = 1u << (n % 32);
      done_[n / 32] = v ? (done_[n / 32] | bit) : (done_[n / 32] & ~bit);
    } else {
      (void)n;
      (void)v;
    }
  }
  void clear_done(const NodeInfo& n) noexcept {
    for (std::size_t i = 0; i < n.child_count; ++i) set_done(child(n, i), false);
  }

  // ---------------------------------------------------------------- halts
  // ControlNode::haltChild / DecoratorNode::resetChild.
  [[gnu::always_inline]] void halt_child(const NodeInfo& n, std::size_t i) noexcept {
    const std::uint16_t c = child(n, i);
    if (status_[c] == Status::RUNNING) halt_node(c);
    reset_status(c);
  }
  // ControlNode::resetChildren.
  void reset_children(const NodeInfo& n) noexcept {
    for (std::size_t i = 0; i < n.child_count; ++i) halt_child(n, i);
  }

  // What a node's halt() clears besides its children and its status.
  void forget(const NodeInfo& n) noexcept {
    switch (n.kind) {
      case NodeKind::Sequence:
      case NodeKind::AsyncSequence:
      case NodeKind::Fallback:
      case NodeKind::AsyncFallback:
        counter(n, 0) = 0;
        counter(n, 1) = 0;
        break;
      case NodeKind::Parallel:
        counter(n, 0) = 0;
        counter(n, 1) = 0;
        clear_done(n);
        break;
      case NodeKind::ParallelAll:
        counter(n, 0) = 0;
        clear_done(n);
        break;
      case NodeKind::IfThenElse:
      case NodeKind::Repeat:
      case NodeKind::RetryUntilSuccessful:
      case NodeKind::Delay: counter(n, 0) = 0; break;
      case NodeKind::Timeout:
        counter(n, 0) = 0;
        counter(n, 1) = 0;
        break;
      case NodeKind::TryCatch:
        // (halt_begin decides first whether the halt ticks the catch child)
        counter(n, 0) = 0;
        counter(n, 1) = 0;
        counter(n, 2) = 0;
        break;
      case NodeKind::PipelineSequence: counter(n, 0) = 0; break;
      case NodeKind::RecoveryNode:
      case NodeKind::RoundRobin:
        counter(n, 0) = 0;
        counter(n, 1) = 0;
        break;
      case NodeKind::Switch:             // no case RUNNING
      case NodeKind::SkipUnlessUpdated:  // child no longer executing (its update counter is kept)
      case NodeKind::WaitValueUpdate: counter(n, 0) = 0; break;
      default:  // SequenceWithMemory keeps its index, RunOnce its memory (as 4.6.2)
        break;
    }
  }

  // TryCatch's counter 2 while its halt has still to tick the catch child (1: in the catch child).
  static constexpr std::int32_t kCatchPending = 2;

  // The start of a node's halt(): forget, and for a TryCatch (4.9.0) whether this halt ticks
  // its catch child: catch_on_halt true when halt() reads it, the node active and not in its
  // catch child already. TryCatchNode::halt() resets its try children, ticks the catch child
  // (halting it when it answers RUNNING), then resets it as ControlNode::halt() does.
  void halt_begin(const NodeInfo& n) noexcept {
    if constexpr (kCatchOnHalt) {
      if (n.kind == NodeKind::TryCatch) {
        const bool catches = catch_on_halt(n) && counter(n, 2) == 0 && is_active(status_[n.index]);
        forget(n);
        if (catches) counter(n, 2) = kCatchPending;
        return;
      }
    }
    forget(n);
  }
  // catch_on_halt as TryCatchNode::halt() reads it: a literal, or getInput<bool> of the entry
  // (false when that fails: the generated read_param keeps the port's default).
  bool catch_on_halt(const NodeInfo& n) noexcept {
    if (n.p1 == 0) return param::catch_on_halt(n);
    std::int64_t v = 0;
    const ErrorSink es = sink();
    return Spec::read_param(bb_, es, n, v) > 0 && v != 0;
  }
  // A node's depth (the root's is 0). While a catch child ticks inside a halt, the ticks and
  // halts it causes keep their frames at the depths of their nodes (execute_at's frame of a
  // node is at its depth or above, halt_node's at its depth): the frames of the ticks and
  // halts in progress, all of them the catch child's ancestors', stay untouched.
  static std::size_t depth(std::uint16_t node) noexcept {
    std::size_t d = 0;
    for (std::uint16_t p = info(node).parent; p != kNoNode; p = info(p).parent) ++d;
    return d;
  }

  // TreeNode::haltNode, depth first over the RUNNING part of the subtree:
  // children in order (RUNNING ones halted first), then the node itself.
  void halt_node(std::uint16_t root) noexcept {
    std::size_t base = 0;
    if constexpr (kCatchOnHalt) base = depth(root);
    std::size_t hp = base;
    halt_begin(info(root));
    halt_stack_[hp++] = HaltFrame{root, 0};
    while (hp > base) {
      HaltFrame& h = halt_stack_[hp - 1];
      const NodeInfo& n = info(h.node);
      if (h.pos < n.child_count) {
        if constexpr (kCatchOnHalt) {
          if (n.kind == NodeKind::TryCatch && h.pos + 1u == n.child_count && counter(n, 2) == kCatchPending) {
            // The try children are reset: the catch child's tick, then the catch child
            // (halted when RUNNING, else reset) as any child below.
            counter(n, 2) = 0;
            const std::uint16_t c = child(n, h.pos);
            (void)execute_at(c, depth(c));
            continue;
          }
        }
        const std::uint16_t c = child(n, h.pos++);
        if (status_[c] == Status::RUNNING) {
          halt_begin(info(c));
          halt_stack_[hp++] = HaltFrame{c, 0};
        } else {
          reset_status(c);
        }
        continue;
      }
      if (n.kind == NodeKind::Action && status_[h.node] == Status::RUNNING) {
        const ErrorSink es = sink();
        Hooks::on_halted(*leaves_, bb_, es, n);
      } else if (n.kind == NodeKind::UserControl || n.kind == NodeKind::UserDecorator) {
        // ControlNode::halt() / DecoratorNode::halt(): the children were halted above; the
        // user's halt() hook resets the node's own state.
        const ErrorSink es = sink();
        Hooks::user_halt(*leaves_, bb_, es, n, ChildOps(&kChildOps, this, &n, 0));
      }
      reset_status(h.node);
      // TreeNode::haltNode runs _onHalted after halt().
      if (has(n, ScriptSlot::kOnHalted)) (void)run_script(n, ScriptSlot::kOnHalted);
      --hp;
    }
  }

  // ---------------------------------------------------------------- ticks
  // TreeNode::executeTick of the root: straight-line code (tick_node) as far
  // as the budget goes, the table interpreter (execute_at) below.
  // enter, resume, finish, sequence_next and halt_child are forced inline
  // ([[gnu::always_inline]]): called once or more per node per tick, as
  // separate functions they cost a call and a save of the callee-saved
  // registers each time (bench/run_benchmarks.py: 120 -> 78.5 instructions
  // per node on bench/missions/balanced_1000.xml with g++ 12 -O2).
  Status execute() noexcept {
    if constexpr (kStraightLine == 0) {
      return execute_at(0, 0);
    } else {
      return tick_node<shape_of(0)>(0);
    }
  }

  // ------------------------------------------------------- compiled ticks
  // tick_node<S>(id) is executeTick of node `id`, whose shape is S, as
  // straight-line code: the same begin / enter / resume / finish as the
  // interpreter, with the node's kind, model, scripts, parameters and
  // children (their shapes, their offsets from `id`) known when compiling,
  // so that g++ folds every branch of other kinds away and calls its
  // children's tick_node directly. Nodes of one shape (Spec::kShape: equal
  // subtrees, e.g. the instances of one SubTree) share the function; their
  // state stays where the interpreter keeps it (status_, counters_, timers_:
  // halts and the user nodes' ChildOps read it there), found from `id` and
  // its table row. The generator gives nodes at kCompiledDepth and below a
  // shape of their own that runs on the interpreter, which also takes the
  // mission's own Controls and Decorators (their children run on the
  // explicit stack, ChildOps) and the shapes beyond the budget.
  static constexpr std::size_t kCompiledDepth = 48;  // generator/btgen/backend_cpp/shapes.py
  static constexpr bool kShaped = engine_detail::has_shapes<Spec>::value;
  static constexpr std::size_t straight_line_budget = engine_detail::straight_line_budget<Spec>::value;
  // A node's weight against the budget (1, or 6 when it runs scripts, plus its children's
  // call sites) is summed by the generator (shapes.py): Spec::kTotalWeight, kRepWeightBefore.
  // A mission whose every node fits in the budget gets a function per node
  // (a shape per node: its index and its state's places are constants, the
  // fastest form); a larger one shares the functions of equal subtrees.
  static constexpr bool per_node() noexcept {
    if constexpr (!kShaped) {
      return false;
    } else {
      return Spec::kTotalWeight <= straight_line_budget;
    }
  }
  static constexpr bool kPerNode = per_node();
  static constexpr std::uint16_t shape_of(std::size_t i) noexcept {
    if constexpr (kPerNode) {
      return static_cast<std::uint16_t>(i);
    } else {
      return Spec::kShape[i];
    }
  }
  // The first node of shape s (kNoNode: a node below the compiled depth).
  static constexpr std::uint16_t rep_of(std::uint16_t s) noexcept {
    if constexpr (kPerNode) {
      return Spec::kShapeRep[Spec::kShape[s]] == kNoNode ? kNoNode : s;
    } else {
      return Spec::kShapeRep[s];
    }
  }
  static constexpr std::size_t uses_of(std::uint16_t s) noexcept {
    if constexpr (kPerNode) {
      (void)s;
      return 1;
    } else {
      return Spec::kShapeUses[s];
    }
  }
  // The shapes first met below this index tick as straight-line code
  // (BTGEN_STRAIGHT_LINE_BUDGET counts the nodes of distinct shapes). A Spec
  // without shape tables runs on the interpreter.
  static constexpr std::size_t straight_line_nodes() noexcept {
    if constexpr (!kShaped) {
      return 0;
    } else if constexpr (kPerNode) {
      return kNodeCount;
    } else {
      // The first node of a compiled shape whose predecessors (Spec::kRepNode, in creation
      // order) weigh the budget or more: a binary search of the generator's running sums (a
      // loop over 65,535 nodes would pass clang's constant-evaluation step limit).
      std::size_t lo = 0;
      std::size_t hi = Spec::kRepNode.size();
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (Spec::kRepWeightBefore[mid] >= straight_line_budget) {
          hi = mid;
        } else {
          lo = mid + 1;
        }
      }
      return lo < Spec::kRepNode.size() ? Spec::kRepNode[lo] : kNodeCount;
    }
  }
  static constexpr std::size_t kStraightLine = straight_line_nodes();
  // Whether any node runs on the table interpreter (execute_at and its
  // stack): a shape beyond the budget or below the compiled depth, or the
  // mission's own Controls and Decorators (their children run there). When
  // none does, the interpreter's stack takes no room.
  static constexpr bool uses_interpreter() noexcept {
    if constexpr (!kShaped) {
      return true;
    } else {
      // (a catch child ticked inside a halt runs there too)
      return kStraightLine < kNodeCount || Spec::kHasDeepShape || Spec::kHasUserControlFlow || kCatchOnHalt;
    }
  }
  static constexpr bool kUsesInterpreter = uses_interpreter();
  // Children ticked through a table of member-function pointers above this
  // many (else a chain of comparisons of the position).
  static constexpr std::size_t kDirectChildren = 8;
  // Sequences and the like with more children take the generic form (clang
  // limits a fold expression to 256 operands).
  static constexpr std::size_t kInRow = 64;

  static constexpr std::uint16_t child_of(std::uint16_t n, std::size_t i) noexcept {
    return Spec::kChildren[std::size_t{Spec::kNodes[n].child_begin} + i];
  }
  // Child I of a node whose shape's first node is R: its shape, its offset
  // from the node. (The helpers below are few and shared, not one per shape
  // and child: g++'s time per straight-line shape grew with their number.)
  template <std::uint16_t R, std::size_t I>
  static constexpr std::uint16_t kChildShape = shape_of(child_of(R, I));
  template <std::uint16_t R, std::size_t I>
  static constexpr std::size_t kChildOffset = child_of(R, I) - R;
  // ControlNode::haltChild of node `c`.
  [[gnu::always_inline]] void halt_child_id(std::size_t c) noexcept {
    if (status_[c] == Status::RUNNING) halt_node(static_cast<std::uint16_t>(c));
    reset_status(c);
  }

  template <NodeKind K>
  [[gnu::always_inline]] Step begin_k(Frame& f) noexcept {
    return begin(f, K);
  }
  template <NodeKind K>
  [[gnu::always_inline]] Step resume_k(Frame& f, Status cs) noexcept {
    return resume(f, cs, K);
  }

  // Which straight-line form shape S takes.
  enum class Form { kInterpreted, kGeneric, kLeaf, kScripted, kSequence, kReactive, kDecorator };
  static constexpr bool kScriptTable = engine_detail::has_script_table<Spec>::value;
  // Leaves whose scripts (Script, ScriptCondition, pre- and post-conditions) the
  // straight-line code calls directly (Form::kScripted).
  static constexpr bool is_scripted_leaf(NodeKind k) noexcept {
    return k == NodeKind::Action || k == NodeKind::Condition || k == NodeKind::AlwaysSuccess ||
           k == NodeKind::AlwaysFailure || k == NodeKind::Script || k == NodeKind::ScriptCondition;
  }
  template <std::uint16_t S>
  static constexpr Form form() noexcept {
    constexpr std::uint16_t R = rep_of(S);
    if (R == kNoNode || R >= kStraightLine) return Form::kInterpreted;
    constexpr const NodeInfo& n = Spec::kNodes[R == kNoNode ? 0 : R];  // (row 0 unused then)
    if (n.kind == NodeKind::UserControl || n.kind == NodeKind::UserDecorator || is_nav2(n.kind)) {
      return Form::kInterpreted;
    }
    if (kScriptTable && n.child_count == 0 && is_scripted_leaf(n.kind) &&
        ((n.scripts & (kPreBits | kPostBits)) != 0 || n.kind == NodeKind::Script ||
         n.kind == NodeKind::ScriptCondition)) {
      return Form::kScripted;
    }
    if ((n.scripts & (kPreBits | kPostBits)) != 0) return Form::kGeneric;
    if (n.child_count == 0) {
      switch (n.kind) {
        case NodeKind::Action:
        case NodeKind::Condition:
        case NodeKind::AlwaysSuccess:
        case NodeKind::AlwaysFailure: return Form::kLeaf;
        default: return Form::kGeneric;
      }
    }
    if (n.child_count > kInRow) return Form::kGeneric;
    switch (n.kind) {
      case NodeKind::Sequence:
      case NodeKind::Fallback: return Form::kSequence;
      case NodeKind::ReactiveSequence:
      case NodeKind::ReactiveFallback: return Form::kReactive;
      case NodeKind::Inverter:
      case NodeKind::ForceSuccess:
      case NodeKind::ForceFailure:
      case NodeKind::SubTree: return Form::kDecorator;  // one child, ticked once
      default: return Form::kGeneric;
    }
  }

  template <std::uint16_t S>
  Status tick_node(std::size_t id) noexcept {
    constexpr Form kForm = form<S>();
    if constexpr (kForm == Form::kInterpreted) {
      return execute_at(static_cast<std::uint16_t>(id), 0);
    } else {
      constexpr std::uint16_t R = rep_of(S);
      // A shape of one node: its index, its row and its state's places are constants.
      if constexpr (uses_of(S) == 1) id = R;
      constexpr NodeKind K = Spec::kNodes[R].kind;
      using Children = std::make_index_sequence<Spec::kNodes[R].child_count>;
      if constexpr (kHooks && kForm != Form::kScripted && kForm != Form::kGeneric) {
        // (these forms have no pre- or post-conditions: the hook comes first)
        if (__builtin_expect(observer_.hooked(id), 0)) {
          const Status h = replaced(id);
          if (h != Status::IDLE) return h;
        }
      }
      if constexpr (kForm == Form::kSequence) {
        return tick_sequence<R, K == NodeKind::Sequence>(id, Children{});
      } else if constexpr (kForm == Form::kReactive) {
        return tick_reactive<R, K == NodeKind::ReactiveSequence>(id, Children{});
      } else if constexpr (kForm == Form::kDecorator) {
        // Inverter, ForceSuccess, ForceFailure, SubTree: enter, resume and finish above.
        const std::size_t c = id + kChildOffset<R, 0>;
        if constexpr (K == NodeKind::SubTree) {
          if (status_[id] == Status::IDLE) set_status(id, Status::RUNNING);
        } else {
          set_status(id, Status::RUNNING);
        }
        return decorated<K>(id, c, tick_node<kChildShape<R, 0>>(c));
      } else if constexpr (kForm == Form::kLeaf) {
        return tick_leaf<K, Spec::kNodes[R].model>(id);
      } else if constexpr (kForm == Form::kScripted) {
        return tick_scripted<R>(id);
      } else {
        Frame f{static_cast<std::uint16_t>(id), 0, 0, Status::IDLE, 0};
        Step step = begin_k<K>(f);
        while (step.child != kNoNode) {
          if constexpr (kWakeUp) f.child_prev = status_[step.child];
          const Status cs = tick_child<R>(id, f.pos, Children{});
          step = resume_k<K>(f, cs);
        }
        return finish(f, step.status);
      }
    }
  }

  // Action, Condition, AlwaysSuccess and AlwaysFailure without pre- or
  // post-conditions: enter and finish above for these kinds, the model's
  // hook called directly. (Written out, not enter and finish folded: g++
  // spent most of a straight-line node's compile time inlining the whole of
  // enter and folding it away.)
  template <NodeKind K, std::uint16_t kModel>
  [[gnu::always_inline]] Status tick_leaf(std::size_t id) noexcept {
    const Status s = post_hook(id, leaf_status<K, kModel>(id));
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }

  // What a leaf answers when its pre-conditions did not decide (enter, for these kinds).
  template <NodeKind K, std::uint16_t kModel>
  [[gnu::always_inline]] Status leaf_status(std::size_t id) noexcept {
    Status s = Status::FAILURE;
    if constexpr (K == NodeKind::AlwaysSuccess) {
      s = Status::SUCCESS;
    } else if constexpr (K == NodeKind::Action || K == NodeKind::Condition) {
      const NodeInfo& n = info(id);
      const Status st = status_[id];
      if (K == NodeKind::Action && st != Status::IDLE && st != Status::RUNNING && !Hooks::sync_action(n)) {
        s = st;
      } else {
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        if constexpr (K == NodeKind::Condition) {
          s = guarded(Hooks::template check_m<kModel>(*leaves_, bb_, es, n), before);
        } else {
          s = guarded(st == Status::IDLE ? Hooks::template on_start_m<kModel>(*leaves_, bb_, es, n)
                                         : Hooks::template on_running_m<kModel>(*leaves_, bb_, es, n),
                      before);
        }
      }
    }
    return s;
  }

  // A leaf with scripts (Script, ScriptCondition, or pre- and post-conditions):
  // begin, enter and finish above for these kinds, every script a direct call
  // of its function (the same for every node of the shape; the node's own error
  // sites are found from `id`).
  template <std::uint16_t R>
  Status tick_scripted(std::size_t id) noexcept {
    constexpr NodeKind K = Spec::kNodes[R].kind;
    constexpr std::uint16_t kBits = Spec::kNodes[R].scripts;
    Status s = Status::IDLE;
    if constexpr ((kBits & kPreBits) != 0) s = pre_conditions_c<R>(id);
    if constexpr (kHooks) {
      if (s == Status::IDLE && __builtin_expect(observer_.hooked(id), 0)) s = forced_slow(id);
    }
    if (s == Status::IDLE) {
      if constexpr (K == NodeKind::Script) {
        s = script_c<R, ScriptSlot::kCode>(id) < 0 ? Status::FAILURE : Status::SUCCESS;
      } else if constexpr (K == NodeKind::ScriptCondition) {
        s = script_c<R, ScriptSlot::kCode>(id) == 1 ? Status::SUCCESS : Status::FAILURE;
      } else {
        s = leaf_status<K, Spec::kNodes[R].model>(id);
      }
    }
    if constexpr ((kBits & kPostBits) != 0) {
      if (is_completed(s)) {
        bool ok = true;
        if constexpr (has_c<R>(ScriptSlot::kOnSuccess)) {
          if (s == Status::SUCCESS) ok = script_c<R, ScriptSlot::kOnSuccess>(id) >= 0;
        }
        if constexpr (has_c<R>(ScriptSlot::kOnFailure)) {
          if (s == Status::FAILURE) ok = script_c<R, ScriptSlot::kOnFailure>(id) >= 0;
        }
        if constexpr (has_c<R>(ScriptSlot::kPost)) {
          if (ok) ok = script_c<R, ScriptSlot::kPost>(id) >= 0;
        }
        if (!ok) s = Status::FAILURE;
      }
    }
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }

  template <std::uint16_t R>
  static constexpr bool has_c(ScriptSlot which) noexcept {
    return has(Spec::kNodes[R], which);
  }
  // Where node R's script for `which` sits among its sites (ScriptSlot order).
  template <std::uint16_t R, ScriptSlot W>
  static constexpr std::uint32_t site_of() noexcept {
    for (std::uint32_t i = Spec::kScriptFirst[R]; i < Spec::kScriptFirst[R + 1u]; ++i) {
      if (Spec::kScripts[i].which == W) return i - Spec::kScriptFirst[R];
    }
    return 0;
  }
  // run_script of a node of shape R (first node R): the function is a constant.
  template <std::uint16_t R, ScriptSlot W>
  [[gnu::always_inline]] int script_c(std::size_t id) noexcept {
    constexpr std::uint32_t k = site_of<R, W>();
    constexpr auto fn = Spec::kScripts[Spec::kScriptFirst[R] + k].fn;
    const ErrorSink es = sink();
    return fn(bb_, info(id), es, Spec::kScripts[Spec::kScriptFirst[id] + k]);
  }
  // pre_conditions with the node's scripts known when compiling.
  template <std::uint16_t R>
  [[gnu::always_inline]] Status pre_conditions_c(std::size_t id) noexcept {
    const Status st = status_[id];
    if (st == Status::IDLE) {
      if constexpr (has_c<R>(ScriptSlot::kFailureIf)) {
        const int r = script_c<R, ScriptSlot::kFailureIf>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 1) return Status::FAILURE;
      }
      if constexpr (has_c<R>(ScriptSlot::kSuccessIf)) {
        const int r = script_c<R, ScriptSlot::kSuccessIf>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 1) return Status::SUCCESS;
      }
      if constexpr (has_c<R>(ScriptSlot::kSkipIf)) {
        const int r = script_c<R, ScriptSlot::kSkipIf>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 1) return Status::SKIPPED;
      }
      if constexpr (has_c<R>(ScriptSlot::kWhile)) {
        const int r = script_c<R, ScriptSlot::kWhile>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 0) return Status::SKIPPED;
      }
    } else if constexpr (has_c<R>(ScriptSlot::kWhile)) {
      if (st == Status::RUNNING) {
        const int r = script_c<R, ScriptSlot::kWhile>(id);
        if (r <= 0) {
          halt_node(static_cast<std::uint16_t>(id));
          return r < 0 ? Status::FAILURE : Status::SKIPPED;
        }
      }
    }
    return Status::IDLE;
  }

  // The rest of a decorator's tick once its child `c` returned `cs`.
  template <NodeKind K>
  [[gnu::always_inline]] Status decorated(std::size_t id, std::size_t c, Status cs) noexcept {
    Status s = cs;
    if (is_completed(cs)) {
      halt_child_id(c);
      if constexpr (K == NodeKind::Inverter) {
        s = cs == Status::SUCCESS ? Status::FAILURE : Status::SUCCESS;
      } else if constexpr (K == NodeKind::ForceSuccess) {
        s = Status::SUCCESS;
      } else if constexpr (K == NodeKind::ForceFailure) {
        s = Status::FAILURE;
      }
    }
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    if (is_completed(status_[c])) reset_status(c);  // DecoratorNode::executeTick
    return s;
  }

  // Sequence (kSeq) and Fallback without pre- or post-conditions: enter,
  // resume and sequence_next above, with the children in a row: child I
  // ticks when the index points at it, and then the node either goes on or
  // returns (RUNNING, or the status that ends it: its children are reset
  // then, by one copy of the resets, not one per child).
  template <std::uint16_t R, bool kSeq, std::size_t... I>
  [[gnu::always_inline]] Status tick_sequence(std::size_t id, std::index_sequence<I...>) noexcept {
    // c[0]: the index; c[1]: a child did not skip (4.6.2), or the children skipped in this run
    // (Sem::skipped_by_count)
    std::int32_t* const c = &counters_[info(id).slot];
    if (!is_active(status_[id])) c[1] = 0;
    set_status(id, Status::RUNNING);
    Status s = Status::IDLE;
    if (!((c[0] == static_cast<std::int32_t>(I) &&
           sequence_step<kSeq>(tick_node<kChildShape<R, I>>(id + kChildOffset<R, I>), c, s)) ||
          ...)) {
      s = all_skipped(c[1], sizeof...(I)) ? Status::SKIPPED : (kSeq ? Status::SUCCESS : Status::FAILURE);
    }
    if (s != Status::RUNNING) {
      (halt_child_id(id + kChildOffset<R, I>), ...);
      c[0] = 0;
    }
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }
  // After the child at the index returned `cs`: true when the node returns `s`.
  template <bool kSeq>
  [[gnu::always_inline]] static bool sequence_step(Status cs, std::int32_t* c, Status& s) noexcept {
    note_skipped(c[1], cs);
    if (cs == Status::RUNNING) {
      s = Status::RUNNING;
      return true;
    }
    if (cs != Status::SKIPPED && cs != (kSeq ? Status::SUCCESS : Status::FAILURE)) {
      s = kSeq ? Status::FAILURE : Status::SUCCESS;
      return true;
    }
    ++c[0];
    return false;
  }

  // Every child of `n` but the one at `keep` halted (one loop, not one copy
  // per child of the reactive node: that grew as its children squared).
  [[gnu::noinline]] void halt_others(const NodeInfo& n, std::size_t keep) noexcept {
    for (std::size_t i = 0; i < n.child_count; ++i) {
      if (i != keep) halt_child(n, i);
    }
  }

  // ReactiveSequence (kSeq) and ReactiveFallback without pre- or post-conditions.
  template <std::uint16_t R, bool kSeq, std::size_t... I>
  [[gnu::always_inline]] Status tick_reactive(std::size_t id, std::index_sequence<I...>) noexcept {
    set_status(id, Status::RUNNING);
    bool all_skipped = true;
    Status s = Status::IDLE;
    if (!(reactive_step<kSeq>(tick_node<kChildShape<R, I>>(id + kChildOffset<R, I>), id, I, id + kChildOffset<R, I>,
                              all_skipped, s) ||
          ...)) {
      s = all_skipped ? Status::SKIPPED : (kSeq ? Status::SUCCESS : Status::FAILURE);
    }
    if (s != Status::RUNNING) (halt_child_id(id + kChildOffset<R, I>), ...);
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }
  // After child `i` (node `c`) returned `cs`: true when the node returns `s`.
  template <bool kSeq>
  [[gnu::always_inline]] bool reactive_step(Status cs, std::size_t id, std::size_t i, std::size_t c, bool& all_skipped,
                                            Status& s) noexcept {
    if (cs != Status::SKIPPED) all_skipped = false;
    if (cs == Status::RUNNING) {
      halt_others(info(id), i);
      s = Status::RUNNING;
      return true;
    }
    if (cs == (kSeq ? Status::FAILURE : Status::SUCCESS)) {
      s = cs;
      return true;
    }
    if (cs == Status::SKIPPED) halt_child_id(c);
    return false;
  }

  // The child at position `pos` of node `id` (the one begin / resume asked for).
  template <std::uint16_t R, std::size_t... I>
  [[gnu::always_inline]] Status tick_child(std::size_t id, std::size_t pos, std::index_sequence<I...>) noexcept {
    if constexpr (sizeof...(I) <= kDirectChildren) {
      Status s = Status::IDLE;
      (void)((pos == I ? (s = tick_node<kChildShape<R, I>>(id + kChildOffset<R, I>), true) : false) || ...);
      return s;
    } else {
      using Tick = Status (Engine::*)(std::size_t) noexcept;
      static constexpr Tick kTicks[] = {&Engine::template tick_node<kChildShape<R, I>>...};
      static constexpr std::uint16_t kOffsets[] = {kChildOffset<R, I>...};
      return (this->*kTicks[pos])(id + kOffsets[pos]);
    }
  }

  // executeTick of `root` on the table interpreter: for a straight-line
  // parent (base 0: no interpreter frame is live then), and for a user
  // Control/Decorator's tick_child(), on the stack above that node's frame
  // (stack_[base] on).
  Status execute_at(std::uint16_t root, std::size_t base) noexcept {
    std::size_t sp = base;
    stack_[sp++] = Frame{root, 0, 0, Status::IDLE, 0};
    Step step = begin(stack_[base], info(root).kind);
    for (;;) {
      if (step.child != kNoNode) {
        if constexpr (kWakeUp) stack_[sp - 1].child_prev = status_[step.child];
        stack_[sp++] = Frame{step.child, 0, 0, Status::IDLE, 0};
        step = begin(stack_[sp - 1], info(step.child).kind);
        continue;
      }
      const Status s = finish(stack_[sp - 1], step.status);
      if (--sp == base) return s;
      step = resume(stack_[sp - 1], s, info(stack_[sp - 1].node).kind);
    }
  }

  // ChildOps of user Controls and Decorators.
  static Status ops_tick_child(void* e, const NodeInfo& n, std::size_t i, std::size_t base) noexcept {
    if (i >= n.child_count) return Status::FAILURE;
    Engine& self = *static_cast<Engine*>(e);
    const std::uint64_t before = self.errors_;
    const Status s = self.execute_at(child(n, i), base);
    Frame& parent = self.stack_[base - 1];
    const std::uint64_t total = parent.aux + (self.errors_ - before);
    parent.aux = static_cast<std::uint16_t>(total < 0xFFFFu ? total : 0xFFFFu);
    return s;
  }
  static void ops_halt_child(void* e, const NodeInfo& n, std::size_t i) noexcept {
    if (i < n.child_count) static_cast<Engine*>(e)->halt_child(n, i);
  }
  static void ops_reset_child_status(void* e, const NodeInfo& n, std::size_t i) noexcept {
    if (i < n.child_count) static_cast<Engine*>(e)->reset_status(child(n, i));
  }
  static Status ops_child_status(const void* e, const NodeInfo& n, std::size_t i) noexcept {
    return i < n.child_count ? static_cast<const Engine*>(e)->status_[child(n, i)] : Status::IDLE;
  }
  static Status ops_status(const void* e, std::uint16_t node) noexcept {
    return static_cast<const Engine*>(e)->status_[node];
  }
  static void ops_set_status(void* e, std::uint16_t node, Status s) noexcept {
    static_cast<Engine*>(e)->set_status(node, s);
  }
  static std::uint64_t ops_now_ms(void* e) noexcept { return static_cast<Engine*>(e)->clock_.now_ms(); }
  static constexpr ChildOpsTable kChildOps{
      &Engine::ops_tick_child,   &Engine::ops_halt_child, &Engine::ops_reset_child_status,
      &Engine::ops_child_status, &Engine::ops_status,     &Engine::ops_set_status,
      &Engine::ops_now_ms};

  // Nav2's Controls and Decorators (the generator's lang/nav2.py), as the traces recorded from
  // Nav2's own plugins show them (tests/conformance/nav2). `halt_self` is the node's halt()
  // called from its own tick: the children reset, the node IDLE, its place forgotten.
  void nav2_halt_self(const NodeInfo& n, const ChildOps& ops) noexcept {
    ops.halt_children();
    ops.set_status(Status::IDLE);
    forget(n);
  }
  // setOutput of PersistentSequence's place (Spec::write_index, generated for missions that
  // have one writing an entry; a literal port is not written, as setOutput fails on it).
  void write_index(const NodeInfo& n, std::int64_t value) noexcept {
    if constexpr (engine_detail::has_write_index<Spec>::value) {
      if (n.p1 != 0) (void)Spec::write_index(bb_, sink(), n, value);
    } else {
      (void)n;
      (void)value;
    }
  }
  Status nav2_tick(const NodeInfo& n, const ChildOps& ops) noexcept {
    const auto count = static_cast<std::int32_t>(n.child_count);
    switch (n.kind) {
      case NodeKind::PipelineSequence: {
        // counter 0: the furthest child that answered RUNNING
        std::int32_t& last = counter(n, 0);
        std::int32_t skipped = 0;
        for (std::int32_t i = 0; i < count; ++i) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(i));
          if (cs == Status::FAILURE) {
            ops.halt_children();
            last = 0;
            return cs;
          }
          if (cs == Status::SKIPPED) {
            ++skipped;
          } else if (cs == Status::RUNNING && i >= last) {
            last = i;
            return cs;
          }
        }
        ops.halt_children();
        last = 0;
        return skipped == count ? Status::SKIPPED : Status::SUCCESS;
      }
      case NodeKind::RecoveryNode: {
        // counters: 0 the child being run, 1 recoveries done, 2 and 3 the `{key}` value read
        // last and whether one was (a failed read keeps it; none yet: Nav2's 1)
        std::int32_t& current = counter(n, 0);
        std::int32_t& tries = counter(n, 1);
        std::int64_t retries = param::number_of_retries(n);
        if (n.p1 != 0) {
          std::int64_t v = 0;
          if (Spec::read_param(bb_, ErrorSink([](void*, const RuntimeError&) noexcept {}, nullptr), n, v) > 0) {
            counter(n, 2) = static_cast<std::int32_t>(v);
            counter(n, 3) = 1;
          }
          retries = counter(n, 3) != 0 ? counter(n, 2) : 1;
        }
        ops.set_status(Status::RUNNING);
        while (current < 2 && tries <= retries) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(current));
          if (cs == Status::RUNNING) return cs;
          if (current == 0) {
            if (cs == Status::SKIPPED) {
              nav2_halt_self(n, ops);
              return cs;
            }
            if (cs == Status::SUCCESS) {
              ops.halt_child(1);
              nav2_halt_self(n, ops);
              return cs;
            }
            if (tries >= retries) {
              nav2_halt_self(n, ops);
              return Status::FAILURE;
            }
            ops.halt_child(0);
            current = 1;
          } else {
            if (cs == Status::SKIPPED) {
              current = 0;
              ops.halt_child(1);
              return Status::FAILURE;
            }
            if (cs == Status::FAILURE) {
              nav2_halt_self(n, ops);
              return cs;
            }
            ops.halt_child(1);
            ++tries;
            current = 0;
          }
        }
        nav2_halt_self(n, ops);
        return Status::FAILURE;
      }
      case NodeKind::RoundRobin: {
        // counters: 0 the next child, 1 failures in a row
        std::int32_t& idx = counter(n, 0);
        std::int32_t& failed = counter(n, 1);
        ops.set_status(Status::RUNNING);
        std::int32_t skipped = 0;
        while (failed + skipped < count) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(idx));
          if (cs != Status::RUNNING && ++idx == count) {
            if (param::wrap_around(n)) {
              idx = 0;
            } else {
              if (cs == Status::SKIPPED) ++skipped;
              if (cs == Status::FAILURE) ++failed;
              break;
            }
          }
          if (cs == Status::SUCCESS) {
            failed = 0;
            ops.halt_children();
            return cs;
          }
          if (cs == Status::RUNNING) return cs;
          if (cs == Status::FAILURE) ++failed;
          if (cs == Status::SKIPPED) ++skipped;
        }
        const bool all_skipped = skipped == count;
        nav2_halt_self(n, ops);
        return all_skipped ? Status::SKIPPED : Status::FAILURE;
      }
      case NodeKind::NonblockingSequence: {
        bool all_success = true;
        for (std::int32_t i = 0; i < count; ++i) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(i));
          if (cs == Status::FAILURE) {
            ops.halt_children();
            return cs;
          }
          if (cs == Status::RUNNING) {
            all_success = false;
          } else if (cs != Status::SUCCESS) {
            (void)sink().fail(n, n.source,
                              "a child returned SKIPPED, which Nav2's NonblockingSequence forbids (it throws)");
            return Status::FAILURE;
          }
        }
        if (!all_success) return Status::RUNNING;
        ops.halt_children();
        return Status::SUCCESS;
      }
      case NodeKind::PersistentSequence: {
        // Its place is the entry `current_child_idx` names: read on every tick (Nav2 throws when
        // it cannot: an error, the node fails), written after each child that completes.
        std::int64_t idx = n.p0;
        if (n.p1 != 0 && Spec::read_param(bb_, sink(), n, idx) < 0) return Status::FAILURE;
        if (idx < 0) {
          (void)sink().fail(n, n.source, "`current_child_idx` is negative: no child has that place");
          return Status::FAILURE;
        }
        ops.set_status(Status::RUNNING);
        while (idx < count) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(idx));
          if (cs == Status::RUNNING) return cs;
          if (cs == Status::FAILURE) {
            ops.halt_children();
            write_index(n, 0);
            return cs;
          }
          ++idx;
          write_index(n, idx);
        }
        ops.halt_children();
        write_index(n, 0);
        return Status::SUCCESS;
      }
      case NodeKind::RateController: {
        // counter 0: the child is ticked on this run's first tick; timer: when the period began.
        // The time since, in float seconds (Nav2's duration<float>), against the period 1/hz.
        // Timer 1 keeps the bits of hz read when the run started (a literal: NodeInfo p0; a
        // `{key}`: getInput<double>, 1.0 when it fails, as Nav2's local default).
        std::int32_t& first = counter(n, 0);
        if (!is_active(status_[n.index])) {
          timer(n) = clock_.now_ms();
          first = 1;
          std::int64_t bits = n.p0;
          if (n.p1 != 0) (void)Spec::read_param(bb_, sink(), n, bits);
          timers_[n.timer + 1] = static_cast<std::uint64_t>(bits);
        }
        ops.set_status(Status::RUNNING);
        double hz = 0.0;
        const std::uint64_t hz_bits = timers_[n.timer + 1];
        std::memcpy(&hz, &hz_bits, sizeof hz);
        const double period = 1.0 / hz;
        const auto ns = static_cast<std::int64_t>(elapsed(n)) * 1000000;
        const float seconds = static_cast<float>(ns) / 1.0e9f;
        if (first != 0 || ops.child_status(0) == Status::RUNNING || static_cast<double>(seconds) >= period) {
          first = 0;
          const Status cs = ops.tick_child(0);
          if (cs == Status::SUCCESS) timer(n) = clock_.now_ms();
          return cs;
        }
        return status_[n.index];
      }
      case NodeKind::SingleTrigger: {
        // counter 0: the child completed during this run of the node
        std::int32_t& spent = counter(n, 0);
        if (!is_active(status_[n.index])) spent = 0;
        ops.set_status(Status::RUNNING);
        if (spent != 0) return Status::FAILURE;
        const Status cs = ops.tick_child(0);
        if (cs == Status::SUCCESS || cs == Status::FAILURE) spent = 1;
        return cs;
      }
      default:
        if (is_nav2_env_node(n.kind)) {
          std::int32_t none = 0;
          std::int32_t& first = n.slot != kNoSlot ? counter(n, 0) : none;
          return nav2_env_tick(n.kind, ops, first, [&]() { return nav2_env_input(n); });
        }
        return Status::FAILURE;
    }
  }
  // The input of a Nav2 Decorator (btgen/nav2.hpp): Leaves' answer, yes or no.
  bool nav2_env_input(const NodeInfo& n) noexcept {
    const Status s = nav2_input(*leaves_, n);
    if (s != Status::SUCCESS && s != Status::FAILURE) {
      (void)sink().fail(n, n.source, "the input of this Nav2 Decorator is SUCCESS (yes) or FAILURE (no)");
    }
    return s == Status::SUCCESS;
  }

  // The start of executeTick: the pre-conditions may decide instead of tick().
  [[gnu::always_inline]] Step begin(Frame& f, NodeKind kind) noexcept {
    const NodeInfo& n = info(f.node);
    if ((kMissionScripts & kPreBits) != 0 && (n.scripts & kPreBits) != 0) {
      const Status decided = pre_conditions(f.node, n);
      if (decided != Status::IDLE) {
        f.decorator = is_decorator(kind) ? 1 : 0;
        return done(decided);
      }
    }
    if constexpr (kHooks) {
      const Status h = __builtin_expect(observer_.hooked(f.node), 0) ? forced_slow(f.node) : Status::IDLE;
      if (h != Status::IDLE) {
        f.decorator = is_decorator(kind) ? 1 : 0;
        return done(h);
      }
    }
    return enter(f, kind);
  }

  // The end of executeTick: the post-conditions of a completed node; a
  // SKIPPED node keeps its status; a decorator resets a child left
  // completed (DecoratorNode::executeTick). Returns the node's result.
  [[gnu::always_inline]] Status finish(const Frame& f, Status s) noexcept {
    const std::uint16_t node = f.node;
    const NodeInfo& n = info(node);
    if ((kMissionScripts & kPostBits) != 0 && (n.scripts & kPostBits) != 0 && is_completed(s)) {
      s = post_conditions(n, s);
    }
    s = post_hook(node, s);
    if (s != Status::SKIPPED) set_status(node, s);
    if (f.decorator != 0) {
      const std::uint16_t c = child(n, 0);
      if (is_completed(status_[c])) reset_status(c);
    }
    return s;
  }

  // Hooks must answer SUCCESS, FAILURE or RUNNING; anything else breaks
  // their contract (BehaviorTree.CPP throws) and counts as FAILURE.
  static constexpr Status sanitize(Status s) noexcept {
    return (s == Status::SUCCESS || s == Status::FAILURE || s == Status::RUNNING) ? s : Status::FAILURE;
  }

  // `else` / `if_empty` = IDLE: the node would set its own status to IDLE,
  // which makes BehaviorTree.CPP 4.6.2 throw (edges table, L1 and L2): a
  // run-time error, and the node fails.
  Status not_idle(const NodeInfo& n, Status s) noexcept {
    if (s != Status::IDLE) return s;
    sink().fail(n, n.source,
                n.kind == NodeKind::Precondition
                    ? std::string_view("the condition is false and `else` is IDLE: a node may not set its own status "
                                       "to IDLE (BehaviorTree.CPP throws)")
                    : std::string_view("the queue is empty and `if_empty` is IDLE: a node may not set its own status "
                                       "to IDLE (BehaviorTree.CPP throws)"));
    return Status::FAILURE;
  }

  // The condition of IfThenElse / WhileDoElse `n` answered SKIPPED, which the library throws
  // on: a run-time error at the condition, and the node fails. (lower.py knows which
  // conditions can skip; only a run can tell whether one does.)
  Status skipped_condition(const NodeInfo& n) noexcept {
    const NodeInfo& cond = info(child(n, 0));
    sink().fail(cond, cond.source,
                n.kind == NodeKind::IfThenElse
                    ? std::string_view("the condition of this `IfThenElse` returned SKIPPED, which makes "
                                       "BehaviorTree.CPP throw (a condition child must not be skippable)")
                    : std::string_view("the condition of this `WhileDoElse` returned SKIPPED, which makes "
                                       "BehaviorTree.CPP throw (a condition child must not be skippable)"));
    return Status::FAILURE;
  }

  static constexpr bool is_sequence(NodeKind k) noexcept {
    return k == NodeKind::Sequence || k == NodeKind::AsyncSequence || k == NodeKind::SequenceWithMemory ||
           k == NodeKind::ReactiveSequence;
  }

  [[gnu::always_inline]] Step enter(Frame& f, NodeKind kind) noexcept {
    const NodeInfo& n = info(f.node);
    switch (kind) {
      case NodeKind::Sequence:
      case NodeKind::AsyncSequence:
      case NodeKind::SequenceWithMemory:
      case NodeKind::Fallback:
      case NodeKind::AsyncFallback:
        // 4.6.2's all_skipped_ flag (counter 1: a child did not skip), cleared
        // only when the node is ticked from IDLE; or 4.7.0's skipped count.
        if (!is_active(status_[f.node])) counter(n, 1) = 0;
        set_status(f.node, Status::RUNNING);
        return sequence_next(f, n, kind);

      case NodeKind::ReactiveSequence:
      case NodeKind::ReactiveFallback:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        f.aux = 1;  // all children skipped so far
        return descend(child(n, 0));

      case NodeKind::TryCatch:
        // TryCatchNode (4.9.0): counter 0 the try child, 1 the try children skipped, 2 in the
        // catch child (the last one).
        if (!is_active(status_[f.node])) {
          counter(n, 1) = 0;
          counter(n, 2) = 0;
        }
        set_status(f.node, Status::RUNNING);
        if (counter(n, 2) != 0) {
          f.pos = static_cast<std::uint16_t>(n.child_count - 1);
          return descend(child(n, f.pos));
        }
        return try_next(f, n);

      case NodeKind::Parallel:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        f.aux = 0;  // skipped this tick
        return parallel_next(f, n);

      case NodeKind::ParallelAll:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        f.aux = 0;
        return parallel_all_next(f, n);

      case NodeKind::IfThenElse:
        set_status(f.node, Status::RUNNING);
        f.pos = static_cast<std::uint16_t>(counter(n, 0));
        return descend(child(n, f.pos));

      case NodeKind::WhileDoElse:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        return descend(child(n, 0));

      case NodeKind::Inverter:
      case NodeKind::ForceSuccess:
      case NodeKind::ForceFailure:
      case NodeKind::KeepRunningUntilFailure:
        f.decorator = 1;
        set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));

      case NodeKind::Repeat:
      case NodeKind::RetryUntilSuccessful:
        f.decorator = 1;
        // 4.6.2's all_skipped_ flag (counter 1: a child did not skip), cleared
        // only from IDLE: a count of 0 or below -1 never ticks the child, so
        // the node answers SKIPPED and stays RUNNING (edges table, R1).
        if (!read_param(n, true)) return done(Status::FAILURE);  // 4.6.2 throws: the node fails
        if (status_[f.node] == Status::IDLE) counter(n, 1) = 0;
        set_status(f.node, Status::RUNNING);
        if (counter(n, 0) < max_cycles(n) || max_cycles(n) == -1) return descend(child(n, 0));
        counter(n, 0) = 0;
        // From 4.7.0 (Sem::loop_end_never_skipped) the loop ends SUCCESS / FAILURE.
        if (!Sem::loop_end_never_skipped && counter(n, 1) == 0) return done(Status::SKIPPED);
        return done(kind == NodeKind::Repeat ? Status::SUCCESS : Status::FAILURE);

      case NodeKind::RunOnce:
        f.decorator = 1;
        if (counter(n, 0) != 0) {
          // then_skip given as `{key}` (p1 is 1): getInput<bool> never throws here, so reading
          // it only once the child has completed is what 4.6.2's read on every tick gives.
          std::int64_t skip = (n.p1 != 0 || param::then_skip(n)) ? 1 : 0;
          if (n.p1 != 0) (void)Spec::read_param(bb_, sink(), n, skip);
          return done(skip != 0 ? Status::SKIPPED : static_cast<Status>(counter(n, 1)));
        }
        set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));

      case NodeKind::Timeout: {
        f.decorator = 1;
        std::int32_t& started = counter(n, 0);
        std::int32_t& armed = counter(n, 1);
        if (!read_param(n, started == 0)) return done(Status::FAILURE);
        if (started == 0) {
          started = 1;
          set_status(f.node, Status::RUNNING);
          armed = duration_ms(n) > 0 ? 1 : 0;
          timer(n) = clock_.now_ms();
        } else if (armed != 0 && reached(elapsed(n), duration_ms(n))) {
          // The timer fires: a RUNNING child is halted and the node fails.
          armed = 0;
          if (status_[child(n, 0)] == Status::RUNNING) {
            halt_child(n, 0);
            started = 0;
            return done(Status::FAILURE);
          }
        }
        return descend(child(n, 0));
      }

      case NodeKind::Delay: {
        f.decorator = 1;
        std::int32_t& started = counter(n, 0);
        if (!read_param(n, started == 0)) return done(Status::FAILURE);
        if (started == 0) {
          started = 1;
          set_status(f.node, Status::RUNNING);
          timer(n) = clock_.now_ms();
        }
        if (reached(elapsed(n), duration_ms(n))) return descend(child(n, 0));
        return done(Status::RUNNING);
      }

      case NodeKind::SubTree:
        f.decorator = 1;
        if (status_[f.node] == Status::IDLE) set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));

      case NodeKind::Switch: {
        // SwitchNode<N>: no RUNNING of its own before the case is ticked;
        // a change of case halts the one that was running.
        const int match = Spec::switch_case(bb_, n);
        std::int32_t& running = counter(n, 0);  // the case RUNNING + 1
        if (running != 0 && running - 1 != match) halt_child(n, static_cast<std::size_t>(running - 1));
        f.pos = static_cast<std::uint16_t>(match);
        return descend(child(n, f.pos));
      }

      case NodeKind::Precondition: {
        f.decorator = 1;
        // 4.6.2 evaluates `if` on every tick; when false it answers `else`
        // without ticking (or halting) its child. From 4.7.0
        // (Sem::precondition_if_until_started) only until the child has
        // started (counter 0), which then runs to completion; halt() does not
        // clear that flag (a quirk of the library, followed).
        if constexpr (Sem::precondition_if_until_started) {
          if (counter(n, 0) != 0) return descend(child(n, 0));
        }
        const int r = run_script(n, ScriptSlot::kCode);
        if (r < 0) return done(Status::FAILURE);
        if (r == 1) {
          if constexpr (Sem::precondition_if_until_started) counter(n, 0) = 1;
          return descend(child(n, 0));
        }
        return done(not_idle(n, param::otherwise(n)));
      }

      case NodeKind::Loop: {
        f.decorator = 1;
        // LoopNode<T>: one element per run of the child (written to
        // `value`), RUNNING after every child success, `if_empty` (p0)
        // once the queue is used up.
        std::int32_t& child_running = counter(n, 0);
        const bool idle = status_[f.node] == Status::IDLE;
        if (idle) child_running = 0;
        if (child_running == 0) {
          const ErrorSink es = sink();
          const int r = Spec::loop_pop(bb_, n, es, idle);
          if (r < 0) return done(Status::FAILURE);
          if (r == 0) return done(not_idle(n, param::otherwise(n)));
        }
        if (idle) set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));
      }

      case NodeKind::SkipUnlessUpdated:
      case NodeKind::WaitValueUpdate: {
        f.decorator = 1;
        // EntryUpdatedDecorator: the child runs only when the entry's
        // update counter moved since this node last looked.
        const Status not_updated = kind == NodeKind::SkipUnlessUpdated ? Status::SKIPPED : Status::RUNNING;
        if (counter(n, 0) != 0) return descend(child(n, 0));  // the child is still executing
        const std::int64_t seq = Spec::entry_seq(bb_, n);
        if (seq < 0) return done(not_updated);
        const std::uint64_t previous = timer(n);
        timer(n) = static_cast<std::uint64_t>(seq);
        if (previous == static_cast<std::uint64_t>(seq)) return done(not_updated);
        return descend(child(n, 0));
      }

      case NodeKind::AlwaysSuccess: return done(Status::SUCCESS);

      case NodeKind::AlwaysFailure: return done(Status::FAILURE);

      case NodeKind::Sleep: {
        const Status st = status_[f.node];
        if (st == Status::IDLE) {
          if (!read_param(n, true)) return done(Status::FAILURE);
          if (duration_ms(n) <= 0) return done(Status::SUCCESS);
          set_status(f.node, Status::RUNNING);
          timer(n) = clock_.now_ms();
          return done(Status::RUNNING);
        }
        if (st == Status::RUNNING) return done(reached(elapsed(n), duration_ms(n)) ? Status::SUCCESS : Status::RUNNING);
        return done(st);
      }

      case NodeKind::Script: return done(run_script(n, ScriptSlot::kCode) < 0 ? Status::FAILURE : Status::SUCCESS);

      case NodeKind::ScriptCondition:
        return done(run_script(n, ScriptSlot::kCode) == 1 ? Status::SUCCESS : Status::FAILURE);

      case NodeKind::SetBlackboard:
      case NodeKind::UnsetBlackboard: {
        const ErrorSink es = sink();
        return done(Spec::data_leaf(bb_, n, es));
      }

      case NodeKind::WasEntryUpdated: {
        const std::int64_t seq = Spec::entry_seq(bb_, n);
        if (seq < 0) return done(Status::FAILURE);
        const std::uint64_t previous = timer(n);
        timer(n) = static_cast<std::uint64_t>(seq);
        return done(previous != static_cast<std::uint64_t>(seq) ? Status::SUCCESS : Status::FAILURE);
      }

      case NodeKind::Action: {
        // StatefulActionNode: onStart from IDLE, onRunning while RUNNING; a
        // node not yet reset by its parent answers its status again (a
        // SyncActionNode, tick() alone, ticks again: LeafHooks::on_start calls it).
        const Status st = status_[f.node];
        if (st != Status::IDLE && st != Status::RUNNING && !Hooks::sync_action(n)) return done(st);
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        const Status s =
            st == Status::IDLE ? Hooks::on_start(*leaves_, bb_, es, n) : Hooks::on_running(*leaves_, bb_, es, n);
        return done(guarded(s, before));
      }

      case NodeKind::Condition: {
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        return done(guarded(Hooks::check(*leaves_, bb_, es, n), before));
      }

      case NodeKind::PipelineSequence:
      case NodeKind::RecoveryNode:
      case NodeKind::RoundRobin:
      case NodeKind::NonblockingSequence:
      case NodeKind::PersistentSequence:
      case NodeKind::RateController:
      case NodeKind::SingleTrigger:
      case NodeKind::DistanceController:
      case NodeKind::SpeedController:
      case NodeKind::GoalUpdatedController:
      case NodeKind::PathLongerOnApproach:
      case NodeKind::GoalUpdater: {
        // Nav2's nodes tick their children as a user Control does, above this frame of the
        // stack; an error of a child fails only the child.
        f.decorator = is_decorator(kind) ? 1 : 0;
        const std::uint64_t before = errors_;
        const std::size_t base = static_cast<std::size_t>(&f - stack_.data()) + 1;
        f.aux = 0;
        const Status s = nav2_tick(n, ChildOps(&kChildOps, this, &n, base));
        if (errors_ - before > f.aux) return done(Status::FAILURE);
        return done(s);
      }

      case NodeKind::UserControl:
      case NodeKind::UserDecorator: {
        // The user's tick(); its children run above this frame of the stack. An error the
        // node reports itself (fail(), a port write) fails it; its children's errors
        // (counted in f.aux by ops_tick_child) only fail them.
        f.decorator = kind == NodeKind::UserDecorator ? 1 : 0;
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        const std::size_t base = static_cast<std::size_t>(&f - stack_.data()) + 1;
        f.aux = 0;
        const Status s = Hooks::user_tick(*leaves_, bb_, es, n, ChildOps(&kChildOps, this, &n, base));
        if (errors_ - before > f.aux) return done(Status::FAILURE);
        if (s == Status::IDLE) {
          // TreeNode::setStatus(IDLE) throws in 4.6.2.
          (void)es.fail(n, n.source, "tick() returned IDLE: a node is not allowed to set its status to IDLE");
          return done(Status::FAILURE);
        }
        return done(s);
      }
    }
    return done(Status::FAILURE);
  }

  [[gnu::always_inline]] Step resume(Frame& f, Status cs, NodeKind kind) noexcept {
    const NodeInfo& n = info(f.node);
    switch (kind) {
      case NodeKind::Sequence:
      case NodeKind::AsyncSequence:
      case NodeKind::SequenceWithMemory: {
        std::int32_t& idx = counter(n, 0);
        note_skipped(counter(n, 1), cs);
        switch (cs) {
          case Status::RUNNING: return done(Status::RUNNING);
          case Status::SUCCESS:
            ++idx;
            // SequenceWithMemory always has the wake-up rule in 4.6.2,
            // AsyncSequence is the plain Sequence with it.
            if (kind != NodeKind::Sequence && f.child_prev == Status::IDLE && idx < n.child_count) {
              return done(Status::RUNNING);
            }
            return sequence_next(f, n, kind);
          case Status::SKIPPED: ++idx; return sequence_next(f, n, kind);
          default:  // FAILURE
            if (kind == NodeKind::SequenceWithMemory) {
              for (std::size_t i = static_cast<std::size_t>(idx); i < n.child_count; ++i) halt_child(n, i);
            } else {
              reset_children(n);
              idx = 0;
            }
            return done(Status::FAILURE);
        }
      }

      case NodeKind::Fallback:
      case NodeKind::AsyncFallback: {
        std::int32_t& idx = counter(n, 0);
        note_skipped(counter(n, 1), cs);
        switch (cs) {
          case Status::RUNNING: return done(Status::RUNNING);
          case Status::FAILURE:
            ++idx;
            if (kind == NodeKind::AsyncFallback && f.child_prev == Status::IDLE && idx < n.child_count) {
              return done(Status::RUNNING);
            }
            return sequence_next(f, n, kind);
          case Status::SKIPPED: ++idx; return sequence_next(f, n, kind);
          default:  // SUCCESS
            reset_children(n);
            idx = 0;
            return done(Status::SUCCESS);
        }
      }

      case NodeKind::ReactiveSequence:
      case NodeKind::ReactiveFallback: {
        const bool seq = kind == NodeKind::ReactiveSequence;
        if (cs != Status::SKIPPED) f.aux = 0;
        if (cs == Status::RUNNING) {
          for (std::size_t i = 0; i < n.child_count; ++i) {
            if (i != f.pos) halt_child(n, i);
          }
          return done(Status::RUNNING);
        }
        if (cs == (seq ? Status::FAILURE : Status::SUCCESS)) {
          reset_children(n);
          return done(cs);
        }
        if (cs == Status::SKIPPED) halt_child(n, f.pos);
        if (++f.pos < n.child_count) return descend(child(n, f.pos));
        reset_children(n);
        return done(f.aux != 0 ? Status::SKIPPED : (seq ? Status::SUCCESS : Status::FAILURE));
      }

      case NodeKind::TryCatch: {
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        if (counter(n, 2) != 0) {  // the catch child finished: the node fails
          reset_children(n);
          counter(n, 0) = 0;
          counter(n, 2) = 0;
          return done(Status::FAILURE);
        }
        if (cs == Status::FAILURE) {  // into the catch child, in this tick
          reset_children(n);
          counter(n, 0) = 0;
          counter(n, 2) = 1;
          f.pos = static_cast<std::uint16_t>(n.child_count - 1);
          return descend(child(n, f.pos));
        }
        if (cs == Status::SKIPPED) ++counter(n, 1);
        ++counter(n, 0);
        return try_next(f, n);
      }

      case NodeKind::Parallel: {
        const std::uint16_t c = child(n, f.pos);
        switch (cs) {
          case Status::SKIPPED: ++f.aux; break;
          case Status::SUCCESS:
            set_done(c, true);
            ++counter(n, 0);
            break;
          case Status::FAILURE:
            set_done(c, true);
            ++counter(n, 1);
            break;
          default: break;
        }
        const Status decided = parallel_check(f, n);
        if (decided != Status::IDLE) return done(decided);
        ++f.pos;
        return parallel_next(f, n);
      }

      case NodeKind::ParallelAll: {
        const std::uint16_t c = child(n, f.pos);
        switch (cs) {
          case Status::SKIPPED: ++f.aux; break;
          case Status::SUCCESS: set_done(c, true); break;
          case Status::FAILURE:
            set_done(c, true);
            ++counter(n, 0);
            break;
          default: break;
        }
        ++f.pos;
        return parallel_all_next(f, n);
      }

      case NodeKind::IfThenElse: {
        std::int32_t& branch = counter(n, 0);
        if (f.pos == 0) {
          if (cs == Status::RUNNING) return done(Status::RUNNING);
          if (cs == Status::SUCCESS) {
            branch = 1;
          } else if (cs == Status::FAILURE && n.child_count == 3) {
            branch = 2;
          } else if (cs == Status::SKIPPED) {
            // The library throws at once (both releases): a run-time error at the condition.
            return done(skipped_condition(n));
          } else {
            return done(Status::FAILURE);  // FAILURE without an else branch
          }
          f.pos = static_cast<std::uint16_t>(branch);
          return descend(child(n, f.pos));
        }
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        reset_children(n);
        branch = 0;
        return done(cs);
      }

      case NodeKind::WhileDoElse: {
        if (f.pos == 0) {
          if (cs == Status::RUNNING) return done(Status::RUNNING);
          if (cs == Status::SUCCESS) {
            if (n.child_count == 3) halt_child(n, 2);
            f.pos = 1;
            return descend(child(n, 1));
          }
          if (cs == Status::FAILURE && n.child_count == 3) {
            halt_child(n, 1);
            f.pos = 2;
            return descend(child(n, 2));
          }
          // FAILURE with two children; a SKIPPED condition: the library resets the children,
          // then throws (its status would become IDLE), in both releases.
          reset_children(n);
          return done(cs == Status::SKIPPED ? skipped_condition(n) : Status::FAILURE);
        }
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        reset_children(n);
        return done(cs);
      }

      case NodeKind::Inverter:
        if (cs == Status::SUCCESS || cs == Status::FAILURE) {
          halt_child(n, 0);
          return done(cs == Status::SUCCESS ? Status::FAILURE : Status::SUCCESS);
        }
        return done(cs);

      case NodeKind::ForceSuccess:
      case NodeKind::ForceFailure:
        if (is_completed(cs)) {
          halt_child(n, 0);
          return done(kind == NodeKind::ForceSuccess ? Status::SUCCESS : Status::FAILURE);
        }
        return done(cs);

      case NodeKind::KeepRunningUntilFailure:
        if (cs == Status::FAILURE) {
          halt_child(n, 0);
          return done(Status::FAILURE);
        }
        if (cs == Status::SUCCESS) halt_child(n, 0);
        return done(Status::RUNNING);

      case NodeKind::Repeat:
      case NodeKind::RetryUntilSuccessful: {
        const bool repeat = kind == NodeKind::Repeat;
        std::int32_t& count = counter(n, 0);
        if (cs != Status::SKIPPED) counter(n, 1) = 1;
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        if (cs == Status::SKIPPED) {
          halt_child(n, 0);
          return done(Status::SKIPPED);
        }
        if (cs == (repeat ? Status::FAILURE : Status::SUCCESS)) {
          count = 0;
          halt_child(n, 0);
          return done(cs);
        }
        // Another cycle (Repeat after SUCCESS, Retry after FAILURE).
        if (count < INT32_MAX) ++count;
        // From 4.7.0 (Sem::retry_rereads_attempts) num_attempts is read again after a failure;
        // a read that fails keeps the count in use.
        if constexpr (Sem::retry_rereads_attempts) {
          if (!repeat) reread_param(n);
        }
        const bool again = count < max_cycles(n) || max_cycles(n) == -1;
        halt_child(n, 0);
        if (again && f.child_prev == Status::IDLE) return done(Status::RUNNING);  // wake-up rule
        if (again) return descend(child(n, 0));
        count = 0;
        return done(repeat ? Status::SUCCESS : Status::FAILURE);
      }

      case NodeKind::RunOnce:
        if (is_completed(cs)) {
          counter(n, 0) = 1;
          counter(n, 1) = static_cast<std::int32_t>(cs);
          halt_child(n, 0);
        }
        return done(cs);

      case NodeKind::Timeout:
        if (is_completed(cs)) {
          counter(n, 0) = 0;
          counter(n, 1) = 0;
          halt_child(n, 0);
        }
        return done(cs);

      case NodeKind::Delay:
        if (is_completed(cs)) {
          counter(n, 0) = 0;
          halt_child(n, 0);
        }
        return done(cs);

      case NodeKind::SubTree:
        if (is_completed(cs)) halt_child(n, 0);
        return done(cs);

      case NodeKind::Switch: {
        std::int32_t& running = counter(n, 0);
        if (cs == Status::SKIPPED) {
          running = 0;
          return done(Status::SKIPPED);
        }
        if (cs == Status::RUNNING) {
          running = static_cast<std::int32_t>(f.pos) + 1;
        } else {
          reset_children(n);
          running = 0;
        }
        return done(cs);
      }

      case NodeKind::Precondition:
        if (is_completed(cs)) {
          halt_child(n, 0);
          if constexpr (Sem::precondition_if_until_started) counter(n, 0) = 0;
        }
        return done(cs);

      case NodeKind::Loop:
        counter(n, 0) = cs == Status::RUNNING ? 1 : 0;
        if (is_completed(cs)) halt_child(n, 0);
        return done(cs == Status::FAILURE ? Status::FAILURE : Status::RUNNING);

      case NodeKind::SkipUnlessUpdated:
      case NodeKind::WaitValueUpdate: counter(n, 0) = cs == Status::RUNNING ? 1 : 0; return done(cs);

      default:  // leaves have no children
        return done(cs);
    }
  }

  // What the Sequence / Fallback family remembers of a child's result for SKIPPED: 4.6.2 a
  // flag "a child did not skip" (cleared from IDLE only), 4.7.0 the children skipped in this
  // run (Sem::skipped_by_count).
  [[gnu::always_inline]] static void note_skipped(std::int32_t& c, Status cs) noexcept {
    if constexpr (Sem::skipped_by_count) {
      if (cs == Status::SKIPPED) ++c;
    } else {
      if (cs != Status::SKIPPED) c = 1;
    }
  }
  // At the end of the loop: whether the node returns SKIPPED (4.7.0 clears its count then).
  [[gnu::always_inline]] static bool all_skipped(std::int32_t& c, std::size_t children) noexcept {
    if constexpr (Sem::skipped_by_count) {
      const bool all = static_cast<std::size_t>(c) == children;
      c = 0;
      return all;
    } else {
      return c == 0;
    }
  }

  // Sequence / Fallback family: tick the child at the stored index, or end.
  // 4.6.2 returns SKIPPED when no child ticked since the node was last IDLE
  // answered anything but SKIPPED; the flag is not reset when the loop ends.
  [[gnu::always_inline]] Step sequence_next(Frame& f, const NodeInfo& n, NodeKind kind) noexcept {
    std::int32_t& idx = counter(n, 0);
    if (idx < n.child_count) {
      f.pos = static_cast<std::uint16_t>(idx);
      return descend(child(n, f.pos));
    }
    const bool skipped = all_skipped(counter(n, 1), n.child_count);
    reset_children(n);
    idx = 0;
    if (skipped) return done(Status::SKIPPED);
    return done(is_sequence(kind) ? Status::SUCCESS : Status::FAILURE);
  }

  // TryCatch: the next try child, or the end of the try block (SKIPPED when all skipped).
  Step try_next(Frame& f, const NodeInfo& n) noexcept {
    std::int32_t& idx = counter(n, 0);
    const std::size_t tries = n.child_count - 1;
    if (static_cast<std::size_t>(idx) < tries) {
      f.pos = static_cast<std::uint16_t>(idx);
      return descend(child(n, f.pos));
    }
    const bool skipped = static_cast<std::size_t>(counter(n, 1)) == tries;
    reset_children(n);
    idx = 0;
    counter(n, 1) = 0;
    return done(skipped ? Status::SKIPPED : Status::SUCCESS);
  }

  Step parallel_next(Frame& f, const NodeInfo& n) noexcept {
    while (f.pos < n.child_count) {
      const std::uint16_t c = child(n, f.pos);
      if (!is_done(c)) return descend(c);
      const Status decided = parallel_check(f, n);
      if (decided != Status::IDLE) return done(decided);
      ++f.pos;
    }
    return done(f.aux == n.child_count ? Status::SKIPPED : Status::RUNNING);
  }

  // The thresholds, checked after every child as 4.6.2 does; IDLE: undecided.
  Status parallel_check(Frame& f, const NodeInfo& n) noexcept {
    const std::int64_t successes = counter(n, 0);
    const std::int64_t failures = counter(n, 1);
    const std::int64_t required = param::success_threshold(n);
    Status decided = Status::IDLE;
    if (successes >= required || (param::success_count_relative(n) && successes + f.aux >= required)) {
      decided = Status::SUCCESS;
    } else if (n.child_count - failures < required || failures == param::failure_threshold(n)) {
      decided = Status::FAILURE;
    }
    if (decided != Status::IDLE) {
      counter(n, 0) = 0;
      counter(n, 1) = 0;
      clear_done(n);
      reset_children(n);
    }
    return decided;
  }

  Step parallel_all_next(Frame& f, const NodeInfo& n) noexcept {
    while (f.pos < n.child_count) {
      const std::uint16_t c = child(n, f.pos);
      if (!is_done(c)) return descend(c);
      ++f.pos;
    }
    if (f.aux == n.child_count) return done(Status::SKIPPED);
    std::size_t completed = 0;
    for (std::size_t i = 0; i < n.child_count; ++i) completed += is_done(child(n, i)) ? 1u : 0u;
    if (f.aux + completed < n.child_count) return done(Status::RUNNING);
    reset_children(n);
    clear_done(n);
    const Status s = counter(n, 0) >= param::max_failures(n) ? Status::FAILURE : Status::SUCCESS;
    counter(n, 0) = 0;
    return done(s);
  }

  Leaves* leaves_;
  Clock clock_;
  Observer observer_;
  Blackboard bb_{};
  std::uint64_t errors_ = 0;
  std::array<Status, kNodeCount> status_{};
  std::array<std::int32_t, Spec::kCounterCount> counters_{};
  std::array<std::uint64_t, Spec::kTimerCount> timers_{};
  std::array<std::uint32_t, Spec::kHasParallel ? (kNodeCount + 31) / 32 : 0> done_{};
  std::array<Frame, kUsesInterpreter ? kMaxDepth : 0> stack_{};  // execute_at's
  std::array<HaltFrame, kMaxDepth> halt_stack_{};
};

}  // namespace btgen
