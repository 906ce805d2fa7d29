// btgen runtime: an observer that live monitors attach to.
//
// A mission's observer is a template parameter, fixed when the mission type
// is written; monitors (btgen::groot2::Publisher, btgen::btlog::FileLogger)
// are created later, at run time. MonitorObserver<Next> is the meeting point:
// the mission holds it by value, monitors attach themselves to it (up to
// kMaxSinks at once) and every status change goes to each attached monitor,
// then to Next (NoObserver by default; TraceWriter, or any observer):
//
//     using Tour = lab_tour::LabTour<Robot, btgen::SteadyClock, btgen::MonitorObserver<>>;
//     static Tour mission(robot);
//     btgen::groot2::Publisher groot2(mission, 1667);   // attaches itself
//     btgen::btlog::FileLogger log(mission, "tour.btlog");
//
// Attach and detach between ticks, from the thread that ticks the mission.
// The cost on the tick path is one indirect call per attached monitor and
// status change; nothing allocates or locks.
//
// One monitor at a time may also force statuses (Groot2's REPLACE hooks,
// btgen::groot2::Publisher): it hands the observer a table of one atomic
// byte per node (attach_hooks). The engine asks forced_status() on each visit
// of a node, after its pre-conditions, as BehaviorTree.CPP 4.6.2 calls a
// node's pre-tick callback: the cost is one relaxed load of that byte (and a
// null test of the table without such a monitor); only a set byte calls the
// monitor. A mission that follows 4.10.0 (Sem::groot2_post_hooks) also asks
// post_forced_status() after each tick of a node, as 4.10.0 calls a node's
// post-tick callback: a second table of one byte per node, read the same way.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "btgen/trace.hpp"

namespace btgen {

// What a monitor implements. Called on the tick thread, inside tick().
class StatusSink {
 public:
  virtual void on_status(const NodeInfo& node, Status from, Status to) noexcept = 0;

 protected:
  StatusSink() = default;
  StatusSink(const StatusSink&) = default;
  StatusSink& operator=(const StatusSink&) = default;
  ~StatusSink() = default;
};

// What a monitor that forces statuses implements. Called on the tick thread,
// inside tick(), when the node's byte in its table is not 0 and the node is not
// completed (4.6.2 calls the pre-tick callback only then). Returns SUCCESS or
// FAILURE to return that instead of ticking the node, anything else to tick it.
class HookSink {
 public:
  virtual Status on_hook(const NodeInfo& node, std::uint8_t hook) noexcept = 0;
  // The same after the node's tick (4.10.0's POST hooks, from the second table): called
  // whatever the node returned. SUCCESS or FAILURE replaces its result.
  virtual Status on_post_hook(const NodeInfo& node, std::uint8_t hook) noexcept {
    (void)node;
    (void)hook;
    return Status::IDLE;
  }

 protected:
  HookSink() = default;
  HookSink(const HookSink&) = default;
  HookSink& operator=(const HookSink&) = default;
  ~HookSink() = default;
};

namespace monitor_detail {
template <class T, class = void>
struct has_on_error : std::false_type {};
template <class T>
struct has_on_error<T, std::void_t<decltype(std::declval<T&>().on_error(std::declval<const RuntimeError&>()))>>
    : std::true_type {};
}  // namespace monitor_detail

template <class Next = NoObserver>
class MonitorObserver {
 public:
  static constexpr std::size_t kMaxSinks = 4;

  MonitorObserver() = default;
  explicit MonitorObserver(Next next) noexcept(std::is_nothrow_move_constructible_v<Next>) : next_(std::move(next)) {}

  void on_status_change(const NodeInfo& node, Status from, Status to) noexcept {
    for (std::size_t i = 0; i < count_; ++i) sinks_[i]->on_status(node, from, to);
    next_.on_status_change(node, from, to);
  }

  // Run-time errors go to Next when it takes them.
  void on_error(const RuntimeError& error) noexcept {
    if constexpr (monitor_detail::has_on_error<Next>::value)
      next_.on_error(error);
    else
      (void)error;
  }

