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
//
// Its parts: btgen/engine/spec.hpp (what a Spec provides), engine/straight_line.hpp (the
// straight-line ticks), engine/nav2_rules.hpp (Nav2's Controls and Decorators) and
// engine/rules.hpp (the built-in nodes' rules), the last three inside the class body.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/clock.hpp"
#include "btgen/engine/spec.hpp"
#include "btgen/leaf_dispatch.hpp"
#include "btgen/nav2.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"
#include "btgen/user_node.hpp"

namespace btgen {

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

#include "btgen/engine/straight_line.hpp"  // members of this class

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

#include "btgen/engine/nav2_rules.hpp"  // members of this class

#include "btgen/engine/rules.hpp"  // members of this class

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
