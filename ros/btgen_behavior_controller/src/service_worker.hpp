// ServiceWorker: the blocking ROS service calls of the leaves, run off the
// tick thread.
//
// The production behaviorController makes one blocking service call inside
// each leaf's tick(), so the whole tree (and Groot2, and a halt) waits for
// the robot. Here an Action's onStart() hands its call to this one worker
// thread and returns RUNNING; onRunning() polls for the result; the tick
// thread never blocks. Calls run one at a time, in the order they were
// started (the mission has no Parallel node, so there is at most one).
//
// Each mission node has one slot, indexed by its node index. A halt (or a
// restart of the node) bumps the slot's generation: a call already running
// cannot be cancelled (ROS 1 services have no cancel), so it completes and
// its result is dropped; a call still queued is never made.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace btgen_behavior_controller {

class ServiceWorker {
 public:
  enum class Poll : std::uint8_t { kRunning, kSucceeded, kFailed };

  explicit ServiceWorker(std::size_t node_count) : slots_(node_count) {
    thread_ = std::thread([this] { run(); });
  }
  ~ServiceWorker() { stop(); }
  ServiceWorker(const ServiceWorker&) = delete;
  ServiceWorker& operator=(const ServiceWorker&) = delete;

  /// Queues `call` (true: the service answered and reported success) for node `index`.
  void start(std::size_t index, std::function<bool()> call) {
    std::lock_guard<std::mutex> lock(mutex_);
    Slot& s = slots_[index];
    ++s.generation;
    s.state = State::kQueued;
    s.call = std::move(call);
    queue_.emplace_back(index, s.generation);
    wake_.notify_one();
  }

  /// The state of node `index`'s call; a finished call is consumed.
  Poll poll(std::size_t index) {
    std::lock_guard<std::mutex> lock(mutex_);
    Slot& s = slots_[index];
    if (s.state != State::kDone) return Poll::kRunning;
    s.state = State::kIdle;
    return s.ok ? Poll::kSucceeded : Poll::kFailed;
  }

  /// Forgets node `index`'s call: not made if still queued, result dropped if running.
  void abandon(std::size_t index) {
    std::lock_guard<std::mutex> lock(mutex_);
    Slot& s = slots_[index];
    ++s.generation;
    s.state = State::kIdle;
    s.call = nullptr;
  }

  /// Makes no further call and joins the thread (after the call in progress, if any:
  /// ros::shutdown() makes a blocking ros::service::call return).
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      queue_.clear();
      wake_.notify_one();
    }
    if (thread_.joinable()) thread_.join();
  }

 private:
  enum class State : std::uint8_t { kIdle, kQueued, kDone };
  struct Slot {
    std::uint64_t generation = 0;
    State state = State::kIdle;
    bool ok = false;
    std::function<bool()> call;
  };

  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      const auto [index, generation] = queue_.front();
      queue_.pop_front();
      Slot& s = slots_[index];
      if (s.generation != generation || !s.call) continue;  // abandoned while queued
      std::function<bool()> call = std::move(s.call);
      s.call = nullptr;
      lock.unlock();
      const bool ok = call();
      lock.lock();
      if (s.generation == generation) {
        s.ok = ok;
        s.state = State::kDone;
      }
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Slot> slots_;
  std::deque<std::pair<std::size_t, std::uint64_t>> queue_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace btgen_behavior_controller