  // False when kMaxSinks monitors are attached already (or `sink` is).
  bool attach(StatusSink* sink) noexcept {
    if (sink == nullptr || count_ == kMaxSinks) return false;
    for (std::size_t i = 0; i < count_; ++i)
      if (sinks_[i] == sink) return false;
    sinks_[count_++] = sink;
    return true;
  }
  void detach(StatusSink* sink) noexcept {
    for (std::size_t i = 0; i < count_; ++i) {
      if (sinks_[i] == sink) {
        for (std::size_t j = i + 1; j < count_; ++j) sinks_[j - 1] = sinks_[j];
        sinks_[--count_] = nullptr;
        return;
      }
    }
  }
  [[nodiscard]] std::size_t attached() const noexcept { return count_; }

  // The engine, on each visit of a node, after its pre-conditions: whether a hook is set
  // there (the fast path: a null test, a relaxed load); then, for a node not completed,
  // forced_status(): SUCCESS or FAILURE when the hook forces it (the node is not ticked),
  // else IDLE.
  // (Built with BTGEN_NO_GROOT2_HOOKS, the observer has neither: the engine compiles the
  // test away, and attach_hooks() refuses.)
#ifndef BTGEN_NO_GROOT2_HOOKS
  [[nodiscard, gnu::always_inline]] bool hooked(std::size_t index) const noexcept {
    return hooks_ != nullptr && hooks_[index].load(std::memory_order_relaxed) != 0;
  }
  [[nodiscard]] Status forced_status(const NodeInfo& node) noexcept {
    if (hooks_ == nullptr) return Status::IDLE;
    const std::uint8_t b = hooks_[node.index].load(std::memory_order_relaxed);
    if (b == 0) return Status::IDLE;
    const Status s = hook_sink_->on_hook(node, b);
    return is_completed(s) ? s : Status::IDLE;
  }
  // The same for the POST table (4.10.0 missions: the engine asks after the node's tick).
  [[nodiscard, gnu::always_inline]] bool post_hooked(std::size_t index) const noexcept {
    return post_hooks_ != nullptr && post_hooks_[index].load(std::memory_order_relaxed) != 0;
  }
  [[nodiscard]] Status post_forced_status(const NodeInfo& node) noexcept {
    if (post_hooks_ == nullptr) return Status::IDLE;
    const std::uint8_t b = post_hooks_[node.index].load(std::memory_order_relaxed);
    if (b == 0) return Status::IDLE;
    const Status s = hook_sink_->on_post_hook(node, b);
    return is_completed(s) ? s : Status::IDLE;
  }
  static constexpr bool kHooks = true;
#else
  static constexpr bool kHooks = false;
#endif
  // `table` holds one byte per node of the mission (indexed by NodeInfo::index) and
  // outlives the attachment; `post_table` likewise, for POST hooks (or null). False when
  // another monitor forces statuses already.
  bool attach_hooks(HookSink* sink, const std::atomic<std::uint8_t>* table,
                    const std::atomic<std::uint8_t>* post_table = nullptr) noexcept {
    if (!kHooks || sink == nullptr || table == nullptr || hook_sink_ != nullptr) return false;
    hook_sink_ = sink;
    hooks_ = table;
    post_hooks_ = post_table;
    return true;
  }
  void detach_hooks(HookSink* sink) noexcept {
    if (hook_sink_ != sink) return;
    hook_sink_ = nullptr;
    hooks_ = nullptr;
    post_hooks_ = nullptr;
  }

  [[nodiscard]] Next& next() noexcept { return next_; }

 private:
  StatusSink* sinks_[kMaxSinks] = {};
  std::size_t count_ = 0;
  HookSink* hook_sink_ = nullptr;
  const std::atomic<std::uint8_t>* hooks_ = nullptr;
  const std::atomic<std::uint8_t>* post_hooks_ = nullptr;
  Next next_{};
};

}  // namespace btgen
