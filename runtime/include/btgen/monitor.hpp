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
#pragma once

#include <cstddef>
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

  [[nodiscard]] Next& next() noexcept { return next_; }

 private:
  StatusSink* sinks_[kMaxSinks] = {};
  std::size_t count_ = 0;
  Next next_{};
};

}  // namespace btgen
